//! Batch kernels: many contacts per call, for the hot loop of a DEM code.
//!
//! The kernels run **the same generic functions** as the per-contact path
//! ([`pair_geometry_unchecked`], [`decompose_pair_with_geometry`],
//! [`contact_step_with_geometry`](crate::laws::step::contact_step_with_geometry)), instantiated
//! for a lane type ([`Lanes`]: `f64`, `f32`, or a SIMD pack of 4 to 16 contacts), so a batch
//! result equals the per-contact result of the same precision. The model's law choices are
//! taken once per call, never per contact.
//!
//! Two ways to feed them ([`StepAccess`], [`DecomposeAccess`]):
//! - particle-major ([`ParticleSteps`], [`ParticleDecompose`]): particle array + contact index
//!   pairs; loads are accumulated into per-particle force and torque arrays, in contact order;
//! - contact-major ([`ContactSteps`], [`ContactDecompose`]): bodies pre-gathered per contact,
//!   results written per contact (no two contacts touch the same output: safe to split a range
//!   of contacts across threads).
//!
//! Mixed precision: the `f32` kernels compute the geometry (branch vector, distance, overlap,
//! branch lengths, normal) in `f64` from the `f64` positions, then the rates, the history
//! transport and update, and the loads in `f32`; the histories are stored in the host's `f64`
//! state (each step re-reads them, so they carry `f32` rounding: about 6e-8 relative per step).
//!
//! Bad input, one pass: each contact is checked (indices, finite inputs and state, radii,
//! coincident centres, branch lengths, normal force, finite results, and finite energy terms
//! when the model tracks energy) lane-wise. An invalid contact is skipped: its state and
//! outputs are untouched; the others are processed. The [`BatchReport`] counts the failures
//! and gives the first failing contact with the error the per-contact checked call would give
//! for it.
//!
//! Where the parts are: [`block`] the staged step kernel, [`dispatch`] the kernel choice and CPU
//! dispatch (what the C layer calls), [`lanes`] the lane types (the x86-64 ones, and the SIMD
//! copiers of the C structs, in the private module `x86`), [`history`] the packed history
//! records, [`states`] where a step finds each contact's state; the slot traits of the C layouts
//! ([`crate::layout`]) and the prefetch hints are in the private modules `c_slots` and `prefetch`.

pub mod block;
mod c_slots;
pub mod dispatch;
pub mod history;
pub mod lanes;
mod prefetch;
pub mod states;
#[cfg(target_arch = "x86_64")]
mod x86;

#[cfg(all(test, target_arch = "x86_64"))]
pub(crate) use block::state_words;
// For the SIMD copiers of `x86::transpose`, which exist on x86-64 only.
#[cfg(target_arch = "x86_64")]
pub(crate) use block::{
    group_of, pair_bodies_by_reference, store_loads_by_value, walls_by_value, BODY_WORDS,
};
pub use block::{step_kernel, GroupCopy, GroupRow, GroupRowsMut, LoadRows, PortableCopy};
pub(crate) use block::{GROUP, STATE_WORDS, WALL_WORDS};
pub use dispatch::{run_decompose, run_history_step, run_step, BatchConfig, Simd};
pub use history::Record;
pub use lanes::{Lanes, MAX_LANES};
pub use states::{ContactStates, IndexedGroups, IndexedStates, OrderedOrIndexed};

use crate::decompose::{
    decompose_pair, decompose_pair_with_geometry, Decomposition, Parts, Sphere, Wall,
};
use crate::error::Error;
use crate::geometry::{
    pair_geometry_unchecked, pair_geometry_valid, ContactGeometry, GeometryOptions,
};
use crate::laws::checked::{contact_step_pair, contact_step_wall};
use crate::laws::materials::Coefficients;
pub use crate::laws::materials::Materials;
use crate::laws::model::{Model, RollingDamping, RollingLaw};
use crate::laws::step::{ContactState, StepInput};
use crate::scalar::{finite_probe as probe, zero_if_finite as zf, Vec3};
use simba::simd::SimdBool;

/// Slip bit of the sliding limit (same value as `RSL_SLIP_SLIDING`).
pub const SLIP_SLIDING: u32 = 1;
/// Slip bit of the rolling limit.
pub const SLIP_ROLLING: u32 = 2;
/// Slip bit of the twisting limit.
pub const SLIP_TWISTING: u32 = 4;

/// Reads one sphere from the host's storage.
pub trait SphereSlot {
    /// The sphere in `f64`.
    fn sphere(&self) -> Sphere<f64>;
    /// Starts loading the slot into the cache (see [`Gather::touch`]). The default loads its
    /// first and last word into `black_box` (safe code has no prefetch instruction); the C
    /// types override it with a real prefetch.
    #[inline(always)]
    fn touch(&self) {
        let s = self.sphere();
        std::hint::black_box(s.position.x);
        std::hint::black_box(s.radius);
    }
    /// Touches `slots[i]` when it exists (the C types prefetch without the bounds check: a
    /// prefetch of any address is harmless).
    #[inline(always)]
    fn touch_in(slots: &[Self], i: usize)
    where
        Self: Sized,
    {
        touch_present(slots, i, Self::touch);
    }
}

/// `touch(&slots[i])` when `i` is in range: the default of the slot traits' `touch_in`.
#[inline(always)]
fn touch_present<T>(slots: &[T], i: usize, touch: impl Fn(&T)) {
    if let Some(s) = slots.get(i) {
        touch(s);
    }
}

/// The host's per-contact history.
pub trait StateSlot {
    /// Reads the state.
    fn load(&self) -> ContactState<f64>;
    /// Writes the state after a successful step, with the `SLIP_*` bits of the step.
    fn store(&mut self, state: &ContactState<f64>, slip: u32);
    /// Starts loading the slot (see [`Gather::touch`]); the default does nothing (a state
    /// array is read in order, which the hardware prefetcher follows on its own).
    #[inline(always)]
    fn touch(&self) {}
    /// Touches `slots[i]` when it exists (see [`SphereSlot::touch_in`]).
    #[inline(always)]
    fn touch_in(slots: &[Self], i: usize)
    where
        Self: Sized,
    {
        touch_present(slots, i, Self::touch);
    }
}

/// A 3-vector accumulator of the host (force or torque of a particle).
pub trait AddSlot {
    /// `self += v`.
    fn add(&mut self, v: [f64; 3]);
    /// The value.
    fn get(&self) -> [f64; 3];
    /// Overwrites the value.
    fn set(&mut self, v: [f64; 3]);
    /// Loads the slot (see [`Gather::touch`]).
    fn touch(&self);
    /// Touches `slots[i]` when it exists (see [`SphereSlot::touch_in`]).
    #[inline(always)]
    fn touch_in(slots: &[Self], i: usize)
    where
        Self: Sized,
    {
        touch_present(slots, i, Self::touch);
    }
}

impl AddSlot for [f64; 3] {
    #[inline(always)]
    fn add(&mut self, v: [f64; 3]) {
        self[0] += v[0];
        self[1] += v[1];
        self[2] += v[2];
    }
    #[inline(always)]
    fn get(&self) -> [f64; 3] {
        *self
    }
    #[inline(always)]
    fn set(&mut self, v: [f64; 3]) {
        *self = v;
    }
    #[inline(always)]
    fn touch(&self) {
        std::hint::black_box(self[0]);
    }
}

impl SphereSlot for Sphere<f64> {
    #[inline(always)]
    fn sphere(&self) -> Sphere<f64> {
        *self
    }
}

/// How the kernels read a wall of a sphere-wall contact (the C `rsl_wall`, or [`Wall`]).
pub trait WallSlot {
    /// The wall's values in `WALL_WORDS` order: point, normal (as given), velocity,
    /// angular velocity.
    fn words(&self) -> [f64; WALL_WORDS];
    /// The wall as its `WALL_WORDS` doubles in memory, when it is laid out so (the C
    /// `rsl_wall`): the SIMD copiers then transpose it. `None` (the default): copied value by
    /// value.
    #[inline(always)]
    fn doubles(&self) -> Option<&[f64; WALL_WORDS]> {
        None
    }
    /// The wall in `f64`, its normal as given.
    #[inline(always)]
    fn wall(&self) -> Wall<f64> {
        let w = self.words();
        let v = |q: usize| Vec3::new(w[q], w[q + 1], w[q + 2]);
        Wall {
            point: v(0),
            normal: v(3),
            velocity: v(6),
            angular_velocity: v(9),
        }
    }
    /// Starts loading `slots[i]` when it exists (see [`SphereSlot::touch_in`]).
    #[inline(always)]
    fn touch_in(slots: &[Self], i: usize)
    where
        Self: Sized,
    {
        touch_present(slots, i, |w| {
            std::hint::black_box(w.words()[0]);
        });
    }
}

impl WallSlot for Wall<f64> {
    #[inline(always)]
    fn words(&self) -> [f64; WALL_WORDS] {
        let (p, n, v, w) = (
            &self.point,
            &self.normal,
            &self.velocity,
            &self.angular_velocity,
        );
        [p.x, p.y, p.z, n.x, n.y, n.z, v.x, v.y, v.z, w.x, w.y, w.z]
    }
}

