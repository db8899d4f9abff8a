//! Where a particle-major batch step finds each contact's state: one slot per contact in
//! contact order (a slice), or in the host's own history array through an index per contact
//! ([`IndexedStates`]), so that a host which keeps one history per neighbour-list entry steps
//! its touching pairs in place, without copying their histories into and out of a buffer
//! ([`IndexedGroups`]: the same for the C states, with each group's addresses formed without a
//! bounds check per state).

use super::block::{group_of, GroupCopy, GroupRow, GROUP, STATE_WORDS};
use super::StateSlot;
use crate::error::Error;
use crate::layout::rsl_contact_state;

/// The state slots of a call's contacts, contact `c < contacts()`.
pub trait ContactStates {
    /// The state slot type.
    type Slot: StateSlot;
    /// Number of contacts served.
    fn contacts(&self) -> usize;
    /// The state of contact `c`.
    fn get(&self, c: usize) -> &Self::Slot;
    /// The state of contact `c`, writable.
    fn get_mut(&mut self, c: usize) -> &mut Self::Slot;
    /// The states of contacts `c..c + GROUP` (all `< contacts()`).
    fn group(&self, c: usize) -> [&Self::Slot; GROUP];
    /// Writes the states of contacts `c..c + GROUP` (all `< contacts()`) from `rows` and their
    /// slip flags from `slip`, with `copy`.
    fn store_group<P, X: GroupCopy<P, Self::Slot>>(
        &mut self,
        copy: X,
        rows: [&GroupRow; STATE_WORDS],
        slip: &[u32; GROUP],
        c: usize,
    );
    /// Starts loading the state of contact `c` when there is one (see
    /// [`StateSlot::touch`]).
    fn touch(&self, c: usize);
    /// Bytes the call reads and writes here.
    fn bytes(&self) -> usize;
}

impl<S: StateSlot> ContactStates for &mut [S] {
    type Slot = S;
    #[inline(always)]
    fn contacts(&self) -> usize {
        self.len()
    }
    #[inline(always)]
    fn get(&self, c: usize) -> &S {
        &self[c]
    }
    #[inline(always)]
    fn get_mut(&mut self, c: usize) -> &mut S {
        &mut self[c]
    }
    #[inline(always)]
    fn group(&self, c: usize) -> [&S; GROUP] {
        let states: &[S; GROUP] = self[c..c + GROUP].try_into().expect("a group of states");
        group_of(|k| &states[k])
    }
    #[inline(always)]
    fn store_group<P, X: GroupCopy<P, S>>(
        &mut self,
        copy: X,
        rows: [&GroupRow; STATE_WORDS],
        slip: &[u32; GROUP],
        c: usize,
    ) {
        let states: &mut [S; GROUP] = (&mut self[c..c + GROUP])
            .try_into()
            .expect("a group of states");
        copy.store_states(rows, slip, states);
    }
    #[inline(always)]
    fn touch(&self, c: usize) {
        S::touch_in(self, c);
    }
    fn bytes(&self) -> usize {
        size_of_val(&**self)
    }
}

/// States kept by the host in its own array (`slots`, e.g. one per neighbour-list entry):
/// contact `c`'s is `slots[index[c]]`. The indices are strictly increasing, so the slots are
/// distinct and each is visited in memory order (checked by [`IndexedStates::new`]).
pub struct IndexedStates<'a, S> {
    slots: &'a mut [S],
    index: &'a [usize],
}

impl<'a, S> IndexedStates<'a, S> {
    /// The states `slots[index[c]]`; an error unless every index is below `slots.len()` and
    /// each is greater than the one before.
    pub fn new(slots: &'a mut [S], index: &'a [usize]) -> Result<Self, Error> {
        if !strictly_increasing(index) {
            return Err(Error::InvalidArgument(
                "state indices must be strictly increasing".to_string(),
            ));
        }
        if index.last().is_some_and(|&i| i >= slots.len()) {
            return Err(Error::InvalidArgument(
                "state index out of range".to_string(),
            ));
        }
        Ok(IndexedStates { slots, index })
    }

    /// The indices, one per contact: strictly increasing and each below `slots().len()`
    /// (checked by [`IndexedStates::new`]; neither can change while `self` lives).
    pub fn index(&self) -> &[usize] {
        self.index
    }

    /// The whole array of slots, indexed or not.
    pub fn slots(&self) -> &[S] {
        self.slots
    }

    /// The whole array of slots, indexed or not, writable.
    pub fn slots_mut(&mut self) -> &mut [S] {
        self.slots
    }

