//! The host's packed history records (`rsl_batch_step_history`) as a batch state type: the
//! layout is `batch::history`'s; this adds the prefetch of the C layer.

use crate::batch::history::record_word;
use crate::batch::StateSlot;
use crate::laws::step::ContactState;
use crate::scalar::Vec3;

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
            twisting_offaxis: v(10),
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
        super::batch::prefetch_l1(&self.0[0]);
        super::batch::prefetch_l1(&self.0[W - 1]);
    }
}
