//! Plain `#[repr(C)]` structs that cross the boundary, and their conversions to the core types.
#![allow(non_camel_case_types)]

use crate::decompose::{Decomposition, Sphere, Wall};
use crate::geometry::ContactGeometry;
use crate::scalar::Vec3;

/// A 3-vector of doubles (any consistent unit system), in the global frame: every vector the
/// library reads or writes (positions, velocities, angular velocities, normals, forces,
/// torques, moments, stored springs) has its components in the host's fixed global frame.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct rsl_vec3 {
    /// x component.
    pub x: f64,
    /// y component.
    pub y: f64,
    /// z component.
    pub z: f64,
}

impl From<rsl_vec3> for Vec3<f64> {
    fn from(v: rsl_vec3) -> Self {
        Vec3::new(v.x, v.y, v.z)
    }
}

impl From<Vec3<f64>> for rsl_vec3 {
    fn from(v: Vec3<f64>) -> Self {
        rsl_vec3 {
            x: v.x,
            y: v.y,
            z: v.z,
        }
    }
}

/// Kinematic state of one sphere (vectors in the global frame).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct rsl_sphere {
    /// Centre position.
    pub position: rsl_vec3,
    /// Velocity of the centre.
    pub velocity: rsl_vec3,
    /// Angular velocity (rad per unit time, global frame).
    pub angular_velocity: rsl_vec3,
    /// Radius (> 0).
    pub radius: f64,
}

impl From<&rsl_sphere> for Sphere<f64> {
    fn from(s: &rsl_sphere) -> Self {
        Sphere {
            position: s.position.into(),
            velocity: s.velocity.into(),
            angular_velocity: s.angular_velocity.into(),
            radius: s.radius,
        }
    }
}

/// A flat wall in rigid motion (body 2 of a sphere-wall contact).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct rsl_wall {
    /// Any point of the wall surface; the reference point of its motion.
    pub point: rsl_vec3,
    /// Outward normal, from the wall towards the sphere's side; any non-zero length (it is
    /// normalised). The contact normal is its opposite.
    pub normal: rsl_vec3,
    /// Velocity of the wall's material point at `point`.
    pub velocity: rsl_vec3,
    /// Angular velocity of the wall.
    pub angular_velocity: rsl_vec3,
}

impl From<&rsl_wall> for Wall<f64> {
    fn from(w: &rsl_wall) -> Self {
        Wall {
            point: w.point.into(),
            normal: w.normal.into(),
            velocity: w.velocity.into(),
            angular_velocity: w.angular_velocity.into(),
        }
    }
}

/// The decomposition of one contact (body 1 relative to body 2, `normal` from 1 to 2). Fields
/// of parts not asked for are 0. For a wall, `distance` and `branch2` are +infinity.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct rsl_decomposition {
    /// Unit normal from body 1 to body 2 (into the wall).
    pub normal: rsl_vec3,
    /// Centre distance `d`.
    pub distance: f64,
    /// Overlap `delta = R1 + R2 - d` (> 0 in contact).
    pub overlap: f64,
    /// Branch length `l1` (centre of body 1 to contact point).
    pub branch1: f64,
    /// Branch length `l2` (centre of body 2 to contact point).
    pub branch2: f64,
    /// Rolling radius `R_r`.
    pub rolling_radius: f64,
    /// Contact point `r1 + l1 n`.
    pub contact_point: rsl_vec3,
    /// Normal rate `ddot = n . (v2 - v1)`; overlap rate is `-ddot`. Part `RSL_PART_NORMAL_RATE`.
    pub normal_rate: f64,
    /// Sliding velocity of body 1 relative to body 2 (tangential). Part `RSL_PART_SLIDING`.
    pub sliding_velocity: rsl_vec3,
    /// Rolling velocity `R_r (w1 - w2) x n` (tangential). Part `RSL_PART_ROLLING`.
    pub rolling_velocity: rsl_vec3,
    /// Twisting rate `(w1 - w2) . n`. Part `RSL_PART_TWISTING`.
    pub twisting_rate: f64,
    /// Contact velocity `d r_c/dt`. Part `RSL_PART_RIGID`.
    pub contact_velocity: rsl_vec3,
    /// Tumbling `w_rbr = n x (v2 - v1)/d` (wall: its tangential angular velocity). Part `RSL_PART_RIGID`.
    pub tumbling: rsl_vec3,
    /// Frame spin `w_rbs = (w1 + w2) . n / 2`. Part `RSL_PART_RIGID`.
    pub frame_spin: f64,
    /// Objective velocity `s1` of body 1. Part `RSL_PART_OBJECTIVE`.
    pub objective_velocity1: rsl_vec3,
    /// Objective velocity `s2` of body 2. Part `RSL_PART_OBJECTIVE`.
    pub objective_velocity2: rsl_vec3,
}

