//! The state of a contact seen with its bodies swapped.
//!
//! A host that stores a contact's history per body pair can meet the pair in the other order
//! later: a neighbour list rebuilt with the two atoms exchanged, an MPI rank that computes the
//! pair from the other atom's side, atom sorting. The history must then be **mirrored**: the
//! state that makes a step of `(body 2, body 1)` give exactly the mirror of the step of
//! `(body 1, body 2)`, i.e. the force on the new body 1 is the old force on body 2 (`-force1`)
//! and the torques trade places. Negating every stored vector (what LAMMPS 20220106 does to its
//! whole history when a pair's order changes) is right for the sliding spring only.
//!
//! With the bodies swapped the normal becomes `-n`, the sliding velocity (body 1 relative to
//! body 2) `-v_s`, the relative spin `w1 - w2` becomes `-(w1 - w2)`, so:
//!
//! | field | mirrored | why |
//! |---|---|---|
//! | `sliding_spring` | negated | `xi_s` integrates `v_s` (YADE preset: the shear force on body 1) |
//! | `rolling_spring`, length form | kept | `v_r = R_r (w1 - w2) x n` is unchanged: both factors change sign |
//! | `rolling_spring`, angle form | negated | `theta_r` integrates `(w1 - w2)_t` (YADE, LIGGGHTS presets: the moment on body 1) |
//! | `twisting_angle` | kept | `w_tw = (w1 - w2) . n` is unchanged (YADE preset: the moment on body 1 along the previous normal, which also flips) |
//! | `model_memory` | YADE preset: negated; others: kept | YADE: part of the moment on body 1; others: the previous stiffnesses, a property of the contact |
//! | `previous_normal` | negated | the normal points from body 1 to body 2 |
//!
//! The transport of the springs uses the same rotation for both orders (the minimal rotation
//! between two normals and the spin about the new normal are both even under `n -> -n` with
//! `w1 + w2` kept), so the mirrored state stays the mirror after any number of steps.

use crate::laws::model::{Model, Preset, RollingForm};
use crate::laws::step::ContactState;
use crate::scalar::Real;

/// The state of the same contact with body 1 and body 2 exchanged (see the module
/// documentation for each field's rule). Applying it twice gives the state back bit for bit
/// (only negations). Every preset and law: only the rolling form changes the rule.
pub fn mirror_state<T: Real>(model: &Model, state: &ContactState<T>) -> ContactState<T> {
    let rolling_spring = match model.rolling.form {
        RollingForm::Length => state.rolling_spring,
        RollingForm::Angle => -state.rolling_spring,
    };
    ContactState {
        sliding_spring: -state.sliding_spring,
        rolling_spring,
        twisting_angle: state.twisting_angle,
        // YADE's off-axis twisting moment is a moment on body 1 (it flips); the previous
        // stiffnesses other models keep there belong to the contact (they do not).
        model_memory: if model.preset == Preset::Yade2023 {
            -state.model_memory
        } else {
            state.model_memory
        },
        previous_normal: -state.previous_normal,
    }
}
