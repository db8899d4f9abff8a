//! Packed contact histories: only the words of [`ContactState`] that a model reads, as a
//! record of doubles per contact (the C layer's `Record` steps them in the batch kernels).
//!
//! A batch step is limited by the memory traffic of the state as much as by its arithmetic:
//! the 13 doubles of a [`ContactState`] (112 bytes in the C struct) are read and written per
//! contact whatever the laws. A model whose transports do not read the previous normal
//! (project-rescale, project, none: the LAMMPS and LIGGGHTS presets) needs only the three
//! springs, 7 doubles; one whose transports do (exact, first order) needs the previous normal
//! too, 10; YADE's vector twisting moment needs its off-axis part as well, 13. The words left
//! out are ones the step never reads, so stepping a record gives the same loads, and the same
//! values of the words it keeps, as stepping the full state with those words zero.
//!
//! Record layout, in doubles: sliding spring (3), rolling spring (3), twisting angle, then
//! with 10 or 13 words the previous normal (3), then with 13 the twisting off-axis part (3).

use crate::laws::model::{Model, Transport};
use crate::laws::step::ContactState;
use crate::scalar::Vec3;

/// Words of a record whose model's transports do not read the previous normal.
pub(crate) const SPRINGS_ONLY: usize = 7;
/// Words of a record with the previous normal.
pub(crate) const WITH_NORMAL: usize = 10;
/// Words of a record with the previous normal and YADE's off-axis twisting moment.
pub(crate) const WITH_OFFAXIS: usize = 13;

/// Doubles per contact of `model`'s packed history: `SPRINGS_ONLY` (7) when neither
/// transport reads the previous normal, `WITH_NORMAL` (10) when one does,
/// `WITH_OFFAXIS` (13) for a preset that keeps the twisting moment as a vector (YADE).
pub fn history_words(model: &Model) -> usize {
    let reads_normal = |t: Transport| matches!(t, Transport::Exact | Transport::FirstOrder);
    if model.preset.conventions().twist_vector {
        WITH_OFFAXIS
    } else if reads_normal(model.sliding_transport) || reads_normal(model.rolling_transport) {
        WITH_NORMAL
    } else {
        SPRINGS_ONLY
    }
}

/// Word `q` of a record, read from `s`.
pub fn record_word(s: &ContactState<f64>, q: usize) -> f64 {
    let v = |v: &Vec3<f64>, i: usize| v[i];
    match q {
        0..=2 => v(&s.sliding_spring, q),
        3..=5 => v(&s.rolling_spring, q - 3),
        6 => s.twisting_angle,
        7..=9 => v(&s.previous_normal, q - 7),
        _ => v(&s.twisting_offaxis, q - 10),
    }
}

/// The state of a packed record `words` (7, 10 or 13 doubles; the fields it does not keep are
/// zero). `None` for another length.
pub fn state_from_words(words: &[f64]) -> Option<ContactState<f64>> {
    if ![SPRINGS_ONLY, WITH_NORMAL, WITH_OFFAXIS].contains(&words.len()) {
        return None;
    }
    let w = |q: usize| words.get(q).copied().unwrap_or(0.0);
    let v = |q: usize| Vec3::new(w(q), w(q + 1), w(q + 2));
    Some(ContactState {
        sliding_spring: v(0),
        rolling_spring: v(3),
        twisting_angle: w(6),
        previous_normal: v(7),
        twisting_offaxis: v(10),
    })
}

/// Writes the packed record of `state` into `words` (7, 10 or 13 doubles); false (nothing
/// written) for another length.
pub fn words_from_state(state: &ContactState<f64>, words: &mut [f64]) -> bool {
    if ![SPRINGS_ONLY, WITH_NORMAL, WITH_OFFAXIS].contains(&words.len()) {
        return false;
    }
    for (q, w) in words.iter_mut().enumerate() {
        *w = record_word(state, q);
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::laws::model::Preset;

    fn state() -> ContactState<f64> {
        ContactState {
            sliding_spring: Vec3::new(1.0, 2.0, 3.0),
            rolling_spring: Vec3::new(4.0, 5.0, 6.0),
            twisting_angle: 7.0,
            twisting_offaxis: Vec3::new(8.0, 9.0, 10.0),
            previous_normal: Vec3::new(11.0, 12.0, 13.0),
        }
    }

    #[test]
    fn records_keep_springs_then_normal_then_offaxis() {
        let s = state();
        let record = |n: usize| {
            let mut words = vec![0.0; n];
            assert!(words_from_state(&s, &mut words));
            words
        };
        assert_eq!(record(7), [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0]);
        assert_eq!(
            record(13),
            [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 11.0, 12.0, 13.0, 8.0, 9.0, 10.0]
        );
        assert_eq!(state_from_words(&record(13)), Some(s));
        let back = state_from_words(&record(10)).unwrap();
        assert_eq!(back.previous_normal, s.previous_normal);
        assert_eq!(back.twisting_offaxis, Vec3::zeros());
        assert_eq!(record(10)[..7], record(7)[..]);
        assert!(!words_from_state(&s, &mut [0.0; 8]));
        assert_eq!(state_from_words(&[0.0; 12]), None);
    }

    #[test]
    fn history_words_follow_the_transports_and_the_preset() {
        assert_eq!(history_words(&Model::default()), WITH_NORMAL);
        assert_eq!(
            history_words(&Model::with_preset(Preset::Lammps2021)),
            SPRINGS_ONLY
        );
        assert_eq!(
            history_words(&Model::with_preset(Preset::Liggghts38)),
            SPRINGS_ONLY
        );
        assert_eq!(
            history_words(&Model::with_preset(Preset::Yade2023)),
            WITH_OFFAXIS
        );
        let mut m = Model::with_preset(Preset::Lammps2021);
        m.rolling_transport = Transport::Exact;
        assert_eq!(history_words(&m), WITH_NORMAL);
    }
}
