//! The objective decomposition of kinematics.md section 3: the relative motion of body 1 with
//! respect to body 2 split into normal rate, sliding, rolling and twisting, plus the rigid-body
//! parts of the pair (contact velocity, tumbling, frame spin) and the objective velocities.
//!
//! Sign conventions: `n` from body 1 to body 2; every relative rate is body 1 relative to
//! body 2. One generic implementation serves scalars and SIMD lanes ([`Real`]).

use crate::error::Error;
use crate::geometry::{
    check_finite_vec, pair_geometry, pair_geometry_unchecked, wall_geometry,
    wall_geometry_unchecked, ContactGeometry, GeometryOptions,
};
use crate::scalar::{cross, dot, tangential, Real, Vec3};
use nalgebra::RealField;

/// Which parts of the decomposition to compute (bit set). The geometry is always computed;
/// a part not asked for is not computed and is reported as zero.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Parts(pub u32);

impl Parts {
    /// Normal rate `ddot = n . (v2 - v1)`.
    pub const NORMAL_RATE: Parts = Parts(1);
    /// Sliding velocity `v_s`.
    pub const SLIDING: Parts = Parts(2);
    /// Rolling velocity `v_r`.
    pub const ROLLING: Parts = Parts(4);
    /// Twisting rate `w_tw`.
    pub const TWISTING: Parts = Parts(8);
    /// Rigid-body parts: contact velocity `v_c`, tumbling `w_rbr`, frame spin `w_rbs`.
    pub const RIGID: Parts = Parts(16);
    /// Objective velocities `s1`, `s2` (needs the rigid parts internally).
    pub const OBJECTIVE: Parts = Parts(32);
    /// Everything.
    pub const ALL: Parts = Parts(63);

    /// True when every bit of `other` is set in `self`.
    #[inline(always)]
    pub fn contains(self, other: Parts) -> bool {
        self.0 & other.0 == other.0
    }

    /// True when `bits` names only known parts.
    pub fn is_valid_bits(bits: u32) -> bool {
        bits & !Parts::ALL.0 == 0
    }
}

impl std::ops::BitOr for Parts {
    type Output = Parts;
    fn bitor(self, rhs: Parts) -> Parts {
        Parts(self.0 | rhs.0)
    }
}

/// Kinematic state of one sphere: centre, velocity, angular velocity, radius.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sphere<T: Real> {
    /// Centre position.
    pub position: Vec3<T>,
    /// Velocity of the centre.
    pub velocity: Vec3<T>,
    /// Angular velocity (rad per unit time).
    pub angular_velocity: Vec3<T>,
    /// Radius (> 0).
    pub radius: T,
}

/// A flat wall moving rigidly: body 2 of a sphere-wall contact.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Wall<T: Real> {
    /// Any point of the wall surface (the reference point of its rigid motion).
    pub point: Vec3<T>,
    /// Outward normal, from the wall towards the sphere's side. The checked entry points
    /// normalise it; the unchecked kernels require it unit.
    pub normal: Vec3<T>,
    /// Velocity of the material point of the wall at `point`.
    pub velocity: Vec3<T>,
    /// Angular velocity of the wall.
    pub angular_velocity: Vec3<T>,
}

/// The decomposition of one contact. Fields of parts not asked for are zero.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Decomposition<T: Real> {
    /// Geometry (always computed).
    pub geometry: ContactGeometry<T>,
    /// `ddot = n . (v2 - v1)`: separation rate; the overlap rate is `-ddot`.
    pub normal_rate: T,
    /// Sliding velocity `v_s = (v1c - v2c)_t` of body 1 relative to body 2 (tangential).
    pub sliding_velocity: Vec3<T>,
    /// Rolling velocity `v_r = R_r (w1 - w2) x n` (tangential).
    pub rolling_velocity: Vec3<T>,
    /// Twisting rate `w_tw = (w1 - w2) . n` (rad per unit time, about `n`).
    pub twisting_rate: T,
    /// Contact velocity `v_c = d r_c / dt` (rigid translation of the pair).
    pub contact_velocity: Vec3<T>,
    /// Tumbling `w_rbr = n x (v2 - v1) / d` (wall: the wall's tangential angular velocity).
    pub tumbling: Vec3<T>,
    /// Frame spin `w_rbs = (w1 + w2) . n / 2` (scalar about `n`).
    pub frame_spin: T,
    /// Objective velocity of body 1, `s1 = v1c - v_c`.
    pub objective_velocity1: Vec3<T>,
    /// Objective velocity of body 2, `s2 = v2c - v_c`.
    pub objective_velocity2: Vec3<T>,
}

/// What the two kinds of contact share once body 2's motion near the contact is known.
struct Relative<T: Real> {
    v1: Vec3<T>,
    w1: Vec3<T>,
    w2: Vec3<T>,
    /// Material velocity of body 2 at the contact point (needed for s2 only).
    material2: Option<Vec3<T>>,
}

