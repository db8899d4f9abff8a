//! C entry points of the decomposition: `rsl_decompose`, `rsl_decompose_wall`, the inverse
//! maps `rsl_compose` / `rsl_compose_wall`, and the legacy measures.
#![allow(non_camel_case_types)]

use super::types::{
    rsl_decomposition, rsl_legacy_rolling, rsl_pair_velocities, rsl_sphere, rsl_wall,
    rsl_wall_velocities,
};
use super::{guard, input, optional_input, output};
use crate::decompose::{decompose_pair, decompose_wall, Parts, Sphere, Wall};
use crate::error::Error;
use crate::geometry::{check_finite_vec, BranchRule, GeometryOptions, RollingRadiusRule};
use crate::inverse::{compose_pair, compose_wall};
use crate::legacy::legacy_rolling;

/// Branch rule `midplane`: `l_k = R_k - delta/2` (default; objective sliding).
pub const RSL_BRANCH_MIDPLANE: i32 = 0;
/// Branch rule `radii`: `l_k = R_k` (the paper's eq. 1 approximation; LAMMPS' sliding).
pub const RSL_BRANCH_RADII: i32 = 1;
/// Rolling radius `l1 l2 / (l1 + l2)` (default; wall: `l1`).
pub const RSL_ROLLING_RADIUS_EXACT: i32 = 0;
/// Rolling radius `R_eff = R1 R2 / (R1 + R2)` (wall: `R1`).
pub const RSL_ROLLING_RADIUS_EFFECTIVE: i32 = 1;

/// Part bit: normal rate.
pub const RSL_PART_NORMAL_RATE: u32 = 1;
/// Part bit: sliding velocity.
pub const RSL_PART_SLIDING: u32 = 2;
/// Part bit: rolling velocity.
pub const RSL_PART_ROLLING: u32 = 4;
/// Part bit: twisting rate.
pub const RSL_PART_TWISTING: u32 = 8;
/// Part bit: rigid-body parts (contact velocity, tumbling, frame spin).
pub const RSL_PART_RIGID: u32 = 16;
/// Part bit: objective velocities s1, s2.
pub const RSL_PART_OBJECTIVE: u32 = 32;
/// Every part.
pub const RSL_PART_ALL: u32 = 63;

/// Options of a decomposition. Pass NULL for the defaults (midplane, exact rolling radius,
/// every part), or start from `rsl_decompose_options_default()`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct rsl_decompose_options {
    /// `RSL_BRANCH_MIDPLANE` or `RSL_BRANCH_RADII`.
    pub branch_rule: i32,
    /// `RSL_ROLLING_RADIUS_EXACT` or `RSL_ROLLING_RADIUS_EFFECTIVE`.
    pub rolling_radius_rule: i32,
    /// OR of `RSL_PART_*` bits: the parts to compute (the geometry is always computed); parts
    /// not asked for are not computed and are reported as 0.
    pub parts: u32,
}

impl Default for rsl_decompose_options {
    fn default() -> Self {
        rsl_decompose_options {
            branch_rule: RSL_BRANCH_MIDPLANE,
            rolling_radius_rule: RSL_ROLLING_RADIUS_EXACT,
            parts: RSL_PART_ALL,
        }
    }
}

/// Validates option codes into the core's options.
pub(crate) fn parse_options(
    o: Option<&rsl_decompose_options>,
) -> Result<(GeometryOptions, Parts), Error> {
    let o = o.copied().unwrap_or_default();
    let branch_rule = match o.branch_rule {
        RSL_BRANCH_MIDPLANE => BranchRule::Midplane,
        RSL_BRANCH_RADII => BranchRule::Radii,
        other => {
            return Err(Error::InvalidArgument(format!(
                "branch_rule {other} is not RSL_BRANCH_MIDPLANE (0) or RSL_BRANCH_RADII (1)"
            )))
        }
    };
    let rolling_radius = match o.rolling_radius_rule {
        RSL_ROLLING_RADIUS_EXACT => RollingRadiusRule::Exact,
        RSL_ROLLING_RADIUS_EFFECTIVE => RollingRadiusRule::Effective,
        other => {
            return Err(Error::InvalidArgument(format!(
                "rolling_radius_rule {other} is not RSL_ROLLING_RADIUS_EXACT (0) or \
                 RSL_ROLLING_RADIUS_EFFECTIVE (1)"
            )))
        }
    };
    if !Parts::is_valid_bits(o.parts) {
        return Err(Error::InvalidArgument(format!(
            "parts 0x{:x} has bits outside RSL_PART_ALL (0x3f)",
            o.parts
        )));
    }
    Ok((
        GeometryOptions {
            branch_rule,
            rolling_radius,
        },
        Parts(o.parts),
    ))
}

/// The default options: midplane branches, exact rolling radius, every part.
#[no_mangle]
pub extern "C" fn rsl_decompose_options_default() -> rsl_decompose_options {
    rsl_decompose_options::default()
}