impl StateSlot for ContactState<f64> {
    #[inline(always)]
    fn load(&self) -> ContactState<f64> {
        *self
    }
    #[inline(always)]
    fn store(&mut self, state: &ContactState<f64>, _slip: u32) {
        *self = *state;
    }
}

/// Loads of one contact: force on body 1 (body 2 gets `-force1`) and torques on both bodies.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PairLoads {
    /// Force on body 1.
    pub force1: [f64; 3],
    /// Torque on body 1 about its centre.
    pub torque1: [f64; 3],
    /// Torque on body 2 about its centre.
    pub torque2: [f64; 3],
}

/// Number of energy terms of a step ([`EnergyTerms`]).
pub const ENERGY_TERMS: usize = 11;

/// The energy terms of one contact step in the order of the C `rsl_contact_energy` (load times
/// length): elastic energy after the step in the sliding, rolling and twisting springs; the
/// energy dissipated this step by the sliding, rolling and twisting dashpots; by the sliding,
/// rolling and twisting sliders; the change of elastic energy the transport of the springs
/// made; the change their stiffness changes made. See
/// [`StepEnergy`](crate::laws::step::StepEnergy).
pub type EnergyTerms = [f64; ENERGY_TERMS];

/// [`EnergyTerms`] of a step's energy (in its lane type).
#[inline(always)]
pub fn energy_terms<T: Copy>(e: &crate::laws::step::StepEnergy<T>) -> [T; ENERGY_TERMS] {
    let (s, r, t) = (&e.sliding, &e.rolling, &e.twisting);
    [
        s.elastic,
        r.elastic,
        t.elastic,
        s.dashpot,
        r.dashpot,
        t.dashpot,
        s.slider,
        r.slider,
        t.slider,
        e.transport,
        e.stiffness,
    ]
}

/// A per-contact output slot of the contact-major step.
pub trait LoadsSlot {
    /// Writes the loads of a successful step.
    fn set(&mut self, loads: &PairLoads);
    /// The slot as nine doubles in place (force 1, torque 1, torque 2), when it is laid out
    /// so: a SIMD delivery then writes a group of slots by transposition. `None` by default.
    #[inline(always)]
    fn words_mut(&mut self) -> Option<&mut [f64; 9]> {
        None
    }
}

impl PairLoads {
    /// The loads in slot `i` of nine load rows, one per component: force on body 1 (rows
    /// 0..3), torque on body 1 (3..6), torque on body 2 (6..9).
    #[inline(always)]
    pub(crate) fn in_slot<R: std::ops::Index<usize, Output = f64>>(
        rows: [&R; 9],
        i: usize,
    ) -> Self {
        PairLoads {
            force1: [rows[0][i], rows[1][i], rows[2][i]],
            torque1: [rows[3][i], rows[4][i], rows[5][i]],
            torque2: [rows[6][i], rows[7][i], rows[8][i]],
        }
    }
}

impl LoadsSlot for PairLoads {
    #[inline(always)]
    fn set(&mut self, loads: &PairLoads) {
        *self = *loads;
    }
}

/// A per-contact output slot of a decomposition batch.
pub trait DecompositionSlot {
    /// Writes the decomposition of a valid contact.
    fn set(&mut self, d: &Decomposition<f64>);
}

impl DecompositionSlot for Decomposition<f64> {
    #[inline(always)]
    fn set(&mut self, d: &Decomposition<f64>) {
        *self = *d;
    }
}

/// Outcome of a batch call.
#[derive(Debug, Default)]
pub struct BatchReport {
    /// Contacts processed (state and outputs written).
    pub processed: usize,
    /// Contacts skipped as invalid (state and outputs untouched).
    pub failed: usize,
    /// Index of the first skipped contact.
    pub first_failed: Option<usize>,
    /// Why the first skipped contact failed (the per-contact checked call's error).
    pub first_error: Option<Error>,
}

impl BatchReport {
    #[cold]
    #[inline(never)]
    fn fail(&mut self, contact: usize, why: impl FnOnce() -> Error) {
        self.failed += 1;
        if self.first_failed.is_none() {
            self.first_failed = Some(contact);
            self.first_error = Some(why());
        }
    }
}

/// How the kernels reach the two bodies of a contact without copying them.
pub trait Gather {
    /// The sphere slot type.
    type P: SphereSlot;
    /// False when body references cannot be formed (contacts but no particle): every contact
    /// then fails as out of range.
    fn gatherable(&self) -> bool;
    /// The two bodies of contact `c`, always readable (an out-of-range index is clamped to a
    /// valid particle), and whether the contact's indices were in range.
    fn body_refs(&self, c: usize) -> (&Self::P, &Self::P, bool);
    /// Starts loading what contact `c` (possibly `>= len()`: nothing) will read from scattered
    /// places, so that the cache misses of several contacts overlap. Safe code cannot issue a
    /// prefetch instruction; a load whose value goes to `black_box` does the same job.
    #[inline(always)]
    fn touch(&self, _c: usize) {}
    /// The part of what contact `c` will read that lies in contact order (its state, and body
    /// 1's data, shared by consecutive contacts of a neighbour list), when [`Gather::touch`]
    /// leaves it out: the block kernels issue these after each lane step, among the arithmetic,
    /// and [`Gather::touch`] a group at a time while gathering. The default touches nothing
    /// (`touch` covers everything).
    #[inline(always)]
    fn touch_in_order(&self, _c: usize) {}
    /// Bytes of every host array the call reads or writes.
    fn footprint(&self) -> usize;
    /// Whether the kernels call [`Gather::touch`] and [`Gather::touch_in_order`]: only for
    /// calls of at least [`PREFETCH_MIN_BYTES`].
    #[inline(always)]
    fn prefetching(&self) -> bool {
        self.footprint() >= PREFETCH_MIN_BYTES
    }
}

/// The references of one group of contacts ([`StepAccess::group_refs`]).
pub struct GroupRefs<'a, P, S> {
    /// Body 1 of each slot.
    pub body1: [&'a P; block::GROUP],
    /// Body 2 of each slot.
    pub body2: [&'a P; block::GROUP],
    /// The state of each slot.
    pub states: [&'a S; block::GROUP],
    /// Bit `k`: slot `k`'s particle indices were in range.
    pub index_ok: u64,
}

/// What the step kernels read and write, per contact index `c < len()`.
pub trait StepAccess: Gather {
    /// The state slot type.
    type State: StateSlot;
    /// True for sphere-wall contacts: body 2's rows hold the wall and the wall's normal its own
    /// rows ([`GroupRowsMut`]), filled by [`StepAccess::copy_group`], and
    /// [`StepAccess::wall_contact`] gives each contact. False (sphere pairs) by default.
    const WALL: bool = false;
    /// The sphere and the wall of contact `c` of a sphere-wall access, `None` when the
    /// contact's particle index is invalid (and for a sphere pair: the default).
    #[inline(always)]
    fn wall_contact(&self, _c: usize) -> Option<(Sphere<f64>, Wall<f64>)> {
        None
    }
    /// Number of contacts.
    fn len(&self) -> usize;
    /// True when there is no contact.
    fn is_empty(&self) -> bool {
        self.len() == 0
    }
    /// The two bodies, or `None` when the contact's particle indices are invalid.
    fn bodies(&self, c: usize) -> Option<(Sphere<f64>, Sphere<f64>)>;
    /// Normal force `f_n` (compressive positive, tensile negative).
    fn normal_force(&self, c: usize) -> f64;
    /// `f_n` of contacts `first..first + GROUP` (all `< len()`), as [`StepAccess::normal_force`]
    /// gives each (the default). The particle- and contact-major accesses copy them from their
    /// slice with one bounds test (`block::group_at`).
    #[inline(always)]
    fn normal_forces(&self, first: usize) -> [f64; GROUP] {
        block::group_of(|k| self.normal_force(first + k))
    }
    /// Normal stiffness `k_n` (read only when the model needs it).
    fn normal_stiffness(&self, c: usize) -> f64;
    /// Per-contact sliding coefficients given instead of the model's (none by default).
    #[inline(always)]
    fn sliding_overrides(&self) -> SlidingOverrides<'_> {
        SlidingOverrides::NONE
    }
    /// The state of contact `c`.
    fn state(&mut self, c: usize) -> &mut Self::State;
    /// The state of contact `c`, read only.
    fn state_ref(&self, c: usize) -> &Self::State;
    /// Writes the states of contacts `c..c + GROUP` (all `< len()`) from `rows` and their slip
    /// flags from `slip`, with `copy`.
    fn store_group<X: GroupCopy<Self::P, Self::State>>(
        &mut self,
        copy: X,
        rows: [&GroupRow; STATE_WORDS],
        slip: &[u32; GROUP],
        c: usize,
    );
    /// Delivers the loads of a successful step of contact `c`.
    fn emit(&mut self, c: usize, loads: &PairLoads);
    /// Where the call returns each stepped contact's energy terms (entry `c` for contact `c`),
    /// if it does; `None` by default.
    #[inline(always)]
    fn energy_out(&mut self) -> Option<&mut [EnergyTerms]> {
        None
    }
    /// The bodies and states of contacts `first..first + n` (`1 <= n <= GROUP`, all
    /// `< len()`), slot `k >= n` repeating the last, and a bit per slot whose particle indices
    /// were in range. The default goes contact by contact ([`Gather::body_refs`],
    /// [`StepAccess::state_ref`]) in a function kept out of line (an access on a hot path
    /// overrides it); the contact-major access takes a whole group from one slice of each
    /// array, one bounds check per array instead of one per element (the particle-major one
    /// overrides [`StepAccess::copy_group`] instead).
    /// `_in_range`: [`StepAccess::indices_in_range`] said every index of the group is in range,
    /// so the access need not test them again.
    #[inline(always)]
    fn group_refs(
        &self,
        first: usize,
        n: usize,
        _in_range: bool,
    ) -> GroupRefs<'_, Self::P, Self::State> {
        group_refs_by_contact(self, first, n)
    }
    /// Copies the bodies and states of contacts `first..first + n` (`1 <= n <= GROUP`, all
    /// `< len()`) into `rows` by `copy`, slot `k >= n` repeating the last, and returns a bit per
    /// slot whose particle indices were in range (`in_range` as for
    /// [`StepAccess::group_refs`]). The default goes through [`StepAccess::group_refs`]; the
    /// particle-major access hands the particle indices to the copier
    /// ([`GroupCopy::pair_bodies`]).
    #[inline(always)]
    fn copy_group<X: GroupCopy<Self::P, Self::State>>(
        &self,
        copy: X,
        first: usize,
        n: usize,
        in_range: bool,
        rows: GroupRowsMut<'_>,
    ) -> u64 {
        copy_group_refs(self, copy, first, n, in_range, rows)
    }
    /// True when every particle index of contacts `first..first + n` (all `< len()`) is known
    /// to be in range; `false` says nothing (the default: each group tests its own). The
    /// particle-major access tests a block's indices at once, on their largest.
    #[inline(always)]
    fn indices_in_range(&self, _first: usize, _n: usize) -> bool {
        false
    }
    /// Delivers the loads of contacts `c0 + k` for each bit `k` of `ok`, in order: the same
    /// as [`StepAccess::emit`] for each (the default), bit for bit.
    #[inline(always)]
    fn emit_run(&mut self, c0: usize, ok: u64, loads: impl Fn(usize) -> PairLoads) {
        let mut bits = ok;
        while bits != 0 {
            let k = bits.trailing_zeros() as usize;
            self.emit(c0 + k, &loads(k));
            bits &= bits - 1;
        }
    }
    /// Delivers the loads of a block, contacts `c0 + k` for each bit `k` of `ok`, in order,
    /// from its [`LoadRows`] (slot `k` of each row). The default goes through
    /// [`StepAccess::emit_run`].
    #[inline(always)]
    fn emit_block<X: GroupCopy<Self::P, Self::State>>(
        &mut self,
        _copy: X,
        c0: usize,
        ok: u64,
        loads: &LoadRows,
    ) {
        self.emit_run(c0, ok, |i| load_at(loads, i));
    }
}

