//! Packed contact histories: only the words of [`ContactState`] that a model reads, as a
//! record of doubles per contact ([`Record`], the state type the batch kernels step for
//! `rsl_batch_step_history`).
//!
//! A batch step is limited by the memory traffic of the state as much as by its arithmetic:
//! the 13 doubles of a [`ContactState`] (112 bytes in the C struct) are read and written per
//! contact whatever the laws. A model whose transports do not read the previous normal
//! (project-rescale, project, none: the LAMMPS and LIGGGHTS presets) needs only the three
//! springs, 7 doubles; one whose transports do (exact, first order) needs the previous normal
//! too, 10; YADE's vector twisting moment needs its off-axis part as well, 13, and so does a
//! model that keeps the previous step's stiffnesses in the same words (energy tracking, a
//! rescaled sliding history). Without a
//! sliding law the sliding spring is left out too (4, 7 or 10 doubles). The words left out are
//! ones the step never reads, so stepping a record gives the same loads, and the same values of
//! the words it keeps, as stepping the full state with those words zero.
//!
//! Record layout: the *full layout* is, in doubles, the sliding spring (3), the rolling spring
//! (3), the twisting angle, the previous normal (3), the model memory (3); a record is
//! the run of it from word [`HistoryLayout::first`] (0, or `NO_SLIDING` = 3 without a sliding
//! law) to word 7, 10 or 13.

use super::prefetch::prefetch_l1;
use super::StateSlot;
use crate::laws::model::{Model, SlidingLaw, Transport};
use crate::laws::step::ContactState;
use crate::scalar::Vec3;

/// Words of a record whose model's transports do not read the previous normal.
pub(crate) const SPRINGS_ONLY: usize = 7;
/// Words of a record with the previous normal.
pub(crate) const WITH_NORMAL: usize = 10;
/// Words of a record with the previous normal and YADE's off-axis twisting moment.
pub(crate) const WITH_OFFAXIS: usize = 13;
/// First word (in the full layout) of the record of a model without a sliding law: the
/// sliding spring's three words are left out.
pub(crate) const NO_SLIDING: usize = 3;

/// Where a model's packed history sits in the full layout (see the module's doc): its words
/// `first..first + words`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct HistoryLayout {
    /// The first word kept: 0, or `NO_SLIDING` (3) when the model has no sliding law.
    pub first: usize,
    /// Doubles per record: 7, 10 or 13 from word 0; 4, 7 or 10 from word 3.
    pub words: usize,
}

impl HistoryLayout {
    /// The layouts a model can have, in the order of [`history_layout`]'s rules.
    pub const ALL: [HistoryLayout; 6] = [
        HistoryLayout::new(0, SPRINGS_ONLY),
        HistoryLayout::new(0, WITH_NORMAL),
        HistoryLayout::new(0, WITH_OFFAXIS),
        HistoryLayout::new(NO_SLIDING, SPRINGS_ONLY - NO_SLIDING),
        HistoryLayout::new(NO_SLIDING, WITH_NORMAL - NO_SLIDING),
        HistoryLayout::new(NO_SLIDING, WITH_OFFAXIS - NO_SLIDING),
    ];

    const fn new(first: usize, words: usize) -> HistoryLayout {
        HistoryLayout { first, words }
    }
}

/// The packed history of `model`: from word 0, or from word `NO_SLIDING` when the sliding
/// law is off (the step neither reads nor writes the sliding spring then), to word
/// `SPRINGS_ONLY` (7) when neither transport reads the previous normal, `WITH_NORMAL` (10)
/// when one does, `WITH_OFFAXIS` (13) for a preset that keeps the twisting moment as a vector
/// (YADE) or a model that keeps the previous stiffnesses there ([`Model::stiffness_memory`]).
pub fn history_layout(model: &Model) -> HistoryLayout {
    let reads_normal = |t: Transport| matches!(t, Transport::Exact | Transport::FirstOrder);
    let end = if model.preset.conventions().twist_vector || model.stiffness_memory() {
        WITH_OFFAXIS
    } else if reads_normal(model.sliding_transport) || reads_normal(model.rolling_transport) {
        WITH_NORMAL
    } else {
        SPRINGS_ONLY
    };
    let first = if model.sliding.law == SlidingLaw::None {
        NO_SLIDING
    } else {
        0
    };
    HistoryLayout {
        first,
        words: end - first,
    }
}

