//! SIMD lane types for the x86-64 batch kernels, each a thin wrapper of one `core::arch`
//! register (or two): [`F64x8`] (zmm, AVX-512 F), [`F64x4`] (ymm, AVX), [`F64x4x2`] (two ymm),
//! [`F64x8x2`] (two zmm), and the `f32` types [`F32x16`] (zmm, AVX-512 F/DQ; its geometry is
//! computed in `F64x8x2`), [`F32x8W`] and [`F32x8N`] (ymm, AVX; their geometry is computed in
//! `F64x8` or `F64x4x2`). Every arithmetic operation is one instruction (`vaddpd`, `vsqrtpd`,
//! `vblendmpd`...), every comparison one `vcmppd` into a mask register (AVX-512) or a lane mask
//! (AVX), and every row load or store one `vmovupd`.
//!
//! They replace simba's array-backed `AutoSimd` packs, which LLVM re-vectorised into mixed
//! xmm/ymm/zmm pieces with many spills and stored masks as arrays of `bool`.
//!
//! **Why hand-written rather than taken from a maintained crate** (`pulp`, `wide`). A lane type
//! must give what the generic physics and the block kernel ask of it, and neither crate gives
//! that as it stands. The physics is written over nalgebra vectors of a
//! [`Real`](crate::scalar::Real) (simba's `SimdRealField` and the `SimdValue`, `SimdBool` and
//! `SimdComplexField` it implies), so a lane type must carry simba's traits and operator
//! overloads. `pulp`'s generic code calls its operations as methods of a per-instruction-set
//! token (`simd.mul_f64s(a, b)`), not on the values, and dispatches at run time through its own
//! `Arch::dispatch`/`WithSimd` entry, around which the kernel families of `batch::dispatch` (one
//! `#[target_feature]` function per level, precision, access type and prefetching choice) would
//! have to be rebuilt. `wide` has operator-overloaded types (simba's optional `wide` feature wraps
//! some of them for its traits), but it builds on `safe_arch`, which picks the instructions by
//! `#[cfg(target_feature)]` at compile time: in this library's build, for baseline x86-64 with
//! the AVX2 and AVX-512 kernels chosen at run time, its 256- and 512-bit types would be compiled
//! for SSE2, not as single ymm or zmm registers. And the kernels use operations that neither
//! offers in this form: masks as bitmasks ([`SimdBool::bitmask`]; an AVX-512 mask register for
//! [`F64x8`] and [`F32x16`]), the fused finiteness probe ([`Lanes::add_zero_times`], one
//! `vfmadd` with a zero factor), `f32` lanes paired with an `f64` geometry type of the same lane
//! count ([`Lanes::Geo`]: [`F32x16`] with [`F64x8x2`], [`F32x8N`] with [`F64x4x2`], [`F32x8W`]
//! with [`F64x8`]) and the conversions between them, the same eight `f64` lanes as one zmm
//! ([`F64x8`]) or two ymm registers ([`F64x4x2`]), and lane semantics held to the scalar code bit
//! for bit (below), which the batch tests check. No A/B measurement against `pulp` or `wide` was
//! made: these are reasons of fit, not measured speed.
//!
//! **Exactness.** Each lane gives the bits the plain `f64` (or `f32`) code gives: addition,
//! subtraction, multiplication, division and square root are IEEE operations rounded to
//! nearest in both (no contraction into FMA: these intrinsics are never fused), `abs` and
//! negation act on the sign bit, comparisons use the ordered predicates of Rust's `<`, `<=`,
//! `>`, `>=`, `==` (false on NaN) and the unordered one of `!=` (true on NaN), `max` and `min`
//! return the other operand where one is NaN as `f64::max` does, and `f64` to `f32` conversion
//! rounds to nearest as `as f32` does. The batch tests compare every kernel with the
//! per-contact call bit for bit.
//!
//! **Safety.** The intrinsics need the CPU features named above; the methods here are not
//! `#[target_feature]` functions (trait methods cannot be), so each calls its intrinsic in an
//! `unsafe` block. That is sound because a value of these types only exists inside the
//! `#[target_feature]` kernels of `batch::dispatch::x86`, which are called only after
//! `is_x86_feature_detected!` confirmed the features; the types are private to `batch`.
//! Inlined into those kernels, each intrinsic becomes its single instruction.

#![allow(clippy::missing_safety_doc)]

use crate::batch::Lanes;
use core::arch::x86_64::*;
use nalgebra::{ComplexField, RealField};
use num_traits::{FromPrimitive, Num, One, Zero};
use simba::scalar::{Field, SubsetOf};
use simba::simd::{
    PrimitiveSimdValue, SimdBool, SimdComplexField, SimdPartialOrd, SimdRealField, SimdSigned,
    SimdValue,
};
use std::fmt;
use std::ops::{
    Add, AddAssign, BitAnd, BitOr, BitXor, Div, DivAssign, Mul, MulAssign, Neg, Not, Rem,
    RemAssign, Sub, SubAssign,
};

// ----------------------------------------------------------------------------------------------
// The registers and their primitive operations.

/// Eight `f64` lanes in one zmm register (AVX-512 F).
#[derive(Clone, Copy)]
pub(crate) struct F64x8(__m512d);

/// A lane mask of [`F64x8`]: bit `k` is lane `k` (an AVX-512 mask register).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Mask8(u8);

/// Four `f64` lanes in one ymm register (AVX).
#[derive(Clone, Copy)]
pub(crate) struct F64x4(__m256d);

/// A lane mask of [`F64x4`]: each lane all ones (true) or all zeros (false).
#[derive(Clone, Copy)]
pub(crate) struct Mask4d(__m256d);

/// Eight `f32` lanes in one ymm register, whose geometry is computed in one [`F64x8`]
/// (the AVX-512 decomposition; the AVX-512 steps run [`F32x16`]).
#[derive(Clone, Copy)]
pub(crate) struct F32x8W(__m256);

/// Eight `f32` lanes in one ymm register, whose geometry is computed in an [`F64x4x2`] (the
/// AVX2 kernels).
#[derive(Clone, Copy)]
pub(crate) struct F32x8N(__m256);

/// A lane mask of the `f32` types: each lane all ones (true) or all zeros (false).
#[derive(Clone, Copy)]
pub(crate) struct Mask8f(__m256);

/// Sixteen `f32` lanes in one zmm register (AVX-512 F/DQ), whose geometry is computed in an
/// [`F64x8x2`] (the single-precision AVX-512 step kernels).
#[derive(Clone, Copy)]
pub(crate) struct F32x16(__m512);

/// A lane mask of [`F32x16`]: bit `k` is lane `k` (an AVX-512 mask register).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Mask16(u16);

/// Runs an intrinsic. SAFETY (every use): a value of these types exists only inside the
/// kernels of `batch::dispatch::x86`, run after the CPU was found to have the features the
/// intrinsic needs (see the module documentation).
macro_rules! arch {
    ($e:expr) => {
        // SAFETY: see the macro's documentation.
        unsafe { $e }
    };
}