/// [`StepAccess::copy_group`]'s default: the group's references, then a copy from each.
#[inline(always)]
fn copy_group_refs<A: StepAccess + ?Sized, X: GroupCopy<A::P, A::State>>(
    access: &A,
    copy: X,
    first: usize,
    n: usize,
    in_range: bool,
    rows: GroupRowsMut<'_>,
) -> u64 {
    let refs = access.group_refs(first, n, in_range);
    copy.bodies(refs.body1, rows.body1);
    copy.bodies(refs.body2, rows.body2);
    copy.states(refs.states, rows.states);
    refs.index_ok
}

/// The loads of slot `i` of a block's [`LoadRows`].
#[inline(always)]
fn load_at(l: &LoadRows, i: usize) -> PairLoads {
    PairLoads::in_slot(l.each_ref(), i)
}

/// What the decomposition kernels read and write.
pub trait DecomposeAccess: Gather {
    /// Number of contacts.
    fn len(&self) -> usize;
    /// True when there is no contact.
    fn is_empty(&self) -> bool {
        self.len() == 0
    }
    /// The two bodies, or `None` when the contact's particle indices are invalid.
    fn bodies(&self, c: usize) -> Option<(Sphere<f64>, Sphere<f64>)>;
    /// Delivers the decomposition of a valid contact `c`.
    fn emit(&mut self, c: usize, d: &Decomposition<f64>);
}

#[inline(always)]
fn pair_refs<P>(particles: &[P], pair: [u32; 2]) -> (&P, &P, bool) {
    let last = particles.len() - 1;
    let (i, j) = (pair[0] as usize, pair[1] as usize);
    (
        &particles[i.min(last)],
        &particles[j.min(last)],
        i <= last && j <= last,
    )
}

#[inline(always)]
fn pair_bodies<P: SphereSlot>(
    particles: &[P],
    pair: [u32; 2],
) -> Option<(Sphere<f64>, Sphere<f64>)> {
    let a = particles.get(pair[0] as usize)?;
    let b = particles.get(pair[1] as usize)?;
    Some((a.sphere(), b.sphere()))
}

/// Per-contact coefficients of a step call, used instead of the model's: sliding arrays (as
/// `rsl_contact_step` uses `RSL_INPUT_SLIDING_STIFFNESS` and `RSL_INPUT_SLIDING_DAMPING`), e.g.
/// the contact-area-dependent `k_t` and `gamma_t` of Hertz-Mindlin laws, and a table of
/// material pairs with each contact's entry ([`Materials`]). A given array wins over the
/// contact's material for its coefficient.
#[derive(Clone, Copy, Debug, Default)]
pub struct SlidingOverrides<'a> {
    /// `k_t` per contact (force/length, finite, >= 0), or `None` for the model's.
    pub stiffness: Option<&'a [f64]>,
    /// `gamma_t` per contact (force/velocity, finite, >= 0), or `None` for the model's.
    pub damping: Option<&'a [f64]>,
    /// Each contact's material pair, or `None`: the model's coefficients for every contact.
    pub materials: Option<Materials<'a>>,
}

impl SlidingOverrides<'_> {
    /// No override: the model's coefficients for every contact.
    pub const NONE: SlidingOverrides<'static> = SlidingOverrides {
        stiffness: None,
        damping: None,
        materials: None,
    };

    /// The sliding overrides of contact `c`.
    #[inline(always)]
    pub fn at(&self, c: usize) -> (Option<f64>, Option<f64>) {
        (self.stiffness.map(|k| k[c]), self.damping.map(|g| g[c]))
    }

    /// Contact `c`'s material: `None` without a table, `Some(None)` for an index out of range.
    #[inline(always)]
    pub fn material(&self, c: usize) -> Option<Option<&Coefficients>> {
        self.materials.as_ref().map(|m| m.at(c))
    }

    /// Whether each array (when given) has `n` values.
    fn fits(&self, n: usize) -> bool {
        self.stiffness.is_none_or(|k| k.len() == n)
            && self.damping.is_none_or(|g| g.len() == n)
            && self.materials.is_none_or(|m| m.index.len() == n)
    }

    /// The bytes of the given arrays.
    fn bytes(&self) -> usize {
        self.stiffness.map_or(0, size_of_val)
            + self.damping.map_or(0, size_of_val)
            + self.materials.map_or(0, |m| size_of_val(m.index))
    }
}

/// Where a particle-major step takes its per-contact sliding coefficients from: the model
/// ([`ModelSliding`], known when the kernel is compiled) or per-contact arrays
/// ([`SlidingOverrides`], read at run time). They are two types, not one value, so that calls
/// without per-contact coefficients run kernels compiled without them: reading
/// [`SlidingOverrides::NONE`] at run time made most particle-major kernels slower in cache, by up
/// to 27% (docs/performance.md, "Per-contact coefficients").
pub trait SlidingSource: Copy {
    /// The per-contact coefficients.
    fn overrides(&self) -> SlidingOverrides<'_>;
}

/// No per-contact sliding coefficients: the model's for every contact.
#[derive(Clone, Copy, Debug, Default)]
pub struct ModelSliding;

impl SlidingSource for ModelSliding {
    #[inline(always)]
    fn overrides(&self) -> SlidingOverrides<'_> {
        SlidingOverrides::NONE
    }
}

impl SlidingSource for SlidingOverrides<'_> {
    #[inline(always)]
    fn overrides(&self) -> SlidingOverrides<'_> {
        *self
    }
}