/// Doubles per contact of `model`'s packed history (`history_layout(model).words`).
pub fn history_words(model: &Model) -> usize {
    history_layout(model).words
}

/// Word `q` of the full layout (see the module's doc), read from `s`.
pub fn record_word(s: &ContactState<f64>, q: usize) -> f64 {
    let v = |v: &Vec3<f64>, i: usize| v[i];
    match q {
        0..=2 => v(&s.sliding_spring, q),
        3..=5 => v(&s.rolling_spring, q - 3),
        6 => s.twisting_angle,
        7..=9 => v(&s.previous_normal, q - 7),
        _ => v(&s.model_memory, q - 10),
    }
}

/// The state of a packed record `words` of `layout` (the fields it does not keep are zero).
/// `None` when `words` is not `layout.words` long or `layout` is none of [`HistoryLayout::ALL`].
pub fn state_from_words(layout: HistoryLayout, words: &[f64]) -> Option<ContactState<f64>> {
    if !HistoryLayout::ALL.contains(&layout) || words.len() != layout.words {
        return None;
    }
    let w = |q: usize| {
        q.checked_sub(layout.first)
            .and_then(|i| words.get(i))
            .copied()
            .unwrap_or(0.0)
    };
    let v = |q: usize| Vec3::new(w(q), w(q + 1), w(q + 2));
    Some(ContactState {
        sliding_spring: v(0),
        rolling_spring: v(3),
        twisting_angle: w(6),
        previous_normal: v(7),
        model_memory: v(10),
    })
}

/// Writes the packed record of `state` in `layout` into `words`; false (nothing written) when
/// `words` is not `layout.words` long or `layout` is none of [`HistoryLayout::ALL`].
pub fn words_from_state(
    state: &ContactState<f64>,
    layout: HistoryLayout,
    words: &mut [f64],
) -> bool {
    if !HistoryLayout::ALL.contains(&layout) || words.len() != layout.words {
        return false;
    }
    for (i, w) in words.iter_mut().enumerate() {
        *w = record_word(state, layout.first + i);
    }
    true
}

/// One contact's packed history of `W` doubles, words `F..F + W` of the full layout of
/// `batch::history` (`F` = 0: 7, 10 or 13 words; `F` = 3, no sliding spring: 4, 7 or 10), as
/// the host keeps it: `W` consecutive doubles of its history array.
#[repr(transparent)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Record<const W: usize, const F: usize>(pub [f64; W]);

impl<const W: usize, const F: usize> Record<W, F> {
    /// The record of `state` (the fields a record does not keep are dropped).
    pub fn from_state(state: &ContactState<f64>) -> Self {
        Record(std::array::from_fn(|i| record_word(state, F + i)))
    }
}

