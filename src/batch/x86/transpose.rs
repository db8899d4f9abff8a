//! SIMD transpositions that move groups of eight contacts between the C structs (`rsl_sphere`,
//! `rsl_contact_state`) and the batch kernel's rows (see `batch::block`).
//!
//! The kernel keeps its inputs in rows, one per quantity, so that each lane value is one vector
//! load. Filling the rows value by value costs a load and a store per double: 33 doubles per
//! contact in (two bodies and the state), 13 out. Here each struct is read as a few vectors and
//! rearranged in registers, so a group of eight contacts costs a handful of loads, shuffles and
//! stores per quantity. Measured on the full LAMMPS law set, AVX-512, in cache: 27 against 31 ns
//! per contact (edited builds of the benchmark driver).
//!
//! The states go in two words at a time: the 128-bit pairs of the even contacts in one register,
//! those of the odd ones in another, then one unpack per row. Shuffles issue on a single port
//! of recent Intel cores, and this takes one per row (of eight lanes under AVX-512, of four
//! under AVX2), against three for an 8 x 8 transposition and two for a 4 x 4 one; the inserts
//! that merge the pairs can go to another port. In cache it took 3-6% off the batch rows. The
//! bodies go in by whole transpositions (two loads per sphere instead of five): by pairs they
//! were at most 2% faster in cache, but on randomly permuted particles at 1.2M contacts, where
//! body 2 is a scattered read, the double kernels took up to 14% more time. Out, the
//! transpositions stay: stores of pairs took 0-6% more time than the 8 x 8 transpositions
//! under AVX-512. The figures are in the docs' performance page, "The gather by pairs of
//! words". The copies are exact: every implementation here gives the rows and states of
//! [`PortableCopy`] bit for bit (tested below).
//!
//! [`PortableCopy`]: crate::batch::PortableCopy

use crate::batch::history::Record;
use crate::batch::{
    group_of, pair_bodies_by_reference, store_loads_by_value, walls_by_value, GroupCopy, GroupRow,
    LoadsSlot, WallSlot, BODY_WORDS, GROUP, STATE_WORDS, WALL_WORDS,
};
use crate::layout::{rsl_contact_state, rsl_sphere};
use std::mem::{offset_of, size_of};

// The transpositions read and write these structs as arrays of doubles: a sphere is its
// `BODY_WORDS` doubles, a state starts with its `STATE_WORDS` doubles (then the slip flags).
const _: () = assert!(size_of::<rsl_sphere>() == BODY_WORDS * 8);
const _: () = assert!(offset_of!(rsl_sphere, radius) == (BODY_WORDS - 1) * 8);
const _: () = assert!(offset_of!(rsl_contact_state, previous_normal) == (STATE_WORDS - 3) * 8);
const _: () = assert!(offset_of!(rsl_contact_state, slip_flags) == STATE_WORDS * 8);
const _: () = assert!(GROUP == 8);

/// A pointer to the first double of `s` (valid for the whole struct, not just its first field).
fn doubles<S>(s: &S) -> *const f64 {
    (s as *const S).cast::<f64>()
}

/// [`GroupCopy`] with AVX2: bodies in by 4 x 4 transpositions, states in by pairs of words,
/// states and loads out by 4 x 4 transpositions (ymm registers).
#[derive(Clone, Copy, Debug)]
pub struct Avx2Copy {
    /// The state words a step can change ([`GroupCopy::writing`]): the only ones written back.
    written: u16,
}

impl Avx2Copy {
    /// The copier, for a CPU known to have AVX2; it writes back every state word.
    ///
    /// # Safety
    /// The CPU must have AVX2.
    pub(crate) unsafe fn assume() -> Self {
        Avx2Copy {
            written: (1 << STATE_WORDS) - 1,
        }
    }
}

/// [`GroupCopy`] with AVX-512 F and DQ: bodies in by 8 x 8 transpositions, states in by pairs of
/// words, states and loads out by 8 x 8 transpositions (zmm registers).
#[derive(Clone, Copy, Debug)]
pub struct Avx512Copy(());

impl Avx512Copy {
    /// The copier, for a CPU known to have AVX-512 F and DQ.
    ///
    /// # Safety
    /// The CPU must have AVX-512 F and DQ.
    pub(crate) unsafe fn assume() -> Self {
        Avx512Copy(())
    }
}

#[cfg(target_arch = "x86_64")]
mod avx2 {
    use super::GroupRow;
    use std::arch::x86_64::*;

    /// `t[i]` lane `j` = `w[j]` lane `i`.
    #[inline]
    #[target_feature(enable = "avx2")]
    fn transpose4(w: [__m256d; 4]) -> [__m256d; 4] {
        let a0 = _mm256_unpacklo_pd(w[0], w[1]);
        let a1 = _mm256_unpackhi_pd(w[0], w[1]);
        let a2 = _mm256_unpacklo_pd(w[2], w[3]);
        let a3 = _mm256_unpackhi_pd(w[2], w[3]);
        [
            _mm256_permute2f128_pd::<0x20>(a0, a2),
            _mm256_permute2f128_pd::<0x20>(a1, a3),
            _mm256_permute2f128_pd::<0x31>(a0, a2),
            _mm256_permute2f128_pd::<0x31>(a1, a3),
        ]
    }

    /// `rows[i][k]` = double `at + i` of `src[k]`, for `i < 4`.
    ///
    /// # Safety
    /// Each `src[k]` points to at least `at + 4` readable doubles; the CPU has AVX2.
    #[inline]
    #[target_feature(enable = "avx2")]
    pub unsafe fn words_to_rows(src: [*const f64; 8], at: usize, mut rows: [&mut GroupRow; 4]) {
        for half in 0..2 {
            // SAFETY: doubles `at..at + 4` of each source, inside the caller's bound.
            let w: [__m256d; 4] =
                std::array::from_fn(|j| unsafe { _mm256_loadu_pd(src[4 * half + j].add(at)) });
            let t = transpose4(w);
            for (row, v) in rows.iter_mut().zip(t) {
                let dst: &mut [f64; 4] = (&mut row[4 * half..4 * half + 4])
                    .try_into()
                    .expect("four slots");
                // SAFETY: `dst` is four writable doubles.
                unsafe { _mm256_storeu_pd(dst.as_mut_ptr(), v) };
            }
        }
    }

    /// Double `at + i` of `dst[k]` = `rows[i][k]`, for `i < 4`.
    ///
    /// # Safety
    /// Each `dst[k]` points to at least `at + 4` writable doubles, none overlapping another's
    /// or the rows; the CPU has AVX2.
    #[inline]
    #[target_feature(enable = "avx2")]
    pub unsafe fn rows_to_words(rows: [&GroupRow; 4], dst: [*mut f64; 8], at: usize) {
        for half in 0..2 {
            let w: [__m256d; 4] = std::array::from_fn(|i| {
                let src: &[f64; 4] = rows[i][4 * half..4 * half + 4]
                    .try_into()
                    .expect("four slots");
                // SAFETY: `src` is four readable doubles.
                unsafe { _mm256_loadu_pd(src.as_ptr()) }
            });
            for (j, v) in transpose4(w).into_iter().enumerate() {
                // SAFETY: doubles `at..at + 4` of a destination, inside the caller's bound.
                unsafe { _mm256_storeu_pd(dst[4 * half + j].add(at), v) };
            }
        }
    }