/// Decomposes the relative motion of two spheres (body 1 relative to body 2, `n` from 1 to 2).
///
/// `body1`, `body2`: the spheres; `options`: NULL for the defaults; `out`: written only when
/// the call returns `RSL_OK`.
/// Errors: `RSL_ERR_NULL_POINTER`, `RSL_ERR_MISALIGNED`, `RSL_ERR_NON_FINITE`,
/// `RSL_ERR_INVALID_RADIUS`, `RSL_ERR_COINCIDENT_CENTRES`, `RSL_ERR_NONPOSITIVE_BRANCH`,
/// `RSL_ERR_INVALID_ARGUMENT` (unknown option code).
///
/// # Safety
/// Each non-NULL pointer must point to a valid object of its type for the whole call; `out`
/// must not overlap the inputs.
#[no_mangle]
pub unsafe extern "C" fn rsl_decompose(
    body1: *const rsl_sphere,
    body2: *const rsl_sphere,
    options: *const rsl_decompose_options,
    out: *mut rsl_decomposition,
) -> i32 {
    guard(|| {
        // SAFETY: the pointer contract is the caller's (documented above); NULL and alignment
        // are checked by the helpers.
        let (b1, b2, opts, out) = unsafe {
            (
                input(body1, "body1")?,
                input(body2, "body2")?,
                optional_input(options, "options")?,
                output(out, "out")?,
            )
        };
        let (geometry, parts) = parse_options(opts)?;
        let d = decompose_pair(&Sphere::from(b1), &Sphere::from(b2), geometry, parts)?;
        *out = rsl_decomposition::from(&d);
        Ok(())
    })
}

/// Decomposes the motion of a sphere (body 1) relative to a flat wall (body 2); `n` points
/// into the wall. The wall has curvature 0: `R_r = l1`, `distance = branch2 = +inf`.
///
/// Errors as `rsl_decompose`, plus `RSL_ERR_INVALID_ARGUMENT` for a zero wall normal and
/// `RSL_ERR_NONPOSITIVE_BRANCH` when the centre is more than one radius behind the wall.
///
/// # Safety
/// As `rsl_decompose`.
#[no_mangle]
pub unsafe extern "C" fn rsl_decompose_wall(
    sphere: *const rsl_sphere,
    wall: *const rsl_wall,
    options: *const rsl_decompose_options,
    out: *mut rsl_decomposition,
) -> i32 {
    guard(|| {
        // SAFETY: as in rsl_decompose.
        let (s, w, opts, out) = unsafe {
            (
                input(sphere, "sphere")?,
                input(wall, "wall")?,
                optional_input(options, "options")?,
                output(out, "out")?,
            )
        };
        let (geometry, parts) = parse_options(opts)?;
        let d = decompose_wall(&Sphere::from(s), &Wall::from(w), geometry, parts)?;
        *out = rsl_decomposition::from(&d);
        Ok(())
    })
}

