//! Lane types the batch kernels are instantiated for: plain `f64` and `f32` (one contact per
//! call of the generic physics) and, for any target, simba's array-backed `AutoSimd` packs
//! (several contacts per call, one per lane), which LLVM vectorises as it sees fit. The x86-64
//! kernels of the C ABI do not use the `AutoSimd` packs: LLVM re-vectorised their arrays into
//! mixed xmm/ymm/zmm pieces with many spills and kept their masks as arrays of `bool` (the
//! AVX-512 kernel ran the full LAMMPS set at 55 ns per contact with them, 45 with the
//! register-backed types of `batch::x86::lanes`, whose every operation is one instruction).

use crate::scalar::Real;
use simba::simd::{AutoF32x8, AutoF64x4, AutoF64x8, AutoSimd};

/// The most lanes of a decomposition kernel's lane type (sizes its per-chunk rows). The step
/// kernels' lane types may have more (16 `f32` lanes under AVX-512): theirs need only divide the
/// block (`step_kernel` asserts it).
pub const MAX_LANES: usize = 8;

/// A [`Real`] type with a known number of lanes, built from and read back as `f64` per lane.
pub trait Lanes: Real {
    /// Number of contacts per value.
    const N: usize;
    /// The `f64` type in which the geometry (branch vector, distance, overlap, branch lengths)
    /// is computed, so that positions are never rounded to `f32`: the same lanes, or half of
    /// them (then the geometry is computed in two halves).
    type Geo: Lanes<Geo = Self::Geo>;
    /// A value whose lane `k` is `f(k)` (rounded to the element type).
    fn from_fn<F: FnMut(usize) -> f64>(f: F) -> Self;
    /// Lane `k` as `f64` (exact).
    fn lane(&self, k: usize) -> f64;
    /// Lane-wise conversion from the geometry type (rounding to `f32` where the element is
    /// `f32`): lanes `0..Geo::N` from `lo`, the others (if any) from `hi`.
    #[inline(always)]
    fn from_geo(lo: Self::Geo, hi: Self::Geo) -> Self {
        let half = <Self::Geo as Lanes>::N;
        Self::from_fn(|k| {
            if k < half {
                lo.lane(k)
            } else {
                hi.lane(k - half)
            }
        })
    }
    /// The value whose lane `k` is `src[k]` (rounded to the element type); `src` holds at
    /// least `N` values.
    #[inline(always)]
    fn load(src: &[f64]) -> Self {
        Self::from_fn(|k| src[k])
    }
    /// Writes lane `k` to `dst[k]` (exact); `dst` holds at least `N` values.
    #[inline(always)]
    fn store(&self, dst: &mut [f64]) {
        for (k, d) in dst[..Self::N].iter_mut().enumerate() {
            *d = self.lane(k);
        }
    }
    /// Scratch array with one `X` per lane.
    type Arr<X: Copy>: Copy + std::ops::Index<usize, Output = X> + std::ops::IndexMut<usize>;
    /// A scratch array filled with `x`.
    fn arr<X: Copy>(x: X) -> Self::Arr<X>;
    /// Whether [`Lanes::add_zero_times`] is one fused instruction (the x86-64 lane types): then
    /// the batch kernels' finiteness tests may add each value with it, to one of four sums
    /// (fused); otherwise they sum a vector's three `0 x` first and add that to one sum.
    const FUSED_PROBE: bool = false;
    /// `acc + 0 x`, lane-wise: `0 x` is a zero where `x` is finite and NaN where it is
    /// infinite or NaN, so a sum that starts at zero stays a zero (of either sign) exactly while
    /// every value added is finite (see [`finite_probe`](crate::scalar::finite_probe)). The
    /// x86-64 lane types fuse it into one `vfmadd` (exact: `0 x` needs no rounding, and a
    /// zero or NaN sum is what the separate product and sum give); the default is the product
    /// and the sum.
    #[inline(always)]
    fn add_zero_times(acc: Self, x: Self) -> Self {
        acc + x * Self::zero()
    }
}

impl Lanes for f64 {
    const N: usize = 1;
    type Geo = f64;
    #[inline(always)]
    fn from_fn<F: FnMut(usize) -> f64>(mut f: F) -> Self {
        f(0)
    }
    #[inline(always)]
    fn lane(&self, _k: usize) -> f64 {
        *self
    }
    type Arr<X: Copy> = [X; 1];
    #[inline(always)]
    fn arr<X: Copy>(x: X) -> [X; 1] {
        [x]
    }
}

impl Lanes for f32 {
    const N: usize = 1;
    type Geo = f64;
    #[inline(always)]
    fn from_fn<F: FnMut(usize) -> f64>(mut f: F) -> Self {
        f(0) as f32
    }
    #[inline(always)]
    fn lane(&self, _k: usize) -> f64 {
        *self as f64
    }
    type Arr<X: Copy> = [X; 1];
    #[inline(always)]
    fn arr<X: Copy>(x: X) -> [X; 1] {
        [x]
    }
}

macro_rules! f64_pack {
    ($t:ty, $n:expr, $($k:expr),+) => {
        impl Lanes for $t {
            const N: usize = $n;
            type Geo = $t;
            #[inline(always)]
            fn from_fn<F: FnMut(usize) -> f64>(mut f: F) -> Self {
                // Spelled out: `std::array::from_fn` leaves a counted loop in the kernels.
                AutoSimd([$(f($k)),+])
            }
            #[inline(always)]
            fn lane(&self, k: usize) -> f64 {
                self.0[k]
            }
            #[inline(always)]
            fn from_geo(lo: $t, _hi: $t) -> Self {
                lo
            }
            #[inline(always)]
            fn load(src: &[f64]) -> Self {
                // One vector load.
                let mut a = [0.0; $n];
                a.copy_from_slice(&src[..$n]);
                AutoSimd(a)
            }
            #[inline(always)]
            fn store(&self, dst: &mut [f64]) {
                dst[..$n].copy_from_slice(&self.0);
            }
            type Arr<X: Copy> = [X; $n];
            #[inline(always)]
            fn arr<X: Copy>(x: X) -> [X; $n] {
                [x; $n]
            }
        }
    };
}
f64_pack!(AutoF64x4, 4, 0, 1, 2, 3);
f64_pack!(AutoF64x8, 8, 0, 1, 2, 3, 4, 5, 6, 7);

impl Lanes for AutoF32x8 {
    const N: usize = 8;
    type Geo = AutoF64x8;
    #[inline(always)]
    fn from_fn<F: FnMut(usize) -> f64>(mut f: F) -> Self {
        AutoSimd([
            f(0) as f32,
            f(1) as f32,
            f(2) as f32,
            f(3) as f32,
            f(4) as f32,
            f(5) as f32,
            f(6) as f32,
            f(7) as f32,
        ])
    }
    #[inline(always)]
    fn lane(&self, k: usize) -> f64 {
        self.0[k] as f64
    }
    type Arr<X: Copy> = [X; 8];
    #[inline(always)]
    fn arr<X: Copy>(x: X) -> [X; 8] {
        [x; 8]
    }
}