    /// `min(i[k], last) * factor` for each of the sixteen `i[k]`, by AVX2 minima and
    /// multiplications (`last * factor` must fit in a `u32`, or the products wrap).
    ///
    /// # Safety
    /// The CPU has AVX2.
    #[inline]
    #[target_feature(enable = "avx2")]
    pub unsafe fn clamped_multiples(i: &[u32], last: u32, factor: u32) -> [u32; 16] {
        let i: &[u32; 16] = i.try_into().expect("sixteen indices");
        let (last, factor) = (
            _mm256_set1_epi32(last as i32),
            _mm256_set1_epi32(factor as i32),
        );
        let mut out = [0u32; 16];
        for half in 0..2 {
            // SAFETY: eight `u32` of `i` and of `out` from `8 * half`, inside both arrays.
            unsafe {
                let v = _mm256_loadu_si256(i.as_ptr().add(8 * half).cast());
                let v = _mm256_mullo_epi32(_mm256_min_epu32(v, last), factor);
                _mm256_storeu_si256(out.as_mut_ptr().add(8 * half).cast(), v);
            }
        }
        out
    }

    /// `rows[i][k]` = double `at + i` of `src[k]`, for `i < 2`: the pairs of contacts k and
    /// k + 2 in one register and of k + 1 and k + 3 in another (a 128-bit load each, the upper
    /// one merged by an insert, which needs no shuffle port), then one unpack per row. Two
    /// shuffles for two rows of four, where a 4 x 4 transposition takes eight for four.
    ///
    /// # Safety
    /// Each `src[k]` points to at least `at + 2` readable doubles; the CPU has AVX2.
    #[inline]
    #[target_feature(enable = "avx2")]
    pub unsafe fn pairs_to_rows(src: [*const f64; 8], at: usize, mut rows: [&mut GroupRow; 2]) {
        // SAFETY: doubles `at..at + 2` of a source, inside the caller's bound.
        let pair = |k: usize| unsafe { _mm_loadu_pd(src[k].add(at)) };
        for half in 0..2 {
            let k = 4 * half;
            // Contacts k and k + 2 in one register, k + 1 and k + 3 in the other.
            let even = _mm256_insertf128_pd::<1>(_mm256_castpd128_pd256(pair(k)), pair(k + 2));
            let odd = _mm256_insertf128_pd::<1>(_mm256_castpd128_pd256(pair(k + 1)), pair(k + 3));
            for (row, v) in rows
                .iter_mut()
                .zip([_mm256_unpacklo_pd(even, odd), _mm256_unpackhi_pd(even, odd)])
            {
                let dst: &mut [f64; 4] = (&mut row[k..k + 4]).try_into().expect("four slots");
                // SAFETY: `dst` is four writable doubles.
                unsafe { _mm256_storeu_pd(dst.as_mut_ptr(), v) };
            }
        }
    }
}

#[cfg(target_arch = "x86_64")]
mod avx512 {
    use super::GroupRow;
    use std::arch::x86_64::*;

    /// `t[i]` lane `j` = `w[j]` lane `i`.
    #[inline]
    #[target_feature(enable = "avx512f")]
    fn transpose8(w: [__m512d; 8]) -> [__m512d; 8] {
        // Pairs of rows interleaved: a[2m] holds even words, a[2m + 1] odd words of w[2m], w[2m+1].
        let a: [__m512d; 8] = std::array::from_fn(|i| {
            let (x, y) = (w[i & !1], w[i | 1]);
            if i % 2 == 0 {
                _mm512_unpacklo_pd(x, y)
            } else {
                _mm512_unpackhi_pd(x, y)
            }
        });
        // 128-bit lanes 0 and 2 (words 0, 4 / 1, 5) or 1 and 3 (words 2, 6 / 3, 7) of two pairs.
        let lo = |x, y| _mm512_shuffle_f64x2::<0b10_00_10_00>(x, y);
        let hi = |x, y| _mm512_shuffle_f64x2::<0b11_01_11_01>(x, y);
        let b = [
            lo(a[0], a[2]),
            lo(a[1], a[3]),
            hi(a[0], a[2]),
            hi(a[1], a[3]),
            lo(a[4], a[6]),
            lo(a[5], a[7]),
            hi(a[4], a[6]),
            hi(a[5], a[7]),
        ];
        [
            lo(b[0], b[4]),
            lo(b[1], b[5]),
            lo(b[2], b[6]),
            lo(b[3], b[7]),
            hi(b[0], b[4]),
            hi(b[1], b[5]),
            hi(b[2], b[6]),
            hi(b[3], b[7]),
        ]
    }

    /// `rows[i][k]` = double `at + i` of `src[k]`, for `i < 8`.
    ///
    /// # Safety
    /// Each `src[k]` points to at least `at + 8` readable doubles; the CPU has AVX-512 F.
    #[inline]
    #[target_feature(enable = "avx512f")]
    pub unsafe fn words_to_rows(src: [*const f64; 8], at: usize, rows: [&mut GroupRow; 8]) {
        // SAFETY: doubles `at..at + 8` of each source, inside the caller's bound.
        let w: [__m512d; 8] = std::array::from_fn(|k| unsafe { _mm512_loadu_pd(src[k].add(at)) });
        for (row, v) in rows.into_iter().zip(transpose8(w)) {
            // SAFETY: a row of a group is eight writable doubles.
            unsafe { _mm512_storeu_pd(row.as_mut_ptr(), v) };
        }
    }

    /// Double `at + i` of `dst[k]` = `rows[i][k]`, for `i < 8`.
    ///
    /// # Safety
    /// Each `dst[k]` points to at least `at + 8` writable doubles, none overlapping another's
    /// or the rows; the CPU has AVX-512 F.
    #[inline]
    #[target_feature(enable = "avx512f")]
    pub unsafe fn rows_to_words(rows: [&GroupRow; 8], dst: [*mut f64; 8], at: usize) {
        // SAFETY: a row of a group is eight readable doubles.
        let w: [__m512d; 8] = std::array::from_fn(|i| unsafe { _mm512_loadu_pd(rows[i].as_ptr()) });
        for (k, v) in transpose8(w).into_iter().enumerate() {
            // SAFETY: doubles `at..at + 8` of a destination, inside the caller's bound.
            unsafe { _mm512_storeu_pd(dst[k].add(at), v) };
        }
    }

