//! Contact geometry of kinematics.md section 2: normal, distance, overlap, branch lengths,
//! rolling radius and contact point, for a sphere pair and for a sphere against a flat wall.
//!
//! Conventions: body 1 is the first sphere; body 2 is the second sphere or the wall. The unit
//! normal `n` points **from body 1 to body 2** (into the wall). Lengths are in the caller's unit.

use crate::error::Error;
use crate::scalar::{
    dot, finite_probe, lit, norm, norm_squared, select, select3, zero_if_finite, Real, Vec3,
};
use nalgebra::RealField;
use simba::simd::SimdBool;

/// Where the two branch vectors end (kinematics.md section 2, a **convention**).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum BranchRule {
    /// `l_k = R_k - delta/2`: both branches end at the same contact point, which makes the
    /// sliding velocity objective. The default; the torque arms of LAMMPS and YADE.
    #[default]
    Midplane,
    /// `l_k = R_k`: the paper's eq. (1) approximation. Not objective when `delta != 0`.
    Radii,
}

/// Which rolling radius `R_r` scales the rolling velocity (a **convention**).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum RollingRadiusRule {
    /// `R_r = l1 l2 / (l1 + l2)` (wall: `l1`). The default.
    #[default]
    Exact,
    /// `R_eff = R1 R2 / (R1 + R2)` (wall: `R1`), as in LAMMPS and the paper; differs by O(delta/R).
    Effective,
}

/// The geometric options of a decomposition.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct GeometryOptions {
    /// Branch rule; default [`BranchRule::Midplane`].
    pub branch_rule: BranchRule,
    /// Rolling radius rule; default [`RollingRadiusRule::Exact`].
    pub rolling_radius: RollingRadiusRule,
}

/// Geometry of one contact. For a wall (curvature 0) `distance` and `branch2` are `+inf`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactGeometry<T: Real> {
    /// Unit normal from body 1 to body 2 (into the wall).
    pub normal: Vec3<T>,
    /// Centre distance `d = |r2 - r1|` (`+inf` for a wall).
    pub distance: T,
    /// Overlap `delta = R1 + R2 - d` (wall: `R1 - h`, `h` the centre's height above the wall);
    /// positive in contact.
    pub overlap: T,
    /// Branch length `l1` of body 1 (centre to contact point along `n`).
    pub branch1: T,
    /// Branch length `l2` of body 2 (`+inf` for a wall).
    pub branch2: T,
    /// Rolling radius `R_r` (see [`RollingRadiusRule`]).
    pub rolling_radius: T,
    /// Contact point `r_c = r1 + l1 n`.
    pub contact_point: Vec3<T>,
    /// `d l1/dt = branch_rate_factor * ddot`: `1/2` under the midplane rule, `0` under `radii`.
    pub branch_rate_factor: T,
}

/// Geometry of a sphere pair, without validation: the formula only, for every [`Real`] type
/// (scalar and SIMD lanes). Use [`pair_geometry`] for checked scalar input.
///
/// `r1`, `r2`: centres; `radius1`, `radius2`: radii (> 0).
#[inline(always)]
pub fn pair_geometry_unchecked<T: Real>(
    r1: &Vec3<T>,
    r2: &Vec3<T>,
    radius1: T,
    radius2: T,
    options: GeometryOptions,
) -> ContactGeometry<T> {
    let branch = r2 - r1;
    let distance = norm(&branch);
    // One division, as LAMMPS and LIGGGHTS do (`rinv = 1/r`), not three.
    let normal = branch * (T::one() / distance);
    let overlap = radius1 + radius2 - distance;
    let (branch1, branch2, branch_rate_factor) = match options.branch_rule {
        BranchRule::Midplane => {
            // l1 = R1 - delta/2 = (d + R1 - R2)/2, written so that l1 + l2 = d to rounding.
            let half = lit::<T>(0.5);
            let l1 = (distance + radius1 - radius2) * half;
            (l1, distance - l1, half)
        }
        BranchRule::Radii => (radius1, radius2, lit(0.0)),
    };
    // The rule picks the two lengths, then one division: the SIMD batch kernels take the rule
    // from the model at run time, and with a division in each arm LLVM computed both.
    let (length1, length2) = match options.rolling_radius {
        RollingRadiusRule::Exact => (branch1, branch2),
        RollingRadiusRule::Effective => (radius1, radius2),
    };
    let rolling_radius = length1 * length2 / (length1 + length2);
    ContactGeometry {
        normal,
        distance,
        overlap,
        branch1,
        branch2,
        rolling_radius,
        contact_point: r1 + normal * branch1,
        branch_rate_factor,
    }
}

