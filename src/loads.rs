//! Loads on both bodies from the work-conjugate contact forces (kinematics.md section 5).
//!
//! Inputs: normal force magnitude `f_n` (compressive positive), tangential (sliding) force
//! `F_t` on body 1, rolling pseudo-force `F_r` (tangential) and twisting moment `M_tw` on
//! body 1 about `n`. Torques are about each body's centre.

use crate::geometry::ContactGeometry;
use crate::scalar::{cross, Real, Vec3};

/// Force and torque on each body of one contact.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactLoads<T: Real> {
    /// Force on body 1: `-f_n n + F_t`.
    pub force1: Vec3<T>,
    /// Torque on body 1 about its centre: `l1 n x F_t + R_r n x F_r + M_tw n`.
    pub torque1: Vec3<T>,
    /// Force on body 2: `-force1`.
    pub force2: Vec3<T>,
    /// Torque on body 2. Sphere: about its centre, `l2 n x F_t - R_r n x F_r - M_tw n`.
    /// Wall (infinite arm): about the contact point, `-R_r n x F_r - M_tw n`; about a point
    /// `X` it is `torque2 + (r_c - X) x force2`.
    pub torque2: Vec3<T>,
}

/// Loads of one contact from the rolling pseudo-force `F_r` (length form); see
/// [`contact_loads_from_moment`] for a rolling moment given directly. Angular momentum about any point is conserved exactly: the force
/// pair acts along a common line through `r_c` and the rolling and twisting parts are couples.
#[inline(always)]
pub fn contact_loads<T: Real>(
    g: &ContactGeometry<T>,
    normal_force: T,
    sliding_force: &Vec3<T>,
    rolling_force: &Vec3<T>,
    twisting_moment: T,
    is_wall: bool,
) -> ContactLoads<T> {
    let rolling_moment = cross(&g.normal, rolling_force) * g.rolling_radius;
    contact_loads_from_moment(
        g,
        normal_force,
        sliding_force,
        &rolling_moment,
        twisting_moment,
        is_wall,
    )
}

/// Loads of one contact from the rolling moment on body 1 (`R_r n x F_r` in the length form,
/// `-k_theta theta_r - ...` in the angle form); body 2 receives its opposite.
#[inline(always)]
pub fn contact_loads_from_moment<T: Real>(
    g: &ContactGeometry<T>,
    normal_force: T,
    sliding_force: &Vec3<T>,
    rolling_moment: &Vec3<T>,
    twisting_moment: T,
    is_wall: bool,
) -> ContactLoads<T> {
    let couple = rolling_moment + g.normal * twisting_moment;
    contact_loads_from_couple(g, normal_force, sliding_force, &couple, is_wall)
}

/// Loads of one contact from the total pure couple on body 1 (rolling moment plus twisting
/// moment); body 2 receives the opposite couple plus the moment of the force pair.
#[inline(always)]
pub fn contact_loads_from_couple<T: Real>(
    g: &ContactGeometry<T>,
    normal_force: T,
    sliding_force: &Vec3<T>,
    couple: &Vec3<T>,
    is_wall: bool,
) -> ContactLoads<T> {
    let n = g.normal;
    let force1 = sliding_force - n * normal_force;
    let n_x_ft = cross(&n, sliding_force);
    let torque1 = n_x_ft * g.branch1 + couple;
    let torque2 = if is_wall {
        // Component by component: nalgebra's `Neg` of a vector of lanes was left out of line in
        // a SIMD kernel (scripts/check_kernels.sh); the same negations.
        Vec3::new(-couple.x, -couple.y, -couple.z)
    } else {
        n_x_ft * g.branch2 - couple
    };
    ContactLoads {
        force1,
        torque1,
        force2: -force1,
        torque2,
    }
}