    /// `rows[0][k]`, `rows[1][k]` = doubles `at`, `at + 1` of `src[k]`. The pairs of the even
    /// contacts go to one register and those of the odd ones to another, a 128-bit load each
    /// (three of the four merged by inserts), and one unpack makes each row: two shuffles for
    /// two rows, where an 8 x 8 transposition takes six, and the inserts can issue on a second
    /// port.
    ///
    /// # Safety
    /// Each `src[k]` points to at least `at + 2` readable doubles; the CPU has AVX-512 F, DQ.
    #[inline]
    #[target_feature(enable = "avx512f,avx512dq")]
    pub unsafe fn pairs_to_rows(src: [*const f64; 8], at: usize, rows: [&mut GroupRow; 2]) {
        // SAFETY: doubles `at..at + 2` of a source, inside the caller's bound.
        let pair = |k: usize| unsafe { _mm_loadu_pd(src[k].add(at)) };
        // Contacts k, k + 2, k + 4, k + 6, two doubles each.
        let four = |k: usize| {
            let v = _mm512_castpd128_pd512(pair(k));
            let v = _mm512_insertf64x2::<1>(v, pair(k + 2));
            let v = _mm512_insertf64x2::<2>(v, pair(k + 4));
            _mm512_insertf64x2::<3>(v, pair(k + 6))
        };
        let (even, odd) = (four(0), four(1));
        let [row0, row1] = rows;
        // SAFETY: a row of a group is eight writable doubles.
        unsafe {
            _mm512_storeu_pd(row0.as_mut_ptr(), _mm512_unpacklo_pd(even, odd));
            _mm512_storeu_pd(row1.as_mut_ptr(), _mm512_unpackhi_pd(even, odd));
        }
    }
}

/// Where the bodies of a group of contacts start, in doubles from the first particle's: slot
/// `2 k` is body 1 of contact `k` and slot `2 k + 1` its body 2 (the order of `pairs`), an index
/// past the last particle taken as the last. `None` when there is no particle or the last one's
/// offset does not fit in a `u32` (over 429 million particles). Two vector minima and two
/// multiplications for the sixteen indices: taking a reference to each body instead (a bounds
/// test, a conditional move and an address per body) cost about 20 instructions per contact in
/// the double AVX2 kernels, and a plain loop over the indices stayed scalar (five instructions
/// per index).
///
/// # Safety
/// The CPU must have AVX2.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
unsafe fn sphere_offsets(particles: usize, pairs: &[[u32; 2]; GROUP]) -> Option<[u32; 2 * GROUP]> {
    let last = u32::try_from(particles.checked_sub(1)?).ok()?;
    let words = BODY_WORDS as u32;
    if last > u32::MAX / words {
        return None;
    }
    // SAFETY: the caller's contract.
    Some(unsafe { avx2::clamped_multiples(pairs.as_flattened(), last, words) })
}

/// Pointers to the first doubles of the bodies of a group's contacts (`[0][k]` body 1 of
/// contact `k`, `[1][k]` its body 2), each a whole sphere of `particles` (an index past the last
/// particle gives the last): [`sphere_offsets`] from the first particle. `None` where it is.
///
/// # Safety
/// The CPU must have AVX2.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
unsafe fn body_pointers(
    particles: &[rsl_sphere],
    pairs: &[[u32; 2]; GROUP],
) -> Option<[[*const f64; GROUP]; 2]> {
    // SAFETY: the caller's contract.
    let offsets = unsafe { sphere_offsets(particles.len(), pairs)? };
    let first = particles.as_ptr().cast::<f64>();
    let side = |s: usize| group_of(|k| first.wrapping_add(offsets[2 * k + s] as usize));
    Some([side(0), side(1)])
}

/// `rows[q][k]` = word `q` of the sphere whose first double `src[k]` points to, by AVX2 4 x 4
/// transpositions of words 0..4 and 4..8 and a pair of words 8..10 (whole transpositions, not
/// pairs: see the module comment).
///
/// # Safety
/// The CPU must have AVX2; each `src[k]` must point to a whole `rsl_sphere`.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
unsafe fn avx2_bodies(src: [*const f64; GROUP], rows: [&mut GroupRow; BODY_WORDS]) {
    let [r0, r1, r2, r3, r4, r5, r6, r7, r8, r9] = rows;
    // SAFETY: the caller's contract; a sphere is `BODY_WORDS` = 10 doubles (asserted above), so
    // words 0..4, 4..8 and 8..10 are inside it.
    unsafe {
        avx2::words_to_rows(src, 0, [r0, r1, r2, r3]);
        avx2::words_to_rows(src, 4, [r4, r5, r6, r7]);
        avx2::pairs_to_rows(src, 8, [r8, r9]);
    }
}

/// As [`avx2_bodies`], by an AVX-512 8 x 8 transposition of words 0..8 and a pair of words
/// 8..10.
///
/// # Safety
/// The CPU must have AVX-512 F and DQ; each `src[k]` must point to a whole `rsl_sphere`.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
unsafe fn avx512_bodies(src: [*const f64; GROUP], rows: [&mut GroupRow; BODY_WORDS]) {
    let [r0, r1, r2, r3, r4, r5, r6, r7, r8, r9] = rows;
    // SAFETY: as in `avx2_bodies`: words 0..8 and 8..10 are inside a sphere.
    unsafe {
        avx512::words_to_rows(src, 0, [r0, r1, r2, r3, r4, r5, r6, r7]);
        avx512::pairs_to_rows(src, 8, [r8, r9]);
    }
}

/// The walls of a group as rows ([`GroupCopy::walls`]) by three 4 x 4 transpositions of words
/// 0..4, 4..8, 8..12 (ymm registers).
///
/// # Safety
/// The CPU must have AVX2; each `src[k]` must point to `WALL_WORDS` readable doubles.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
unsafe fn avx2_walls(src: [*const f64; GROUP], rows: [&mut GroupRow; WALL_WORDS]) {
    let [r0, r1, r2, r3, r4, r5, r6, r7, r8, r9, r10, r11] = rows;
    // SAFETY: the caller's contract: words 0..4, 4..8 and 8..12 are inside each wall.
    unsafe {
        avx2::words_to_rows(src, 0, [r0, r1, r2, r3]);
        avx2::words_to_rows(src, 4, [r4, r5, r6, r7]);
        avx2::words_to_rows(src, 8, [r8, r9, r10, r11]);
    }
}

/// As [`avx2_walls`], by an AVX-512 8 x 8 transposition of words 0..8 and a 4 x 4 one of
/// words 8..12.
///
/// # Safety
/// The CPU must have AVX-512 F and DQ, and AVX2; each `src[k]` must point to `WALL_WORDS`
/// readable doubles.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
unsafe fn avx512_walls(src: [*const f64; GROUP], rows: [&mut GroupRow; WALL_WORDS]) {
    let [r0, r1, r2, r3, r4, r5, r6, r7, r8, r9, r10, r11] = rows;
    // SAFETY: as in `avx2_walls`: words 0..8 and 8..12 are inside each wall.
    unsafe {
        avx512::words_to_rows(src, 0, [r0, r1, r2, r3, r4, r5, r6, r7]);
        avx2::words_to_rows(src, 8, [r8, r9, r10, r11]);
    }
}

/// The first doubles of a group of walls laid out as `WALL_WORDS` doubles
/// ([`WallSlot::doubles`]), or `None` for another layout.
#[inline(always)]
fn wall_doubles<W: WallSlot>(walls: &[&W; GROUP]) -> Option<[*const f64; GROUP]> {
    walls[0].doubles()?;
    let ptr = |k: usize| walls[k].doubles().map_or(std::ptr::null(), |d| d.as_ptr());
    Some(group_of(ptr))
}

