//! The number types the physics is written for.
//!
//! Every kinematic formula in this crate is written once, generic over [`Real`]: plain `f64`,
//! plain `f32`, and SIMD lane types such as [`simba::simd::WideF64x4`] (four contacts at once)
//! all instantiate the same code, so the per-contact and batch paths cannot drift apart.

use nalgebra::{SimdRealField, Vector3};
use simba::simd::SimdBool;

/// A real number type the kinematics can be evaluated in: a scalar (`f32`, `f64`) or a SIMD
/// pack of lanes (for example `simba::simd::WideF64x4`), one contact per lane.
pub trait Real: SimdRealField + Copy {}

impl<T: SimdRealField + Copy> Real for T {}

/// A 3-vector of [`Real`] numbers (positions, velocities, angular velocities).
pub type Vec3<T> = Vector3<T>;

/// Converts an `f64` constant into `T` (exact for `f64`, rounded for `f32`, splat for SIMD).
#[inline(always)]
pub fn lit<T: Real>(x: f64) -> T {
    nalgebra::convert(x)
}

/// The cross product `a x b`, as nalgebra's `Matrix::cross` computes it (the same products
/// and differences in the same order, so the same bits), but always inlined: the batch kernels'
/// SIMD lane types reach their instructions only where the physics is inlined into a kernel
/// compiled for those instructions.
#[inline(always)]
pub fn cross<T: Real>(a: &Vec3<T>, b: &Vec3<T>) -> Vec3<T> {
    Vec3::new(
        a.y * b.z - a.z * b.y,
        a.z * b.x - a.x * b.z,
        a.x * b.y - a.y * b.x,
    )
}

/// The dot product `a . b = (a_x b_x + a_y b_y) + a_z b_z`, as nalgebra's `dot` computes it
/// for 3-vectors (same order, same bits), always inlined (see [`cross`]).
#[inline(always)]
pub fn dot<T: Real>(a: &Vec3<T>, b: &Vec3<T>) -> T {
    a.x * b.x + a.y * b.y + a.z * b.z
}

/// `|v|^2 = v . v`, with nalgebra's bits (its `norm_squared` adds `v . v` to a zero, which
/// changes no bit of a square), always inlined.
#[inline(always)]
pub fn norm_squared<T: Real>(v: &Vec3<T>) -> T {
    dot(v, v)
}

/// `|v| = sqrt(v . v)`, with nalgebra's bits, always inlined.
#[inline(always)]
pub fn norm<T: Real>(v: &Vec3<T>) -> T {
    norm_squared(v).simd_sqrt()
}

/// The tangential part of `v` with respect to the unit normal `n`: `v - (v . n) n`.
#[inline(always)]
pub fn tangential<T: Real>(v: &Vec3<T>, n: &Vec3<T>) -> Vec3<T> {
    v - n * dot(v, n)
}

/// Lane-wise choice: `a` where `cond` holds, else `b` (a plain `if` for scalars).
#[inline(always)]
pub fn select<T: Real>(cond: T::SimdBool, a: T, b: T) -> T {
    a.select(cond, b)
}

/// Lane-wise choice of vectors: `a` where `cond` holds, else `b`.
#[inline(always)]
pub fn select3<T: Real>(cond: T::SimdBool, a: &Vec3<T>, b: &Vec3<T>) -> Vec3<T> {
    Vec3::new(
        select(cond, a.x, b.x),
        select(cond, a.y, b.y),
        select(cond, a.z, b.z),
    )
}

/// A lane mask with every lane set to `value`.
#[inline(always)]
pub fn mask<T: Real>(value: bool) -> T::SimdBool {
    if value {
        T::zero().simd_le(T::zero())
    } else {
        T::zero().simd_gt(T::zero())
    }
}

/// A vector's length recomputed where its square overflowed (see [`rescale_overflowed`]).
#[derive(Clone, Copy, Debug)]
pub struct Rescaled<T> {
    /// What the vector is divided by: its largest absolute component where `v . v` overflowed,
    /// 1 in every other lane (dividing by it changes no bit there).
    pub divisor: T,
    /// `|v / divisor|`: between 1 and `sqrt 3` where the vector was rescaled, the given norm
    /// in every other lane.
    pub scaled_norm: T,
    /// `|v|` itself, `divisor * scaled_norm`: +inf only where `|v|` exceeds the largest finite
    /// value; the given norm in every other lane.
    pub norm: T,
}