impl<const W: usize, const F: usize> StateSlot for Record<W, F> {
    #[inline(always)]
    fn load(&self) -> ContactState<f64> {
        let w = |q: usize| {
            if (F..F + W).contains(&q) {
                self.0[q - F]
            } else {
                0.0
            }
        };
        let v = |q: usize| Vec3::new(w(q), w(q + 1), w(q + 2));
        ContactState {
            sliding_spring: v(0),
            rolling_spring: v(3),
            twisting_angle: w(6),
            previous_normal: v(7),
            model_memory: v(10),
        }
    }
    #[inline(always)]
    fn store(&mut self, state: &ContactState<f64>, _slip: u32) {
        for (i, w) in self.0.iter_mut().enumerate() {
            *w = record_word(state, F + i);
        }
    }
    #[inline(always)]
    fn touch(&self) {
        // The record's first and last doubles: its one or two cache lines.
        prefetch_l1(&self.0[0]);
        prefetch_l1(&self.0[W - 1]);
    }
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
            model_memory: Vec3::new(8.0, 9.0, 10.0),
            previous_normal: Vec3::new(11.0, 12.0, 13.0),
        }
    }

    #[test]
    fn records_keep_springs_then_normal_then_offaxis() {
        let s = state();
        let record = |first: usize, words: usize| {
            let layout = HistoryLayout { first, words };
            let mut record = vec![0.0; words];
            assert!(words_from_state(&s, layout, &mut record));
            record
        };
        assert_eq!(record(0, 7), [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0]);
        assert_eq!(
            record(0, 13),
            [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 11.0, 12.0, 13.0, 8.0, 9.0, 10.0]
        );
        assert_eq!(record(3, 4), [4.0, 5.0, 6.0, 7.0]);
        assert_eq!(
            record(3, 10),
            [4.0, 5.0, 6.0, 7.0, 11.0, 12.0, 13.0, 8.0, 9.0, 10.0]
        );
        let layout = |first: usize, words: usize| HistoryLayout { first, words };
        assert_eq!(state_from_words(layout(0, 13), &record(0, 13)), Some(s));
        let back = state_from_words(layout(0, 10), &record(0, 10)).unwrap();
        assert_eq!(back.previous_normal, s.previous_normal);
        assert_eq!(back.model_memory, Vec3::zeros());
        assert_eq!(record(0, 10)[..7], record(0, 7)[..]);
        let back = state_from_words(layout(3, 7), &record(3, 7)).unwrap();
        assert_eq!(back.sliding_spring, Vec3::zeros());
        assert_eq!(back.rolling_spring, s.rolling_spring);
        assert_eq!(back.twisting_angle, 7.0);
        assert_eq!(back.previous_normal, s.previous_normal);
        assert_eq!(back.model_memory, Vec3::zeros());
        // A length or layout that is not a model's is refused.
        assert!(!words_from_state(&s, layout(0, 8), &mut [0.0; 8]));
        assert!(!words_from_state(&s, layout(0, 7), &mut [0.0; 4]));
        assert!(!words_from_state(&s, layout(1, 6), &mut [0.0; 6]));
        assert_eq!(state_from_words(layout(0, 12), &[0.0; 12]), None);
        assert_eq!(state_from_words(layout(3, 4), &[0.0; 7]), None);
    }

    #[test]
    fn history_layouts_follow_the_transports_the_preset_and_the_sliding_law() {
        let with_sliding = |mut m: Model| {
            m.sliding.law = SlidingLaw::Linear;
            m
        };
        let layout = |first: usize, words: usize| HistoryLayout { first, words };
        let objective = Model::default();
        assert_eq!(
            history_layout(&with_sliding(objective)),
            layout(0, WITH_NORMAL)
        );
        assert_eq!(history_layout(&objective), layout(NO_SLIDING, 7));
        for (preset, end) in [
            (Preset::Lammps2021, SPRINGS_ONLY),
            (Preset::Liggghts38, SPRINGS_ONLY),
            (Preset::Yade2023, WITH_OFFAXIS),
        ] {
            let m = Model::with_preset(preset);
            assert_eq!(history_layout(&with_sliding(m)), layout(0, end));
            assert_eq!(history_layout(&m), layout(NO_SLIDING, end - NO_SLIDING));
            assert_eq!(history_words(&m), end - NO_SLIDING);
        }
        let mut m = with_sliding(Model::with_preset(Preset::Lammps2021));
        m.rolling_transport = Transport::Exact;
        assert_eq!(history_layout(&m), layout(0, WITH_NORMAL));
        m.sliding.law = SlidingLaw::None;
        assert_eq!(history_layout(&m), layout(NO_SLIDING, 7));
    }
}
