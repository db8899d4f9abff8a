//! The inverse map of kinematics.md section 3: from the decomposition (rates and geometry) back
//! to the body velocities. Together with [`crate::decompose`] it is a bijection of 12 numbers;
//! a round trip returns the inputs to rounding.

use crate::decompose::Decomposition;
use crate::scalar::{cross, lit, Real, Vec3};

/// Velocities of two spheres recovered from a decomposition.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PairVelocities<T: Real> {
    /// Velocity of the centre of body 1.
    pub velocity1: Vec3<T>,
    /// Angular velocity of body 1.
    pub angular_velocity1: Vec3<T>,
    /// Velocity of the centre of body 2.
    pub velocity2: Vec3<T>,
    /// Angular velocity of body 2.
    pub angular_velocity2: Vec3<T>,
}

/// Velocities of a sphere and a wall recovered from a sphere-wall decomposition.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WallVelocities<T: Real> {
    /// Velocity of the sphere's centre.
    pub velocity1: Vec3<T>,
    /// Angular velocity of the sphere.
    pub angular_velocity1: Vec3<T>,
    /// Angular velocity of the wall.
    pub wall_angular_velocity: Vec3<T>,
    /// Velocity of the wall's material point at the contact point.
    pub wall_contact_velocity: Vec3<T>,
}

/// `(w1 - w2)_t` from the rolling velocity: `n x v_r / R_r`.
#[inline(always)]
fn tangential_spin_difference<T: Real>(d: &Decomposition<T>) -> Vec3<T> {
    cross(&d.geometry.normal, &d.rolling_velocity) / d.geometry.rolling_radius
}

/// Velocity of body 1 from the contact velocity: `v1 = v_c - (dl1/dt) n - l1 w_rbr x n`.
#[inline(always)]
fn velocity1<T: Real>(d: &Decomposition<T>) -> Vec3<T> {
    let g = &d.geometry;
    d.contact_velocity
        - g.normal * (g.branch_rate_factor * d.normal_rate)
        - cross(&d.tumbling, &g.normal) * g.branch1
}

/// Recovers `(v1, w1, v2, w2)` of a sphere pair. `d` must hold every part
/// ([`crate::decompose::Parts::ALL`] or at least normal, sliding, rolling, twisting, rigid) and
/// come from a sphere-pair decomposition.
pub fn compose_pair<T: Real>(d: &Decomposition<T>) -> PairVelocities<T> {
    let g = &d.geometry;
    let n = g.normal;
    let spin_diff_t = tangential_spin_difference(d);
    // A = (l1 w1 + l2 w2)_t = n x v_s + d w_rbr.
    let arms_t = cross(&n, &d.sliding_velocity) + d.tumbling * g.distance;
    let half_twist = d.twisting_rate * lit(0.5);
    // l1 + l2 = d under the midplane rule, R1 + R2 under the radii rule.
    let span = g.branch1 + g.branch2;
    let w1 = (arms_t + spin_diff_t * g.branch2) / span + n * (d.frame_spin + half_twist);
    let w2 = (arms_t - spin_diff_t * g.branch1) / span + n * (d.frame_spin - half_twist);
    let v1 = velocity1(d);
    let dv = n * d.normal_rate + cross(&d.tumbling, &n) * g.distance;
    PairVelocities {
        velocity1: v1,
        angular_velocity1: w1,
        velocity2: v1 + dv,
        angular_velocity2: w2,
    }
}

/// Recovers the sphere's `(v1, w1)`, the wall's angular velocity and the wall's material
/// velocity at the contact point from a sphere-wall decomposition holding every part.
pub fn compose_wall<T: Real>(d: &Decomposition<T>) -> WallVelocities<T> {
    let g = &d.geometry;
    let n = g.normal;
    let half_twist = d.twisting_rate * lit(0.5);
    let wall_w = d.tumbling + n * (d.frame_spin - half_twist);
    let w1 = d.tumbling + tangential_spin_difference(d) + n * (d.frame_spin + half_twist);
    let v1 = velocity1(d);
    let material1 = v1 + cross(&w1, &n) * g.branch1;
    let material1_t = material1 - n * material1.dot(&n);
    let wall_contact_velocity = material1_t - d.sliding_velocity + n * (v1.dot(&n) + d.normal_rate);
    WallVelocities {
        velocity1: v1,
        angular_velocity1: w1,
        wall_angular_velocity: wall_w,
        wall_contact_velocity,
    }
}