/// Particle-major step: particles + index pairs; loads accumulated per particle
/// (`force[i] += F1`, `force[j] -= F1`, `torque[i] += M1`, `torque[j] += M2`).
pub struct ParticleSteps<'a, P, St, V, O = ModelSliding> {
    /// Particles (index space of `pairs`).
    pub particles: &'a [P],
    /// Contacts `(i, j)`: body 1 is particle `i`, body 2 particle `j`.
    pub pairs: &'a [[u32; 2]],
    /// `f_n` per contact.
    pub normal_force: &'a [f64],
    /// `k_n` per contact when the model needs it.
    pub normal_stiffness: Option<&'a [f64]>,
    /// State per contact: a slice in contact order (`&mut [S]`), or the host's own array
    /// through an index per contact ([`IndexedStates`]).
    pub states: St,
    /// Force accumulator per particle.
    pub force: &'a mut [V],
    /// Torque accumulator per particle.
    pub torque: &'a mut [V],
    /// Per-contact sliding coefficients ([`ModelSliding`]: the model's).
    pub sliding: O,
    /// Energy terms per contact ([`EnergyTerms`], contact order), written for each stepped
    /// contact when given (the model must track energy), or `None`.
    pub energy: Option<&'a mut [EnergyTerms]>,
}

impl<P: SphereSlot, St, V: AddSlot, O> ParticleSteps<'_, P, St, V, O> {
    /// Touches particle `idx`'s sphere, force and torque.
    #[inline(always)]
    fn touch_body(&self, idx: usize) {
        P::touch_in(self.particles, idx);
        V::touch_in(self.force, idx);
        V::touch_in(self.torque, idx);
    }
}

impl<'a, P, St: ContactStates, V, O: SlidingSource> ParticleSteps<'a, P, St, V, O> {
    /// Checks that the per-contact arrays have one entry per pair and the per-particle ones one
    /// per particle.
    pub fn check(&self) -> Result<(), Error> {
        let nc = self.pairs.len();
        let np = self.particles.len();
        let ok = self.normal_force.len() == nc
            && self.normal_stiffness.is_none_or(|k| k.len() == nc)
            && self.states.contacts() == nc
            && self.force.len() == np
            && self.torque.len() == np
            && self.sliding.overrides().fits(nc)
            && self.energy.as_ref().is_none_or(|e| e.len() == nc);
        if ok {
            Ok(())
        } else {
            Err(Error::InvalidArgument(
                "batch array lengths do not match".to_string(),
            ))
        }
    }
}

impl<P: SphereSlot, St: ContactStates, V: AddSlot, O: SlidingSource> Gather
    for ParticleSteps<'_, P, St, V, O>
{
    type P = P;
    #[inline(always)]
    fn gatherable(&self) -> bool {
        !self.particles.is_empty()
    }
    #[inline(always)]
    fn body_refs(&self, c: usize) -> (&P, &P, bool) {
        pair_refs(self.particles, self.pairs[c])
    }
    /// Body 2's particle, force and torque: scattered (a neighbour's), so touched while
    /// gathering. Issued among the arithmetic instead, with the rest, they cost the double
    /// AVX-512 kernels 16-27% on permuted particles (workload B).
    #[inline(always)]
    fn touch(&self, c: usize) {
        if let Some(&[_, j]) = self.pairs.get(c) {
            self.touch_body(j as usize);
        }
    }
    /// The state and body 1's particle, force and torque.
    #[inline(always)]
    fn touch_in_order(&self, c: usize) {
        self.states.touch(c);
        if let Some(&[i, _]) = self.pairs.get(c) {
            self.touch_body(i as usize);
        }
    }
    fn footprint(&self) -> usize {
        let n = self.pairs.len();
        reachable_bytes(self.particles, n)
            + size_of_val(self.pairs)
            + size_of_val(self.normal_force)
            + self.normal_stiffness.map_or(0, size_of_val)
            + self.states.bytes()
            + reachable_bytes(self.force, n)
            + reachable_bytes(self.torque, n)
            + self.sliding.overrides().bytes()
    }
}

impl<P: SphereSlot, St: ContactStates, V: AddSlot, O: SlidingSource> StepAccess
    for ParticleSteps<'_, P, St, V, O>
{
    type State = St::Slot;
    #[inline(always)]
    fn len(&self) -> usize {
        self.pairs.len()
    }
    #[inline(always)]
    fn bodies(&self, c: usize) -> Option<(Sphere<f64>, Sphere<f64>)> {
        pair_bodies(self.particles, self.pairs[c])
    }
    #[inline(always)]
    fn normal_force(&self, c: usize) -> f64 {
        self.normal_force[c]
    }
    #[inline(always)]
    fn normal_forces(&self, first: usize) -> [f64; GROUP] {
        block::group_at(self.normal_force, first)
    }
    #[inline(always)]
    fn normal_stiffness(&self, c: usize) -> f64 {
        self.normal_stiffness.map_or(0.0, |k| k[c])
    }
    #[inline(always)]
    fn sliding_overrides(&self) -> SlidingOverrides<'_> {
        self.sliding.overrides()
    }
    #[inline(always)]
    fn state(&mut self, c: usize) -> &mut St::Slot {
        self.states.get_mut(c)
    }
    #[inline(always)]
    fn store_group<X: GroupCopy<P, St::Slot>>(
        &mut self,
        copy: X,
        rows: [&GroupRow; STATE_WORDS],
        slip: &[u32; GROUP],
        c: usize,
    ) {
        self.states.store_group(copy, rows, slip, c);
    }
    #[inline(always)]
    fn state_ref(&self, c: usize) -> &St::Slot {
        self.states.get(c)
    }
    #[inline(always)]
    fn energy_out(&mut self) -> Option<&mut [EnergyTerms]> {
        self.energy.as_deref_mut()
    }
    #[inline(always)]
    fn emit(&mut self, c: usize, l: &PairLoads) {
        let [i, j] = self.pairs[c];
        let (i, j) = (i as usize, j as usize);
        self.force[i].add(l.force1);
        self.force[j].add([-l.force1[0], -l.force1[1], -l.force1[2]]);
        self.torque[i].add(l.torque1);
        self.torque[j].add(l.torque2);
    }
    #[inline(always)]
    fn indices_in_range(&self, first: usize, n: usize) -> bool {
        // One loop over the indices alone, which LLVM compiles to vector maxima. Tested pair by
        // pair in each group it cost about 8.6 instructions per contact, and a maximum per group
        // stayed scalar (LLVM reused the loads of the indices that address the bodies).
        let largest = self.pairs[first..first + n]
            .as_flattened()
            .iter()
            .fold(0, |m, &i| m.max(i));
        (largest as usize) < self.particles.len()
    }
    /// The particle indices go to the copier ([`GroupCopy::pair_bodies`]), which finds the
    /// bodies from them: taking a reference to each body first cost about 20 instructions per
    /// contact in the double AVX2 kernels (a bounds test, a conditional move and an address
    /// per body, and the 24 references moved through the stack).
    #[inline(always)]
    fn copy_group<X: GroupCopy<P, St::Slot>>(
        &self,
        copy: X,
        first: usize,
        n: usize,
        in_range: bool,
        rows: GroupRowsMut<'_>,
    ) -> u64 {
        if n < block::GROUP {
            return copy_group_refs(self, copy, first, n, in_range, rows);
        }
        let pairs: &[[u32; 2]; block::GROUP] = self.pairs[first..first + block::GROUP]
            .try_into()
            .expect("a group of pairs");
        let mut index_ok = lane_bits(block::GROUP);
        if !in_range {
            let len = self.particles.len();
            index_ok = 0;
            for (k, &[i, j]) in pairs.iter().enumerate() {
                index_ok |= (((i as usize) < len && (j as usize) < len) as u64) << k;
            }
        }
        // `gatherable` (checked before any kernel runs): there is a particle.
        copy.pair_bodies(self.particles, pairs, rows.body1, rows.body2);
        copy.states(self.states.group(first), rows.states);
        index_ok
    }
    /// As [`StepAccess::emit`] contact by contact, but body 1's force and torque stay in
    /// registers while consecutive contacts share it (neighbour-list order): loaded once, the
    /// same additions in the same order, stored when body 1 changes. A body 2 equal to the
    /// held body 1 adds to the held sums, so every accumulator sees exactly the sequence of
    /// additions of the contact-by-contact order.
    #[inline(always)]
    fn emit_run(&mut self, c0: usize, ok: u64, loads: impl Fn(usize) -> PairLoads) {
        // One length for both accumulators (`check` makes them equal), so that body 2's index
        // is tested once for the two.
        let n = self.force.len().min(self.torque.len());
        let (forces, torques) = (&mut self.force[..n], &mut self.torque[..n]);
        let pairs = &self.pairs[c0..];
        let mut held = usize::MAX;
        let (mut force, mut torque) = ([0.0; 3], [0.0; 3]);
        let mut bits = ok;
        while bits != 0 {
            let k = bits.trailing_zeros() as usize;
            bits &= bits - 1;
            let l = loads(k);
            let [i, j] = pairs[k];
            let (i, j) = (i as usize, j as usize);
            if i != held {
                if held != usize::MAX {
                    forces[held].set(force);
                    torques[held].set(torque);
                }
                held = i;
                force = forces[i].get();
                torque = torques[i].get();
            }
            let reaction = [-l.force1[0], -l.force1[1], -l.force1[2]];
            for q in 0..3 {
                force[q] += l.force1[q];
                torque[q] += l.torque1[q];
            }
            if j == held {
                for q in 0..3 {
                    force[q] += reaction[q];
                    torque[q] += l.torque2[q];
                }
            } else {
                forces[j].add(reaction);
                torques[j].add(l.torque2);
            }
        }
        if held != usize::MAX {
            forces[held].set(force);
            torques[held].set(torque);
        }
    }
}