/// The primitive operations of a 512-bit register type (`__m512d` or `__m512`, AVX-512 F) and
/// of its mask (`$bits`, one bit per lane in a mask register).
macro_rules! avx512_ops {
    ($t:ident, $mask:ident, $e:ty, $n:expr, $bits:ty, $set1:ident, $loadu:ident, $storeu:ident,
     $add:ident, $sub:ident, $mul:ident, $div:ident, $sqrt:ident, $to_int:ident,
     $from_int:ident, $max:ident, $min:ident, $blend:ident, $cmp:ident) => {
        impl $t {
            #[inline(always)]
            fn splat_(x: $e) -> Self {
                Self(arch!($set1(x)))
            }
            #[inline(always)]
            fn from_array(a: [$e; $n]) -> Self {
                Self(arch!($loadu(a.as_ptr())))
            }
            #[inline(always)]
            fn to_array(self) -> [$e; $n] {
                let mut a = [0.0; $n];
                arch!($storeu(a.as_mut_ptr(), self.0));
                a
            }
            #[inline(always)]
            fn add_(self, o: Self) -> Self {
                Self(arch!($add(self.0, o.0)))
            }
            #[inline(always)]
            fn sub_(self, o: Self) -> Self {
                Self(arch!($sub(self.0, o.0)))
            }
            #[inline(always)]
            fn mul_(self, o: Self) -> Self {
                Self(arch!($mul(self.0, o.0)))
            }
            #[inline(always)]
            fn div_(self, o: Self) -> Self {
                Self(arch!($div(self.0, o.0)))
            }
            #[inline(always)]
            fn sqrt_(self) -> Self {
                Self(arch!($sqrt(self.0)))
            }
            #[inline(always)]
            fn sign_bits() -> Self {
                Self::splat_(-0.0)
            }
            #[inline(always)]
            fn neg_(self) -> Self {
                Self(arch!($from_int(_mm512_xor_si512(
                    $to_int(self.0),
                    $to_int(Self::sign_bits().0)
                ))))
            }
            #[inline(always)]
            fn abs_(self) -> Self {
                Self(arch!($from_int(_mm512_andnot_si512(
                    $to_int(Self::sign_bits().0),
                    $to_int(self.0)
                ))))
            }
            #[inline(always)]
            fn max_(self, o: Self) -> Self {
                // vmaxp* returns its second operand where either is NaN or they are equal (0
                // and -0); max returns the operand that is not NaN, and `self` for 0 and -0.
                let m = Self(arch!($max(o.0, self.0)));
                m.blend_(self.ne_(self), o)
            }
            #[inline(always)]
            fn min_(self, o: Self) -> Self {
                let m = Self(arch!($min(o.0, self.0)));
                m.blend_(self.ne_(self), o)
            }
            /// `self` where `m` is false, `other` where it is true.
            #[inline(always)]
            fn blend_(self, m: $mask, other: Self) -> Self {
                Self(arch!($blend(m.0, self.0, other.0)))
            }
            #[inline(always)]
            fn gt_(self, o: Self) -> $mask {
                $mask(arch!($cmp::<_CMP_GT_OQ>(self.0, o.0)))
            }
            #[inline(always)]
            fn lt_(self, o: Self) -> $mask {
                $mask(arch!($cmp::<_CMP_LT_OQ>(self.0, o.0)))
            }
            #[inline(always)]
            fn ge_(self, o: Self) -> $mask {
                $mask(arch!($cmp::<_CMP_GE_OQ>(self.0, o.0)))
            }
            #[inline(always)]
            fn le_(self, o: Self) -> $mask {
                $mask(arch!($cmp::<_CMP_LE_OQ>(self.0, o.0)))
            }
            #[inline(always)]
            fn eq_(self, o: Self) -> $mask {
                $mask(arch!($cmp::<_CMP_EQ_OQ>(self.0, o.0)))
            }
            #[inline(always)]
            fn ne_(self, o: Self) -> $mask {
                $mask(arch!($cmp::<_CMP_NEQ_UQ>(self.0, o.0)))
            }
        }

        impl $mask {
            #[inline(always)]
            fn splat_(b: bool) -> Self {
                $mask(if b { <$bits>::MAX } else { 0 })
            }
            #[inline(always)]
            fn bits_(self) -> u64 {
                self.0 as u64
            }
            #[inline(always)]
            fn and_(self, o: Self) -> Self {
                $mask(self.0 & o.0)
            }
            #[inline(always)]
            fn or_(self, o: Self) -> Self {
                $mask(self.0 | o.0)
            }
            #[inline(always)]
            fn xor_(self, o: Self) -> Self {
                $mask(self.0 ^ o.0)
            }
            #[inline(always)]
            fn not_(self) -> Self {
                $mask(!self.0)
            }
            #[inline(always)]
            fn from_bits(bits: u64) -> Self {
                $mask(bits as $bits)
            }
        }
    };
}

avx512_ops!(
    F64x8,
    Mask8,
    f64,
    8,
    u8,
    _mm512_set1_pd,
    _mm512_loadu_pd,
    _mm512_storeu_pd,
    _mm512_add_pd,
    _mm512_sub_pd,
    _mm512_mul_pd,
    _mm512_div_pd,
    _mm512_sqrt_pd,
    _mm512_castpd_si512,
    _mm512_castsi512_pd,
    _mm512_max_pd,
    _mm512_min_pd,
    _mm512_mask_blend_pd,
    _mm512_cmp_pd_mask
);
avx512_ops!(
    F32x16,
    Mask16,
    f32,
    16,
    u16,
    _mm512_set1_ps,
    _mm512_loadu_ps,
    _mm512_storeu_ps,
    _mm512_add_ps,
    _mm512_sub_ps,
    _mm512_mul_ps,
    _mm512_div_ps,
    _mm512_sqrt_ps,
    _mm512_castps_si512,
    _mm512_castsi512_ps,
    _mm512_max_ps,
    _mm512_min_ps,
    _mm512_mask_blend_ps,
    _mm512_cmp_ps_mask
);

/// The primitive operations of a 256-bit register type (`__m256d` or `__m256`): the
/// intrinsics of `avx_body` spelled out for the suffix `pd` or `ps`.
macro_rules! avx_ops {
    ($t:ident, $mask:ident, f64, $n:expr, pd) => {
        avx_body!(
            $t,
            $mask,
            f64,
            $n,
            _mm256_set1_pd,
            _mm256_loadu_pd,
            _mm256_storeu_pd,
            _mm256_add_pd,
            _mm256_sub_pd,
            _mm256_mul_pd,
            _mm256_div_pd,
            _mm256_sqrt_pd,
            _mm256_xor_pd,
            _mm256_andnot_pd,
            _mm256_and_pd,
            _mm256_or_pd,
            _mm256_max_pd,
            _mm256_min_pd,
            _mm256_blendv_pd,
            _mm256_cmp_pd,
            _mm256_movemask_pd,
            _mm256_setzero_pd
        );
    };
    ($t:ident, $mask:ident, f32, $n:expr, ps) => {
        avx_body!(
            $t,
            $mask,
            f32,
            $n,
            _mm256_set1_ps,
            _mm256_loadu_ps,
            _mm256_storeu_ps,
            _mm256_add_ps,
            _mm256_sub_ps,
            _mm256_mul_ps,
            _mm256_div_ps,
            _mm256_sqrt_ps,
            _mm256_xor_ps,
            _mm256_andnot_ps,
            _mm256_and_ps,
            _mm256_or_ps,
            _mm256_max_ps,
            _mm256_min_ps,
            _mm256_blendv_ps,
            _mm256_cmp_ps,
            _mm256_movemask_ps,
            _mm256_setzero_ps
        );
    };
}

