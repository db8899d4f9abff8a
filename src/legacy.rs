//! Legacy rolling definitions, **for comparison only** (kinematics.md section 4). They show
//! what older codes computed; neither is the objective rolling velocity of this library.

use crate::decompose::{decompose_pair, Parts, Sphere};
use crate::error::Error;
use crate::geometry::GeometryOptions;
use crate::scalar::{cross, lit, tangential, Real, Vec3};
use nalgebra::RealField;

/// Two legacy rolling measures of one sphere pair (body 1 relative to body 2).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LegacyRolling<T: Real> {
    /// LEGACY. Kuhn & Bagi's mean contact travel `1/2 (s1 + s2)_t`: objective, but equals
    /// `v_r + (R1 - R2)/(2 (R1 + R2)) v_s`, so it reports rolling during pure sliding of
    /// unequal spheres.
    pub kuhn_bagi: Vec3<T>,
    /// LEGACY. Iwashita & Oda's `1/2 (R1 w1 - R2 w2) x n`: not objective (changes by
    /// `1/2 (R1 - R2) W x n` under a superposed spin `W`).
    pub iwashita_oda: Vec3<T>,
}

/// Computes both legacy rolling measures of a sphere pair, with the checks of
/// [`decompose_pair`]. `options` sets the branch rule used for `s1`, `s2`.
pub fn legacy_rolling<T: RealField + Copy>(
    body1: &Sphere<T>,
    body2: &Sphere<T>,
    options: GeometryOptions,
) -> Result<LegacyRolling<T>, Error> {
    let d = decompose_pair(body1, body2, options, Parts::OBJECTIVE)?;
    let n = d.geometry.normal;
    let half = lit::<T>(0.5);
    let mean = (d.objective_velocity1 + d.objective_velocity2) * half;
    let io = cross(
        &(body1.angular_velocity * body1.radius - body2.angular_velocity * body2.radius),
        &n,
    ) * half;
    let out = LegacyRolling {
        kuhn_bagi: tangential(&mean, &n),
        iwashita_oda: io,
    };
    // R_k w_k can overflow where the decomposition itself did not (found by fuzzing).
    if !(out.kuhn_bagi.iter().all(|x| x.is_finite())
        && out.iwashita_oda.iter().all(|x| x.is_finite()))
    {
        return Err(Error::NonFinite("result overflowed (inputs too large)"));
    }
    Ok(out)
}