/// Pointers to the first double of each state, to write (each valid for its whole struct).
fn doubles_mut(states: &mut [rsl_contact_state; GROUP]) -> [*mut f64; GROUP] {
    states
        .each_mut()
        .map(|s| (s as *mut rsl_contact_state).cast::<f64>())
}

/// A pointer to the first double of `state`, to write (valid for the whole struct).
fn doubles_of(state: &mut rsl_contact_state) -> *mut f64 {
    (state as *mut rsl_contact_state).cast::<f64>()
}

/// Writes each state's slip flags (the transpositions write only its doubles).
fn set_slip_flags(states: &mut [rsl_contact_state; GROUP], slip: &[u32; GROUP]) {
    for (state, &flags) in states.iter_mut().zip(slip) {
        state.slip_flags = flags;
    }
}

/// [`set_slip_flags`] for states that need not be adjacent.
fn set_slip_flags_at(states: [&mut rsl_contact_state; GROUP], slip: &[u32; GROUP]) {
    for (state, &flags) in states.into_iter().zip(slip) {
        state.slip_flags = flags;
    }
}

/// Writes word `q` of the state at `dst[k]` from `rows[q][k]` (its first 13 doubles) for
/// every word of `written` (bit `q`: word `q`), by AVX2 4 x 4 transpositions of the windows
/// that hold one: words 0..4 (sliding spring), 3..7 (rolling spring, twisting angle), 7..11
/// (off-axis twisting part) and 9..13 (previous normal). A window also writes its neighbours'
/// words from their rows, which hold the values the states hold (read by the gather, or
/// written by the step): every word of every state ends as its row says. With every word
/// written, this is four windows; the LAMMPS-style law sets write two or three.
///
/// # Safety
/// The CPU must have AVX2; each `dst[k]` must be writable for a whole `rsl_contact_state` and
/// not overlap another or the rows.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
unsafe fn avx2_rows_to_states(
    rows: [&GroupRow; STATE_WORDS],
    dst: [*mut f64; GROUP],
    written: u16,
) {
    let [r0, r1, r2, r3, r4, r5, r6, r7, r8, r9, r10, r11, r12] = rows;
    // SAFETY: the caller's contract; a state starts with 13 doubles (asserted above), so every
    // window is inside it.
    unsafe {
        if written & 0b111 != 0 {
            avx2::rows_to_words([r0, r1, r2, r3], dst, 0);
        }
        if written & 0b1111 << 3 != 0 {
            avx2::rows_to_words([r3, r4, r5, r6], dst, 3);
        }
        if written & 0b111 << 7 != 0 {
            avx2::rows_to_words([r7, r8, r9, r10], dst, 7);
        }
        if written & 0b111 << 10 != 0 {
            avx2::rows_to_words([r9, r10, r11, r12], dst, 9);
        }
    }
}

/// As [`avx2_rows_to_states`] by AVX-512 8 x 8 transpositions: words 0..8 and 5..13 (5..8
/// written twice with the same values).
///
/// # Safety
/// The CPU must have AVX-512 F and DQ; `dst` as for [`avx2_rows_to_states`].
#[cfg(target_arch = "x86_64")]
#[inline(always)]
unsafe fn avx512_rows_to_states(rows: [&GroupRow; STATE_WORDS], dst: [*mut f64; GROUP]) {
    let [r0, r1, r2, r3, r4, r5, r6, r7, r8, r9, r10, r11, r12] = rows;
    // SAFETY: as in `avx2_rows_to_states`.
    unsafe {
        avx512::rows_to_words([r0, r1, r2, r3, r4, r5, r6, r7], dst, 0);
        avx512::rows_to_words([r5, r6, r7, r8, r9, r10, r11, r12], dst, 5);
    }
}

/// A pointer to the nine doubles of each output slot, or `None` when the slot type is not
/// laid out as nine doubles ([`LoadsSlot::words_mut`]); the pointers come from distinct `&mut`
/// slots, so they do not overlap.
#[inline(always)]
fn load_words<O: LoadsSlot>(out: &mut [O; GROUP]) -> Option<[*mut f64; GROUP]> {
    let mut dst = [std::ptr::null_mut::<f64>(); GROUP];
    for (d, slot) in dst.iter_mut().zip(out.iter_mut()) {
        *d = slot.words_mut()?.as_mut_ptr();
    }
    Some(dst)
}

#[cfg(target_arch = "x86_64")]
impl GroupCopy<rsl_sphere, rsl_contact_state> for Avx2Copy {
    #[inline(always)]
    fn bodies(self, bodies: [&rsl_sphere; GROUP], rows: [&mut GroupRow; BODY_WORDS]) {
        // SAFETY: an `Avx2Copy` exists only on a CPU with AVX2 (`Avx2Copy::assume`); each
        // pointer comes from a reference to a whole sphere.
        unsafe { avx2_bodies(bodies.map(doubles), rows) }
    }

    #[inline(always)]
    fn pair_bodies(
        self,
        particles: &[rsl_sphere],
        pairs: &[[u32; 2]; GROUP],
        rows1: [&mut GroupRow; BODY_WORDS],
        rows2: [&mut GroupRow; BODY_WORDS],
    ) {
        // SAFETY: an `Avx2Copy` exists only on a CPU with AVX2 (`Avx2Copy::assume`).
        let Some([src1, src2]) = (unsafe { body_pointers(particles, pairs) }) else {
            return pair_bodies_by_reference::<_, rsl_contact_state, _>(
                self, particles, pairs, rows1, rows2,
            );
        };
        // SAFETY: the CPU has AVX2 (as in `bodies`); every pointer is that of a whole sphere of
        // `particles` (`body_pointers`).
        unsafe {
            avx2_bodies(src1, rows1);
            avx2_bodies(src2, rows2);
        }
    }

    #[inline(always)]
    fn states(self, states: [&rsl_contact_state; GROUP], rows: [&mut GroupRow; STATE_WORDS]) {
        let src = states.map(doubles);
        let [r0, r1, r2, r3, r4, r5, r6, r7, r8, r9, r10, r11, r12] = rows;
        // SAFETY: as in `bodies`; a state starts with `STATE_WORDS` = 13 doubles (asserted
        // above): words 0..2, 2..4, ..., 10..12 and 11..13 are inside them. Row 11 is written
        // twice with the same values.
        unsafe {
            avx2::pairs_to_rows(src, 0, [r0, r1]);
            avx2::pairs_to_rows(src, 2, [r2, r3]);
            avx2::pairs_to_rows(src, 4, [r4, r5]);
            avx2::pairs_to_rows(src, 6, [r6, r7]);
            avx2::pairs_to_rows(src, 8, [r8, r9]);
            avx2::pairs_to_rows(src, 10, [r10, &mut *r11]);
            avx2::pairs_to_rows(src, 11, [r11, r12]);
        }
    }

    #[inline(always)]
    fn walls<W: WallSlot>(self, walls: [&W; GROUP], rows: [&mut GroupRow; WALL_WORDS]) {
        match wall_doubles(&walls) {
            // SAFETY: an `Avx2Copy` exists only on a CPU with AVX2 (`Avx2Copy::assume`); each
            // pointer is that of a wall's `WALL_WORDS` doubles (`WallSlot::doubles`).
            Some(src) => unsafe { avx2_walls(src, rows) },
            None => walls_by_value(walls, rows),
        }
    }