/// Geometry of a sphere against a flat wall, without validation.
///
/// `r1`, `radius1`: the sphere; `wall_point`: any point of the wall surface; `wall_normal`:
/// **unit** outward normal of the wall (pointing from the wall towards the sphere's side).
/// The contact normal is `n = -wall_normal`.
#[inline(always)]
pub fn wall_geometry_unchecked<T: Real>(
    r1: &Vec3<T>,
    radius1: T,
    wall_point: &Vec3<T>,
    wall_normal: &Vec3<T>,
    options: GeometryOptions,
) -> ContactGeometry<T> {
    // Component by component: nalgebra's `Neg` of a vector of lanes was left out of line in a
    // SIMD kernel (scripts/check_kernels.sh); the same negations.
    let normal = Vec3::new(-wall_normal.x, -wall_normal.y, -wall_normal.z);
    let height = dot(&(r1 - wall_point), wall_normal);
    let overlap = radius1 - height;
    let infinity = lit::<T>(f64::INFINITY);
    let (branch1, branch_rate_factor) = match options.branch_rule {
        // The limit R2 -> inf of l1 = R1 - delta/2.
        BranchRule::Midplane => (radius1 - overlap * lit(0.5), lit(0.5)),
        BranchRule::Radii => (radius1, lit(0.0)),
    };
    let rolling_radius = match options.rolling_radius {
        RollingRadiusRule::Exact => branch1,
        RollingRadiusRule::Effective => radius1,
    };
    ContactGeometry {
        normal,
        distance: infinity,
        overlap,
        branch1,
        branch2: infinity,
        rolling_radius,
        contact_point: r1 + normal * branch1,
        branch_rate_factor,
    }
}

/// Checks that every component of `v` is finite.
pub(crate) fn check_finite_vec<T: RealField + Copy>(
    v: &Vec3<T>,
    what: &'static str,
) -> Result<(), Error> {
    if v.iter().all(|x| x.is_finite()) {
        Ok(())
    } else {
        Err(Error::NonFinite(what))
    }
}

pub(crate) fn check_radius<T: RealField + Copy>(r: T, what: &'static str) -> Result<(), Error> {
    if !r.is_finite() {
        return Err(Error::NonFinite(what));
    }
    if r <= T::zero() {
        return Err(Error::InvalidRadius(what));
    }
    Ok(())
}

/// `x > 0`, false for NaN (so NaN is refused wherever positivity is required).
fn is_positive<T: RealField + Copy>(x: T) -> bool {
    x > T::zero()
}

fn check_branches<T: RealField + Copy>(g: &ContactGeometry<T>) -> Result<(), Error> {
    if !is_positive(g.branch1) {
        return Err(Error::NonPositiveBranch("l1"));
    }
    if !is_positive(g.branch2) {
        return Err(Error::NonPositiveBranch("l2"));
    }
    Ok(())
}

/// True when `n` has unit length to rounding. It fails only when the length it was divided by
/// was computed inaccurately: a vector below `sqrt(MIN_POSITIVE)` (~1.5e-154 in f64) whose
/// squared components underflow into subnormal numbers (found by fuzzing: centres 1e-160 apart
/// gave |n| = 1.3).
fn is_unit<T: RealField + Copy>(n: &Vec3<T>) -> bool {
    (norm_squared(n) - T::one()).abs() <= lit::<T>(16.0) * T::default_epsilon()
}