macro_rules! avx_body {
    ($t:ident, $mask:ident, $e:ty, $n:expr, $set1:ident, $loadu:ident, $storeu:ident,
     $add:ident, $sub:ident, $mul:ident, $div:ident, $sqrt:ident, $xor:ident, $andnot:ident,
     $and:ident, $or:ident, $max:ident, $min:ident, $blendv:ident, $cmp:ident, $movemask:ident,
     $zero:ident) => {
        impl $t {
            #[inline(always)]
            fn splat_(x: $e) -> Self {
                Self(arch!($set1(x)))
            }
            #[inline(always)]
            fn from_array(a: [$e; $n]) -> Self {
                Self(arch!($loadu(a.as_ptr())))
            }
            #[inline(always)]
            fn to_array(self) -> [$e; $n] {
                let mut a = [0.0; $n];
                arch!($storeu(a.as_mut_ptr(), self.0));
                a
            }
            #[inline(always)]
            fn add_(self, o: Self) -> Self {
                Self(arch!($add(self.0, o.0)))
            }
            #[inline(always)]
            fn sub_(self, o: Self) -> Self {
                Self(arch!($sub(self.0, o.0)))
            }
            #[inline(always)]
            fn mul_(self, o: Self) -> Self {
                Self(arch!($mul(self.0, o.0)))
            }
            #[inline(always)]
            fn div_(self, o: Self) -> Self {
                Self(arch!($div(self.0, o.0)))
            }
            #[inline(always)]
            fn sqrt_(self) -> Self {
                Self(arch!($sqrt(self.0)))
            }
            #[inline(always)]
            fn neg_(self) -> Self {
                Self(arch!($xor(self.0, $set1(-0.0))))
            }
            #[inline(always)]
            fn abs_(self) -> Self {
                Self(arch!($andnot($set1(-0.0), self.0)))
            }
            #[inline(always)]
            fn max_(self, o: Self) -> Self {
                // vmaxp* returns its second operand where either is NaN or they are equal (0
                // and -0); max returns the operand that is not NaN, and `self` for 0 and -0.
                let m = Self(arch!($max(o.0, self.0)));
                m.blend_(self.ne_(self), o)
            }
            #[inline(always)]
            fn min_(self, o: Self) -> Self {
                let m = Self(arch!($min(o.0, self.0)));
                m.blend_(self.ne_(self), o)
            }
            /// `self` where `m` is false, `other` where it is true.
            #[inline(always)]
            fn blend_(self, m: $mask, other: Self) -> Self {
                Self(arch!($blendv(self.0, other.0, m.0)))
            }
            #[inline(always)]
            fn gt_(self, o: Self) -> $mask {
                $mask(arch!($cmp::<_CMP_GT_OQ>(self.0, o.0)))
            }
            #[inline(always)]
            fn lt_(self, o: Self) -> $mask {
                $mask(arch!($cmp::<_CMP_LT_OQ>(self.0, o.0)))
            }
            #[inline(always)]
            fn ge_(self, o: Self) -> $mask {
                $mask(arch!($cmp::<_CMP_GE_OQ>(self.0, o.0)))
            }
            #[inline(always)]
            fn le_(self, o: Self) -> $mask {
                $mask(arch!($cmp::<_CMP_LE_OQ>(self.0, o.0)))
            }
            #[inline(always)]
            fn eq_(self, o: Self) -> $mask {
                $mask(arch!($cmp::<_CMP_EQ_OQ>(self.0, o.0)))
            }
            #[inline(always)]
            fn ne_(self, o: Self) -> $mask {
                $mask(arch!($cmp::<_CMP_NEQ_UQ>(self.0, o.0)))
            }
        }

        impl $mask {
            #[inline(always)]
            fn splat_(b: bool) -> Self {
                let z = arch!($zero());
                if b {
                    Self(arch!($cmp::<_CMP_EQ_OQ>(z, z)))
                } else {
                    Self(z)
                }
            }
            #[inline(always)]
            fn bits_(self) -> u64 {
                arch!($movemask(self.0)) as u32 as u64
            }
            #[inline(always)]
            fn and_(self, o: Self) -> Self {
                Self(arch!($and(self.0, o.0)))
            }
            #[inline(always)]
            fn or_(self, o: Self) -> Self {
                Self(arch!($or(self.0, o.0)))
            }
            #[inline(always)]
            fn xor_(self, o: Self) -> Self {
                Self(arch!($xor(self.0, o.0)))
            }
            #[inline(always)]
            fn not_(self) -> Self {
                self.xor_(Self::splat_(true))
            }
        }

        impl fmt::Debug for $mask {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                write!(f, "{}({:#b})", stringify!($mask), self.bits_())
            }
        }

        impl PartialEq for $mask {
            #[inline(always)]
            fn eq(&self, o: &Self) -> bool {
                self.bits_() == o.bits_()
            }
        }
    };
}

avx_ops!(F64x4, Mask4d, f64, 4, pd);
avx_ops!(F32x8W, Mask8f, f32, 8, ps);

// `F32x8N` shares `F32x8W`'s register, mask and operations.
impl F32x8N {
    #[inline(always)]
    fn w(self) -> F32x8W {
        F32x8W(self.0)
    }
    #[inline(always)]
    fn n(w: F32x8W) -> Self {
        F32x8N(w.0)
    }
    #[inline(always)]
    fn splat_(x: f32) -> Self {
        Self::n(F32x8W::splat_(x))
    }
    #[inline(always)]
    fn from_array(a: [f32; 8]) -> Self {
        Self::n(F32x8W::from_array(a))
    }
    #[inline(always)]
    fn to_array(self) -> [f32; 8] {
        self.w().to_array()
    }
    #[inline(always)]
    fn add_(self, o: Self) -> Self {
        Self::n(self.w().add_(o.w()))
    }
    #[inline(always)]
    fn sub_(self, o: Self) -> Self {
        Self::n(self.w().sub_(o.w()))
    }
    #[inline(always)]
    fn mul_(self, o: Self) -> Self {
        Self::n(self.w().mul_(o.w()))
    }
    #[inline(always)]
    fn div_(self, o: Self) -> Self {
        Self::n(self.w().div_(o.w()))
    }
    #[inline(always)]
    fn sqrt_(self) -> Self {
        Self::n(self.w().sqrt_())
    }
    #[inline(always)]
    fn neg_(self) -> Self {
        Self::n(self.w().neg_())
    }
    #[inline(always)]
    fn abs_(self) -> Self {
        Self::n(self.w().abs_())
    }
    #[inline(always)]
    fn max_(self, o: Self) -> Self {
        Self::n(self.w().max_(o.w()))
    }
    #[inline(always)]
    fn min_(self, o: Self) -> Self {
        Self::n(self.w().min_(o.w()))
    }
    #[inline(always)]
    fn blend_(self, m: Mask8f, other: Self) -> Self {
        Self::n(self.w().blend_(m, other.w()))
    }
    #[inline(always)]
    fn gt_(self, o: Self) -> Mask8f {
        self.w().gt_(o.w())
    }
    #[inline(always)]
    fn lt_(self, o: Self) -> Mask8f {
        self.w().lt_(o.w())
    }
    #[inline(always)]
    fn ge_(self, o: Self) -> Mask8f {
        self.w().ge_(o.w())
    }
    #[inline(always)]
    fn le_(self, o: Self) -> Mask8f {
        self.w().le_(o.w())
    }
    #[inline(always)]
    fn eq_(self, o: Self) -> Mask8f {
        self.w().eq_(o.w())
    }
    #[inline(always)]
    fn ne_(self, o: Self) -> Mask8f {
        self.w().ne_(o.w())
    }
}

/// Eight `f64` lanes in two ymm registers (AVX): lanes 0-3, then 4-7. The geometry type of
/// [`F32x8N`], whose block rows hold eight contacts.
#[derive(Clone, Copy)]
pub(crate) struct F64x4x2([F64x4; 2]);

/// A lane mask of [`F64x4x2`]: lanes 0-3, then 4-7.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Mask4dx2([Mask4d; 2]);

/// The primitive operations of `$pair`, two `$half` values side by side (`$n` lanes each).
macro_rules! pair_ops {
    ($pair:ident, $half:ident, $pmask:ident, $hmask:ident, $e:ty, $n:expr) => {
        impl $pair {
            #[inline(always)]
            fn splat_(x: $e) -> Self {
                Self([$half::splat_(x); 2])
            }
            #[inline(always)]
            fn from_array(a: [$e; 2 * $n]) -> Self {
                Self([
                    $half::from_array(std::array::from_fn(|k| a[k])),
                    $half::from_array(std::array::from_fn(|k| a[$n + k])),
                ])
            }
            #[inline(always)]
            fn to_array(self) -> [$e; 2 * $n] {
                let (lo, hi) = (self.0[0].to_array(), self.0[1].to_array());
                std::array::from_fn(|k| if k < $n { lo[k] } else { hi[k - $n] })
            }
            pair_ops!(@bin $half, add_, sub_, mul_, div_, max_, min_);
            pair_ops!(@un sqrt_, neg_, abs_);
            pair_ops!(@cmp $pmask, gt_, lt_, ge_, le_, eq_, ne_);
            /// `self` where `m` is false, `other` where it is true.
            #[inline(always)]
            fn blend_(self, m: $pmask, other: Self) -> Self {
                Self([
                    self.0[0].blend_(m.0[0], other.0[0]),
                    self.0[1].blend_(m.0[1], other.0[1]),
                ])
            }
        }

        impl $pmask {
            #[inline(always)]
            fn splat_(b: bool) -> Self {
                Self([$hmask::splat_(b); 2])
            }
            #[inline(always)]
            fn bits_(self) -> u64 {
                self.0[0].bits_() | self.0[1].bits_() << $n
            }
            #[inline(always)]
            fn and_(self, o: Self) -> Self {
                Self([self.0[0].and_(o.0[0]), self.0[1].and_(o.0[1])])
            }
            #[inline(always)]
            fn or_(self, o: Self) -> Self {
                Self([self.0[0].or_(o.0[0]), self.0[1].or_(o.0[1])])
            }
            #[inline(always)]
            fn xor_(self, o: Self) -> Self {
                Self([self.0[0].xor_(o.0[0]), self.0[1].xor_(o.0[1])])
            }
            #[inline(always)]
            fn not_(self) -> Self {
                Self([self.0[0].not_(), self.0[1].not_()])
            }
            #[inline(always)]
            fn from_bits(bits: u64) -> Self {
                Self([
                    $hmask::from_bits(bits & ((1 << $n) - 1)),
                    $hmask::from_bits(bits >> $n),
                ])
            }
        }
    };
    (@bin $half:ident, $($op:ident),*) => {
        $(
            #[inline(always)]
            fn $op(self, o: Self) -> Self {
                Self([self.0[0].$op(o.0[0]), self.0[1].$op(o.0[1])])
            }
        )*
    };
    (@un $($op:ident),*) => {
        $(
            #[inline(always)]
            fn $op(self) -> Self {
                Self([self.0[0].$op(), self.0[1].$op()])
            }
        )*
    };
    (@cmp $pmask:ident, $($op:ident),*) => {
        $(
            #[inline(always)]
            fn $op(self, o: Self) -> $pmask {
                $pmask([self.0[0].$op(o.0[0]), self.0[1].$op(o.0[1])])
            }
        )*
    };
}