    /// The slots of contacts `c..c + GROUP`, split off the slots one after the other: `new`
    /// checked that the indices increase and stay in range, so no split fails. (The standard
    /// `get_disjoint_mut`, which compares every pair of indices, and `array::map` were both left
    /// out of line by LLVM in the kernels: a call per group, which `scripts/check_kernels.sh`
    /// now refuses.)
    #[inline(always)]
    fn group_mut(&mut self, c: usize) -> [&mut S; GROUP] {
        const _: () = assert!(GROUP == 8);
        let index: &[usize; GROUP] = self.index[c..c + GROUP].try_into().expect("a group");
        let (mut rest, mut at) = (&mut *self.slots, 0);
        let (r, a) = (&mut rest, &mut at);
        [
            take_slot(r, a, index[0]),
            take_slot(r, a, index[1]),
            take_slot(r, a, index[2]),
            take_slot(r, a, index[3]),
            take_slot(r, a, index[4]),
            take_slot(r, a, index[5]),
            take_slot(r, a, index[6]),
            take_slot(r, a, index[7]),
        ]
    }
}

/// Whether each index is greater than the one before: every pair of a chunk compared without
/// an early exit, which runs 4.6 instructions per index where the short-circuiting `all` ran 7
/// (`scripts/count_instructions.sh`; a host passes a million indices per step).
fn strictly_increasing(index: &[usize]) -> bool {
    const CHUNK: usize = 256;
    if index.len() < 2 {
        return true;
    }
    let (head, tail) = (&index[..index.len() - 1], &index[1..]);
    head.chunks(CHUNK)
        .zip(tail.chunks(CHUNK))
        .all(|(a, b)| a.iter().zip(b).fold(true, |ok, (x, y)| ok & (x < y)))
}

/// Splits slot `i` off `rest` (whose first slot is slot `at` of the whole array, `at <= i`),
/// leaving the slots after it.
#[inline(always)]
fn take_slot<'a, S>(rest: &mut &'a mut [S], at: &mut usize, i: usize) -> &'a mut S {
    let (_, tail) = std::mem::take(rest).split_at_mut(i - *at);
    let (slot, tail) = tail.split_first_mut().expect("state index in range");
    (*rest, *at) = (tail, i + 1);
    slot
}

impl<S: StateSlot> ContactStates for IndexedStates<'_, S> {
    type Slot = S;
    #[inline(always)]
    fn contacts(&self) -> usize {
        self.index.len()
    }
    #[inline(always)]
    fn get(&self, c: usize) -> &S {
        &self.slots[self.index[c]]
    }
    #[inline(always)]
    fn get_mut(&mut self, c: usize) -> &mut S {
        &mut self.slots[self.index[c]]
    }
    #[inline(always)]
    fn group(&self, c: usize) -> [&S; GROUP] {
        let index: &[usize; GROUP] = self.index[c..c + GROUP].try_into().expect("a group");
        group_of(|k| &self.slots[index[k]])
    }
    #[inline(always)]
    fn store_group<P, X: GroupCopy<P, S>>(
        &mut self,
        copy: X,
        rows: [&GroupRow; STATE_WORDS],
        slip: &[u32; GROUP],
        c: usize,
    ) {
        copy.store_states_at(rows, slip, self.group_mut(c));
    }
    #[inline(always)]
    fn touch(&self, c: usize) {
        if let Some(&i) = self.index.get(c) {
            S::touch_in(self.slots, i);
        }
    }
    fn bytes(&self) -> usize {
        size_of_val(self.index) + self.index.len().min(self.slots.len()) * size_of::<S>()
    }
}

/// [`IndexedStates`] of C states, whose groups the batch kernels reach without a bounds check
/// per state; what `rsl_batch_step_indexed` steps.
///
/// [`IndexedStates`] finds each group's eight states with a bounds check per state and hands
/// them out as `&mut` by splitting the array eight times, since safe Rust cannot know that its
/// indices increase. That cost 20 instructions per contact on top of the contiguous call
/// (double AVX2, rolling + twisting, in cache; `scripts/count_instructions.sh`).
/// `IndexedGroups` wraps it and forms each group's addresses straight from the indices, which
/// [`IndexedStates::new`] has checked: every index below the array's length and each greater
/// than the one before, so the eight states of a group are distinct.
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