/// Checks a decomposition handed back by the caller before inverting it. Every field must be
/// finite (a wall's `distance` and `branch2` may be +inf, as `rsl_decompose_wall` gives them);
/// a non-finite one is named in the error.
fn check_for_inverse(d: &rsl_decomposition, wall: bool) -> Result<(), Error> {
    use super::types::rsl_vec3;
    let vecs: [(&rsl_vec3, &'static str); 8] = [
        (&d.normal, "decomposition.normal"),
        (&d.contact_point, "decomposition.contact_point"),
        (&d.sliding_velocity, "decomposition.sliding_velocity"),
        (&d.rolling_velocity, "decomposition.rolling_velocity"),
        (&d.contact_velocity, "decomposition.contact_velocity"),
        (&d.tumbling, "decomposition.tumbling"),
        (&d.objective_velocity1, "decomposition.objective_velocity1"),
        (&d.objective_velocity2, "decomposition.objective_velocity2"),
    ];
    for (v, what) in vecs {
        if !(v.x.is_finite() && v.y.is_finite() && v.z.is_finite()) {
            return Err(Error::NonFinite(what));
        }
    }
    let scalars: [(f64, &'static str); 6] = [
        (d.overlap, "decomposition.overlap"),
        (d.branch1, "decomposition.branch1"),
        (d.rolling_radius, "decomposition.rolling_radius"),
        (d.normal_rate, "decomposition.normal_rate"),
        (d.twisting_rate, "decomposition.twisting_rate"),
        (d.frame_spin, "decomposition.frame_spin"),
    ];
    for (x, what) in scalars {
        if !x.is_finite() {
            return Err(Error::NonFinite(what));
        }
    }
    for (x, what) in [
        (d.distance, "decomposition.distance"),
        (d.branch2, "decomposition.branch2"),
    ] {
        if !(x.is_finite() || (wall && x == f64::INFINITY)) {
            return Err(Error::NonFinite(what));
        }
    }
    let len = (d.normal.x * d.normal.x + d.normal.y * d.normal.y + d.normal.z * d.normal.z).sqrt();
    if (len - 1.0).abs() > 1e-10 {
        return Err(Error::InvalidArgument(format!(
            "decomposition.normal must be unit (|n| = {len})"
        )));
    }
    if !(d.branch1 > 0.0 && d.branch2 > 0.0 && d.rolling_radius > 0.0 && d.distance > 0.0) {
        return Err(Error::NonPositiveBranch(
            "l1, l2, R_r and d must be > 0 to invert",
        ));
    }
    Ok(())
}

fn branch_rate_factor(options: &GeometryOptions) -> f64 {
    match options.branch_rule {
        BranchRule::Midplane => 0.5,
        BranchRule::Radii => 0.0,
    }
}

/// Inverse map for a sphere pair: recovers `(v1, w1, v2, w2)` from a decomposition computed
/// with every part and the same `options` (NULL for the defaults; only the branch rule matters).
///
/// # Safety
/// As `rsl_decompose`.
#[no_mangle]
pub unsafe extern "C" fn rsl_compose(
    decomposition: *const rsl_decomposition,
    options: *const rsl_decompose_options,
    out: *mut rsl_pair_velocities,
) -> i32 {
    guard(|| {
        // SAFETY: as in rsl_decompose.
        let (d, opts, out) = unsafe {
            (
                input(decomposition, "decomposition")?,
                optional_input(options, "options")?,
                output(out, "out")?,
            )
        };
        let (geometry, _) = parse_options(opts)?;
        check_for_inverse(d, false)?;
        let v = compose_pair(&d.to_core(branch_rate_factor(&geometry)));
        for x in [
            v.velocity1,
            v.angular_velocity1,
            v.velocity2,
            v.angular_velocity2,
        ] {
            check_finite_vec(&x, "result overflowed (inputs too large)")?;
        }
        *out = rsl_pair_velocities {
            velocity1: v.velocity1.into(),
            angular_velocity1: v.angular_velocity1.into(),
            velocity2: v.velocity2.into(),
            angular_velocity2: v.angular_velocity2.into(),
        };
        Ok(())
    })
}

/// Inverse map for a sphere-wall contact: recovers the sphere's `(v1, w1)`, the wall's angular
/// velocity and the wall's material velocity at the contact point.
///
/// # Safety
/// As `rsl_decompose`.
#[no_mangle]
pub unsafe extern "C" fn rsl_compose_wall(
    decomposition: *const rsl_decomposition,
    options: *const rsl_decompose_options,
    out: *mut rsl_wall_velocities,
) -> i32 {
    guard(|| {
        // SAFETY: as in rsl_decompose.
        let (d, opts, out) = unsafe {
            (
                input(decomposition, "decomposition")?,
                optional_input(options, "options")?,
                output(out, "out")?,
            )
        };
        let (geometry, _) = parse_options(opts)?;
        check_for_inverse(d, true)?;
        let v = compose_wall(&d.to_core(branch_rate_factor(&geometry)));
        for x in [
            v.velocity1,
            v.angular_velocity1,
            v.wall_angular_velocity,
            v.wall_contact_velocity,
        ] {
            check_finite_vec(&x, "result overflowed (inputs too large)")?;
        }
        *out = rsl_wall_velocities {
            velocity1: v.velocity1.into(),
            angular_velocity1: v.angular_velocity1.into(),
            wall_angular_velocity: v.wall_angular_velocity.into(),
            wall_contact_velocity: v.wall_contact_velocity.into(),
        };
        Ok(())
    })
}

/// LEGACY rolling measures of a sphere pair (Kuhn-Bagi mean travel, Iwashita-Oda), for
/// comparing with older codes. Not objective rolling; see the fields of `rsl_legacy_rolling`.
///
/// # Safety
/// As `rsl_decompose`.
#[no_mangle]
pub unsafe extern "C" fn rsl_decompose_legacy(
    body1: *const rsl_sphere,
    body2: *const rsl_sphere,
    options: *const rsl_decompose_options,
    out: *mut rsl_legacy_rolling,
) -> i32 {
    guard(|| {
        // SAFETY: as in rsl_decompose.
        let (b1, b2, opts, out) = unsafe {
            (
                input(body1, "body1")?,
                input(body2, "body2")?,
                optional_input(options, "options")?,
                output(out, "out")?,
            )
        };
        let (geometry, _) = parse_options(opts)?;
        let l = legacy_rolling(&Sphere::from(b1), &Sphere::from(b2), geometry)?;
        *out = rsl_legacy_rolling {
            kuhn_bagi: l.kuhn_bagi.into(),
            iwashita_oda: l.iwashita_oda.into(),
        };
        Ok(())
    })
}