pair_ops!(F64x4x2, F64x4, Mask4dx2, Mask4d, f64, 4);

/// Sixteen `f64` lanes in two zmm registers (AVX-512 F): lanes 0-7, then 8-15. The geometry
/// type of [`F32x16`].
#[derive(Clone, Copy)]
pub(crate) struct F64x8x2([F64x8; 2]);

/// A lane mask of [`F64x8x2`]: lanes 0-7, then 8-15.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Mask8x2([Mask8; 2]);

pair_ops!(F64x8x2, F64x8, Mask8x2, Mask8, f64, 8);

/// `acc + 0 x` in one fused multiply-add per register, for [`Lanes::add_zero_times`]: the
/// product `0 x` is exact (a zero or NaN), so fusing it rounds nothing (the exactness note of
/// the module documentation concerns the physics, which never fuses).
macro_rules! fused_probe {
    ($t:ident, $fmadd:ident, $zero:ident) => {
        impl $t {
            #[inline(always)]
            fn add_zero_times_(acc: Self, x: Self) -> Self {
                Self(arch!($fmadd(x.0, $zero(), acc.0)))
            }
        }
    };
    ($pair:ident, $half:ident) => {
        impl $pair {
            #[inline(always)]
            fn add_zero_times_(acc: Self, x: Self) -> Self {
                Self([
                    $half::add_zero_times_(acc.0[0], x.0[0]),
                    $half::add_zero_times_(acc.0[1], x.0[1]),
                ])
            }
        }
    };
}

fused_probe!(F64x8, _mm512_fmadd_pd, _mm512_setzero_pd);
fused_probe!(F64x4, _mm256_fmadd_pd, _mm256_setzero_pd);
fused_probe!(F32x8W, _mm256_fmadd_ps, _mm256_setzero_ps);
fused_probe!(F32x8N, _mm256_fmadd_ps, _mm256_setzero_ps);
fused_probe!(F32x16, _mm512_fmadd_ps, _mm512_setzero_ps);
fused_probe!(F64x4x2, F64x4);
fused_probe!(F64x8x2, F64x8);

// ----------------------------------------------------------------------------------------------
// The traits the generic physics needs (simba's SimdRealField and what it implies), written
// once over the primitive operations above.

/// The mask traits of `$mask` (`$n` lanes).
macro_rules! mask_traits {
    ($mask:ident, $n:expr) => {
        impl BitAnd for $mask {
            type Output = Self;
            #[inline(always)]
            fn bitand(self, o: Self) -> Self {
                self.and_(o)
            }
        }
        impl BitOr for $mask {
            type Output = Self;
            #[inline(always)]
            fn bitor(self, o: Self) -> Self {
                self.or_(o)
            }
        }
        impl BitXor for $mask {
            type Output = Self;
            #[inline(always)]
            fn bitxor(self, o: Self) -> Self {
                self.xor_(o)
            }
        }
        impl Not for $mask {
            type Output = Self;
            #[inline(always)]
            fn not(self) -> Self {
                self.not_()
            }
        }
        impl SimdValue for $mask {
            const LANES: usize = $n;
            type Element = bool;
            type SimdBool = Self;
            #[inline(always)]
            fn splat(val: bool) -> Self {
                Self::splat_(val)
            }
            #[inline(always)]
            fn extract(&self, i: usize) -> bool {
                assert!(i < $n);
                (self.bits_() >> i) & 1 == 1
            }
            #[inline(always)]
            unsafe fn extract_unchecked(&self, i: usize) -> bool {
                (self.bits_() >> i) & 1 == 1
            }
            #[inline(always)]
            fn replace(&mut self, i: usize, val: bool) {
                assert!(i < $n);
                let lane = Self::from_bits(1 << i);
                *self = (*self & !lane) | (lane & Self::splat_(val));
            }
            #[inline(always)]
            unsafe fn replace_unchecked(&mut self, i: usize, val: bool) {
                self.replace(i, val)
            }
            #[inline(always)]
            fn select(self, cond: Self, other: Self) -> Self {
                (self & cond) | (other & !cond)
            }
        }
        impl SimdBool for $mask {
            #[inline(always)]
            fn bitmask(self) -> u64 {
                self.bits_()
            }
            #[inline(always)]
            fn and(self) -> bool {
                self.bits_() == (1u64 << $n) - 1
            }
            #[inline(always)]
            fn or(self) -> bool {
                self.bits_() != 0
            }
            #[inline(always)]
            fn xor(self) -> bool {
                self.bits_().count_ones() % 2 == 1
            }
            #[inline(always)]
            fn all(self) -> bool {
                self.and()
            }
            #[inline(always)]
            fn any(self) -> bool {
                self.or()
            }
            #[inline(always)]
            fn none(self) -> bool {
                !self.or()
            }
            #[inline(always)]
            fn if_else<Res: SimdValue<SimdBool = Self>>(
                self,
                if_value: impl FnOnce() -> Res,
                else_value: impl FnOnce() -> Res,
            ) -> Res {
                let a = if_value();
                let b = else_value();
                a.select(self, b)
            }
            #[inline(always)]
            fn if_else2<Res: SimdValue<SimdBool = Self>>(
                self,
                if_value: impl FnOnce() -> Res,
                else_if: (impl FnOnce() -> Self, impl FnOnce() -> Res),
                else_value: impl FnOnce() -> Res,
            ) -> Res {
                let a = if_value();
                let cond = else_if.0();
                let b = else_if.1();
                let c = else_value();
                a.select(self, b.select(cond, c))
            }
            #[inline(always)]
            fn if_else3<Res: SimdValue<SimdBool = Self>>(
                self,
                if_value: impl FnOnce() -> Res,
                else_if: (impl FnOnce() -> Self, impl FnOnce() -> Res),
                else_else_if: (impl FnOnce() -> Self, impl FnOnce() -> Res),
                else_value: impl FnOnce() -> Res,
            ) -> Res {
                let a = if_value();
                let c1 = else_if.0();
                let b = else_if.1();
                let c2 = else_else_if.0();
                let c = else_else_if.1();
                let d = else_value();
                a.select(self, b.select(c1, c.select(c2, d)))
            }
        }
    };
}

impl Mask4d {
    #[inline(always)]
    fn from_bits(bits: u64) -> Self {
        let lane = |k: u32| {
            if (bits >> k) & 1 == 1 {
                f64::from_bits(!0)
            } else {
                0.0
            }
        };
        Mask4d(F64x4::from_array([lane(0), lane(1), lane(2), lane(3)]).0)
    }
}
impl Mask8f {
    #[inline(always)]
    fn from_bits(bits: u64) -> Self {
        let lane = |k: u32| {
            if (bits >> k) & 1 == 1 {
                f32::from_bits(!0)
            } else {
                0.0
            }
        };
        Mask8f(F32x8W::from_array(std::array::from_fn(|k| lane(k as u32))).0)
    }
}

mask_traits!(Mask8, 8);
mask_traits!(Mask4d, 4);
mask_traits!(Mask8f, 8);
mask_traits!(Mask4dx2, 8);
mask_traits!(Mask16, 16);
mask_traits!(Mask8x2, 16);