/// Where `norm` (that is `|v|`, `sqrt(v . v)`) overflowed to +inf, the lengths to use
/// instead: `v . v` overflows from `|v|` about `1.3e154` in `f64` (`1.8e19` in `f32`), long
/// before `v` itself does, and a clip `v * (limit / |v|)` or a direction `v / |v|` then gives
/// zero. Returns `None` when no lane overflowed (the common case: `v` and `norm` are right as
/// they are, and nothing else is computed); otherwise the divisor that brings `v` into range
/// lane-wise, with `v / divisor` and `scaled_norm` to clip or normalise with, and the true
/// length for comparisons. Lanes that did not overflow keep their bits: their divisor is 1 and
/// their lengths are `norm`. A lane with an infinite or NaN component stays non-finite.
#[inline(always)]
pub fn rescale_overflowed<T: Real>(v: &Vec3<T>, norm: T) -> Option<Rescaled<T>> {
    let over = norm.simd_eq(lit(f64::INFINITY));
    if over.none() {
        return None;
    }
    let largest =
        v.x.simd_abs()
            .simd_max(v.y.simd_abs())
            .simd_max(v.z.simd_abs());
    let divisor = select(over, largest, T::one());
    let scaled_norm = select(over, self::norm(&(v / divisor)), norm);
    Some(Rescaled {
        divisor,
        scaled_norm,
        norm: select(over, divisor * scaled_norm, norm),
    })
}

/// `0 x`: 0 for a finite `x`, NaN for an infinite or NaN one (lane-wise). Summing these over
/// many inputs tests them all finite with one comparison.
#[inline(always)]
pub fn zero_if_finite<T: Real>(x: T) -> T {
    x * T::zero()
}

/// `acc + 0 v_x + 0 v_y + 0 v_z`: stays 0 while `acc` is 0 and every component is finite, NaN
/// otherwise (see [`zero_if_finite`]).
#[inline(always)]
pub fn finite_probe<T: Real>(acc: T, v: &Vec3<T>) -> T {
    acc + (zero_if_finite(v.x) + zero_if_finite(v.y) + zero_if_finite(v.z))
}

/// Running sums of many `f64` values, four independent sums (value `i` of each added array
/// goes to sum `i % 4`: four short dependency chains, which the compiler may pack): a quick test
/// that a set of values is finite. The total is finite only if every value is (an infinity or
/// a NaN makes it infinite or NaN), so [`FiniteSums::all_finite`] never says yes to a
/// non-finite value; it says no to finite values whose sum overflows (beyond ~1.8e308), which
/// a caller treats as "not shown finite" and checks one by one.
#[derive(Clone, Copy, Debug, Default)]
pub struct FiniteSums([f64; 4]);

impl FiniteSums {
    /// Adds `values`, value `i` to sum `i % 4`.
    #[inline(always)]
    pub fn add<const N: usize>(&mut self, values: [f64; N]) {
        for (i, x) in values.into_iter().enumerate() {
            self.0[i % 4] += x;
        }
    }

    /// Adds the components of `v`.
    #[inline(always)]
    pub fn add_vec(&mut self, v: &Vec3<f64>) {
        self.add([v.x, v.y, v.z]);
    }

    /// True when the total is finite, hence every value added is.
    #[inline(always)]
    pub fn all_finite(&self) -> bool {
        let [a, b, c, d] = self.0;
        let total = (a + b) + (c + d);
        total.is_finite()
    }
}

#[cfg(test)]
mod tests {
    use super::FiniteSums;

    fn finite<const N: usize>(values: [f64; N]) -> bool {
        let mut sums = FiniteSums::default();
        sums.add(values);
        sums.all_finite()
    }

    /// Yes for finite values whatever their signs (zeros of either sign, subnormals, opposite
    /// values in one sum); no for any NaN or infinity in any of the four sums, and for finite
    /// values whose sum overflows (the documented false "no").
    #[test]
    fn finite_sums_say_yes_only_for_finite_values() {
        assert!(finite::<0>([]));
        assert!(finite([-0.0, 0.0, 5e-324, -5e-324]));
        assert!(finite([1e308, 2.0, 3.0, 4.0, -1e308]));
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            for at in 0..6 {
                let mut v = [1.0; 6];
                v[at] = bad;
                assert!(!finite(v), "{bad} at {at}");
            }
        }
        assert!(!finite([f64::INFINITY, 0.0, 0.0, 0.0, f64::NEG_INFINITY]));
        assert!(!finite([f64::MAX, 0.0, 0.0, 0.0, f64::MAX]));
        let mut sums = FiniteSums::default();
        sums.add_vec(&super::Vec3::new(1.0, f64::NAN, 2.0));
        assert!(!sums.all_finite());
    }
}