    #[inline(always)]
    fn store_states(
        self,
        rows: [&GroupRow; STATE_WORDS],
        slip: &[u32; GROUP],
        states: &mut [rsl_contact_state; GROUP],
    ) {
        // SAFETY: as in `bodies`; the pointers come from distinct `&mut` states (so they do not
        // overlap each other or the rows).
        unsafe { avx2_rows_to_states(rows, doubles_mut(states), self.written) };
        set_slip_flags(states, slip);
    }

    #[inline(always)]
    fn store_states_at(
        self,
        rows: [&GroupRow; STATE_WORDS],
        slip: &[u32; GROUP],
        mut states: [&mut rsl_contact_state; GROUP],
    ) {
        let dst = states.each_mut().map(|s| doubles_of(s));
        // SAFETY: as in `store_states` (distinct `&mut` states).
        unsafe { avx2_rows_to_states(rows, dst, self.written) };
        set_slip_flags_at(states, slip);
    }

    #[inline(always)]
    fn writing(self, words: u16) -> Self {
        Avx2Copy { written: words }
    }

    #[inline(always)]
    fn store_loads<O: LoadsSlot>(self, rows: [&GroupRow; 9], out: &mut [O; GROUP]) {
        let Some(dst) = load_words(out) else {
            return store_loads_by_value(rows, out);
        };
        let [r0, r1, r2, r3, r4, r5, r6, r7, r8] = rows;
        // SAFETY: an `Avx2Copy` exists only on a CPU with AVX2 (`Avx2Copy::assume`); each
        // pointer comes from a distinct `&mut` slot of nine doubles (`load_words`, so they do
        // not overlap each other or the rows): words 0..4, 4..8 and 5..9 are inside it (5..8
        // written twice with the same values).
        unsafe {
            avx2::rows_to_words([r0, r1, r2, r3], dst, 0);
            avx2::rows_to_words([r4, r5, r6, r7], dst, 4);
            avx2::rows_to_words([r5, r6, r7, r8], dst, 5);
        }
    }
}

#[cfg(target_arch = "x86_64")]
impl GroupCopy<rsl_sphere, rsl_contact_state> for Avx512Copy {
    #[inline(always)]
    fn bodies(self, bodies: [&rsl_sphere; GROUP], rows: [&mut GroupRow; BODY_WORDS]) {
        // SAFETY: an `Avx512Copy` exists only on a CPU with AVX-512 F and DQ
        // (`Avx512Copy::assume`); each pointer comes from a reference to a whole sphere.
        unsafe { avx512_bodies(bodies.map(doubles), rows) }
    }

    #[inline(always)]
    fn pair_bodies(
        self,
        particles: &[rsl_sphere],
        pairs: &[[u32; 2]; GROUP],
        rows1: [&mut GroupRow; BODY_WORDS],
        rows2: [&mut GroupRow; BODY_WORDS],
    ) {
        // SAFETY: the CPU has AVX2 (an `Avx512Copy` exists only where the batch dispatch found
        // AVX2 too, `Simd::available`).
        let Some([src1, src2]) = (unsafe { body_pointers(particles, pairs) }) else {
            return pair_bodies_by_reference::<_, rsl_contact_state, _>(
                self, particles, pairs, rows1, rows2,
            );
        };
        // SAFETY: the CPU has AVX-512 F and DQ (as in `bodies`); every pointer is that of a
        // whole sphere of `particles` (`body_pointers`).
        unsafe {
            avx512_bodies(src1, rows1);
            avx512_bodies(src2, rows2);
        }
    }

    #[inline(always)]
    fn states(self, states: [&rsl_contact_state; GROUP], rows: [&mut GroupRow; STATE_WORDS]) {
        let src = states.map(doubles);
        let [r0, r1, r2, r3, r4, r5, r6, r7, r8, r9, r10, r11, r12] = rows;
        // SAFETY: as in `bodies`; a state starts with `STATE_WORDS` = 13 doubles (asserted
        // above): words 0..2, 2..4, ..., 10..12 and 11..13 are inside them. Row 11 is written
        // twice with the same values.
        unsafe {
            avx512::pairs_to_rows(src, 0, [r0, r1]);
            avx512::pairs_to_rows(src, 2, [r2, r3]);
            avx512::pairs_to_rows(src, 4, [r4, r5]);
            avx512::pairs_to_rows(src, 6, [r6, r7]);
            avx512::pairs_to_rows(src, 8, [r8, r9]);
            avx512::pairs_to_rows(src, 10, [r10, &mut *r11]);
            avx512::pairs_to_rows(src, 11, [r11, r12]);
        }
    }

    #[inline(always)]
    fn walls<W: WallSlot>(self, walls: [&W; GROUP], rows: [&mut GroupRow; WALL_WORDS]) {
        match wall_doubles(&walls) {
            // SAFETY: an `Avx512Copy` exists only on a CPU with AVX-512 F and DQ and AVX2
            // (`Avx512Copy::assume`, `Simd::available`); each pointer is that of a wall's
            // `WALL_WORDS` doubles (`WallSlot::doubles`).
            Some(src) => unsafe { avx512_walls(src, rows) },
            None => walls_by_value(walls, rows),
        }
    }

    #[inline(always)]
    fn store_states(
        self,
        rows: [&GroupRow; STATE_WORDS],
        slip: &[u32; GROUP],
        states: &mut [rsl_contact_state; GROUP],
    ) {
        // SAFETY: as in `bodies`; the pointers come from distinct `&mut` states (so they do not
        // overlap each other or the rows).
        unsafe { avx512_rows_to_states(rows, doubles_mut(states)) };
        set_slip_flags(states, slip);
    }

    #[inline(always)]
    fn store_states_at(
        self,
        rows: [&GroupRow; STATE_WORDS],
        slip: &[u32; GROUP],
        mut states: [&mut rsl_contact_state; GROUP],
    ) {
        let dst = states.each_mut().map(|s| doubles_of(s));
        // SAFETY: as in `store_states` (distinct `&mut` states).
        unsafe { avx512_rows_to_states(rows, dst) };
        set_slip_flags_at(states, slip);
    }

    #[inline(always)]
    fn store_loads<O: LoadsSlot>(self, rows: [&GroupRow; 9], out: &mut [O; GROUP]) {
        let Some(dst) = load_words(out) else {
            return store_loads_by_value(rows, out);
        };
        let [r0, r1, r2, r3, r4, r5, r6, r7, r8] = rows;
        // SAFETY: an `Avx512Copy` exists only on a CPU with AVX-512 F and DQ
        // (`Avx512Copy::assume`); each pointer comes from a distinct `&mut` slot of nine
        // doubles (so they do not overlap each other or the rows): words 0..8 and 1..9 are
        // inside it (1..8 written twice with the same values).
        unsafe {
            avx512::rows_to_words([r0, r1, r2, r3, r4, r5, r6, r7], dst, 0);
            avx512::rows_to_words([r1, r2, r3, r4, r5, r6, r7, r8], dst, 1);
        }
    }
}