/// Sphere-wall step, particle-major: contact `c` is particle `spheres[c]` (body 1) against
/// `walls[c]` (body 2); its loads are accumulated on the particle (`force[i] += F1`,
/// `torque[i] += M1`, in contact order). The wall receives nothing.
pub struct WallSteps<'a, P, W, St, V> {
    /// Particles (index space of `spheres`).
    pub particles: &'a [P],
    /// The particle of each contact.
    pub spheres: &'a [u32],
    /// The wall of each contact (its normal of any non-zero length).
    pub walls: &'a [W],
    /// `f_n` per contact.
    pub normal_force: &'a [f64],
    /// `k_n` per contact when the model needs it.
    pub normal_stiffness: Option<&'a [f64]>,
    /// State per contact ([`ContactStates`]).
    pub states: St,
    /// Force accumulator per particle.
    pub force: &'a mut [V],
    /// Torque accumulator per particle.
    pub torque: &'a mut [V],
    /// Per-contact sliding coefficients and material pairs (none: the model's).
    pub sliding: SlidingOverrides<'a>,
    /// Energy terms per contact, as for [`ParticleSteps::energy`].
    pub energy: Option<&'a mut [EnergyTerms]>,
}

impl<P, W, St: ContactStates, V> WallSteps<'_, P, W, St, V> {
    /// Checks that the per-contact arrays have one entry per contact and the per-particle ones
    /// one per particle.
    pub fn check(&self) -> Result<(), Error> {
        let nc = self.spheres.len();
        let np = self.particles.len();
        let ok = self.walls.len() == nc
            && self.normal_force.len() == nc
            && self.normal_stiffness.is_none_or(|k| k.len() == nc)
            && self.states.contacts() == nc
            && self.force.len() == np
            && self.torque.len() == np
            && self.sliding.fits(nc)
            && self.energy.as_ref().is_none_or(|e| e.len() == nc);
        if ok {
            Ok(())
        } else {
            Err(Error::InvalidArgument(
                "batch array lengths do not match".to_string(),
            ))
        }
    }

    /// Particle `spheres[c]`, clamped to the last particle, and whether it was in range.
    #[inline(always)]
    fn sphere_ref(&self, c: usize) -> (&P, bool) {
        let last = self.particles.len() - 1;
        let i = self.spheres[c] as usize;
        (&self.particles[i.min(last)], i <= last)
    }
}

impl<P: SphereSlot, W: WallSlot, St: ContactStates, V: AddSlot> Gather
    for WallSteps<'_, P, W, St, V>
{
    type P = P;
    #[inline(always)]
    fn gatherable(&self) -> bool {
        !self.particles.is_empty()
    }
    /// The sphere as both bodies (the kernels read the wall through
    /// [`StepAccess::copy_group`]).
    #[inline(always)]
    fn body_refs(&self, c: usize) -> (&P, &P, bool) {
        let (p, ok) = self.sphere_ref(c);
        (p, p, ok)
    }
    /// The state, the wall, and the particle's sphere, force and torque (a host's wall contacts
    /// come in particle order: all in order).
    #[inline(always)]
    fn touch_in_order(&self, c: usize) {
        self.states.touch(c);
        W::touch_in(self.walls, c);
        if let Some(&i) = self.spheres.get(c) {
            let i = i as usize;
            P::touch_in(self.particles, i);
            V::touch_in(self.force, i);
            V::touch_in(self.torque, i);
        }
    }
    fn footprint(&self) -> usize {
        let n = self.spheres.len();
        reachable_bytes(self.particles, n)
            + size_of_val(self.spheres)
            + size_of_val(self.walls)
            + size_of_val(self.normal_force)
            + self.normal_stiffness.map_or(0, size_of_val)
            + self.states.bytes()
            + reachable_bytes(self.force, n)
            + reachable_bytes(self.torque, n)
            + self.sliding.bytes()
    }
}

impl<P: SphereSlot, W: WallSlot, St: ContactStates, V: AddSlot> StepAccess
    for WallSteps<'_, P, W, St, V>
{
    type State = St::Slot;
    const WALL: bool = true;
    #[inline(always)]
    fn wall_contact(&self, c: usize) -> Option<(Sphere<f64>, Wall<f64>)> {
        let sphere = self.particles.get(self.spheres[c] as usize)?;
        Some((sphere.sphere(), self.walls[c].wall()))
    }
    #[inline(always)]
    fn len(&self) -> usize {
        self.spheres.len()
    }
    /// Not used for walls ([`StepAccess::wall_contact`] is): the sphere twice.
    #[inline(always)]
    fn bodies(&self, c: usize) -> Option<(Sphere<f64>, Sphere<f64>)> {
        let s = self.particles.get(self.spheres[c] as usize)?.sphere();
        Some((s, s))
    }
    #[inline(always)]
    fn normal_force(&self, c: usize) -> f64 {
        self.normal_force[c]
    }
    #[inline(always)]
    fn normal_forces(&self, first: usize) -> [f64; GROUP] {
        block::group_at(self.normal_force, first)
    }
    #[inline(always)]
    fn normal_stiffness(&self, c: usize) -> f64 {
        self.normal_stiffness.map_or(0.0, |k| k[c])
    }
    #[inline(always)]
    fn sliding_overrides(&self) -> SlidingOverrides<'_> {
        self.sliding
    }
    #[inline(always)]
    fn state(&mut self, c: usize) -> &mut St::Slot {
        self.states.get_mut(c)
    }
    #[inline(always)]
    fn state_ref(&self, c: usize) -> &St::Slot {
        self.states.get(c)
    }
    #[inline(always)]
    fn store_group<X: GroupCopy<P, St::Slot>>(
        &mut self,
        copy: X,
        rows: [&GroupRow; STATE_WORDS],
        slip: &[u32; GROUP],
        c: usize,
    ) {
        self.states.store_group(copy, rows, slip, c);
    }
    #[inline(always)]
    fn energy_out(&mut self) -> Option<&mut [EnergyTerms]> {
        self.energy.as_deref_mut()
    }
    #[inline(always)]
    fn emit(&mut self, c: usize, l: &PairLoads) {
        let i = self.spheres[c] as usize;
        self.force[i].add(l.force1);
        self.torque[i].add(l.torque1);
    }
    #[inline(always)]
    fn indices_in_range(&self, first: usize, n: usize) -> bool {
        let largest = self.spheres[first..first + n]
            .iter()
            .fold(0, |m, &i| m.max(i));
        (largest as usize) < self.particles.len()
    }
    /// The spheres and states through `copy`; the walls value by value into body 2's rows
    /// (point, velocity, angular velocity) and the normal's rows.
    #[inline(always)]
    fn copy_group<X: GroupCopy<P, St::Slot>>(
        &self,
        copy: X,
        first: usize,
        n: usize,
        in_range: bool,
        rows: GroupRowsMut<'_>,
    ) -> u64 {
        let contact = |k: usize| first + k.min(n - 1);
        let mut index_ok = lane_bits(GROUP);
        if !in_range {
            index_ok = 0;
            for k in 0..GROUP {
                index_ok |= (self.sphere_ref(contact(k)).1 as u64) << k;
            }
        }
        copy.bodies(
            block::group_of(|k| self.sphere_ref(contact(k)).0),
            rows.body1,
        );
        let states = if n == GROUP {
            self.states.group(first)
        } else {
            block::group_of(|k| self.states.get(contact(k)))
        };
        copy.states(states, rows.states);
        let [px, py, pz, vx, vy, vz, wx, wy, wz, _radius] = rows.body2;
        let [nx, ny, nz] = rows.wall_normal;
        let walls = &self.walls[first..first + n];
        copy.walls(
            block::group_of(|k| &walls[k.min(n - 1)]),
            [px, py, pz, nx, ny, nz, vx, vy, vz, wx, wy, wz],
        );
        index_ok
    }
}

/// Contact-major step: bodies pre-gathered per contact, loads written per contact.
pub struct ContactSteps<'a, P, S, O> {
    /// Body 1 of each contact.
    pub body1: &'a [P],
    /// Body 2 of each contact.
    pub body2: &'a [P],
    /// `f_n` per contact.
    pub normal_force: &'a [f64],
    /// `k_n` per contact when the model needs it.
    pub normal_stiffness: Option<&'a [f64]>,
    /// State per contact.
    pub states: &'a mut [S],
    /// Loads per contact.
    pub out: &'a mut [O],
    /// Per-contact sliding coefficients ([`SlidingOverrides::NONE`]: the model's).
    pub sliding: SlidingOverrides<'a>,
    /// Energy terms per contact ([`EnergyTerms`]), written for each stepped contact when given
    /// (the model must track energy), or `None`.
    pub energy: Option<&'a mut [EnergyTerms]>,
}

