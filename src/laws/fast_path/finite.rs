//! Finiteness tests of the C structs of a contact step, done where the values are stored: the
//! per-contact fast path tests its inputs with them (a non-finite value sends
//! the step to the checked path, which names it).
//!
//! Both tests add the values up: the total is finite only if every value is, so "yes" is always
//! right, and "no" also comes for finite values whose sum overflows (beyond ~1.8e308), which the
//! checked path then sorts out. [`Portable`] adds them as scalars; [`Avx2`] loads each struct
//! four doubles at a time (12 loads and adds for the inputs instead of 41 scalar ones).

use crate::layout::{rsl_contact_input, rsl_contact_state, rsl_sphere, rsl_vec3};
use crate::scalar::FiniteSums;
use std::mem::{offset_of, size_of};

/// A finiteness test of the fast path's C structs.
pub(crate) trait FiniteTest: Copy {
    /// Every double of both spheres, of the input's first eight fields (`normal_force` to
    /// `inertia2`, the ones a plain step reads) and of the state is finite.
    fn inputs(
        self,
        body1: &rsl_sphere,
        body2: &rsl_sphere,
        input: &rsl_contact_input,
        state: &rsl_contact_state,
    ) -> bool;

    /// Every double of one sphere, of the input's first eight fields and of the state is
    /// finite (a sphere-wall step; the caller tests the wall's values).
    fn sphere_inputs(
        self,
        sphere: &rsl_sphere,
        input: &rsl_contact_input,
        state: &rsl_contact_state,
    ) -> bool;
}

/// [`FiniteTest`] with scalar adds (any CPU).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Portable;

fn add_vec(sums: &mut FiniteSums, v: &rsl_vec3) {
    sums.add([v.x, v.y, v.z]);
}

fn add_sphere(sums: &mut FiniteSums, s: &rsl_sphere) {
    for v in [&s.position, &s.velocity, &s.angular_velocity] {
        add_vec(sums, v);
    }
    sums.add([s.radius]);
}

fn add_state(sums: &mut FiniteSums, s: &rsl_contact_state) {
    for v in [&s.sliding_spring, &s.rolling_spring] {
        add_vec(sums, v);
    }
    sums.add([s.twisting_angle]);
    for v in [&s.model_memory, &s.previous_normal] {
        add_vec(sums, v);
    }
}

fn add_input(sums: &mut FiniteSums, i: &rsl_contact_input) {
    sums.add([
        i.normal_force,
        i.dt,
        i.normal_stiffness,
        i.contact_radius,
        i.mass1,
        i.mass2,
        i.inertia1,
        i.inertia2,
    ]);
}

impl FiniteTest for Portable {
    #[inline(always)]
    fn inputs(
        self,
        body1: &rsl_sphere,
        body2: &rsl_sphere,
        i: &rsl_contact_input,
        state: &rsl_contact_state,
    ) -> bool {
        let mut sums = FiniteSums::default();
        add_sphere(&mut sums, body1);
        add_sphere(&mut sums, body2);
        add_state(&mut sums, state);
        add_input(&mut sums, i);
        sums.all_finite()
    }

    #[inline(always)]
    fn sphere_inputs(
        self,
        sphere: &rsl_sphere,
        i: &rsl_contact_input,
        state: &rsl_contact_state,
    ) -> bool {
        let mut sums = FiniteSums::default();
        add_sphere(&mut sums, sphere);
        add_state(&mut sums, state);
        add_input(&mut sums, i);
        sums.all_finite()
    }
}

// The layouts the AVX2 test reads: each struct starts with this many doubles, nothing between.
const SPHERE_DOUBLES: usize = 10;
const STATE_DOUBLES: usize = 13;
const INPUT_DOUBLES: usize = 8;
const _: () = {
    assert!(size_of::<rsl_vec3>() == 3 * 8);
    assert!(size_of::<rsl_sphere>() == SPHERE_DOUBLES * 8);
    assert!(offset_of!(rsl_sphere, radius) == 9 * 8);
    assert!(offset_of!(rsl_contact_state, previous_normal) == (STATE_DOUBLES - 3) * 8);
    assert!(offset_of!(rsl_contact_state, twisting_angle) == 6 * 8);
    assert!(offset_of!(rsl_contact_input, inertia2) == (INPUT_DOUBLES - 1) * 8);
};

