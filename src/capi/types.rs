//! Plain `#[repr(C)]` structs that cross the boundary, and their conversions to the core types.
//! The ones the engine reads and writes in place (`rsl_vec3`, `rsl_sphere`, `rsl_wall` here) are
//! defined in the core's `layout` and re-exported.
#![allow(non_camel_case_types)]

pub use crate::layout::{rsl_sphere, rsl_vec3, rsl_wall};

use crate::decompose::{Decomposition, Wall};
use crate::geometry::ContactGeometry;

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

/// Energy terms of one step (load times length; 0 unless the model tracks energy).
///
/// Per mode (sliding, rolling, twisting), the work the step's load took out of the relative
/// motion equals the change of elastic energy plus dashpot plus slider, less `transport` and
/// `stiffness_change` (the energy the springs gained without work): the
/// budget of a simulation closes with them, up to the integrator's error (first order in the
/// time step). While a spring sticks its slider term is 0 and the work is the spring's midpoint
/// work plus the dashpot's; while it slips, the work is that of the applied, clipped load. Only
/// the sum of a mode's dashpot and slider terms is the mode's dissipation: while the spring
/// slips under the clip rules that keep the dashpot inside the limit (LAMMPS', the objective
/// preset's), the reset spring can take back part of what the dashpot term counts, and the
/// slider term is then negative.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct rsl_contact_energy {
    /// Elastic energy in the sliding spring after the step.
    pub elastic_sliding: f64,
    /// Elastic energy in the rolling spring after the step.
    pub elastic_rolling: f64,
    /// Elastic energy in the twisting spring after the step.
    pub elastic_twisting: f64,
    /// Dissipated by the sliding dashpot this step.
    pub dashpot_sliding: f64,
    /// Dissipated by the rolling dashpot (viscous law included) this step.
    pub dashpot_rolling: f64,
    /// Dissipated by the twisting dashpot this step.
    pub dashpot_twisting: f64,
    /// Dissipated by the sliding slider (friction) this step: 0 while the spring sticks.
    pub slider_sliding: f64,
    /// Dissipated by the rolling slider (cdt included) this step: 0 while the spring sticks.
    pub slider_rolling: f64,
    /// Dissipated by the twisting slider this step: 0 while the spring sticks.
    pub slider_twisting: f64,
    /// Change of elastic energy caused by transporting the springs this step (0 to rounding
    /// for exact and project-rescale transport).
    pub transport: f64,
    /// Elastic energy the springs gained (negative: lost) this step because their stiffness
    /// changed since the previous step, with no work done: a per-contact `k_t` (Hertz-Mindlin's
    /// follows the contact radius), Marshall twisting's `k_t a^2 / 2`, a rolling stiffness
    /// derived from `k_n`, or a rescaled sliding history shrinking. The springs' energy at the
    /// start of the step with this step's stiffnesses, less their energy at the end of the
    /// previous step (the state keeps the previous stiffnesses in `model_memory`). 0 with the
    /// YADE_2023 preset, whose state has no room for them.
    pub stiffness_change: f64,
}

/// Loads of one contact step. Body 2 receives `-force1` and `torque2`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct rsl_contact_loads {
    /// Force on body 1: `-f_n n + F_t`.
    pub force1: rsl_vec3,
    /// Torque on body 1 about its centre.
    pub torque1: rsl_vec3,
    /// Torque on body 2 about its centre (wall: about the contact point).
    pub torque2: rsl_vec3,
    /// Sliding force `F_t` on body 1.
    pub sliding_force: rsl_vec3,
    /// Rolling moment on body 1 (body 2 gets its opposite).
    pub rolling_moment: rsl_vec3,
    /// Twisting torque on body 1, `M_tw n` (YADE preset: its vector twisting moment); body 2
    /// gets the opposite.
    pub twisting_torque: rsl_vec3,
    /// Energy terms.
    pub energy: rsl_contact_energy,
    /// `RSL_SLIP_*` bits.
    pub slip_flags: u32,
    /// Padding.
    pub reserved: u32,
}