impl<'a, P, S, O> ContactSteps<'a, P, S, O> {
    /// Checks that every array has one entry per contact.
    pub fn check(&self) -> Result<(), Error> {
        let n = self.body1.len();
        let ok = self.body2.len() == n
            && self.normal_force.len() == n
            && self.normal_stiffness.is_none_or(|k| k.len() == n)
            && self.states.len() == n
            && self.out.len() == n
            && self.sliding.fits(n)
            && self.energy.as_ref().is_none_or(|e| e.len() == n);
        if ok {
            Ok(())
        } else {
            Err(Error::InvalidArgument(
                "batch array lengths do not match".to_string(),
            ))
        }
    }
}

impl<P: SphereSlot, S: StateSlot, O> Gather for ContactSteps<'_, P, S, O> {
    type P = P;
    #[inline(always)]
    fn gatherable(&self) -> bool {
        true
    }
    #[inline(always)]
    fn body_refs(&self, c: usize) -> (&P, &P, bool) {
        (&self.body1[c], &self.body2[c], true)
    }
    /// The arrays are read in order, but the hardware prefetcher alone does not keep the
    /// streams (two bodies, the state read and written, the loads) ahead of the kernel: on
    /// workload A, 1.2 million contacts, full LAMMPS set, AVX-512, the contact-major step took
    /// 41-42 ns per contact without this and 32-33 with it (24 in cache).
    #[inline(always)]
    fn touch(&self, c: usize) {
        S::touch_in(self.states, c);
        P::touch_in(self.body1, c);
        P::touch_in(self.body2, c);
    }
    fn footprint(&self) -> usize {
        size_of_val(self.body1)
            + size_of_val(self.body2)
            + size_of_val(self.normal_force)
            + self.normal_stiffness.map_or(0, size_of_val)
            + size_of_val(&*self.states)
            + size_of_val(&*self.out)
            + self.sliding.bytes()
    }
}

impl<P: SphereSlot, S: StateSlot, O: LoadsSlot> StepAccess for ContactSteps<'_, P, S, O> {
    type State = S;
    #[inline(always)]
    fn len(&self) -> usize {
        self.body1.len()
    }
    #[inline(always)]
    fn bodies(&self, c: usize) -> Option<(Sphere<f64>, Sphere<f64>)> {
        Some((self.body1[c].sphere(), self.body2[c].sphere()))
    }
    #[inline(always)]
    fn normal_force(&self, c: usize) -> f64 {
        self.normal_force[c]
    }
    #[inline(always)]
    fn normal_forces(&self, first: usize) -> [f64; GROUP] {
        block::group_at(self.normal_force, first)
    }
    #[inline(always)]
    fn normal_stiffness(&self, c: usize) -> f64 {
        self.normal_stiffness.map_or(0.0, |k| k[c])
    }
    #[inline(always)]
    fn sliding_overrides(&self) -> SlidingOverrides<'_> {
        self.sliding
    }
    #[inline(always)]
    fn state(&mut self, c: usize) -> &mut S {
        &mut self.states[c]
    }
    #[inline(always)]
    fn store_group<X: GroupCopy<P, S>>(
        &mut self,
        copy: X,
        rows: [&GroupRow; STATE_WORDS],
        slip: &[u32; GROUP],
        c: usize,
    ) {
        self.states.store_group(copy, rows, slip, c);
    }
    #[inline(always)]
    fn state_ref(&self, c: usize) -> &S {
        &self.states[c]
    }
    #[inline(always)]
    fn energy_out(&mut self) -> Option<&mut [EnergyTerms]> {
        self.energy.as_deref_mut()
    }
    #[inline(always)]
    fn emit(&mut self, c: usize, l: &PairLoads) {
        self.out[c].set(l);
    }
    /// Each group of `block::GROUP` valid contacts has its loads written by `copy`
    /// ([`GroupCopy::store_loads`]), the others contact by contact.
    #[inline(always)]
    fn emit_block<X: GroupCopy<P, S>>(&mut self, copy: X, c0: usize, ok: u64, loads: &LoadRows) {
        let whole = lane_bits(block::GROUP);
        for g in (0..loads[0].len()).step_by(block::GROUP) {
            let bits = (ok >> g) & whole;
            if bits == whole {
                let rows = loads.each_ref().map(|row| {
                    <&[f64; block::GROUP]>::try_from(&row[g..g + block::GROUP]).expect("a group")
                });
                let out: &mut [O; block::GROUP] = (&mut self.out[c0 + g..c0 + g + block::GROUP])
                    .try_into()
                    .expect("a group of outputs");
                copy.store_loads(rows, out);
            } else if bits != 0 {
                self.emit_run(c0 + g, bits, |k| load_at(loads, g + k));
            }
        }
    }
    #[inline(always)]
    fn group_refs(&self, first: usize, n: usize, _in_range: bool) -> GroupRefs<'_, P, S> {
        if n < block::GROUP {
            return group_refs_by_contact(self, first, n);
        }
        let group = first..first + block::GROUP;
        let body1: &[P; block::GROUP] = self.body1[group.clone()].try_into().expect("a group");
        let body2: &[P; block::GROUP] = self.body2[group.clone()].try_into().expect("a group");
        let states: &[S; block::GROUP] = self.states[group].try_into().expect("a group");
        GroupRefs {
            body1: block::group_of(|k| &body1[k]),
            body2: block::group_of(|k| &body2[k]),
            states: block::group_of(|k| &states[k]),
            index_ok: lane_bits(block::GROUP),
        }
    }
}

/// [`StepAccess::group_refs`]' default, contact by contact: the particle- and contact-major
/// accesses call it only for a call's last group when it is partial, so it stays out of line
/// (inlined, it grew each SIMD kernel by about 700 instructions, and the AVX-512 kernels took
/// 7-31% more time).
#[cold]
#[inline(never)]
fn group_refs_by_contact<A: StepAccess + ?Sized>(
    access: &A,
    first: usize,
    n: usize,
) -> GroupRefs<'_, A::P, A::State> {
    let c = |k: usize| first + k.min(n - 1);
    let mut index_ok = 0;
    for k in 0..block::GROUP {
        index_ok |= (access.body_refs(c(k)).2 as u64) << k;
    }
    GroupRefs {
        body1: block::group_of(|k| access.body_refs(c(k)).0),
        body2: block::group_of(|k| access.body_refs(c(k)).1),
        states: block::group_of(|k| access.state_ref(c(k))),
        index_ok,
    }
}

/// Particle-major decomposition: particles + index pairs, one decomposition per contact.
pub struct ParticleDecompose<'a, P, D> {
    /// Particles.
    pub particles: &'a [P],
    /// Contacts `(i, j)`.
    pub pairs: &'a [[u32; 2]],
    /// Output per contact.
    pub out: &'a mut [D],
}

impl<P: SphereSlot, D> Gather for ParticleDecompose<'_, P, D> {
    type P = P;
    #[inline(always)]
    fn gatherable(&self) -> bool {
        !self.particles.is_empty()
    }
    #[inline(always)]
    fn body_refs(&self, c: usize) -> (&P, &P, bool) {
        pair_refs(self.particles, self.pairs[c])
    }
    #[inline(always)]
    fn touch(&self, c: usize) {
        if let Some(&[i, j]) = self.pairs.get(c) {
            for idx in [i as usize, j as usize] {
                P::touch_in(self.particles, idx);
            }
        }
    }
    fn footprint(&self) -> usize {
        reachable_bytes(self.particles, self.pairs.len())
            + size_of_val(self.pairs)
            + size_of_val(&*self.out)
    }
}

impl<P: SphereSlot, D: DecompositionSlot> DecomposeAccess for ParticleDecompose<'_, P, D> {
    #[inline(always)]
    fn len(&self) -> usize {
        self.pairs.len()
    }
    #[inline(always)]
    fn bodies(&self, c: usize) -> Option<(Sphere<f64>, Sphere<f64>)> {
        pair_bodies(self.particles, self.pairs[c])
    }
    #[inline(always)]
    fn emit(&mut self, c: usize, d: &Decomposition<f64>) {
        self.out[c].set(d);
    }
}

/// Contact-major decomposition: bodies pre-gathered per contact.
pub struct ContactDecompose<'a, P, D> {
    /// Body 1 of each contact.
    pub body1: &'a [P],
    /// Body 2 of each contact.
    pub body2: &'a [P],
    /// Output per contact.
    pub out: &'a mut [D],
}

impl<P: SphereSlot, D> Gather for ContactDecompose<'_, P, D> {
    type P = P;
    #[inline(always)]
    fn gatherable(&self) -> bool {
        true
    }
    #[inline(always)]
    fn body_refs(&self, c: usize) -> (&P, &P, bool) {
        (&self.body1[c], &self.body2[c], true)
    }
    fn footprint(&self) -> usize {
        size_of_val(self.body1) + size_of_val(self.body2) + size_of_val(&*self.out)
    }
}