/// [`FiniteTest`] with AVX2 loads. Only [`Avx2::assume`] makes one.
#[cfg(target_arch = "x86_64")]
#[derive(Clone, Copy, Debug)]
pub(crate) struct Avx2(());

#[cfg(target_arch = "x86_64")]
impl Avx2 {
    /// The test.
    ///
    /// # Safety
    /// The CPU must have AVX2 (`Simd::Avx2.available()`).
    pub(crate) unsafe fn assume() -> Self {
        Avx2(())
    }
}

#[cfg(target_arch = "x86_64")]
mod avx2 {
    use std::arch::x86_64::*;

    /// The sum of the first `N` (>= 4) doubles at `p`, four lanes (the last load overlaps the
    /// previous one when `N` is not a multiple of 4: a value counted twice changes nothing about
    /// finiteness).
    ///
    /// # Safety
    /// `p` must point to `N` readable, initialised doubles; the CPU must have AVX2.
    #[inline]
    #[target_feature(enable = "avx2")]
    pub unsafe fn sum<const N: usize>(p: *const f64) -> __m256d {
        // SAFETY (both loads): `at + 4 <= N`, inside the caller's `N` doubles; unaligned loads.
        let mut acc = unsafe { _mm256_loadu_pd(p.add(N - 4)) };
        let mut at = 0;
        while at + 4 < N {
            acc = _mm256_add_pd(acc, unsafe { _mm256_loadu_pd(p.add(at)) });
            at += 4;
        }
        acc
    }

    /// Whether the four lanes of `s` are finite (|s| < inf; false for NaN).
    #[inline]
    #[target_feature(enable = "avx2")]
    pub fn all_finite(s: __m256d) -> bool {
        let magnitude = _mm256_andnot_pd(_mm256_set1_pd(-0.0), s);
        let below = _mm256_cmp_pd::<_CMP_LT_OQ>(magnitude, _mm256_set1_pd(f64::INFINITY));
        _mm256_movemask_pd(below) == 0b1111
    }

    /// Lane-wise sum.
    #[inline]
    #[target_feature(enable = "avx2")]
    pub fn add(a: __m256d, b: __m256d) -> __m256d {
        _mm256_add_pd(a, b)
    }
}

/// A pointer to the first double of `s`, valid for the whole struct (not just its first field).
#[cfg(target_arch = "x86_64")]
fn doubles<S>(s: &S) -> *const f64 {
    (s as *const S).cast::<f64>()
}

#[cfg(target_arch = "x86_64")]
impl FiniteTest for Avx2 {
    #[inline(always)]
    fn inputs(
        self,
        body1: &rsl_sphere,
        body2: &rsl_sphere,
        input: &rsl_contact_input,
        state: &rsl_contact_state,
    ) -> bool {
        // SAFETY: an `Avx2` exists only on a CPU with AVX2 (`Avx2::assume`); each pointer comes
        // from a reference to a whole struct that starts with that many doubles (asserted
        // above), alive and unchanged during the call.
        unsafe {
            let spheres = avx2::add(
                avx2::sum::<SPHERE_DOUBLES>(doubles(body1)),
                avx2::sum::<SPHERE_DOUBLES>(doubles(body2)),
            );
            let rest = avx2::add(
                avx2::sum::<STATE_DOUBLES>(doubles(state)),
                avx2::sum::<INPUT_DOUBLES>(doubles(input)),
            );
            avx2::all_finite(avx2::add(spheres, rest))
        }
    }

    #[inline(always)]
    fn sphere_inputs(
        self,
        sphere: &rsl_sphere,
        input: &rsl_contact_input,
        state: &rsl_contact_state,
    ) -> bool {
        // SAFETY: as in `inputs`.
        unsafe {
            let rest = avx2::add(
                avx2::sum::<STATE_DOUBLES>(doubles(state)),
                avx2::sum::<INPUT_DOUBLES>(doubles(input)),
            );
            avx2::all_finite(avx2::add(
                avx2::sum::<SPHERE_DOUBLES>(doubles(sphere)),
                rest,
            ))
        }
    }
}