/// Geometry of a sphere pair with every check of kinematics.md section 7: finite input,
/// radii > 0, `d >= eps (R1 + R2)`, a normal of unit length (`d` above ~1.5e-154 in f64),
/// `l1, l2 > 0`.
pub fn pair_geometry<T: RealField + Copy>(
    r1: &Vec3<T>,
    r2: &Vec3<T>,
    radius1: T,
    radius2: T,
    options: GeometryOptions,
) -> Result<ContactGeometry<T>, Error> {
    check_finite_vec(r1, "position of body 1")?;
    check_finite_vec(r2, "position of body 2")?;
    check_radius(radius1, "radius of body 1")?;
    check_radius(radius2, "radius of body 2")?;
    let d = norm(&(r2 - r1));
    if !d.is_finite() {
        return Err(Error::NonFinite("centre distance (overflow)"));
    }
    if d < T::default_epsilon() * (radius1 + radius2) {
        return Err(Error::CoincidentCentres);
    }
    let g = pair_geometry_unchecked(r1, r2, radius1, radius2, options);
    if !is_unit(&g.normal) {
        return Err(Error::InvalidArgument(
            "centre distance too small for a unit normal (its square underflows, below \
             ~1.5e-154): rescale the lengths"
                .to_string(),
        ));
    }
    check_branches(&g)?;
    Ok(g)
}

/// Lane-wise, whether [`pair_geometry`] would accept these inputs and their geometry `g`
/// (from [`pair_geometry_unchecked`]): finite centres and radii, radii > 0,
/// `d >= eps (R1 + R2)`, a normal of unit length to rounding, `l1, l2 > 0`. The batch kernels
/// and the per-contact fast path test validity with it without branching per check.
#[inline(always)]
pub fn pair_geometry_valid<T: Real>(
    r1: &Vec3<T>,
    r2: &Vec3<T>,
    radius1: T,
    radius2: T,
    g: &ContactGeometry<T>,
) -> T::SimdBool {
    let mut acc = zero_if_finite(radius1) + zero_if_finite(radius2) + zero_if_finite(g.distance);
    acc = finite_probe(acc, r1);
    acc = finite_probe(acc, r2);
    acc.simd_eq(T::zero()) & pair_geometry_in_range(radius1, radius2, g)
}

/// [`pair_geometry_valid`] without its finiteness test (for a caller that has shown the
/// centres, the radii and `g.distance` finite by other means): radii > 0,
/// `d >= eps (R1 + R2)`, a normal of unit length to rounding, `l1, l2 > 0`.
#[inline(always)]
pub fn pair_geometry_in_range<T: Real>(
    radius1: T,
    radius2: T,
    g: &ContactGeometry<T>,
) -> T::SimdBool {
    let zero = T::zero();
    let eps = T::simd_default_epsilon();
    radius1.simd_gt(zero)
        & radius2.simd_gt(zero)
        & g.distance.simd_ge(eps * (radius1 + radius2))
        // A distance whose square underflows (below ~1.5e-154) gives a normal that is not
        // unit: refused (see `is_unit`).
        & (norm_squared(&g.normal) - T::one())
            .simd_abs()
            .simd_le(lit::<T>(16.0) * eps)
        & g.branch1.simd_gt(zero)
        & g.branch2.simd_gt(zero)
}

/// The checked normalisation (`unit_vector`) lane-wise, for the batch kernels of sphere-wall
/// contacts: the unit vector of each lane with the bits the checked normalisation gives it (the
/// plain `v / |v|` where that is accurate, else `v` divided by its largest absolute component
/// first), and the lanes where `v` can be normalised (finite and non-zero; the others hold
/// whatever the formulas give). The rescaled form is computed only when some lane needs it.
#[inline(always)]
pub fn unit_vector_lanes<T: Real>(v: &Vec3<T>) -> (Vec3<T>, T::SimdBool) {
    let zero = T::zero();
    let len = norm(v);
    let unit = v / len;
    let accurate = len.simd_gt(zero)
        & len.simd_lt(lit(f64::INFINITY))
        & (norm_squared(&unit) - T::one())
            .simd_abs()
            .simd_le(lit::<T>(16.0) * T::simd_default_epsilon());
    if accurate.all() {
        return (unit, accurate);
    }
    let finite = finite_probe(zero, v).simd_eq(zero);
    let largest =
        v.x.simd_abs()
            .simd_max(v.y.simd_abs())
            .simd_max(v.z.simd_abs());
    let nonzero = largest.simd_gt(zero);
    let scaled = v / select(nonzero, largest, T::one());
    let rescaled = scaled / norm(&scaled);
    (
        select3(accurate, &unit, &rescaled),
        finite & (accurate | nonzero),
    )
}