#[inline(always)]
fn finish<T: Real>(
    geometry: ContactGeometry<T>,
    rel: Relative<T>,
    normal_rate: T,
    sliding_velocity: Vec3<T>,
    tumbling: Vec3<T>,
    parts: Parts,
) -> Decomposition<T> {
    let n = geometry.normal;
    let zero = T::zero();
    let zero3 = Vec3::<T>::zeros();
    let need_rigid = parts.contains(Parts::RIGID) || parts.contains(Parts::OBJECTIVE);
    let mut out = Decomposition {
        geometry,
        normal_rate: zero,
        sliding_velocity: zero3,
        rolling_velocity: zero3,
        twisting_rate: zero,
        contact_velocity: zero3,
        tumbling: zero3,
        frame_spin: zero,
        objective_velocity1: zero3,
        objective_velocity2: zero3,
    };
    if parts.contains(Parts::NORMAL_RATE) {
        out.normal_rate = normal_rate;
    }
    if parts.contains(Parts::SLIDING) {
        out.sliding_velocity = sliding_velocity;
    }
    if parts.contains(Parts::ROLLING) || parts.contains(Parts::TWISTING) {
        // Form w1 - w2 first (kinematics.md section 7).
        let dw = rel.w1 - rel.w2;
        if parts.contains(Parts::ROLLING) {
            out.rolling_velocity = cross(&dw, &n) * geometry.rolling_radius;
        }
        if parts.contains(Parts::TWISTING) {
            out.twisting_rate = dot(&dw, &n);
        }
    }
    if need_rigid {
        let spin = dot(&(rel.w1 + rel.w2), &n) * crate::scalar::lit(0.5);
        let contact_velocity = rel.v1
            + n * (geometry.branch_rate_factor * normal_rate)
            + cross(&tumbling, &n) * geometry.branch1;
        if parts.contains(Parts::RIGID) {
            out.contact_velocity = contact_velocity;
            out.tumbling = tumbling;
            out.frame_spin = spin;
        }
        if parts.contains(Parts::OBJECTIVE) {
            let material1 = rel.v1 + cross(&rel.w1, &n) * geometry.branch1;
            out.objective_velocity1 = material1 - contact_velocity;
            if let Some(material2) = rel.material2 {
                out.objective_velocity2 = material2 - contact_velocity;
            }
        }
    }
    out
}

/// Decomposes the relative motion of two spheres, without input checks (every [`Real`] type,
/// SIMD lanes included). Inputs must satisfy what [`decompose_pair`] checks.
#[inline(always)]
pub fn decompose_pair_unchecked<T: Real>(
    body1: &Sphere<T>,
    body2: &Sphere<T>,
    options: GeometryOptions,
    parts: Parts,
) -> Decomposition<T> {
    let g = pair_geometry_unchecked(
        &body1.position,
        &body2.position,
        body1.radius,
        body2.radius,
        options,
    );
    decompose_pair_in(g, body1, body2, parts)
}

/// Decomposes the relative motion of two spheres for a geometry already computed from the same
/// two bodies (for example in higher precision than `T`, or once for several uses). The rates
/// use the bodies' velocities and angular velocities only; their positions and radii are read
/// through `geometry`. Same formulas as [`decompose_pair_unchecked`], which calls this.
#[inline(always)]
pub fn decompose_pair_with_geometry<T: Real>(
    geometry: ContactGeometry<T>,
    body1: &Sphere<T>,
    body2: &Sphere<T>,
    parts: Parts,
) -> Decomposition<T> {
    decompose_pair_in(geometry, body1, body2, parts)
}

/// The sphere-pair rates for a geometry already computed from the same two bodies.
#[inline(always)]
fn decompose_pair_in<T: Real>(
    g: ContactGeometry<T>,
    body1: &Sphere<T>,
    body2: &Sphere<T>,
    parts: Parts,
) -> Decomposition<T> {
    let n = g.normal;
    let dv = body2.velocity - body1.velocity;
    let normal_rate = dot(&dv, &n);
    let need_rigid = parts.contains(Parts::RIGID) || parts.contains(Parts::OBJECTIVE);
    let sliding = if parts.contains(Parts::SLIDING) {
        // v_s = -(dv)_t + (l1 w1 + l2 w2) x n; the cross product is tangential by construction.
        let arms = body1.angular_velocity * g.branch1 + body2.angular_velocity * g.branch2;
        cross(&arms, &n) - tangential(&dv, &n)
    } else {
        Vec3::zeros()
    };
    let tumbling = if need_rigid {
        cross(&n, &dv) / g.distance
    } else {
        Vec3::zeros()
    };
    let material2 = if parts.contains(Parts::OBJECTIVE) {
        Some(body2.velocity - cross(&body2.angular_velocity, &n) * g.branch2)
    } else {
        None
    };
    let rel = Relative {
        v1: body1.velocity,
        w1: body1.angular_velocity,
        w2: body2.angular_velocity,
        material2,
    };
    finish(g, rel, normal_rate, sliding, tumbling, parts)
}