/// Packed histories ([`Record`]) in windows of four words of the full layout, each moved by a
/// 4 x 4 AVX2 transposition (AVX-512 CPUs have AVX2): full-layout words 0..4 and 3..7 are the
/// springs (rows 0..7), words 6..10 the twisting angle again and the previous normal (rows 6,
/// 10, 11, 12), words 9..13 the previous normal's last word again and the off-axis part (rows
/// 12, 7, 8, 9). A word in two windows is moved twice with the same value. A record without the
/// sliding spring (`F` = 3) skips the first window, and its rows (the sliding spring's) are
/// zero, as in a state whose sliding spring is zero.
///
/// # Safety
/// The CPU must have AVX2.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
unsafe fn records_to_rows<const W: usize, const F: usize>(
    records: [&Record<W, F>; GROUP],
    rows: [&mut GroupRow; STATE_WORDS],
) {
    const { assert!((F == 0 || F == 3) && matches!(F + W, 7 | 10 | 13)) };
    let src = records.map(|r| r.0.as_ptr());
    let [r0, r1, r2, r3, r4, r5, r6, r7, r8, r9, r10, r11, r12] = rows;
    // SAFETY: each pointer comes from a whole record of `W` doubles, full-layout words
    // `F..F + W`, and every window read (full-layout words 0..4 when `F = 0`, 3..7, then 6..10
    // when `F + W >= 10`, 9..13 when `F + W = 13`, at record word `at - F`) is inside it (the
    // const assertion above); the CPU has AVX2 (the caller's contract).
    unsafe {
        if F == 0 {
            avx2::words_to_rows(src, 0, [r0, r1, r2, &mut *r3]);
        } else {
            for row in [r0, r1, r2] {
                *row = [0.0; GROUP];
            }
        }
        avx2::words_to_rows(src, 3 - F, [r3, r4, r5, &mut *r6]);
        if F + W >= 10 {
            avx2::words_to_rows(src, 6 - F, [r6, r10, r11, &mut *r12]);
        }
        if F + W >= 13 {
            avx2::words_to_rows(src, 9 - F, [r12, r7, r8, r9]);
        }
    }
}

/// The inverse of [`records_to_rows`]: the record words from the rows (slip flags are not
/// kept in a record, nor the sliding spring's rows when `F` = 3).
///
/// # Safety
/// The CPU must have AVX2.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
unsafe fn rows_to_records<const W: usize, const F: usize>(
    rows: [&GroupRow; STATE_WORDS],
    records: &mut [Record<W, F>; GROUP],
) {
    const { assert!((F == 0 || F == 3) && matches!(F + W, 7 | 10 | 13)) };
    let dst = records.each_mut().map(|r| r.0.as_mut_ptr());
    let [r0, r1, r2, r3, r4, r5, r6, r7, r8, r9, r10, r11, r12] = rows;
    // SAFETY: each pointer comes from a distinct `&mut` record of `W` doubles (so they do not
    // overlap each other or the rows), and every window written is inside it (as in
    // `records_to_rows`); the CPU has AVX2 (the caller's contract).
    unsafe {
        if F == 0 {
            avx2::rows_to_words([r0, r1, r2, r3], dst, 0);
        }
        avx2::rows_to_words([r3, r4, r5, r6], dst, 3 - F);
        if F + W >= 10 {
            avx2::rows_to_words([r6, r10, r11, r12], dst, 6 - F);
        }
        if F + W >= 13 {
            avx2::rows_to_words([r12, r7, r8, r9], dst, 9 - F);
        }
    }
}

macro_rules! record_copy {
    ($copy:ty) => {
        #[cfg(target_arch = "x86_64")]
        impl<const W: usize, const F: usize> GroupCopy<rsl_sphere, Record<W, F>> for $copy {
            #[inline(always)]
            fn bodies(self, bodies: [&rsl_sphere; GROUP], rows: [&mut GroupRow; BODY_WORDS]) {
                GroupCopy::<rsl_sphere, rsl_contact_state>::bodies(self, bodies, rows)
            }

            #[inline(always)]
            fn pair_bodies(
                self,
                particles: &[rsl_sphere],
                pairs: &[[u32; 2]; GROUP],
                rows1: [&mut GroupRow; BODY_WORDS],
                rows2: [&mut GroupRow; BODY_WORDS],
            ) {
                GroupCopy::<rsl_sphere, rsl_contact_state>::pair_bodies(
                    self, particles, pairs, rows1, rows2,
                )
            }

            #[inline(always)]
            fn states(self, states: [&Record<W, F>; GROUP], rows: [&mut GroupRow; STATE_WORDS]) {
                // SAFETY: an `Avx2Copy` exists only on a CPU with AVX2 and an `Avx512Copy` only
                // on one with AVX-512 F and DQ (their `assume`); the batch dispatch runs the
                // AVX-512 kernels only where AVX2 is present too (`Simd::available`).
                unsafe { records_to_rows(states, rows) }
            }

            #[inline(always)]
            fn store_states(
                self,
                rows: [&GroupRow; STATE_WORDS],
                _slip: &[u32; GROUP],
                states: &mut [Record<W, F>; GROUP],
            ) {
                // SAFETY: as in `states`.
                unsafe { rows_to_records(rows, states) }
            }

            #[inline(always)]
            fn store_loads<O: LoadsSlot>(self, rows: [&GroupRow; 9], out: &mut [O; GROUP]) {
                GroupCopy::<rsl_sphere, rsl_contact_state>::store_loads(self, rows, out)
            }
        }
    };
}

record_copy!(Avx2Copy);
record_copy!(Avx512Copy);

#[cfg(all(test, target_arch = "x86_64"))]
mod tests {
    use super::*;
    use crate::batch::{state_words, PortableCopy, Simd, StateSlot};
    use crate::layout::tests::state_bits;
    use crate::layout::{rsl_batch_loads, rsl_vec3};

    /// Distinct doubles (none repeated, so a misplaced word shows), including signed zeros and
    /// subnormals which must be copied bit for bit.
    fn value(i: usize) -> f64 {
        match i % 7 {
            0 => -0.0,
            1 => f64::MIN_POSITIVE / 3.0 * i as f64,
            _ => (i as f64 * 0.618_033_988_749_895).sin() * 10f64.powi((i % 5) as i32 - 2),
        }
    }

    fn vec3(i: usize) -> rsl_vec3 {
        rsl_vec3 {
            x: value(i),
            y: value(i + 1),
            z: value(i + 2),
        }
    }

    fn spheres() -> Vec<rsl_sphere> {
        (0..GROUP)
            .map(|k| rsl_sphere {
                position: vec3(100 * k),
                velocity: vec3(100 * k + 3),
                angular_velocity: vec3(100 * k + 6),
                radius: value(100 * k + 9),
            })
            .collect()
    }