/// Every trait of simba's `SimdRealField` for the lane type `$t` of `$n` lanes of `$e`, with
/// mask `$mask`. The operations the physics uses map to the primitive operations; the others
/// (transcendental functions, rounding, horizontal reductions) go lane by lane through the
/// scalar functions, so they too give each lane the scalar's bits.
macro_rules! real_traits {
    ($t:ident, $mask:ident, $e:ident, $n:expr) => {
        impl $t {
            #[inline(always)]
            fn map(self, f: impl Fn($e) -> $e) -> Self {
                Self::from_array(self.to_array().map(f))
            }
            #[inline(always)]
            fn zip(self, o: Self, f: impl Fn($e, $e) -> $e) -> Self {
                let (a, b) = (self.to_array(), o.to_array());
                Self::from_array(std::array::from_fn(|k| f(a[k], b[k])))
            }
        }
        impl fmt::Debug for $t {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                write!(f, "{}({:?})", stringify!($t), self.to_array())
            }
        }
        impl PartialEq for $t {
            #[inline(always)]
            fn eq(&self, o: &Self) -> bool {
                self.eq_(*o).all()
            }
        }
        impl PrimitiveSimdValue for $t {}
        impl SimdValue for $t {
            const LANES: usize = $n;
            type Element = $e;
            type SimdBool = $mask;
            #[inline(always)]
            fn splat(val: $e) -> Self {
                Self::splat_(val)
            }
            #[inline(always)]
            fn extract(&self, i: usize) -> $e {
                self.to_array()[i]
            }
            #[inline(always)]
            unsafe fn extract_unchecked(&self, i: usize) -> $e {
                self.to_array()[i]
            }
            #[inline(always)]
            fn replace(&mut self, i: usize, val: $e) {
                let mut a = self.to_array();
                a[i] = val;
                *self = Self::from_array(a);
            }
            #[inline(always)]
            unsafe fn replace_unchecked(&mut self, i: usize, val: $e) {
                self.replace(i, val)
            }
            #[inline(always)]
            fn select(self, cond: $mask, other: Self) -> Self {
                other.blend_(cond, self)
            }
        }
        impl Add for $t {
            type Output = Self;
            #[inline(always)]
            fn add(self, o: Self) -> Self {
                self.add_(o)
            }
        }
        impl Sub for $t {
            type Output = Self;
            #[inline(always)]
            fn sub(self, o: Self) -> Self {
                self.sub_(o)
            }
        }
        impl Mul for $t {
            type Output = Self;
            #[inline(always)]
            fn mul(self, o: Self) -> Self {
                self.mul_(o)
            }
        }
        impl Div for $t {
            type Output = Self;
            #[inline(always)]
            fn div(self, o: Self) -> Self {
                self.div_(o)
            }
        }
        impl Rem for $t {
            type Output = Self;
            #[inline(always)]
            fn rem(self, o: Self) -> Self {
                self.zip(o, |a, b| a % b)
            }
        }
        impl Neg for $t {
            type Output = Self;
            #[inline(always)]
            fn neg(self) -> Self {
                self.neg_()
            }
        }
        impl AddAssign for $t {
            #[inline(always)]
            fn add_assign(&mut self, o: Self) {
                *self = *self + o;
            }
        }
        impl SubAssign for $t {
            #[inline(always)]
            fn sub_assign(&mut self, o: Self) {
                *self = *self - o;
            }
        }
        impl MulAssign for $t {
            #[inline(always)]
            fn mul_assign(&mut self, o: Self) {
                *self = *self * o;
            }
        }
        impl DivAssign for $t {
            #[inline(always)]
            fn div_assign(&mut self, o: Self) {
                *self = *self / o;
            }
        }
        impl RemAssign for $t {
            #[inline(always)]
            fn rem_assign(&mut self, o: Self) {
                *self = *self % o;
            }
        }
        impl Zero for $t {
            #[inline(always)]
            fn zero() -> Self {
                Self::splat_(0.0)
            }
            #[inline(always)]
            fn is_zero(&self) -> bool {
                self.eq_(Self::zero()).all()
            }
        }
        impl One for $t {
            #[inline(always)]
            fn one() -> Self {
                Self::splat_(1.0)
            }
        }
        impl Num for $t {
            type FromStrRadixErr = <$e as Num>::FromStrRadixErr;
            fn from_str_radix(s: &str, radix: u32) -> Result<Self, Self::FromStrRadixErr> {
                <$e>::from_str_radix(s, radix).map(Self::splat_)
            }
        }
        impl FromPrimitive for $t {
            #[inline(always)]
            fn from_i64(n: i64) -> Option<Self> {
                <$e>::from_i64(n).map(Self::splat_)
            }
            #[inline(always)]
            fn from_u64(n: u64) -> Option<Self> {
                <$e>::from_u64(n).map(Self::splat_)
            }
            #[inline(always)]
            fn from_f64(n: f64) -> Option<Self> {
                <$e>::from_f64(n).map(Self::splat_)
            }
        }
        impl Field for $t {}
        impl SubsetOf<$t> for $t {
            #[inline(always)]
            fn to_superset(&self) -> Self {
                *self
            }
            #[inline(always)]
            fn from_superset_unchecked(element: &Self) -> Self {
                *element
            }
            #[inline(always)]
            fn is_in_subset(_: &Self) -> bool {
                true
            }
        }
        #[allow(clippy::unnecessary_cast)]
        impl SubsetOf<$t> for f64 {
            #[inline(always)]
            fn to_superset(&self) -> $t {
                $t::splat_(*self as $e)
            }
            #[inline(always)]
            fn from_superset_unchecked(element: &$t) -> f64 {
                element.extract(0) as f64
            }
            #[inline(always)]
            fn is_in_subset(c: &$t) -> bool {
                let a = c.to_array();
                a.iter().all(|&x| x == a[0])
            }
        }
        #[allow(clippy::unnecessary_cast)]
        impl SubsetOf<$t> for f32 {
            #[inline(always)]
            fn to_superset(&self) -> $t {
                $t::splat_(*self as $e)
            }
            #[inline(always)]
            fn from_superset_unchecked(element: &$t) -> f32 {
                element.extract(0) as f32
            }
            #[inline(always)]
            fn is_in_subset(c: &$t) -> bool {
                let a = c.to_array();
                a.iter().all(|&x| x == a[0])
            }
        }
        impl SimdPartialOrd for $t {
            #[inline(always)]
            fn simd_gt(self, o: Self) -> $mask {
                self.gt_(o)
            }
            #[inline(always)]
            fn simd_lt(self, o: Self) -> $mask {
                self.lt_(o)
            }
            #[inline(always)]
            fn simd_ge(self, o: Self) -> $mask {
                self.ge_(o)
            }
            #[inline(always)]
            fn simd_le(self, o: Self) -> $mask {
                self.le_(o)
            }
            #[inline(always)]
            fn simd_eq(self, o: Self) -> $mask {
                self.eq_(o)
            }
            #[inline(always)]
            fn simd_ne(self, o: Self) -> $mask {
                self.ne_(o)
            }
            #[inline(always)]
            fn simd_max(self, o: Self) -> Self {
                self.max_(o)
            }
            #[inline(always)]
            fn simd_min(self, o: Self) -> Self {
                self.min_(o)
            }
            #[inline(always)]
            fn simd_clamp(self, min: Self, max: Self) -> Self {
                self.max_(min).min_(max)
            }
            #[inline(always)]
            fn simd_horizontal_min(self) -> $e {
                self.to_array().into_iter().fold(<$e>::INFINITY, <$e>::min)
            }
            #[inline(always)]
            fn simd_horizontal_max(self) -> $e {
                self.to_array().into_iter().fold(<$e>::NEG_INFINITY, <$e>::max)
            }
        }
        impl SimdSigned for $t {
            #[inline(always)]
            fn simd_abs(&self) -> Self {
                self.abs_()
            }
            #[inline(always)]
            fn simd_abs_sub(&self, o: &Self) -> Self {
                (*self - *o).max_(Self::zero())
            }
            #[inline(always)]
            fn simd_signum(&self) -> Self {
                self.map(|x: $e| num_traits::Signed::signum(&x))
            }
            #[inline(always)]
            fn is_simd_positive(&self) -> $mask {
                self.gt_(Self::zero())
            }
            #[inline(always)]
            fn is_simd_negative(&self) -> $mask {
                self.lt_(Self::zero())
            }
        }
        impl SimdRealField for $t {
            #[inline(always)]
            fn simd_copysign(self, sign: Self) -> Self {
                self.zip(sign, <$e>::copysign)
            }
            #[inline(always)]
            fn simd_atan2(self, o: Self) -> Self {
                self.zip(o, <$e>::atan2)
            }
            #[inline(always)]
            fn simd_default_epsilon() -> Self {
                Self::splat_(<$e>::EPSILON)
            }
            #[inline(always)]
            fn simd_pi() -> Self {
                Self::splat_(<$e as RealField>::pi())
            }
            #[inline(always)]
            fn simd_two_pi() -> Self {
                Self::splat_(<$e as RealField>::two_pi())
            }
            #[inline(always)]
            fn simd_frac_pi_2() -> Self {
                Self::splat_(<$e as RealField>::frac_pi_2())
            }
            #[inline(always)]
            fn simd_frac_pi_3() -> Self {
                Self::splat_(<$e as RealField>::frac_pi_3())
            }
            #[inline(always)]
            fn simd_frac_pi_4() -> Self {
                Self::splat_(<$e as RealField>::frac_pi_4())
            }
            #[inline(always)]
            fn simd_frac_pi_6() -> Self {
                Self::splat_(<$e as RealField>::frac_pi_6())
            }
            #[inline(always)]
            fn simd_frac_pi_8() -> Self {
                Self::splat_(<$e as RealField>::frac_pi_8())
            }
            #[inline(always)]
            fn simd_frac_1_pi() -> Self {
                Self::splat_(<$e as RealField>::frac_1_pi())
            }
            #[inline(always)]
            fn simd_frac_2_pi() -> Self {
                Self::splat_(<$e as RealField>::frac_2_pi())
            }
            #[inline(always)]
            fn simd_frac_2_sqrt_pi() -> Self {
                Self::splat_(<$e as RealField>::frac_2_sqrt_pi())
            }
            #[inline(always)]
            fn simd_e() -> Self {
                Self::splat_(<$e as RealField>::e())
            }
            #[inline(always)]
            fn simd_log2_e() -> Self {
                Self::splat_(<$e as RealField>::log2_e())
            }
            #[inline(always)]
            fn simd_log10_e() -> Self {
                Self::splat_(<$e as RealField>::log10_e())
            }
            #[inline(always)]
            fn simd_ln_2() -> Self {
                Self::splat_(<$e as RealField>::ln_2())
            }
            #[inline(always)]
            fn simd_ln_10() -> Self {
                Self::splat_(<$e as RealField>::ln_10())
            }
        }
        impl SimdComplexField for $t {
            type SimdRealField = Self;
            #[inline(always)]
            fn from_simd_real(re: Self) -> Self {
                re
            }
            #[inline(always)]
            fn simd_real(self) -> Self {
                self
            }
            #[inline(always)]
            fn simd_imaginary(self) -> Self {
                Self::zero()
            }
            #[inline(always)]
            fn simd_modulus(self) -> Self {
                self.abs_()
            }
            #[inline(always)]
            fn simd_modulus_squared(self) -> Self {
                self * self
            }
            #[inline(always)]
            fn simd_argument(self) -> Self {
                self.map(<$e as ComplexField>::argument)
            }
            #[inline(always)]
            fn simd_norm1(self) -> Self {
                self.abs_()
            }
            #[inline(always)]
            fn simd_scale(self, factor: Self) -> Self {
                self * factor
            }
            #[inline(always)]
            fn simd_unscale(self, factor: Self) -> Self {
                self / factor
            }
            #[inline(always)]
            fn simd_to_polar(self) -> (Self, Self) {
                (self.simd_modulus(), self.simd_argument())
            }
            #[inline(always)]
            fn simd_to_exp(self) -> (Self, Self) {
                (self.simd_modulus(), self.simd_signum())
            }
            #[inline(always)]
            fn simd_signum(self) -> Self {
                <Self as SimdSigned>::simd_signum(&self)
            }
            #[inline(always)]
            fn simd_floor(self) -> Self {
                self.map(<$e>::floor)
            }
            #[inline(always)]
            fn simd_ceil(self) -> Self {
                self.map(<$e>::ceil)
            }
            #[inline(always)]
            fn simd_round(self) -> Self {
                self.map(<$e>::round)
            }
            #[inline(always)]
            fn simd_trunc(self) -> Self {
                self.map(<$e>::trunc)
            }
            #[inline(always)]
            fn simd_fract(self) -> Self {
                self.map(<$e>::fract)
            }
            #[inline(always)]
            fn simd_mul_add(self, a: Self, b: Self) -> Self {
                let (x, y, z) = (self.to_array(), a.to_array(), b.to_array());
                Self::from_array(std::array::from_fn(|k| x[k].mul_add(y[k], z[k])))
            }
            #[inline(always)]
            fn simd_abs(self) -> Self {
                self.abs_()
            }
            #[inline(always)]
            fn simd_hypot(self, o: Self) -> Self {
                self.zip(o, <$e>::hypot)
            }
            #[inline(always)]
            fn simd_recip(self) -> Self {
                Self::one() / self
            }
            #[inline(always)]
            fn simd_conjugate(self) -> Self {
                self
            }
            #[inline(always)]
            fn simd_sin(self) -> Self {
                self.map(<$e>::sin)
            }
            #[inline(always)]
            fn simd_cos(self) -> Self {
                self.map(<$e>::cos)
            }
            #[inline(always)]
            fn simd_sin_cos(self) -> (Self, Self) {
                (self.simd_sin(), self.simd_cos())
            }
            #[inline(always)]
            fn simd_tan(self) -> Self {
                self.map(<$e>::tan)
            }
            #[inline(always)]
            fn simd_asin(self) -> Self {
                self.map(<$e>::asin)
            }
            #[inline(always)]
            fn simd_acos(self) -> Self {
                self.map(<$e>::acos)
            }
            #[inline(always)]
            fn simd_atan(self) -> Self {
                self.map(<$e>::atan)
            }
            #[inline(always)]
            fn simd_sinh(self) -> Self {
                self.map(<$e>::sinh)
            }
            #[inline(always)]
            fn simd_cosh(self) -> Self {
                self.map(<$e>::cosh)
            }
            #[inline(always)]
            fn simd_tanh(self) -> Self {
                self.map(<$e>::tanh)
            }
            #[inline(always)]
            fn simd_asinh(self) -> Self {
                self.map(<$e>::asinh)
            }
            #[inline(always)]
            fn simd_acosh(self) -> Self {
                self.map(<$e>::acosh)
            }
            #[inline(always)]
            fn simd_atanh(self) -> Self {
                self.map(<$e>::atanh)
            }
            #[inline(always)]
            fn simd_log(self, base: Self) -> Self {
                self.zip(base, <$e>::log)
            }
            #[inline(always)]
            fn simd_log2(self) -> Self {
                self.map(<$e>::log2)
            }
            #[inline(always)]
            fn simd_log10(self) -> Self {
                self.map(<$e>::log10)
            }
            #[inline(always)]
            fn simd_ln(self) -> Self {
                self.map(<$e>::ln)
            }
            #[inline(always)]
            fn simd_ln_1p(self) -> Self {
                self.map(<$e>::ln_1p)
            }
            #[inline(always)]
            fn simd_sqrt(self) -> Self {
                self.sqrt_()
            }
            #[inline(always)]
            fn simd_exp(self) -> Self {
                self.map(<$e>::exp)
            }
            #[inline(always)]
            fn simd_exp2(self) -> Self {
                self.map(<$e>::exp2)
            }
            #[inline(always)]
            fn simd_exp_m1(self) -> Self {
                self.map(<$e>::exp_m1)
            }
            #[inline(always)]
            fn simd_powi(self, n: i32) -> Self {
                self.map(|x| x.powi(n))
            }
            #[inline(always)]
            fn simd_powf(self, n: Self) -> Self {
                self.zip(n, <$e>::powf)
            }
            #[inline(always)]
            fn simd_powc(self, n: Self) -> Self {
                self.zip(n, <$e>::powf)
            }
            #[inline(always)]
            fn simd_cbrt(self) -> Self {
                self.map(<$e>::cbrt)
            }
            #[inline(always)]
            fn simd_horizontal_sum(self) -> $e {
                self.to_array().into_iter().sum()
            }
            #[inline(always)]
            fn simd_horizontal_product(self) -> $e {
                self.to_array().into_iter().product()
            }
        }
    };
}