/// Decomposes the motion of a sphere (body 1) relative to a flat wall (body 2), without input
/// checks; `wall.normal` must be unit. The wall is the limit of a sphere of infinite radius:
/// `R_r = l1`, tumbling is the wall's tangential angular velocity.
#[inline(always)]
pub fn decompose_wall_unchecked<T: Real>(
    sphere: &Sphere<T>,
    wall: &Wall<T>,
    options: GeometryOptions,
    parts: Parts,
) -> Decomposition<T> {
    let g = wall_geometry_unchecked(
        &sphere.position,
        sphere.radius,
        &wall.point,
        &wall.normal,
        options,
    );
    decompose_wall_in(g, sphere, wall, parts)
}

/// Decomposes the motion of a sphere relative to a flat wall for a geometry already computed
/// from the same sphere and wall (see [`decompose_pair_with_geometry`]).
#[inline(always)]
pub fn decompose_wall_with_geometry<T: Real>(
    geometry: ContactGeometry<T>,
    sphere: &Sphere<T>,
    wall: &Wall<T>,
    parts: Parts,
) -> Decomposition<T> {
    decompose_wall_in(geometry, sphere, wall, parts)
}

/// The sphere-wall rates for a geometry already computed from the same sphere and wall.
#[inline(always)]
fn decompose_wall_in<T: Real>(
    g: ContactGeometry<T>,
    sphere: &Sphere<T>,
    wall: &Wall<T>,
    parts: Parts,
) -> Decomposition<T> {
    let n = g.normal;
    // Material velocity of the wall at the contact point.
    let material2 = wall.velocity + cross(&wall.angular_velocity, &(g.contact_point - wall.point));
    let normal_rate = dot(&(material2 - sphere.velocity), &n);
    let sliding = if parts.contains(Parts::SLIDING) {
        let material1 = sphere.velocity + cross(&sphere.angular_velocity, &n) * g.branch1;
        tangential(&(material1 - material2), &n)
    } else {
        Vec3::zeros()
    };
    let tumbling = if parts.contains(Parts::RIGID) || parts.contains(Parts::OBJECTIVE) {
        tangential(&wall.angular_velocity, &n)
    } else {
        Vec3::zeros()
    };
    let rel = Relative {
        v1: sphere.velocity,
        w1: sphere.angular_velocity,
        w2: wall.angular_velocity,
        material2: Some(material2),
    };
    finish(g, rel, normal_rate, sliding, tumbling, parts)
}

fn check_sphere<T: RealField + Copy>(s: &Sphere<T>, which: u8) -> Result<(), Error> {
    let (v, w) = if which == 1 {
        ("velocity of body 1", "angular velocity of body 1")
    } else {
        ("velocity of body 2", "angular velocity of body 2")
    };
    check_finite_vec(&s.velocity, v)?;
    check_finite_vec(&s.angular_velocity, w)
}

fn check_outputs<T: RealField + Copy>(d: &Decomposition<T>) -> Result<(), Error> {
    let vecs = [
        &d.sliding_velocity,
        &d.rolling_velocity,
        &d.contact_velocity,
        &d.tumbling,
        &d.objective_velocity1,
        &d.objective_velocity2,
    ];
    let finite = d.normal_rate.is_finite()
        && d.twisting_rate.is_finite()
        && d.frame_spin.is_finite()
        && vecs.iter().all(|v| v.iter().all(|x| x.is_finite()));
    if finite {
        Ok(())
    } else {
        Err(Error::NonFinite("result overflowed (inputs too large)"))
    }
}

/// Decomposes the relative motion of two spheres with every check of kinematics.md section 7.
///
/// Errors: non-finite input or result, radius `<= 0`, coincident centres, branch `<= 0`.
pub fn decompose_pair<T: RealField + Copy>(
    body1: &Sphere<T>,
    body2: &Sphere<T>,
    options: GeometryOptions,
    parts: Parts,
) -> Result<Decomposition<T>, Error> {
    let g = pair_geometry(
        &body1.position,
        &body2.position,
        body1.radius,
        body2.radius,
        options,
    )?;
    check_sphere(body1, 1)?;
    check_sphere(body2, 2)?;
    let d = decompose_pair_in(g, body1, body2, parts);
    check_outputs(&d)?;
    Ok(d)
}

/// Decomposes the motion of a sphere relative to a flat wall with every check; the wall normal
/// need not be unit (it is normalised).
pub fn decompose_wall<T: RealField + Copy>(
    sphere: &Sphere<T>,
    wall: &Wall<T>,
    options: GeometryOptions,
    parts: Parts,
) -> Result<Decomposition<T>, Error> {
    let (g, unit) = wall_geometry(
        &sphere.position,
        sphere.radius,
        &wall.point,
        &wall.normal,
        options,
    )?;
    check_sphere(sphere, 1)?;
    check_finite_vec(&wall.velocity, "wall velocity")?;
    check_finite_vec(&wall.angular_velocity, "wall angular velocity")?;
    let wall = Wall {
        normal: unit,
        ..*wall
    };
    let d = decompose_wall_in(g, sphere, &wall, parts);
    check_outputs(&d)?;
    Ok(d)
}