    fn states() -> Vec<rsl_contact_state> {
        (0..GROUP)
            .map(|k| rsl_contact_state {
                sliding_spring: vec3(1000 + 100 * k),
                rolling_spring: vec3(1003 + 100 * k),
                twisting_angle: value(1006 + 100 * k),
                model_memory: vec3(1007 + 100 * k),
                previous_normal: vec3(1010 + 100 * k),
                slip_flags: 7,
                reserved: 0xdead_beef,
            })
            .collect()
    }

    fn bits<const Q: usize>(rows: &[GroupRow; Q]) -> Vec<u64> {
        rows.iter().flatten().map(|v| v.to_bits()).collect()
    }

    /// What `copy` puts in the rows and the states, for comparison with [`PortableCopy`].
    #[allow(clippy::type_complexity)]
    fn run<X: GroupCopy<rsl_sphere, rsl_contact_state>>(
        copy: X,
    ) -> (Vec<u64>, Vec<u64>, Vec<Vec<u64>>) {
        let spheres = spheres();
        let states = states();
        let mut body_rows = [[f64::NAN; GROUP]; BODY_WORDS];
        copy.bodies(std::array::from_fn(|k| &spheres[k]), body_rows.each_mut());
        let mut state_rows = [[f64::NAN; GROUP]; STATE_WORDS];
        copy.states(std::array::from_fn(|k| &states[k]), state_rows.each_mut());
        // Write back rows that differ from the states read (reversed contacts), new slip bits.
        let reversed: [GroupRow; STATE_WORDS] = state_rows.map(|mut r| {
            r.reverse();
            r
        });
        let mut out: [rsl_contact_state; GROUP] = states.clone().try_into().expect("a group");
        let slip = [1, 2, 3, 4, 5, 6, 7, 0];
        copy.store_states(reversed.each_ref(), &slip, &mut out);
        // The same through references (states apart in memory, as `IndexedStates` has them):
        // every other slot of a longer array, in reverse order of the group's slots.
        let mut apart = states.iter().chain(&states).cloned().collect::<Vec<_>>();
        let mut refs = apart.iter_mut().step_by(2).collect::<Vec<_>>();
        refs.reverse();
        let refs: [&mut rsl_contact_state; GROUP] = refs.try_into().expect("a group");
        let rows: [GroupRow; STATE_WORDS] = reversed.map(|mut r| {
            r.reverse();
            r
        });
        let mut slip_back = slip;
        slip_back.reverse();
        copy.store_states_at(rows.each_ref(), &slip_back, refs);
        let at: Vec<_> = apart.iter().step_by(2).map(state_bits).collect();
        let out: Vec<_> = out.iter().map(state_bits).collect();
        assert_eq!(at, out, "store_states_at writes what store_states writes");
        (bits(&body_rows), bits(&state_rows), out)
    }

    #[test]
    fn transpositions_copy_as_the_portable_copy_does() {
        let expected = run(PortableCopy);
        // The portable copy itself: row q, slot k is word q of contact k.
        let spheres = spheres();
        assert_eq!(expected.0[9 * GROUP + 3], spheres[3].radius.to_bits());
        assert_eq!(expected.0[GROUP + 5], spheres[5].position.y.to_bits());
        let mut ran = 0;
        if Simd::Avx2.available() {
            // SAFETY: the CPU has AVX2 (checked just above).
            assert_eq!(run(unsafe { Avx2Copy::assume() }), expected, "AVX2");
            ran += 1;
        }
        if Simd::Avx512.available() {
            // SAFETY: the CPU has AVX-512 F and DQ (checked just above).
            assert_eq!(run(unsafe { Avx512Copy::assume() }), expected, "AVX-512");
            ran += 1;
        }
        if ran < 2 {
            eprintln!(
                "transposition test: {ran} of the 2 SIMD copies ran (this CPU lacks the others)"
            );
        }
    }

    /// The walls of a group: row `q`, slot `k` is word `q` of wall `k` (point, normal, velocity,
    /// angular velocity), bit for bit the portable copy's, for the C `rsl_wall` (transposed by
    /// the SIMD copies) and the core's `Wall` (value by value in every copy).
    #[test]
    fn walls_copy_as_the_portable_copy_does() {
        use crate::decompose::Wall;
        use crate::layout::rsl_wall;
        let walls: Vec<rsl_wall> = (0..GROUP)
            .map(|k| rsl_wall {
                point: vec3(2000 + 100 * k),
                normal: vec3(2003 + 100 * k),
                velocity: vec3(2006 + 100 * k),
                angular_velocity: vec3(2009 + 100 * k),
            })
            .collect();
        let cores: Vec<Wall<f64>> = walls.iter().map(Wall::from).collect();
        fn rows_of<W: WallSlot, X: GroupCopy<rsl_sphere, rsl_contact_state>>(
            copy: X,
            walls: &[W],
        ) -> Vec<u64> {
            let mut rows = [[f64::NAN; GROUP]; WALL_WORDS];
            copy.walls(std::array::from_fn(|k| &walls[k]), rows.each_mut());
            bits(&rows)
        }
        let expected = rows_of(PortableCopy, &walls);
        assert_eq!(expected[4 * GROUP + 6], walls[6].normal.y.to_bits());
        assert_eq!(
            expected[11 * GROUP + 2],
            walls[2].angular_velocity.z.to_bits()
        );
        assert_eq!(rows_of(PortableCopy, &cores), expected, "core walls");
        let mut ran = 0;
        if Simd::Avx2.available() {
            // SAFETY: the CPU has AVX2 (checked just above).
            let copy = unsafe { Avx2Copy::assume() };
            assert_eq!(rows_of(copy, &walls), expected, "AVX2");
            assert_eq!(rows_of(copy, &cores), expected, "AVX2, core walls");
            ran += 1;
        }
        if Simd::Avx512.available() {
            // SAFETY: the CPU has AVX-512 F and DQ, and AVX2 (checked just above).
            let copy = unsafe { Avx512Copy::assume() };
            assert_eq!(rows_of(copy, &walls), expected, "AVX-512");
            assert_eq!(rows_of(copy, &cores), expected, "AVX-512, core walls");
            ran += 1;
        }
        if ran < 2 {
            eprintln!("wall copy test: {ran} of the 2 SIMD copies ran (this CPU lacks the others)");
        }
    }

    /// The bodies of a group given by particle indices: row `q`, slot `k` is word `q` of the
    /// particle each side of pair `k` names, the last particle for an index past it (repeated
    /// indices, both ends of the index range), for the portable copy and the SIMD copies.
    #[test]
    fn pair_bodies_copy_the_particles_the_indices_name() {
        let particles = spheres();
        let pairs: [[u32; 2]; GROUP] = [
            [0, 7],
            [7, 0],
            [3, 3],
            [8, 2],
            [u32::MAX, 5],
            [1, 9],
            [6, 4],
            [5, 1 << 31],
        ];
        let last = particles.len() - 1;
        let expected = |side: usize| {
            let mut rows = [[0.0; GROUP]; BODY_WORDS];
            let sphere = |k: usize| &particles[(pairs[k][side] as usize).min(last)];
            GroupCopy::<rsl_sphere, rsl_contact_state>::bodies(
                PortableCopy,
                std::array::from_fn(sphere),
                rows.each_mut(),
            );
            bits(&rows)
        };
        // The portable rows themselves: slot 3 of body 1 is the last particle's (index 8).
        let body1 = expected(0);
        assert_eq!(body1[9 * GROUP + 3], particles[7].radius.to_bits());
        let want = (body1, expected(1));
        assert_eq!(
            pair_rows(PortableCopy, &particles, &pairs),
            want,
            "portable"
        );
        if Simd::Avx2.available() {
            // SAFETY: the CPU has AVX2 (checked just above).
            let copy = unsafe { Avx2Copy::assume() };
            assert_eq!(pair_rows(copy, &particles, &pairs), want, "AVX2");
        }
        if Simd::Avx512.available() {
            // SAFETY: the CPU has AVX-512 F and DQ (checked just above).
            let copy = unsafe { Avx512Copy::assume() };
            assert_eq!(pair_rows(copy, &particles, &pairs), want, "AVX-512");
        }
    }