real_traits!(F64x8, Mask8, f64, 8);
real_traits!(F64x4, Mask4d, f64, 4);
real_traits!(F64x4x2, Mask4dx2, f64, 8);
real_traits!(F32x8W, Mask8f, f32, 8);
real_traits!(F32x8N, Mask8f, f32, 8);
real_traits!(F32x16, Mask16, f32, 16);
real_traits!(F64x8x2, Mask8x2, f64, 16);

// ----------------------------------------------------------------------------------------------
// What the batch kernels need: lane counts, the geometry type, row loads and stores.

impl Lanes for F64x8 {
    const FUSED_PROBE: bool = true;
    #[inline(always)]
    fn add_zero_times(acc: Self, x: Self) -> Self {
        Self::add_zero_times_(acc, x)
    }
    const N: usize = 8;
    type Geo = F64x8;
    #[inline(always)]
    fn from_fn<F: FnMut(usize) -> f64>(mut f: F) -> Self {
        Self::from_array([f(0), f(1), f(2), f(3), f(4), f(5), f(6), f(7)])
    }
    #[inline(always)]
    fn lane(&self, k: usize) -> f64 {
        self.to_array()[k]
    }
    #[inline(always)]
    fn from_geo(lo: Self, _hi: Self) -> Self {
        lo
    }
    #[inline(always)]
    fn load(src: &[f64]) -> Self {
        let src = &src[..8];
        Self(arch!(_mm512_loadu_pd(src.as_ptr())))
    }
    #[inline(always)]
    fn store(&self, dst: &mut [f64]) {
        let dst = &mut dst[..8];
        arch!(_mm512_storeu_pd(dst.as_mut_ptr(), self.0));
    }
    type Arr<X: Copy> = [X; 8];
    #[inline(always)]
    fn arr<X: Copy>(x: X) -> [X; 8] {
        [x; 8]
    }
}

