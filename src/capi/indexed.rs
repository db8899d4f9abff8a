//! The host's history array of `rsl_batch_step_indexed`, as the batch kernels reach it a group
//! of contacts at a time.
//!
//! The core's [`IndexedStates`] finds each group's eight states with a bounds check per state
//! and hands them out as `&mut` by splitting the array eight times, since safe Rust cannot
//! know that its indices increase. That cost 20 instructions per contact on top of the
//! contiguous call (double AVX2, rolling + twisting, in cache; `scripts/count_instructions.sh`).
//! [`IndexedGroups`] wraps it and forms each group's addresses straight from the indices,
//! which [`IndexedStates::new`] has checked: every index below the array's length and each
//! greater than the one before, so the eight states of a group are distinct.

use super::contact::rsl_contact_state;
use crate::batch::block::{group_of, GroupCopy, GroupRow, GROUP, STATE_WORDS};
use crate::batch::{ContactStates, IndexedStates};

/// [`IndexedStates`] of C states, whose groups the batch kernels reach without a bounds check
/// per state (see the module's comment); what `rsl_batch_step_indexed` steps.
pub struct IndexedGroups<'a>(IndexedStates<'a, rsl_contact_state>);

impl<'a> From<IndexedStates<'a, rsl_contact_state>> for IndexedGroups<'a> {
    fn from(states: IndexedStates<'a, rsl_contact_state>) -> Self {
        IndexedGroups(states)
    }
}

impl IndexedGroups<'_> {
    /// The indices of contacts `c..c + GROUP` (a checked slice: `c + GROUP <= contacts()`).
    #[inline(always)]
    fn group_index(&self, c: usize) -> [usize; GROUP] {
        let index: &[usize; GROUP] = self.0.index()[c..c + GROUP].try_into().expect("a group");
        *index
    }
}

impl ContactStates for IndexedGroups<'_> {
    type Slot = rsl_contact_state;
    #[inline(always)]
    fn contacts(&self) -> usize {
        self.0.contacts()
    }
    #[inline(always)]
    fn get(&self, c: usize) -> &rsl_contact_state {
        self.0.get(c)
    }
    #[inline(always)]
    fn get_mut(&mut self, c: usize) -> &mut rsl_contact_state {
        self.0.get_mut(c)
    }
    #[inline(always)]
    fn group(&self, c: usize) -> [&rsl_contact_state; GROUP] {
        let index = self.group_index(c);
        let base = self.0.slots().as_ptr();
        // SAFETY: `IndexedStates::new` checked every index to be below the length of the
        // array `base` starts, which `self` borrows (shared here) for its whole life.
        group_of(|k| unsafe { &*base.add(index[k]) })
    }
    #[inline(always)]
    fn store_group<P, X: GroupCopy<P, rsl_contact_state>>(
        &mut self,
        copy: X,
        rows: [&GroupRow; STATE_WORDS],
        slip: &[u32; GROUP],
        c: usize,
    ) {
        let index = self.group_index(c);
        let base = self.0.slots_mut().as_mut_ptr();
        // SAFETY: every index is below the array's length and each is greater than the one
        // before (checked by `IndexedStates::new`), so the eight references are in bounds and
        // distinct; `self` borrows the array exclusively for its whole life, and the
        // references end with this call.
        let states = group_of(|k| unsafe { &mut *base.add(index[k]) });
        copy.store_states_at(rows, slip, states);
    }
    #[inline(always)]
    fn touch(&self, c: usize) {
        self.0.touch(c);
    }
    fn bytes(&self) -> usize {
        self.0.bytes()
    }
}