impl From<&Decomposition<f64>> for rsl_decomposition {
    // Inline: the SIMD decomposition kernels deliver through it, and with several codegen units
    // (Cargo.toml) a plain function here was left out of line, a call per contact.
    #[inline]
    fn from(d: &Decomposition<f64>) -> Self {
        let g = &d.geometry;
        rsl_decomposition {
            normal: g.normal.into(),
            distance: g.distance,
            overlap: g.overlap,
            branch1: g.branch1,
            branch2: g.branch2,
            rolling_radius: g.rolling_radius,
            contact_point: g.contact_point.into(),
            normal_rate: d.normal_rate,
            sliding_velocity: d.sliding_velocity.into(),
            rolling_velocity: d.rolling_velocity.into(),
            twisting_rate: d.twisting_rate,
            contact_velocity: d.contact_velocity.into(),
            tumbling: d.tumbling.into(),
            frame_spin: d.frame_spin,
            objective_velocity1: d.objective_velocity1.into(),
            objective_velocity2: d.objective_velocity2.into(),
        }
    }
}

impl rsl_decomposition {
    /// The core decomposition, with the branch-rate factor of the branch rule in force.
    pub(crate) fn to_core(self, branch_rate_factor: f64) -> Decomposition<f64> {
        Decomposition {
            geometry: ContactGeometry {
                normal: self.normal.into(),
                distance: self.distance,
                overlap: self.overlap,
                branch1: self.branch1,
                branch2: self.branch2,
                rolling_radius: self.rolling_radius,
                contact_point: self.contact_point.into(),
                branch_rate_factor,
            },
            normal_rate: self.normal_rate,
            sliding_velocity: self.sliding_velocity.into(),
            rolling_velocity: self.rolling_velocity.into(),
            twisting_rate: self.twisting_rate,
            contact_velocity: self.contact_velocity.into(),
            tumbling: self.tumbling.into(),
            frame_spin: self.frame_spin,
            objective_velocity1: self.objective_velocity1.into(),
            objective_velocity2: self.objective_velocity2.into(),
        }
    }
}

/// Velocities of two spheres (output of `rsl_compose`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct rsl_pair_velocities {
    /// Velocity of the centre of body 1.
    pub velocity1: rsl_vec3,
    /// Angular velocity of body 1.
    pub angular_velocity1: rsl_vec3,
    /// Velocity of the centre of body 2.
    pub velocity2: rsl_vec3,
    /// Angular velocity of body 2.
    pub angular_velocity2: rsl_vec3,
}

/// Velocities of a sphere and a wall (output of `rsl_compose_wall`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct rsl_wall_velocities {
    /// Velocity of the sphere's centre.
    pub velocity1: rsl_vec3,
    /// Angular velocity of the sphere.
    pub angular_velocity1: rsl_vec3,
    /// Angular velocity of the wall.
    pub wall_angular_velocity: rsl_vec3,
    /// Velocity of the wall's material point at the contact point.
    pub wall_contact_velocity: rsl_vec3,
}

/// LEGACY rolling measures, for comparison with older codes only.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct rsl_legacy_rolling {
    /// LEGACY Kuhn-Bagi mean contact travel `(s1 + s2)_t / 2`: reports rolling in pure sliding
    /// of unequal spheres.
    pub kuhn_bagi: rsl_vec3,
    /// LEGACY Iwashita-Oda `(R1 w1 - R2 w2) x n / 2`: not objective.
    pub iwashita_oda: rsl_vec3,
}