impl Lanes for F64x4 {
    const FUSED_PROBE: bool = true;
    #[inline(always)]
    fn add_zero_times(acc: Self, x: Self) -> Self {
        Self::add_zero_times_(acc, x)
    }
    const N: usize = 4;
    type Geo = F64x4;
    #[inline(always)]
    fn from_fn<F: FnMut(usize) -> f64>(mut f: F) -> Self {
        Self::from_array([f(0), f(1), f(2), f(3)])
    }
    #[inline(always)]
    fn lane(&self, k: usize) -> f64 {
        self.to_array()[k]
    }
    #[inline(always)]
    fn from_geo(lo: Self, _hi: Self) -> Self {
        lo
    }
    #[inline(always)]
    fn load(src: &[f64]) -> Self {
        let src = &src[..4];
        Self(arch!(_mm256_loadu_pd(src.as_ptr())))
    }
    #[inline(always)]
    fn store(&self, dst: &mut [f64]) {
        let dst = &mut dst[..4];
        arch!(_mm256_storeu_pd(dst.as_mut_ptr(), self.0));
    }
    type Arr<X: Copy> = [X; 4];
    #[inline(always)]
    fn arr<X: Copy>(x: X) -> [X; 4] {
        [x; 4]
    }
}

impl Lanes for F32x8W {
    const FUSED_PROBE: bool = true;
    #[inline(always)]
    fn add_zero_times(acc: Self, x: Self) -> Self {
        Self::add_zero_times_(acc, x)
    }
    const N: usize = 8;
    type Geo = F64x8;
    #[inline(always)]
    fn from_fn<F: FnMut(usize) -> f64>(f: F) -> Self {
        Self::from_geo(F64x8::from_fn(f), F64x8::zero())
    }
    #[inline(always)]
    fn lane(&self, k: usize) -> f64 {
        self.to_array()[k] as f64
    }
    #[inline(always)]
    fn from_geo(lo: F64x8, _hi: F64x8) -> Self {
        // vcvtpd2ps rounds to nearest (the default MXCSR mode), as `as f32` does.
        Self(arch!(_mm512_cvtpd_ps(lo.0)))
    }
    #[inline(always)]
    fn load(src: &[f64]) -> Self {
        Self::from_geo(F64x8::load(src), F64x8::zero())
    }
    #[inline(always)]
    fn store(&self, dst: &mut [f64]) {
        // Widening to f64 is exact.
        F64x8(arch!(_mm512_cvtps_pd(self.0))).store(dst)
    }
    type Arr<X: Copy> = [X; 8];
    #[inline(always)]
    fn arr<X: Copy>(x: X) -> [X; 8] {
        [x; 8]
    }
}

impl Lanes for F64x4x2 {
    const FUSED_PROBE: bool = true;
    #[inline(always)]
    fn add_zero_times(acc: Self, x: Self) -> Self {
        Self::add_zero_times_(acc, x)
    }
    const N: usize = 8;
    type Geo = F64x4x2;
    #[inline(always)]
    fn from_fn<F: FnMut(usize) -> f64>(mut f: F) -> Self {
        Self::from_array([f(0), f(1), f(2), f(3), f(4), f(5), f(6), f(7)])
    }
    #[inline(always)]
    fn lane(&self, k: usize) -> f64 {
        self.to_array()[k]
    }
    #[inline(always)]
    fn from_geo(lo: Self, _hi: Self) -> Self {
        lo
    }
    #[inline(always)]
    fn load(src: &[f64]) -> Self {
        Self([F64x4::load(src), F64x4::load(&src[4..])])
    }
    #[inline(always)]
    fn store(&self, dst: &mut [f64]) {
        self.0[0].store(dst);
        self.0[1].store(&mut dst[4..]);
    }
    type Arr<X: Copy> = [X; 8];
    #[inline(always)]
    fn arr<X: Copy>(x: X) -> [X; 8] {
        [x; 8]
    }
}

impl Lanes for F32x8N {
    const FUSED_PROBE: bool = true;
    #[inline(always)]
    fn add_zero_times(acc: Self, x: Self) -> Self {
        Self::add_zero_times_(acc, x)
    }
    const N: usize = 8;
    type Geo = F64x4x2;
    #[inline(always)]
    fn from_fn<F: FnMut(usize) -> f64>(f: F) -> Self {
        let g = F64x4x2::from_fn(f);
        Self::from_geo(g, g)
    }
    #[inline(always)]
    fn lane(&self, k: usize) -> f64 {
        self.to_array()[k] as f64
    }
    #[inline(always)]
    fn from_geo(lo: F64x4x2, _hi: F64x4x2) -> Self {
        // vcvtpd2ps rounds to nearest (the default MXCSR mode), as `as f32` does.
        let [a, b] = lo.0;
        Self(arch!(_mm256_set_m128(
            _mm256_cvtpd_ps(b.0),
            _mm256_cvtpd_ps(a.0)
        )))
    }
    #[inline(always)]
    fn load(src: &[f64]) -> Self {
        let g = F64x4x2::load(src);
        Self::from_geo(g, g)
    }
    #[inline(always)]
    fn store(&self, dst: &mut [f64]) {
        // Widening to f64 is exact.
        let lo = F64x4(arch!(_mm256_cvtps_pd(_mm256_castps256_ps128(self.0))));
        let hi = F64x4(arch!(_mm256_cvtps_pd(_mm256_extractf128_ps::<1>(self.0))));
        F64x4x2([lo, hi]).store(dst);
    }
    type Arr<X: Copy> = [X; 8];
    #[inline(always)]
    fn arr<X: Copy>(x: X) -> [X; 8] {
        [x; 8]
    }
}

impl Lanes for F64x8x2 {
    const FUSED_PROBE: bool = true;
    #[inline(always)]
    fn add_zero_times(acc: Self, x: Self) -> Self {
        Self::add_zero_times_(acc, x)
    }
    const N: usize = 16;
    type Geo = F64x8x2;
    #[inline(always)]
    fn from_fn<F: FnMut(usize) -> f64>(mut f: F) -> Self {
        let lo = F64x8::from_fn(&mut f);
        let hi = F64x8::from_fn(|k| f(8 + k));
        Self([lo, hi])
    }
    #[inline(always)]
    fn lane(&self, k: usize) -> f64 {
        self.to_array()[k]
    }
    #[inline(always)]
    fn from_geo(lo: Self, _hi: Self) -> Self {
        lo
    }
    #[inline(always)]
    fn load(src: &[f64]) -> Self {
        Self([F64x8::load(src), F64x8::load(&src[8..])])
    }
    #[inline(always)]
    fn store(&self, dst: &mut [f64]) {
        self.0[0].store(dst);
        self.0[1].store(&mut dst[8..]);
    }
    type Arr<X: Copy> = [X; 16];
    #[inline(always)]
    fn arr<X: Copy>(x: X) -> [X; 16] {
        [x; 16]
    }
}

impl Lanes for F32x16 {
    const FUSED_PROBE: bool = true;
    #[inline(always)]
    fn add_zero_times(acc: Self, x: Self) -> Self {
        Self::add_zero_times_(acc, x)
    }
    const N: usize = 16;
    type Geo = F64x8x2;
    #[inline(always)]
    fn from_fn<F: FnMut(usize) -> f64>(f: F) -> Self {
        let g = F64x8x2::from_fn(f);
        Self::from_geo(g, g)
    }
    #[inline(always)]
    fn lane(&self, k: usize) -> f64 {
        self.to_array()[k] as f64
    }
    #[inline(always)]
    fn from_geo(lo: F64x8x2, _hi: F64x8x2) -> Self {
        // vcvtpd2ps rounds to nearest (the default MXCSR mode), as `as f32` does.
        let [a, b] = lo.0;
        Self(arch!(_mm512_insertf32x8::<1>(
            _mm512_castps256_ps512(_mm512_cvtpd_ps(a.0)),
            _mm512_cvtpd_ps(b.0)
        )))
    }
    #[inline(always)]
    fn load(src: &[f64]) -> Self {
        let g = F64x8x2::load(src);
        Self::from_geo(g, g)
    }
    #[inline(always)]
    fn store(&self, dst: &mut [f64]) {
        // Widening to f64 is exact.
        let lo = F64x8(arch!(_mm512_cvtps_pd(_mm512_castps512_ps256(self.0))));
        let hi = F64x8(arch!(_mm512_cvtps_pd(_mm512_extractf32x8_ps::<1>(self.0))));
        F64x8x2([lo, hi]).store(dst);
    }
    type Arr<X: Copy> = [X; 16];
    #[inline(always)]
    fn arr<X: Copy>(x: X) -> [X; 16] {
        [x; 16]
    }
}