impl<P: SphereSlot, D: DecompositionSlot> DecomposeAccess for ContactDecompose<'_, P, D> {
    #[inline(always)]
    fn len(&self) -> usize {
        self.body1.len()
    }
    #[inline(always)]
    fn bodies(&self, c: usize) -> Option<(Sphere<f64>, Sphere<f64>)> {
        Some((self.body1[c].sphere(), self.body2[c].sphere()))
    }
    #[inline(always)]
    fn emit(&mut self, c: usize, d: &Decomposition<f64>) {
        self.out[c].set(d);
    }
}

/// Whether the model reads `k_n` per contact (see [`Model::needs_normal_stiffness`]).
pub fn needs_normal_stiffness(model: &Model) -> bool {
    model.needs_normal_stiffness()
}

/// Checks that a model can run in a batch: the batch passes only `f_n`, `dt` and optionally
/// `k_n` per contact, so damping-ratio rolling damping (masses, inertias) is refused.
pub fn check_batch_model(model: &Model) -> Result<(), Error> {
    model.validate()?;
    if model.rolling.law == RollingLaw::Epsd && model.rolling.damping_rule == RollingDamping::Ratio
    {
        return Err(Error::InvalidArgument(
            "batch step: damping-ratio rolling damping needs masses per contact; use \
             rsl_contact_step"
                .to_string(),
        ));
    }
    Ok(())
}

/// Checks the time step of a batch call.
pub fn check_time_step(dt: f64) -> Result<(), Error> {
    if dt.is_finite() && dt > 0.0 {
        Ok(())
    } else {
        Err(Error::InvalidTimeStep)
    }
}

#[inline(always)]
fn vec_lanes<L: Lanes>(f: impl Fn(usize) -> Vec3<f64>) -> Vec3<L> {
    Vec3::new(
        L::from_fn(|k| f(k).x),
        L::from_fn(|k| f(k).y),
        L::from_fn(|k| f(k).z),
    )
}

#[inline(always)]
fn conv3<L: Lanes>(lo: &Vec3<L::Geo>, hi: &Vec3<L::Geo>) -> Vec3<L> {
    Vec3::new(
        L::from_geo(lo.x, hi.x),
        L::from_geo(lo.y, hi.y),
        L::from_geo(lo.z, hi.z),
    )
}

/// How many contacts ahead of the current chunk the kernels touch the scattered data and the
/// state. Measured at 1M contacts (f64, AVX-512), when the kernel took 51-54 ns per contact:
/// 16 to 96 all gave that; without the state in the prefetch, 87 at every distance. Remeasured
/// on the Zen 5 host of docs/performance.md at 1.2M contacts, where the kernels take 15-18 ns:
/// 24 took 1.15x (double full set) to 1.40x (double rolling + twisting) the time of 48, and 64
/// took 1.01x and 1.02x, single precision's full set 1.22x (alternating runs, medians).
const TOUCH_AHEAD: usize = 48;

/// A call whose host arrays take fewer bytes than this ([`Gather::footprint`]) does not
/// prefetch: its data most likely sits in cache already (the host has just written it, or the
/// previous step read it), where the prefetches only cost instructions. 1 MiB is at most the
/// L2 cache of current x86 cores and well inside any L3. Measured on the Zen 5 host of
/// docs/performance.md (workload A, alternating runs, every SIMD kernel, a build without
/// prefetches against one with): 8-14% less time at 2,000 contacts (about 0.3 MB), 5-11% at
/// 6,000 and 20,000 (1 and 3 MB), 1-6% at 60,000 (10 MB), 9-31% more at 200,000 (32 MB, this
/// CPU's L3) and 30-50% more at 1.2 million.
pub const PREFETCH_MIN_BYTES: usize = 1 << 20;

/// The bytes of a per-particle array that `n_contacts` contacts can reach: at most two
/// particles each. A host that steps a large scene in chunks (a pair style handing over a few
/// hundred contacts at a time with its whole particle array) touches only those, most likely
/// in cache; counting the whole array would make every chunk run the prefetching kernel.
fn reachable_bytes<T>(per_particle: &[T], n_contacts: usize) -> usize {
    size_of::<T>() * per_particle.len().min(n_contacts.saturating_mul(2))
}

/// Bits `0..lanes` set.
#[inline(always)]
fn lane_bits(lanes: usize) -> u64 {
    if lanes >= 64 {
        u64::MAX
    } else {
        (1u64 << lanes) - 1
    }
}

/// The bodies of one chunk of lanes, the geometry in `f64` (one or two halves of the lanes),
/// and the mask of lanes whose inputs are valid.
struct Gathered<L: Lanes> {
    body1: Sphere<L>,
    body2: Sphere<L>,
    geometry: [ContactGeometry<L::Geo>; 2],
    valid: u64,
}

impl<L: Lanes> Gathered<L> {
    /// The geometry in the lane type.
    #[inline(always)]
    fn geometry_in(&self) -> ContactGeometry<L> {
        let [lo, hi] = &self.geometry;
        geometry_in::<L>(lo, hi)
    }
}

/// The geometry in the lane type `L` (rounded to `f32` for the mixed-precision kernels): lanes
/// `0..L::Geo::N` from `lo`, the others (if any) from `hi`.
#[inline(always)]
fn geometry_in<L: Lanes>(
    lo: &ContactGeometry<L::Geo>,
    hi: &ContactGeometry<L::Geo>,
) -> ContactGeometry<L> {
    ContactGeometry {
        normal: conv3::<L>(&lo.normal, &hi.normal),
        distance: L::from_geo(lo.distance, hi.distance),
        overlap: L::from_geo(lo.overlap, hi.overlap),
        branch1: L::from_geo(lo.branch1, hi.branch1),
        branch2: L::from_geo(lo.branch2, hi.branch2),
        rolling_radius: L::from_geo(lo.rolling_radius, hi.rolling_radius),
        contact_point: conv3::<L>(&lo.contact_point, &hi.contact_point),
        branch_rate_factor: L::from_geo(lo.branch_rate_factor, hi.branch_rate_factor),
    }
}

/// Marks every contact failed when the call's index pairs reach outside the particle array
/// (nothing can be gathered); returns true in that case.
fn refuse_ungatherable<A: Gather>(access: &A, n: usize, report: &mut BatchReport) -> bool {
    if n == 0 || access.gatherable() {
        return false;
    }
    for c in 0..n {
        report.fail(c, || {
            Error::InvalidArgument("contact's particle index out of range".to_string())
        });
    }
    true
}

/// The chunk of contacts starting at `c0`: how many lanes are real, each lane's contact index
/// (lanes past the end repeat the last contact; their results are dropped), the two bodies of
/// each lane, and the mask of lanes whose particle indices are in range. Prefetches the chunk
/// `TOUCH_AHEAD` contacts ahead when `PREFETCH` ([`Gather::prefetching`]).
#[inline(always)]
#[allow(clippy::type_complexity)]
fn chunk<const PREFETCH: bool, L: Lanes, A: Gather>(
    access: &A,
    c0: usize,
    n: usize,
) -> (usize, L::Arr<usize>, L::Arr<(&A::P, &A::P)>, u64) {
    let lanes = (n - c0).min(L::N);
    if PREFETCH {
        for k in 0..L::N {
            access.touch(c0 + TOUCH_AHEAD + k);
            access.touch_in_order(c0 + TOUCH_AHEAD + k);
        }
    }
    let mut idx = L::arr(c0);
    for k in 0..L::N {
        idx[k] = c0 + k.min(lanes - 1);
    }
    let first = access.body_refs(c0);
    let mut refs = L::arr((first.0, first.1));
    let mut index_ok = 0u64;
    for k in 0..L::N {
        let (x, y, ok) = access.body_refs(idx[k]);
        refs[k] = (x, y);
        index_ok |= (ok as u64) << k;
    }
    (lanes, idx, refs, index_ok)
}

/// The geometry of lanes `offset..offset + G::N` in `f64` lanes, and the mask (shifted to those
/// lanes) of what `decompose_pair` checks on it: finite positions and radii, radii > 0,
/// `d >= eps (R1 + R2)`, a unit normal, `l1, l2 > 0`.
#[inline(always)]
fn geometry_half<G: Lanes>(
    at: impl Fn(usize) -> (f64, f64, Vec3<f64>, Vec3<f64>),
    offset: usize,
    options: GeometryOptions,
) -> (ContactGeometry<G>, u64) {
    let p1 = vec_lanes::<G>(|k| at(offset + k).2);
    let p2 = vec_lanes::<G>(|k| at(offset + k).3);
    let r1 = G::from_fn(|k| at(offset + k).0);
    let r2 = G::from_fn(|k| at(offset + k).1);
    let g = pair_geometry_unchecked(&p1, &p2, r1, r2, options);
    let ok = pair_geometry_valid(&p1, &p2, r1, r2, &g);
    (g, ok.bitmask() << offset)
}