    /// The rows `copy` gives the bodies of `pairs` ([`GroupCopy::pair_bodies`]), as bits.
    fn pair_rows<X: GroupCopy<rsl_sphere, rsl_contact_state>>(
        copy: X,
        particles: &[rsl_sphere],
        pairs: &[[u32; 2]; GROUP],
    ) -> (Vec<u64>, Vec<u64>) {
        let mut rows1 = [[f64::NAN; GROUP]; BODY_WORDS];
        let mut rows2 = [[f64::NAN; GROUP]; BODY_WORDS];
        copy.pair_bodies(particles, pairs, rows1.each_mut(), rows2.each_mut());
        (bits(&rows1), bits(&rows2))
    }

    /// The offsets of the bodies: in doubles, body 1 then body 2 of each pair, an index past
    /// the last particle taken as the last; none without particles or past `u32` offsets.
    #[test]
    fn sphere_offsets_clamp_and_refuse_what_does_not_fit() {
        let mut pairs = [[0u32; 2]; GROUP];
        pairs[0] = [2, 5];
        pairs[7] = [u32::MAX, 4];
        if !Simd::Avx2.available() {
            eprintln!("sphere offsets test skipped: this CPU lacks AVX2");
            return;
        }
        // SAFETY (each call): the CPU has AVX2 (checked just above).
        let offsets = |n: usize| unsafe { sphere_offsets(n, &pairs) };
        let five = offsets(5).expect("five particles");
        assert_eq!(five[..2], [20, 40]);
        assert_eq!(five[14..], [40, 40]);
        assert_eq!(five[2..14], [0; 12]);
        assert_eq!(offsets(0), None);
        // The last particle whose offset fits (429,496,729 x 10 <= u32::MAX), and one past it.
        let fits = (u32::MAX / 10) as usize + 1;
        assert_eq!(offsets(fits).expect("fits")[14], u32::MAX / 10 * 10);
        assert_eq!(offsets(fits + 1), None);
    }

    /// Told which words a step changes, the AVX2 copy writes every one of them (and the slip
    /// flags), through the fewest of its four windows (0..4, 3..7, 7..11, 9..13), and leaves
    /// the words outside those windows alone; through references as in place.
    #[test]
    fn avx2_copy_writes_back_the_windows_of_the_written_words() {
        if !Simd::Avx2.available() {
            eprintln!("written-words test skipped: this CPU lacks AVX2");
            return;
        }
        let prev = 0b111 << 10;
        // (words changed, words left alone): every word, the LAMMPS full set, rolling +
        // twisting, sliding alone.
        let cases: [(u16, &[usize]); 4] = [
            ((1 << STATE_WORDS) - 1, &[]),
            (0b111_1111 | prev, &[7, 8]),
            (0b1111 << 3 | prev, &[0, 1, 2, 7, 8]),
            (0b111 | prev, &[4, 5, 6, 7, 8]),
        ];
        let rows: [GroupRow; STATE_WORDS] =
            std::array::from_fn(|q| std::array::from_fn(|k| value(5000 + 20 * k + q)));
        let slip = [1, 2, 3, 4, 5, 6, 7, 0];
        for (written, alone) in cases {
            // SAFETY: the CPU has AVX2 (checked above).
            let copy = <Avx2Copy as GroupCopy<rsl_sphere, rsl_contact_state>>::writing(
                unsafe { Avx2Copy::assume() },
                written,
            );
            let before = states();
            let mut out: [rsl_contact_state; GROUP] = before.clone().try_into().expect("a group");
            copy.store_states(rows.each_ref(), &slip, &mut out);
            let mut apart = before.clone();
            let refs: [&mut rsl_contact_state; GROUP] = apart
                .iter_mut()
                .collect::<Vec<_>>()
                .try_into()
                .expect("a group");
            copy.store_states_at(rows.each_ref(), &slip, refs);
            for (k, s) in out.iter().enumerate() {
                assert_eq!(
                    state_bits(s),
                    state_bits(&apart[k]),
                    "{written:#x} slot {k}"
                );
                assert_eq!(s.slip_flags, slip[k]);
                assert_eq!(s.reserved, before[k].reserved);
                let (now, old) = (state_words(&s.load()), state_words(&before[k].load()));
                for q in 0..STATE_WORDS {
                    let expected = if alone.contains(&q) {
                        old[q]
                    } else {
                        rows[q][k]
                    };
                    assert_eq!(now[q].to_bits(), expected.to_bits(), "{written:#x} {k} {q}");
                }
            }
        }
    }

    /// The bits of the nine doubles of each output slot that `copy` writes from a group's load
    /// rows.
    fn loads_written<X: GroupCopy<rsl_sphere, rsl_contact_state>>(copy: X) -> Vec<u64> {
        let rows: [GroupRow; 9] =
            std::array::from_fn(|q| std::array::from_fn(|k| value(2000 + 10 * k + q)));
        let sentinel = vec3(9999);
        let mut out = [rsl_batch_loads {
            force1: sentinel,
            torque1: sentinel,
            torque2: sentinel,
        }; GROUP];
        copy.store_loads(rows.each_ref(), &mut out);
        out.iter()
            .flat_map(|l| [l.force1, l.torque1, l.torque2])
            .flat_map(|v| [v.x, v.y, v.z])
            .map(f64::to_bits)
            .collect()
    }

    #[test]
    fn loads_are_written_as_the_portable_copy_writes_them() {
        let expected = loads_written(PortableCopy);
        // Slot k, word q (force 1, torque 1, torque 2) is row q's slot k.
        for k in 0..GROUP {
            for q in 0..9 {
                assert_eq!(expected[9 * k + q], value(2000 + 10 * k + q).to_bits());
            }
        }
        if Simd::Avx2.available() {
            // SAFETY: the CPU has AVX2 (checked just above).
            assert_eq!(
                loads_written(unsafe { Avx2Copy::assume() }),
                expected,
                "AVX2"
            );
        }
        if Simd::Avx512.available() {
            // SAFETY: the CPU has AVX-512 F and DQ (checked just above).
            assert_eq!(
                loads_written(unsafe { Avx512Copy::assume() }),
                expected,
                "AVX-512"
            );
        } else {
            eprintln!("load transposition test: this CPU lacks AVX-512 F and DQ");
        }
    }
}