#[cfg(test)]
mod tests {
    //! Each lane type against the scalar operations, bit for bit, on values that probe the
    //! corners: signed zeros, subnormals, the largest finite values, infinities and NaN.
    use super::*;

    const SPECIAL: [f64; 16] = [
        0.0,
        -0.0,
        1.0,
        -1.5,
        3.0,
        0.1,
        5e-324,
        -2.2e-308,
        1.7e308,
        -1.7e308,
        1e154,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::NAN,
        2.0,
        -7.25,
    ];

    /// Same bits, or both NaN (the payload is not part of any result the library returns).
    fn same(a: f64, b: f64) -> bool {
        a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan())
    }

    /// Checks lane type `L` (elements `E`) against `E`'s scalar operations on every ordered
    /// pair of `SPECIAL` values, eight pairs per call.
    macro_rules! check_type {
        ($t:ty, $e:ty) => {{
            let n = <$t as SimdValue>::LANES;
            let pairs: Vec<($e, $e)> = SPECIAL
                .iter()
                .flat_map(|&a| SPECIAL.iter().map(move |&b| (a as $e, b as $e)))
                .collect();
            for chunk in pairs.chunks(n) {
                let lane = |k: usize| chunk[k % chunk.len()];
                let a = <$t>::from_array(std::array::from_fn(|k| lane(k).0));
                let b = <$t>::from_array(std::array::from_fn(|k| lane(k).1));
                type Bin = (&'static str, fn($t, $t) -> $t, fn($e, $e) -> $e);
                let binary: [Bin; 7] = [
                    ("add", |a, b| a + b, |a, b| a + b),
                    // The fused `a + 0 b` of the finiteness tests: the same bits as the product
                    // and the sum (`0 b` is exact).
                    ("add_zero_times", <$t as Lanes>::add_zero_times, |a, b| a + b * 0.0),
                    ("sub", |a, b| a - b, |a, b| a - b),
                    ("mul", |a, b| a * b, |a, b| a * b),
                    ("div", |a, b| a / b, |a, b| a / b),
                    ("max", |a, b| a.simd_max(b), <$e>::max),
                    ("min", |a, b| a.simd_min(b), <$e>::min),
                ];
                for (name, vector, scalar) in binary {
                    let got = vector(a, b).to_array();
                    for k in 0..n {
                        let (x, y) = lane(k);
                        assert!(
                            same(got[k] as f64, scalar(x, y) as f64),
                            "{} {name}({x:e}, {y:e}) = {:e}",
                            stringify!($t),
                            got[k]
                        );
                    }
                }
                type Un = (&'static str, fn($t) -> $t, fn($e) -> $e);
                let unary: [Un; 3] = [
                    ("sqrt", |a| a.simd_sqrt(), <$e>::sqrt),
                    ("abs", |a| SimdSigned::simd_abs(&a), <$e>::abs),
                    ("neg", |a| -a, |a| -a),
                ];
                for (name, vector, scalar) in unary {
                    let got = vector(a).to_array();
                    for k in 0..n {
                        let x = lane(k).0;
                        assert!(same(got[k] as f64, scalar(x) as f64), "{name}({x:e})");
                    }
                }
                type Cmp = (&'static str, fn($t, $t) -> u64, fn(&$e, &$e) -> bool);
                let compares: [Cmp; 6] = [
                    ("gt", |a, b| a.simd_gt(b).bitmask(), |a, b| a > b),
                    ("lt", |a, b| a.simd_lt(b).bitmask(), |a, b| a < b),
                    ("ge", |a, b| a.simd_ge(b).bitmask(), |a, b| a >= b),
                    ("le", |a, b| a.simd_le(b).bitmask(), |a, b| a <= b),
                    ("eq", |a, b| a.simd_eq(b).bitmask(), |a, b| a == b),
                    ("ne", |a, b| a.simd_ne(b).bitmask(), |a, b| a != b),
                ];
                for (name, vector, scalar) in compares {
                    let bits = vector(a, b);
                    for k in 0..n {
                        let (x, y) = lane(k);
                        assert_eq!((bits >> k) & 1 == 1, scalar(&x, &y), "{name}({x:e}, {y:e})");
                    }
                }
                // select, and the mask algebra it is built from.
                let m = a.simd_gt(b);
                let picked = a.select(m, b).to_array();
                let notm = (!m).bitmask();
                let both = (m & a.simd_lt(b)).bitmask();
                let either = (m | a.simd_eq(b)).bitmask();
                let odd = (m ^ a.simd_ge(b)).bitmask();
                let all = (1u64 << n) - 1;
                for k in 0..n {
                    let (x, y) = lane(k);
                    let want = if x > y { x } else { y };
                    assert!(same(picked[k] as f64, want as f64));
                    assert_eq!((notm >> k) & 1 == 1, x.partial_cmp(&y) != Some(std::cmp::Ordering::Greater));
                    assert_eq!((both >> k) & 1, 0);
                    assert_eq!((either >> k) & 1 == 1, x >= y);
                    assert_eq!((odd >> k) & 1 == 1, x == y);
                }
                assert_eq!(notm & !all, 0, "no bits beyond the lanes");
                assert_eq!(
                    <$t as SimdValue>::SimdBool::splat(true).bitmask(),
                    all
                );
                assert!(<$t as SimdValue>::SimdBool::splat(false).none());
            }
        }};
    }

    #[test]
    fn avx_lane_types_match_scalar_operations() {
        if !(is_x86_feature_detected!("avx2") && is_x86_feature_detected!("fma")) {
            eprintln!("skipped: this CPU has no AVX2/FMA");
            return;
        }
        check_type!(F64x4, f64);
        check_type!(F64x4x2, f64);
        check_type!(F32x8W, f32);
        check_type!(F32x8N, f32);
    }

    #[test]
    fn avx512_lane_type_matches_scalar_operations() {
        if !(is_x86_feature_detected!("avx512f") && is_x86_feature_detected!("avx512dq")) {
            eprintln!("skipped: this CPU has no AVX-512 F/DQ");
            return;
        }
        check_type!(F64x8, f64);
        check_type!(F64x8x2, f64);
        check_type!(F32x16, f32);
    }

    #[test]
    fn conversions_between_precisions_round_as_scalar_casts() {
        if !is_x86_feature_detected!("avx2") {
            eprintln!("skipped: this CPU has no AVX2");
            return;
        }
        for chunk in SPECIAL.chunks(8) {
            let src: Vec<f64> = (0..8).map(|k| chunk[k % chunk.len()] * 1.0000001).collect();
            let narrow = F32x8N::load(&src);
            let mut back = [0.0; 8];
            narrow.store(&mut back);
            for k in 0..8 {
                assert!(same(narrow.lane(k), src[k] as f32 as f64));
                assert!(same(back[k], src[k] as f32 as f64));
            }
            if is_x86_feature_detected!("avx512f") && is_x86_feature_detected!("avx512dq") {
                let src16: Vec<f64> = (0..16)
                    .map(|k| src[k % 8] * if k < 8 { 1.0 } else { -3.0 })
                    .collect();
                let sixteen = F32x16::load(&src16);
                let mut back = [0.0; 16];
                sixteen.store(&mut back);
                for k in 0..16 {
                    assert!(same(sixteen.lane(k), src16[k] as f32 as f64));
                    assert!(same(back[k], src16[k] as f32 as f64));
                }
                let wide = F32x8W::load(&src);
                let mut back = [0.0; 8];
                wide.store(&mut back);
                for k in 0..8 {
                    assert!(same(wide.lane(k), src[k] as f32 as f64));
                    assert!(same(back[k], src[k] as f32 as f64));
                }
            }
        }
    }
}