/// The lanes whose sphere-wall geometry the checked step accepts, as far as the geometry
/// shows it, for a wall normal `normalisable` ([`unit_vector_lanes`]): finite centre, radius
/// and wall point, radius > 0, finite overlap, `l1 > 0`.
#[inline(always)]
pub fn wall_geometry_valid<T: Real>(
    r1: &Vec3<T>,
    radius1: T,
    wall_point: &Vec3<T>,
    normalisable: T::SimdBool,
    g: &ContactGeometry<T>,
) -> T::SimdBool {
    let zero = T::zero();
    let mut acc = zero_if_finite(radius1) + zero_if_finite(g.overlap);
    acc = finite_probe(acc, r1);
    acc = finite_probe(acc, wall_point);
    acc.simd_eq(zero) & normalisable & radius1.simd_gt(zero) & g.branch1.simd_gt(zero)
}

/// `v / |v|` for a finite `v` of any non-zero length, `None` for the zero vector. The plain
/// `v / |v|` where it is accurate (its bits are kept there); where `|v|^2` overflows (`|v|`
/// above ~1.3e154 in f64) or underflows into subnormal numbers (below ~1.5e-154: `|v|` is
/// then inaccurate or 0), `v` is first divided by its largest absolute component, which
/// brings the length to between 1 and `sqrt 3`.
fn unit_vector<T: RealField + Copy>(v: &Vec3<T>) -> Option<Vec3<T>> {
    let (unit, accurate) = plain_unit_vector(v);
    if accurate {
        return Some(unit);
    }
    let largest = v.x.abs().max(v.y.abs()).max(v.z.abs());
    if !is_positive(largest) {
        return None;
    }
    let scaled = v / largest;
    Some(scaled / norm(&scaled))
}

/// The plain `v / |v|` of the checked wall geometry's normalisation ([`wall_geometry`]) and
/// whether it is that normalisation's result: `|v|` finite and > 0 and the quotient of unit
/// length to rounding (false for a NaN anywhere). The per-contact fast path of a wall takes the
/// quotient only when this says so, and so gets the checked path's bits.
#[inline(always)]
pub fn plain_unit_vector<T: RealField + Copy>(v: &Vec3<T>) -> (Vec3<T>, bool) {
    let len = norm(v);
    let unit = v / len;
    let accurate = is_positive(len) & len.is_finite() & is_unit(&unit);
    (unit, accurate)
}

/// Geometry of a sphere against a flat wall with every check: finite input, radius > 0, a
/// wall normal of any finite non-zero length (normalised here, overflow- and underflow-safe,
/// so it need not be unit), `l1 > 0`.
///
/// Returns the geometry and the unit wall normal.
pub fn wall_geometry<T: RealField + Copy>(
    r1: &Vec3<T>,
    radius1: T,
    wall_point: &Vec3<T>,
    wall_normal: &Vec3<T>,
    options: GeometryOptions,
) -> Result<(ContactGeometry<T>, Vec3<T>), Error> {
    check_finite_vec(r1, "position of the sphere")?;
    check_radius(radius1, "radius of the sphere")?;
    check_finite_vec(wall_point, "wall point")?;
    check_finite_vec(wall_normal, "wall normal")?;
    let unit = unit_vector(wall_normal).ok_or_else(|| {
        Error::InvalidArgument("wall normal must be a non-zero vector".to_string())
    })?;
    let g = wall_geometry_unchecked(r1, radius1, wall_point, &unit, options);
    if !g.overlap.is_finite() {
        return Err(Error::NonFinite("wall overlap (overflow)"));
    }
    if !is_positive(g.branch1) {
        return Err(Error::NonPositiveBranch("l1"));
    }
    Ok((g, unit))
}
