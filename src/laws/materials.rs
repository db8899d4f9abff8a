//! Mixed materials: the coefficients of one material pair (the values a model's laws take, as
//! LAMMPS' `pair_coeff` gives per type pair), and the table of them a host steps in one batch.
//!
//! Every set of a table goes with the same laws, transports and preset (only the values
//! differ), so one step runs every contact of a call: each contact's set reaches the step as
//! per-contact values ([`Coefficients::apply`]), which give the bits of a step with that set's
//! own model.

use crate::laws::model::{Model, RollingStiffness};
use crate::laws::step::StepInput;
use crate::scalar::Real;

/// Number of values in a coefficient set.
pub const COEFFICIENTS: usize = 9;

/// Index of the sliding stiffness `k_t` (force/length) in [`Coefficients::values`].
pub const SLIDING_STIFFNESS: usize = 0;
/// Index of the sliding damping `gamma_t` (force/velocity).
pub const SLIDING_DAMPING: usize = 1;
/// Index of the sliding friction coefficient `mu_s` (dimensionless).
pub const SLIDING_FRICTION: usize = 2;
/// Index of the rolling stiffness (`k_r` in the length form, `k_theta` in the angle form; read
/// only with the `Given` stiffness rule).
pub const ROLLING_STIFFNESS: usize = 3;
/// Index of the rolling damping (`gamma_r` or `c_theta`, or the damping ratio with `Ratio`).
pub const ROLLING_DAMPING: usize = 4;
/// Index of the rolling limit coefficient (`mu_r`, or `eta` in the angle form).
pub const ROLLING_FRICTION: usize = 5;
/// Index of the twisting stiffness (`sds`, moment/angle).
pub const TWISTING_STIFFNESS: usize = 6;
/// Index of the twisting damping (`sds`, moment/angular velocity).
pub const TWISTING_DAMPING: usize = 7;
/// Index of the twisting limit length `mu_tw` (`sds`).
pub const TWISTING_FRICTION: usize = 8;

/// The coefficients of one material pair: the stiffness, damping and limit coefficient of each
/// law, in the units of the model's laws (see the index constants).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Coefficients {
    /// The values, by the index constants ([`SLIDING_STIFFNESS`] ...).
    pub values: [f64; COEFFICIENTS],
}

impl Coefficients {
    /// The coefficients of `model`'s laws.
    pub fn of(model: &Model) -> Self {
        let (s, r, t) = (&model.sliding, &model.rolling, &model.twisting);
        Coefficients {
            values: [
                s.stiffness,
                s.damping,
                s.friction,
                r.stiffness,
                r.damping,
                r.friction,
                t.stiffness,
                t.damping,
                t.friction,
            ],
        }
    }

    /// `base` with these coefficients: the model of this material pair.
    pub fn model(&self, base: &Model) -> Model {
        let mut m = *base;
        let v = &self.values;
        let (s, r, t) = (&mut m.sliding, &mut m.rolling, &mut m.twisting);
        (s.stiffness, s.damping, s.friction) = (v[0], v[1], v[2]);
        (r.stiffness, r.damping, r.friction) = (v[3], v[4], v[5]);
        (t.stiffness, t.damping, t.friction) = (v[6], v[7], v[8]);
        m
    }

    /// Sets the step's per-contact values to `values` (this set's, in lanes): the step then
    /// gives the bits of a step with the model whose coefficients these are. The rolling
    /// stiffness is given only under the `Given` rule (a derived rule computes its own).
    #[inline(always)]
    pub fn apply<T: Real>(model: &Model, values: [T; COEFFICIENTS], input: &mut StepInput<T>) {
        input.sliding_stiffness = Some(values[SLIDING_STIFFNESS]);
        input.sliding_damping = Some(values[SLIDING_DAMPING]);
        input.sliding_friction = Some(values[SLIDING_FRICTION]);
        input.rolling_stiffness = (model.rolling.stiffness_rule == RollingStiffness::Given)
            .then_some(values[ROLLING_STIFFNESS]);
        input.rolling_damping = Some(values[ROLLING_DAMPING]);
        input.rolling_friction = Some(values[ROLLING_FRICTION]);
        input.twisting_stiffness = Some(values[TWISTING_STIFFNESS]);
        input.twisting_damping = Some(values[TWISTING_DAMPING]);
        input.twisting_friction = Some(values[TWISTING_FRICTION]);
    }
}

/// `model` with its coefficients zeroed: two models with the same laws, transports, preset and
/// options give the same value.
fn laws_only(model: &Model) -> Model {
    let mut m = *model;
    for v in [
        &mut m.sliding.stiffness,
        &mut m.sliding.damping,
        &mut m.sliding.friction,
        &mut m.rolling.stiffness,
        &mut m.rolling.damping,
        &mut m.rolling.friction,
        &mut m.twisting.stiffness,
        &mut m.twisting.damping,
        &mut m.twisting.friction,
    ] {
        *v = 0.0;
    }
    m
}

/// Whether `a` and `b` differ at most in their coefficients ([`Coefficients::of`]): the same
/// laws, forms, rules, transports, preset, geometry options and switches.
pub fn same_laws(a: &Model, b: &Model) -> bool {
    laws_only(a) == laws_only(b)
}

/// A table of material pairs and each contact's entry in it, for one batch call.
#[derive(Clone, Copy, Debug)]
pub struct Materials<'a> {
    /// The coefficient sets (of models with the laws of the call's model).
    pub table: &'a [Coefficients],
    /// Each contact's set: an index into `table` (a contact whose index is not below
    /// `table.len()` is refused, as one with a particle index out of range).
    pub index: &'a [u32],
}

impl Materials<'_> {
    /// Contact `c`'s coefficients, or `None` when its index is out of range.
    #[inline(always)]
    pub fn at(&self, c: usize) -> Option<&Coefficients> {
        self.table.get(self.index[c] as usize)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::laws::model::{Preset, RollingLaw, TwistingLaw};

    #[test]
    fn same_laws_ignores_the_values_and_nothing_else() {
        let mut a = Model::with_preset(Preset::Lammps2021);
        a.rolling.law = RollingLaw::Epsd;
        let mut b = a;
        b.sliding.stiffness = 3.0;
        b.rolling.friction = 0.2;
        b.twisting.damping = 1.0;
        assert!(same_laws(&a, &b));
        assert_ne!(Coefficients::of(&a), Coefficients::of(&b));
        b.twisting.law = TwistingLaw::Sds;
        assert!(!same_laws(&a, &b));
        let mut c = a;
        c.rolling.stiffness_factor = 2.0;
        assert!(!same_laws(&a, &c));
        let mut d = a;
        d.track_energy = true;
        assert!(!same_laws(&a, &d));
    }

    #[test]
    fn a_set_of_a_model_in_index_order() {
        let mut m = Model::with_preset(Preset::Objective);
        (m.sliding.stiffness, m.sliding.damping, m.sliding.friction) = (1.0, 2.0, 3.0);
        (m.rolling.stiffness, m.rolling.damping, m.rolling.friction) = (4.0, 5.0, 6.0);
        (m.twisting.stiffness, m.twisting.damping) = (7.0, 8.0);
        m.twisting.friction = 9.0;
        let set = Coefficients::of(&m);
        let v = set.values;
        assert_eq!(v, [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0]);
        assert_eq!(set.model(&Model::with_preset(Preset::Objective)), m);
        assert_eq!(
            [
                v[SLIDING_FRICTION],
                v[ROLLING_DAMPING],
                v[TWISTING_FRICTION]
            ],
            [3.0, 5.0, 9.0]
        );
    }
}