/// C states in contact order or through an index, chosen by the call ([`IndexedGroups`] when
/// the host gives indices): what `rsl_batch_step_walls` steps, one kernel for both (a branch per
/// group on which, always the same within a call).
pub enum OrderedOrIndexed<'a> {
    /// `states[c]` for contact `c`.
    Ordered(&'a mut [rsl_contact_state]),
    /// `states[index[c]]`.
    Indexed(IndexedGroups<'a>),
}

impl ContactStates for OrderedOrIndexed<'_> {
    type Slot = rsl_contact_state;
    #[inline(always)]
    fn contacts(&self) -> usize {
        match self {
            Self::Ordered(s) => s.contacts(),
            Self::Indexed(s) => s.contacts(),
        }
    }
    #[inline(always)]
    fn get(&self, c: usize) -> &rsl_contact_state {
        match self {
            Self::Ordered(s) => ContactStates::get(s, c),
            Self::Indexed(s) => s.get(c),
        }
    }
    #[inline(always)]
    fn get_mut(&mut self, c: usize) -> &mut rsl_contact_state {
        match self {
            Self::Ordered(s) => ContactStates::get_mut(s, c),
            Self::Indexed(s) => s.get_mut(c),
        }
    }
    #[inline(always)]
    fn group(&self, c: usize) -> [&rsl_contact_state; GROUP] {
        match self {
            Self::Ordered(s) => ContactStates::group(s, c),
            Self::Indexed(s) => s.group(c),
        }
    }
    #[inline(always)]
    fn store_group<P, X: GroupCopy<P, rsl_contact_state>>(
        &mut self,
        copy: X,
        rows: [&GroupRow; STATE_WORDS],
        slip: &[u32; GROUP],
        c: usize,
    ) {
        match self {
            Self::Ordered(s) => s.store_group(copy, rows, slip, c),
            Self::Indexed(s) => s.store_group(copy, rows, slip, c),
        }
    }
    #[inline(always)]
    fn touch(&self, c: usize) {
        match self {
            Self::Ordered(s) => ContactStates::touch(s, c),
            Self::Indexed(s) => s.touch(c),
        }
    }
    fn bytes(&self) -> usize {
        match self {
            Self::Ordered(s) => s.bytes(),
            Self::Indexed(s) => s.bytes(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::laws::step::ContactState;
    use crate::scalar::Vec3;

    fn state(x: f64) -> ContactState<f64> {
        ContactState {
            sliding_spring: Vec3::new(x, 0.0, 0.0),
            ..ContactState::default()
        }
    }

    #[test]
    fn indices_must_increase_and_stay_in_range() {
        let mut slots = vec![state(0.0); 4];
        assert!(IndexedStates::new(&mut slots, &[0, 2, 3]).is_ok());
        assert!(IndexedStates::new(&mut slots, &[]).is_ok());
        assert!(IndexedStates::new(&mut slots, &[0, 2, 2]).is_err());
        assert!(IndexedStates::new(&mut slots, &[1, 0]).is_err());
        assert!(IndexedStates::new(&mut slots, &[0, 4]).is_err());
    }

    /// The chunked test agrees with the pairwise definition wherever a violation falls (first
    /// pair, either side of a chunk boundary, last pair) and for lengths 0 to 3 chunks.
    #[test]
    fn increasing_test_finds_every_violation() {
        let pairwise = |index: &[usize]| index.windows(2).all(|w| w[0] < w[1]);
        for n in [0, 1, 2, 255, 256, 257, 258, 513, 768] {
            let rising: Vec<usize> = (0..n).map(|i| 10 + 3 * i).collect();
            assert!(strictly_increasing(&rising), "{n}");
            for at in [1, 255, 256, 257, 512, n.saturating_sub(1)] {
                if at == 0 || at >= n {
                    continue;
                }
                for drop in [0, 3, 4] {
                    let mut bad = rising.clone();
                    bad[at] = bad[at - 1] + 3 - drop;
                    assert_eq!(strictly_increasing(&bad), pairwise(&bad), "{n} {at} {drop}");
                }
            }
        }
    }

    #[test]
    fn a_group_is_the_indexed_slots_in_order() {
        let mut slots: Vec<ContactState<f64>> = (0..20).map(|i| state(i as f64)).collect();
        let index = [1, 2, 4, 7, 8, 11, 15, 19];
        let mut states = IndexedStates::new(&mut slots, &index).unwrap();
        let read = states.group(0).map(|s| s.sliding_spring.x);
        assert_eq!(read, [1.0, 2.0, 4.0, 7.0, 8.0, 11.0, 15.0, 19.0]);
        for (k, s) in states.group_mut(0).into_iter().enumerate() {
            s.sliding_spring.y = k as f64;
        }
        assert_eq!(states.get(3).sliding_spring.y, 3.0);
        assert_eq!(slots[7].sliding_spring.y, 3.0);
        assert_eq!(slots[3].sliding_spring.y, 0.0);
    }
}