/// Packs the lanes' bodies (read in place), computes the geometry in `f64` lanes, and validates
/// lane-wise what `decompose_pair` checks (finite input, radii > 0, `d >= eps (R1 + R2)`,
/// `l1, l2 > 0`); velocities are checked finite in the lane precision.
#[inline(always)]
fn gather<L: Lanes, P: SphereSlot>(
    refs: &L::Arr<(&P, &P)>,
    options: GeometryOptions,
) -> Gathered<L> {
    let at = |k: usize| {
        let (a, b) = (refs[k].0.sphere(), refs[k].1.sphere());
        (a.radius, b.radius, a.position, b.position)
    };
    let half = <L::Geo as Lanes>::N;
    let (g0, m0) = geometry_half::<L::Geo>(at, 0, options);
    let (g1, m1) = if L::N > half {
        geometry_half::<L::Geo>(at, half, options)
    } else {
        (g0, 0)
    };
    let v1 = vec_lanes::<L>(|k| refs[k].0.sphere().velocity);
    let v2 = vec_lanes::<L>(|k| refs[k].1.sphere().velocity);
    let w1 = vec_lanes::<L>(|k| refs[k].0.sphere().angular_velocity);
    let w2 = vec_lanes::<L>(|k| refs[k].1.sphere().angular_velocity);
    let mut acc = L::zero();
    for v in [&v1, &v2, &w1, &w2] {
        acc = probe(acc, v);
    }
    let sphere = |p: Vec3<L>, v: Vec3<L>, w: Vec3<L>, r: L| Sphere {
        position: p,
        velocity: v,
        angular_velocity: w,
        radius: r,
    };
    // Positions are not read by the rates or the laws (they use the geometry); they are kept
    // in the lane type for completeness.
    let p1 = vec_lanes::<L>(|k| refs[k].0.sphere().position);
    let p2 = vec_lanes::<L>(|k| refs[k].1.sphere().position);
    Gathered {
        body1: sphere(p1, v1, w1, L::from_fn(|k| refs[k].0.sphere().radius)),
        body2: sphere(p2, v2, w2, L::from_fn(|k| refs[k].1.sphere().radius)),
        geometry: [g0, g1],
        valid: (m0 | m1) & acc.simd_eq(L::zero()).bitmask(),
    }
}

/// Body 2 of a contact the kernel refused, for [`step_error`].
#[derive(Clone, Copy, Debug)]
pub(crate) enum Body2 {
    /// A sphere.
    Sphere(Sphere<f64>),
    /// A wall (its normal as given).
    Wall(Wall<f64>),
}

/// The error the checked per-contact step gives for a contact the kernel refused.
#[cold]
#[allow(clippy::too_many_arguments)]
fn step_error(
    model: &Model,
    dt: f64,
    bodies: Option<(Sphere<f64>, Body2)>,
    f_n: f64,
    k_n: f64,
    sliding: (Option<f64>, Option<f64>),
    material: Option<Option<&Coefficients>>,
    state: &ContactState<f64>,
) -> Error {
    let Some((b1, b2)) = bodies else {
        return Error::InvalidArgument("contact's particle index out of range".to_string());
    };
    // A contact's material pair steps as the model with that pair's coefficients.
    let material_model = match material {
        None => *model,
        Some(None) => {
            return Error::InvalidArgument("contact's material index out of range".to_string())
        }
        Some(Some(set)) => set.model(model),
    };
    let mut input = StepInput::new(f_n, dt);
    input.normal_stiffness = k_n;
    (input.sliding_stiffness, input.sliding_damping) = sliding;
    let mut s = *state;
    let stepped = match b2 {
        Body2::Sphere(b2) => contact_step_pair(&material_model, &b1, &b2, &input, &mut s),
        Body2::Wall(w) => contact_step_wall(&material_model, &b1, &w, &input, &mut s),
    };
    match stepped {
        Err(e) => e,
        Ok(_) => Error::NonFinite("result overflowed in the batch's precision"),
    }
}

/// Values of a decomposition written out per contact: 12 of the geometry, 21 of the rates.
const DECOMPOSITION_ROWS: usize = 33;

/// The decomposition of one chunk, one row of lanes per value, each vector stored once (reading
/// lanes one by one from the vectors would store every vector again for each lane: twice the
/// kernel's time under AVX-512 on Zen 5, measured). Lane `k` of row `r` is the exact value.
#[inline(always)]
fn decomposition_rows<L: Lanes>(
    geometry: &[ContactGeometry<L::Geo>; 2],
    d: &Decomposition<L>,
) -> [[f64; MAX_LANES]; DECOMPOSITION_ROWS] {
    let mut rows = [[0.0; MAX_LANES]; DECOMPOSITION_ROWS];
    let geometry_values = |g: &ContactGeometry<L::Geo>| {
        [
            g.normal.x,
            g.normal.y,
            g.normal.z,
            g.distance,
            g.overlap,
            g.branch1,
            g.branch2,
            g.rolling_radius,
            g.contact_point.x,
            g.contact_point.y,
            g.contact_point.z,
            g.branch_rate_factor,
        ]
    };
    let half = <L::Geo as Lanes>::N;
    let (geometry_rows, rate_rows) = rows.split_at_mut(12);
    for ((row, lo), hi) in geometry_rows
        .iter_mut()
        .zip(geometry_values(&geometry[0]))
        .zip(geometry_values(&geometry[1]))
    {
        lo.store(&mut row[..]);
        if L::N > half {
            hi.store(&mut row[half..]);
        }
    }
    let rates = [
        d.normal_rate,
        d.sliding_velocity.x,
        d.sliding_velocity.y,
        d.sliding_velocity.z,
        d.rolling_velocity.x,
        d.rolling_velocity.y,
        d.rolling_velocity.z,
        d.twisting_rate,
        d.contact_velocity.x,
        d.contact_velocity.y,
        d.contact_velocity.z,
        d.tumbling.x,
        d.tumbling.y,
        d.tumbling.z,
        d.frame_spin,
        d.objective_velocity1.x,
        d.objective_velocity1.y,
        d.objective_velocity1.z,
        d.objective_velocity2.x,
        d.objective_velocity2.y,
        d.objective_velocity2.z,
    ];
    for (row, value) in rate_rows.iter_mut().zip(rates) {
        value.store(&mut row[..]);
    }
    rows
}

/// Lane `k` of the rows of [`decomposition_rows`], as the scalar decomposition.
#[inline(always)]
fn decomposition_of_lane(
    rows: &[[f64; MAX_LANES]; DECOMPOSITION_ROWS],
    k: usize,
) -> Decomposition<f64> {
    let v = |r: usize| rows[r][k];
    let v3 = |r: usize| Vec3::new(v(r), v(r + 1), v(r + 2));
    Decomposition {
        geometry: ContactGeometry {
            normal: v3(0),
            distance: v(3),
            overlap: v(4),
            branch1: v(5),
            branch2: v(6),
            rolling_radius: v(7),
            contact_point: v3(8),
            branch_rate_factor: v(11),
        },
        normal_rate: v(12),
        sliding_velocity: v3(13),
        rolling_velocity: v3(16),
        twisting_rate: v(19),
        contact_velocity: v3(20),
        tumbling: v3(23),
        frame_spin: v(26),
        objective_velocity1: v3(27),
        objective_velocity2: v3(30),
    }
}

/// Decomposes every contact of `access` (lane type `L`; in `f32` lanes the geometry is `f64`
/// and the rates `f32`), touching the contacts ahead when `PREFETCH` (pass
/// [`Gather::prefetching`] of `access`; a constant for the reason given at
/// `block::step_kernel`).
#[inline(always)]
pub fn decompose_kernel<const PREFETCH: bool, L: Lanes, A: DecomposeAccess>(
    options: GeometryOptions,
    parts: Parts,
    access: &mut A,
) -> BatchReport {
    let n = access.len();
    let mut report = BatchReport::default();
    if refuse_ungatherable(&*access, n, &mut report) {
        return report;
    }
    let mut c0 = 0;
    while c0 < n {
        let (lanes, _idx, refs, index_ok) = chunk::<PREFETCH, L, A>(&*access, c0, n);
        let gathered = gather::<L, A::P>(&refs, options);
        let d = decompose_pair_with_geometry(
            gathered.geometry_in(),
            &gathered.body1,
            &gathered.body2,
            parts,
        );
        let mut acc = zf(d.normal_rate) + zf(d.twisting_rate) + zf(d.frame_spin);
        for v in [
            &d.sliding_velocity,
            &d.rolling_velocity,
            &d.contact_velocity,
            &d.tumbling,
            &d.objective_velocity1,
            &d.objective_velocity2,
        ] {
            acc = probe(acc, v);
        }
        let valid = gathered.valid & index_ok & acc.simd_eq(L::zero()).bitmask() & lane_bits(lanes);
        let rows = decomposition_rows(&gathered.geometry, &d);
        for k in 0..lanes {
            let c = c0 + k;
            if valid >> k & 1 == 1 {
                let out = decomposition_of_lane(&rows, k);
                access.emit(c, &out);
                report.processed += 1;
            } else {
                report.fail(c, || match access.bodies(c) {
                    None => {
                        Error::InvalidArgument("contact's particle index out of range".to_string())
                    }
                    Some((b1, b2)) => {
                        decompose_pair(&b1, &b2, options, parts)
                            .err()
                            .unwrap_or(Error::NonFinite(
                                "result overflowed in the batch's precision",
                            ))
                    }
                });
            }
        }
        c0 += lanes;
    }
    report
}
