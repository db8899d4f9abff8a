//! The step kernel, staged through a block of contacts laid out by quantity.
//!
//! A batch step moves more data than it computes on: two bodies (20 doubles), a state (13) and
//! `f_n` in, a state and three load vectors out, per contact. Packing these into SIMD lanes
//! straight from the host's arrays (per-lane pointers, lane inserts and extracts woven through
//! the physics) cost more instructions than the physics itself (measured: about 390 of 624
//! instructions per contact, 4-lane AVX2, LAMMPS law set). So each block of `BLOCK` contacts
//! goes through three simple loops:
//!
//! 1. **gather**: each contact's bodies, state and `f_n` are copied into a `Block`, one row
//!    per quantity (structure of arrays), eight contacts at a time by a [`GroupCopy`] (value by
//!    value, or by SIMD transposition where the C layer supplies one for its structs);
//! 2. **step**: the generic physics runs over the block, `L::N` contacts at a time, with every
//!    lane value one vector load from a row, and writes the new state and the loads back into
//!    rows, with the lane-wise validity and slip masks;
//! 3. **deliver**: each valid contact's state is written and its loads handed to the host
//!    (added to the particles' accumulators, or written per contact); an invalid one is
//!    skipped and reported. The states of eight valid contacts in a row go back through the
//!    [`GroupCopy`] too.
//!
//! The physics, the validation and the rounding are those of the lane-by-lane kernel it
//! replaces: the results are bitwise the same.

use super::{
    conv3, energy_terms, geometry_in, lane_bits, needs_normal_stiffness, step_error, BatchReport,
    Body2, Lanes, LoadsSlot, Materials, PairLoads, SlidingOverrides, StateSlot, StepAccess,
    WallSlot, ENERGY_TERMS, SLIP_ROLLING, SLIP_SLIDING, SLIP_TWISTING, TOUCH_AHEAD,
};
use crate::batch::SphereSlot;
use crate::decompose::Sphere;
use crate::decompose::Wall;
use crate::geometry::{
    pair_geometry_unchecked, pair_geometry_valid, unit_vector_lanes, wall_geometry_unchecked,
    wall_geometry_valid,
};
use crate::laws::materials::{Coefficients, COEFFICIENTS, SLIDING_DAMPING, SLIDING_STIFFNESS};
use crate::laws::model::Model;
use crate::laws::step::{
    contact_step_with_geometry, written_fields, ContactState, Partner, StepInput, StepOutput,
    WrittenFields,
};
use crate::scalar::Vec3;
use simba::simd::SimdBool;

/// Contacts per block: a multiple of every lane count, and small enough that a block's rows
/// (about 11 KB) stay in the L1 cache.
pub(crate) const BLOCK: usize = 32;

/// Contacts per group: the unit in which a [`GroupCopy`] moves data between the host's structs
/// and a block's rows.
pub(crate) const GROUP: usize = 8;

/// Doubles of a body, in this order: position (3), velocity (3), angular velocity (3), radius.
pub(crate) const BODY_WORDS: usize = 10;

/// Doubles of a wall, in this order: point (3), outward normal (3), velocity (3), angular
/// velocity (3) (the order of the C `rsl_wall`).
pub(crate) const WALL_WORDS: usize = 12;

/// Doubles of a state, in the order of [`ContactState`]: sliding spring (3), rolling spring
/// (3), twisting angle, model memory (3), previous normal (3).
pub(crate) const STATE_WORDS: usize = 13;

/// Bit `q` set: word `q` of a state ([`STATE_WORDS`] order) belongs to a field the step can
/// change ([`WrittenFields`]); the step leaves the others as it read them.
pub(crate) fn written_words(f: WrittenFields) -> u16 {
    let bits = |on: bool, first: u32, n: u32| if on { ((1u16 << n) - 1) << first } else { 0 };
    bits(f.sliding_spring, 0, 3)
        | bits(f.rolling_spring, 3, 3)
        | bits(f.twisting_angle, 6, 1)
        | bits(f.model_memory, 7, 3)
        | bits(f.previous_normal, 10, 3)
}

// The group divides the block, and the per-block masks (`u64`) have a bit per contact. (The
// block is a multiple of the lane count: `step_kernel` asserts it for each lane type.)
const _: () = assert!(BLOCK.is_multiple_of(GROUP) && BLOCK <= 64);

/// Eight contacts' values of one quantity (one row's share of a group).
pub type GroupRow = [f64; GROUP];

/// One group's slots of a block's input rows, to fill: the two bodies' (`BODY_WORDS` order)
/// and the state's (`STATE_WORDS` order). For a sphere-wall contact, body 2's rows hold the
/// wall (`WALL_WORDS` order: its point, velocity and angular velocity where a sphere has its
/// centre, velocity and angular velocity) and `wall_normal` its normal as given.
pub struct GroupRowsMut<'a> {
    /// Body 1's rows.
    pub body1: [&'a mut GroupRow; BODY_WORDS],
    /// Body 2's rows.
    pub body2: [&'a mut GroupRow; BODY_WORDS],
    /// The state's rows.
    pub states: [&'a mut GroupRow; STATE_WORDS],
    /// A wall's normal (x, y, z), for sphere-wall contacts; unused for pairs.
    pub wall_normal: [&'a mut GroupRow; 3],
}

/// `[f(0), f(1), ..., f(GROUP - 1)]`, always inlined. `std::array::from_fn` is not: LLVM left
/// it out of line in every SIMD kernel (two calls per group, for the body references), with a
/// bounds check per element and the array passed back through memory.
#[inline(always)]
pub(crate) fn group_of<T>(f: impl Fn(usize) -> T) -> [T; GROUP] {
    const _: () = assert!(GROUP == 8);
    [f(0), f(1), f(2), f(3), f(4), f(5), f(6), f(7)]
}

/// `values[first..first + GROUP]` as an array: one bounds test for the group (value by value,
/// a test each cost about five instructions per contact in the double AVX2 kernels).
#[inline(always)]
pub(crate) fn group_at(values: &[f64], first: usize) -> [f64; GROUP] {
    values[first..first + GROUP]
        .try_into()
        .expect("a group of values")
}

/// How the block moves a group of `GROUP` consecutive contacts between the host's structs
/// (`P` a body, `S` a state) and its rows: row `q`, slot `k` holds word `q` of contact `k`
/// (`BODY_WORDS`, `STATE_WORDS` give the word order). It only copies: every implementation
/// gives the same rows and states bit for bit. [`PortableCopy`] copies value by value; the C
/// layer transposes its own structs with SIMD shuffles.
pub trait GroupCopy<P, S>: Copy {
    /// `rows[q][k]` = word `q` of `bodies[k]`.
    fn bodies(self, bodies: [&P; GROUP], rows: [&mut GroupRow; BODY_WORDS]);
    /// `rows1[q][k]` = word `q` of particle `pairs[k][0]` and `rows2[q][k]` that of particle
    /// `pairs[k][1]`: the bodies of a group of contacts given by particle indices. An index
    /// past the last particle reads the last particle instead (the caller refuses its contact).
    /// `particles` is not empty. The default takes a reference to each body and goes through
    /// [`GroupCopy::bodies`]; the C layer computes the eight offsets of a side in vector
    /// registers instead of one bounds test and one address per body.
    #[inline(always)]
    fn pair_bodies(
        self,
        particles: &[P],
        pairs: &[[u32; 2]; GROUP],
        rows1: [&mut GroupRow; BODY_WORDS],
        rows2: [&mut GroupRow; BODY_WORDS],
    ) {
        pair_bodies_by_reference(self, particles, pairs, rows1, rows2);
    }
    /// `rows[q][k]` = word `q` of `states[k]`.
    fn states(self, states: [&S; GROUP], rows: [&mut GroupRow; STATE_WORDS]);
    /// Writes word `q` of `states[k]` from `rows[q][k]` and its slip flags from `slip[k]` (as
    /// [`StateSlot::store`]).
    fn store_states(
        self,
        rows: [&GroupRow; STATE_WORDS],
        slip: &[u32; GROUP],
        states: &mut [S; GROUP],
    );
    /// As [`GroupCopy::store_states`], into states that need not be adjacent in memory
    /// (distinct slots, e.g. those of [`IndexedStates`](super::IndexedStates)). The default
    /// writes them one by one, as [`PortableCopy`] does.
    #[inline(always)]
    fn store_states_at(
        self,
        rows: [&GroupRow; STATE_WORDS],
        slip: &[u32; GROUP],
        states: [&mut S; GROUP],
    ) where
        S: StateSlot,
    {
        store_states_by_value(rows, slip, states);
    }
    /// `rows[q][k]` = word `q` of `walls[k]` (`WALL_WORDS` order), for the sphere-wall
    /// access. The default copies value by value; the C layer's copiers transpose the walls
    /// that are their doubles in memory ([`WallSlot::doubles`]).
    #[inline(always)]
    fn walls<W: WallSlot>(self, walls: [&W; GROUP], rows: [&mut GroupRow; WALL_WORDS]) {
        walls_by_value(walls, rows);
    }
    /// This copier, told that a step changes only the state words of `words` (bit `q`: word
    /// `q`, `written_words`): its [`GroupCopy::store_states`] may then leave the other words
    /// alone, since the states still hold what [`GroupCopy::states`] read (the default ignores
    /// it and writes every word).
    #[inline(always)]
    fn writing(self, _words: u16) -> Self {
        self
    }
    /// `out[k]` = the loads in slot `k` of `rows` (force 1, torque 1, torque 2), as
    /// [`LoadsSlot::set`] writes them (the default).
    #[inline(always)]
    fn store_loads<O: LoadsSlot>(self, rows: [&GroupRow; 9], out: &mut [O; GROUP]) {
        store_loads_by_value(rows, out);
    }
}

/// [`GroupCopy::store_states`] slot by slot, through [`StateSlot::store`].
#[inline(always)]
fn store_states_by_value<'a, S: StateSlot + 'a>(
    rows: [&GroupRow; STATE_WORDS],
    slip: &[u32; GROUP],
    states: impl IntoIterator<Item = &'a mut S>,
) {
    for (k, state) in states.into_iter().enumerate() {
        state.store(&state_from_words(|q| rows[q][k]), slip[k]);
    }
}

/// [`GroupCopy::store_loads`] slot by slot, through [`LoadsSlot::set`].
#[inline(always)]
pub(crate) fn store_loads_by_value<O: LoadsSlot>(rows: [&GroupRow; 9], out: &mut [O; GROUP]) {
    for (k, slot) in out.iter_mut().enumerate() {
        slot.set(&PairLoads::in_slot(rows, k));
    }
}

/// [`GroupCopy::walls`]' default: value by value.
#[inline(always)]
pub(crate) fn walls_by_value<W: WallSlot>(
    walls: [&W; GROUP],
    mut rows: [&mut GroupRow; WALL_WORDS],
) {
    for (k, wall) in walls.iter().enumerate() {
        for (row, v) in rows.iter_mut().zip(wall.words()) {
            row[k] = v;
        }
    }
}

/// [`GroupCopy::pair_bodies`]' default: a reference to each body, then
/// [`GroupCopy::bodies`].
#[inline(always)]
pub(crate) fn pair_bodies_by_reference<P, S, X: GroupCopy<P, S>>(
    copy: X,
    particles: &[P],
    pairs: &[[u32; 2]; GROUP],
    rows1: [&mut GroupRow; BODY_WORDS],
    rows2: [&mut GroupRow; BODY_WORDS],
) {
    let last = particles.len() - 1;
    let body = |i: u32| &particles[(i as usize).min(last)];
    copy.bodies(group_of(|k| body(pairs[k][0])), rows1);
    copy.bodies(group_of(|k| body(pairs[k][1])), rows2);
}

/// [`GroupCopy`] value by value, for any body and state type.
#[derive(Clone, Copy, Debug, Default)]
pub struct PortableCopy;

impl<P: SphereSlot, S: StateSlot> GroupCopy<P, S> for PortableCopy {
    #[inline(always)]
    fn bodies(self, bodies: [&P; GROUP], mut rows: [&mut GroupRow; BODY_WORDS]) {
        for (k, body) in bodies.iter().enumerate() {
            let b = body.sphere();
            let words = [
                b.position.x,
                b.position.y,
                b.position.z,
                b.velocity.x,
                b.velocity.y,
                b.velocity.z,
                b.angular_velocity.x,
                b.angular_velocity.y,
                b.angular_velocity.z,
                b.radius,
            ];
            for (row, w) in rows.iter_mut().zip(words) {
                row[k] = w;
            }
        }
    }

    #[inline(always)]
    fn states(self, states: [&S; GROUP], mut rows: [&mut GroupRow; STATE_WORDS]) {
        for (k, state) in states.iter().enumerate() {
            for (row, w) in rows.iter_mut().zip(state_words(&state.load())) {
                row[k] = w;
            }
        }
    }

    #[inline(always)]
    fn store_states(
        self,
        rows: [&GroupRow; STATE_WORDS],
        slip: &[u32; GROUP],
        states: &mut [S; GROUP],
    ) {
        store_states_by_value(rows, slip, states);
    }
}

/// The words of a state, in [`STATE_WORDS`] order.
#[inline(always)]
pub(crate) fn state_words(s: &ContactState<f64>) -> [f64; STATE_WORDS] {
    [
        s.sliding_spring.x,
        s.sliding_spring.y,
        s.sliding_spring.z,
        s.rolling_spring.x,
        s.rolling_spring.y,
        s.rolling_spring.z,
        s.twisting_angle,
        s.model_memory.x,
        s.model_memory.y,
        s.model_memory.z,
        s.previous_normal.x,
        s.previous_normal.y,
        s.previous_normal.z,
    ]
}

/// The state whose word `q` is `word(q)` ([`STATE_WORDS`] order).
#[inline(always)]
fn state_from_words(word: impl Fn(usize) -> f64) -> ContactState<f64> {
    let v = |q: usize| Vec3::new(word(q), word(q + 1), word(q + 2));
    ContactState {
        sliding_spring: v(0),
        rolling_spring: v(3),
        twisting_angle: word(6),
        model_memory: v(7),
        previous_normal: v(10),
    }
}

/// First word of the position in [`BODY_WORDS`] order.
const POSITION: usize = 0;
/// First word of the velocity.
const VELOCITY: usize = 3;
/// First word of the angular velocity.
const ANGULAR_VELOCITY: usize = 6;
/// The radius' word.
const RADIUS: usize = 9;

/// One quantity for every contact of a block.
type Row = [f64; BLOCK];

/// The rows of a 3-vector quantity.
type Rows3 = [Row; 3];

/// The loads of a block's contacts, a row per component: force on body 1 (x, y, z), torque on
/// body 1, torque on body 2 (N and N m, global frame); slot `k` is the block's contact `k`.
pub type LoadRows = [[f64; BLOCK]; 9];

/// One block of contacts, a row per quantity (inputs, then the results of the step).
///
/// Aligned to a cache line, in declaration order (`repr(C)`; every field before `slip` is a
/// whole number of lines): each group's slots of a row are one aligned 64-byte line, so the
/// zmm (and ymm) loads and stores of the rows never straddle two lines. Unaligned, the block
/// sat where the kernel's frame put it, 56 bytes past a line boundary in the build measured,
/// and every row access split. Measured on the Zen 5 host of docs/performance.md (A, 2,000
/// contacts, 5 alternating runs, medians): every SIMD kernel 2-7% faster but the double AVX2
/// full set (+2%); at 1.2M contacts the result depends on where the host's arrays lie modulo
/// 4 KB (loads from the rows can wait on unrelated stores 4 KB apart), in both builds.
#[repr(C, align(64))]
struct Block {
    /// Body 1 in [`BODY_WORDS`] order.
    body1: [Row; BODY_WORDS],
    /// Body 2 in [`BODY_WORDS`] order (a wall: point, velocity, angular velocity).
    body2: [Row; BODY_WORDS],
    /// A wall's normal as given (sphere-wall contacts only).
    wall_normal: [Row; 3],
    normal_force: Row,
    normal_stiffness: Row,
    /// Per-contact coefficients ([`COEFFICIENTS`] order, see `laws::materials`): each contact's
    /// material pair's when the call gives a table, with `k_t` and `gamma_t` from the call's
    /// arrays when it gives them (only those two rows are filled without a table).
    coefficients: [Row; COEFFICIENTS],
    /// The state in [`STATE_WORDS`] order. The step writes the new state over it.
    state: [Row; STATE_WORDS],
    /// Force on body 1 (3), torque on body 1 (3), torque on body 2 (3).
    loads: LoadRows,
    /// The energy terms ([`EnergyTerms`] order), when the call returns them.
    energy: [Row; ENERGY_TERMS],
    /// `SLIP_*` bits per contact.
    slip: [u32; BLOCK],
    /// Bit `i`: contact `i`'s particle indices were in range.
    index_ok: u64,
    /// Bit `i`: contact `i` was stepped (valid inputs, finite results).
    valid: u64,
}

impl Block {
    fn new() -> Block {
        Block {
            body1: [[0.0; BLOCK]; BODY_WORDS],
            body2: [[0.0; BLOCK]; BODY_WORDS],
            wall_normal: [[0.0; BLOCK]; 3],
            normal_force: [0.0; BLOCK],
            normal_stiffness: [1.0; BLOCK],
            coefficients: [[0.0; BLOCK]; COEFFICIENTS],
            state: [[0.0; BLOCK]; STATE_WORDS],
            loads: [[0.0; BLOCK]; 9],
            energy: [[0.0; BLOCK]; ENERGY_TERMS],
            slip: [0; BLOCK],
            index_ok: 0,
            valid: 0,
        }
    }
}

#[inline(always)]
fn load3<L: Lanes>(rows: &Rows3, at: usize) -> Vec3<L> {
    Vec3::new(
        L::load(&rows[0][at..]),
        L::load(&rows[1][at..]),
        L::load(&rows[2][at..]),
    )
}

#[inline(always)]
fn store3<L: Lanes>(rows: &mut Rows3, at: usize, v: &Vec3<L>) {
    v.x.store(&mut rows[0][at..]);
    v.y.store(&mut rows[1][at..]);
    v.z.store(&mut rows[2][at..]);
}

/// The three rows of `rows` from `first`.
#[inline(always)]
fn rows3<const Q: usize>(rows: &[Row; Q], first: usize) -> &Rows3 {
    let rows: &[Row] = &rows[first..first + 3];
    rows.try_into().expect("three rows")
}

/// The three rows of `rows` from `first`, to write.
#[inline(always)]
fn rows3_mut<const Q: usize>(rows: &mut [Row; Q], first: usize) -> &mut Rows3 {
    let rows: &mut [Row] = &mut rows[first..first + 3];
    rows.try_into().expect("three rows")
}

/// Slots `g..g + GROUP` of each row.
#[inline(always)]
fn group_mut<const Q: usize>(rows: &mut [Row; Q], g: usize) -> [&mut GroupRow; Q] {
    rows.each_mut()
        .map(|row| (&mut row[g..g + GROUP]).try_into().expect("a group"))
}

/// Slots `g..g + GROUP` of each row, to read.
#[inline(always)]
fn group<const Q: usize>(rows: &[Row; Q], g: usize) -> [&GroupRow; Q] {
    rows.each_ref()
        .map(|row| (&row[g..g + GROUP]).try_into().expect("a group"))
}

/// Copies contacts `c0..c0 + count` into the block's rows (slots `0..count`), a group of
/// [`GROUP`] at a time, and pads the slots of the last group with the last contact (their
/// results are dropped). With 16 lanes a step can also cover slots past the last group, which
/// keep an earlier block's values (or the initial ones): their lanes are stepped and dropped
/// in the same way. When `prefetch` ([`Gather::prefetching`](super::Gather::prefetching)),
/// calls [`Gather::touch`](super::Gather::touch) for the contacts `TOUCH_AHEAD` further on;
/// their in-order part ([`Gather::touch_in_order`](super::Gather::touch_in_order)) goes after
/// each lane step, in [`step_kernel`].
#[cfg_attr(not(debug_assertions), inline(always))]
#[cfg_attr(debug_assertions, inline)] // one copy in unoptimised builds: see `step_kernel`
fn gather<A: StepAccess, X: GroupCopy<A::P, A::State>>(
    prefetch: bool,
    access: &A,
    copy: X,
    c0: usize,
    count: usize,
    needs_kn: bool,
    b: &mut Block,
) {
    b.index_ok = 0;
    let in_range = access.indices_in_range(c0, count);
    let sliding = access.sliding_overrides();
    let mut g = 0;
    // The per-contact numbers go row by row, each test made once per group. One closure per
    // slot, doing the prefetches and every optional row, stayed out of line in the prefetching
    // kernels: a call per contact, its captures reloaded and each test repeated (about 53
    // instructions per contact in the double AVX2 rolling + twisting kernel).
    while g < count {
        let whole = g + GROUP <= count;
        // Slot `g + k`'s contact: the last one for the slots past the end.
        let contact = |k: usize| c0 + (g + k).min(count - 1);
        if prefetch {
            for k in 0..GROUP {
                access.touch(c0 + g + k + TOUCH_AHEAD);
            }
        }
        if whole {
            b.normal_force[g..g + GROUP].copy_from_slice(&access.normal_forces(c0 + g));
        } else {
            for k in 0..GROUP {
                b.normal_force[g + k] = access.normal_force(contact(k));
            }
        }
        if needs_kn {
            for k in 0..GROUP {
                b.normal_stiffness[g + k] = access.normal_stiffness(contact(k));
            }
        }
        let mut material_ok = lane_bits(GROUP);
        if let Some(m) = &sliding.materials {
            material_ok = gather_materials(m, &contact, &mut b.coefficients, g);
        }
        let [k_t, gamma_t] = b
            .coefficients
            .get_disjoint_mut([SLIDING_STIFFNESS, SLIDING_DAMPING])
            .expect("two coefficient rows");
        for (row, given) in [(k_t, sliding.stiffness), (gamma_t, sliding.damping)] {
            if let Some(values) = given {
                if whole {
                    row[g..g + GROUP].copy_from_slice(&group_at(values, c0 + g));
                } else {
                    for k in 0..GROUP {
                        row[g + k] = values[contact(k)];
                    }
                }
            }
        }
        let rows = GroupRowsMut {
            body1: group_mut(&mut b.body1, g),
            body2: group_mut(&mut b.body2, g),
            states: group_mut(&mut b.state, g),
            wall_normal: group_mut(&mut b.wall_normal, g),
        };
        let index_ok = access.copy_group(copy, c0 + g, (count - g).min(GROUP), in_range, rows);
        b.index_ok |= (index_ok & material_ok) << g;
        g += GROUP;
    }
}

/// Fills slots `g..g + GROUP` of the coefficient rows with the material pairs of the contacts
/// `contact(0..GROUP)`; returns a bit per slot whose material index is in the table (a slot
/// out of range gets the table's last set, and its contact is refused).
#[inline(always)]
fn gather_materials(
    m: &Materials<'_>,
    contact: &impl Fn(usize) -> usize,
    rows: &mut [Row; COEFFICIENTS],
    g: usize,
) -> u64 {
    let last = m.table.len().saturating_sub(1);
    let mut ok = 0;
    for k in 0..GROUP {
        let i = m.index[contact(k)] as usize;
        ok |= u64::from(i < m.table.len()) << k;
        let set = m.table.get(i.min(last)).copied().unwrap_or_default();
        for (row, v) in rows.iter_mut().zip(set.values) {
            row[g + k] = v;
        }
    }
    ok
}

/// Centres and radii of `N` contacts' two bodies, in `f64` lanes.
type Centres<G> = (Vec3<G>, Vec3<G>, G, G);

/// Which per-contact coefficients a call gives: `k_t` and `gamma_t` arrays, a table of
/// material pairs.
#[derive(Clone, Copy, Debug)]
struct Given {
    stiffness: bool,
    damping: bool,
    materials: bool,
}

impl Given {
    /// What `c` gives.
    #[inline(always)]
    fn of(c: &SlidingOverrides<'_>) -> Given {
        Given {
            stiffness: c.stiffness.is_some(),
            damping: c.damping.is_some(),
            materials: c.materials.is_some(),
        }
    }
}

/// Where a step reads the inputs of its `L::N` contacts, one per lane: the block's rows
/// ([`RowsAt`]) or one contact's structs ([`Single`]). Each group is read where the step first
/// needs it (positions, then motion and forces, then the state).
trait LaneSource<L: Lanes> {
    /// Centres and radii in `f64` lanes, for the geometry.
    fn geometry(&self) -> Centres<L::Geo>;
    /// The two bodies' motion (positions left at zero: the rates read the geometry).
    fn bodies(&self) -> (Sphere<L>, Sphere<L>);
    /// `f_n`, and `k_n` when `needs_kn` (else 1).
    fn forces(&self, needs_kn: bool) -> (L, L);
    /// The per-contact `k_t` and `gamma_t` arrays' values, each where `given` says the call
    /// has them.
    fn sliding(&self, given: Given) -> (Option<L>, Option<L>);
    /// The contacts' material coefficients, where `given` says the call has a table (with the
    /// `k_t` and `gamma_t` arrays' values over them).
    fn materials(&self, given: Given) -> Option<[L; COEFFICIENTS]>;
    /// The contacts' state.
    fn state(&self) -> ContactState<L>;
}

/// Slots `at..at + L::N` of a block.
struct RowsAt<'a> {
    block: &'a Block,
    at: usize,
}

impl<L: Lanes> LaneSource<L> for RowsAt<'_> {
    #[inline(always)]
    fn geometry(&self) -> Centres<L::Geo> {
        let (b, at) = (self.block, self.at);
        (
            load3::<L::Geo>(rows3(&b.body1, POSITION), at),
            load3::<L::Geo>(rows3(&b.body2, POSITION), at),
            L::Geo::load(&b.body1[RADIUS][at..]),
            L::Geo::load(&b.body2[RADIUS][at..]),
        )
    }
    #[inline(always)]
    fn bodies(&self) -> (Sphere<L>, Sphere<L>) {
        (
            body_at(&self.block.body1, self.at),
            body_at(&self.block.body2, self.at),
        )
    }
    #[inline(always)]
    fn forces(&self, needs_kn: bool) -> (L, L) {
        let (b, at) = (self.block, self.at);
        let k_n = if needs_kn {
            L::load(&b.normal_stiffness[at..])
        } else {
            L::one()
        };
        (L::load(&b.normal_force[at..]), k_n)
    }
    #[inline(always)]
    fn sliding(&self, given: Given) -> (Option<L>, Option<L>) {
        // `if`, not `bool::then` with a closure: LLVM left that closure out of line in the
        // AVX2 single-precision kernels (scripts/check_kernels.sh now fails on it).
        let (b, at) = (self.block, self.at);
        let stiffness = if given.stiffness {
            Some(L::load(&b.coefficients[SLIDING_STIFFNESS][at..]))
        } else {
            None
        };
        let damping = if given.damping {
            Some(L::load(&b.coefficients[SLIDING_DAMPING][at..]))
        } else {
            None
        };
        (stiffness, damping)
    }
    #[inline(always)]
    fn materials(&self, given: Given) -> Option<[L; COEFFICIENTS]> {
        let (b, at) = (self.block, self.at);
        if given.materials {
            Some(std::array::from_fn(|q| L::load(&b.coefficients[q][at..])))
        } else {
            None
        }
    }
    #[inline(always)]
    fn state(&self) -> ContactState<L> {
        let (st, at) = (&self.block.state, self.at);
        ContactState {
            sliding_spring: load3(rows3(st, 0), at),
            rolling_spring: load3(rows3(st, 3), at),
            twisting_angle: L::load(&st[6][at..]),
            model_memory: load3(rows3(st, 7), at),
            previous_normal: load3(rows3(st, 10), at),
        }
    }
}

/// One contact read straight from the host's structs (one-lane types).
struct Single {
    body1: Sphere<f64>,
    body2: Sphere<f64>,
    normal_force: f64,
    normal_stiffness: f64,
    sliding: (Option<f64>, Option<f64>),
    /// The contact's material pair, when the call has a table.
    material: Option<Coefficients>,
    state: ContactState<f64>,
}

/// `v` in every lane.
#[inline(always)]
fn splat3<T: Lanes>(v: &Vec3<f64>) -> Vec3<T> {
    Vec3::new(
        T::from_fn(|_| v.x),
        T::from_fn(|_| v.y),
        T::from_fn(|_| v.z),
    )
}

impl<L: Lanes> LaneSource<L> for Single {
    #[inline(always)]
    fn geometry(&self) -> Centres<L::Geo> {
        let (one, two) = (&self.body1, &self.body2);
        (
            splat3(&one.position),
            splat3(&two.position),
            L::Geo::from_fn(|_| one.radius),
            L::Geo::from_fn(|_| two.radius),
        )
    }
    #[inline(always)]
    fn bodies(&self) -> (Sphere<L>, Sphere<L>) {
        let body = |b: &Sphere<f64>| {
            moving(
                splat3(&b.velocity),
                splat3(&b.angular_velocity),
                L::from_fn(|_| b.radius),
            )
        };
        (body(&self.body1), body(&self.body2))
    }
    #[inline(always)]
    fn forces(&self, needs_kn: bool) -> (L, L) {
        let k_n = if needs_kn {
            L::from_fn(|_| self.normal_stiffness)
        } else {
            L::one()
        };
        (L::from_fn(|_| self.normal_force), k_n)
    }
    #[inline(always)]
    fn sliding(&self, _given: Given) -> (Option<L>, Option<L>) {
        let lanes = |v: Option<f64>| v.map(|v| L::from_fn(|_| v));
        (lanes(self.sliding.0), lanes(self.sliding.1))
    }
    #[inline(always)]
    fn materials(&self, _given: Given) -> Option<[L; COEFFICIENTS]> {
        self.material
            .map(|set| set.values.map(|v| L::from_fn(|_| v)))
    }
    #[inline(always)]
    fn state(&self) -> ContactState<L> {
        let s = &self.state;
        ContactState {
            sliding_spring: splat3(&s.sliding_spring),
            rolling_spring: splat3(&s.rolling_spring),
            twisting_angle: L::from_fn(|_| s.twisting_angle),
            model_memory: splat3(&s.model_memory),
            previous_normal: splat3(&s.previous_normal),
        }
    }
}

/// What [`step_inputs`] returns: the new state and the loads per lane, the lanes that were
/// stepped (valid inputs, finite results: bit `k` for lane `k`) and the slip masks.
struct LaneResults<L: Lanes> {
    state: ContactState<L>,
    force1: Vec3<L>,
    torque1: Vec3<L>,
    torque2: Vec3<L>,
    energy: [L; ENERGY_TERMS],
    valid: u64,
    slips: [u64; 3],
}

/// A running finiteness test of lanes: sums of `0 x` over the values tested, which stay zeros
/// while every value added is finite and become NaN with the first that is not, exactly as
/// [`finite_probe`](crate::scalar::finite_probe) does.
///
/// Fused (`fused`, which needs [`Lanes::FUSED_PROBE`]): each value is one fused `acc + 0 x`,
/// one instruction per register, on one of four sums (x components, y components, z components
/// and single values), so that no chain of dependent instructions is long. The step's results
/// are tested at the end of a group, where a long chain holds up what follows: with a single
/// sum the double AVX2 full-set kernel executed 3% fewer instructions but took 4% more time in
/// cache. Otherwise a vector's three products are summed first and added to one sum, as
/// `finite_probe` does.
struct FiniteLanes<L: Lanes> {
    sums: [Option<L>; 4],
    fused: bool,
}

impl<L: Lanes> FiniteLanes<L> {
    /// An empty test, fused if `fused` and the lanes can fuse.
    #[inline(always)]
    fn new(fused: bool) -> Self {
        FiniteLanes {
            sums: [None; 4],
            fused: fused && L::FUSED_PROBE,
        }
    }

    /// `sum + 0 x` on sum `i` (`0 x` alone for its first value).
    #[inline(always)]
    fn add_to(&mut self, i: usize, x: L) {
        let sum = &mut self.sums[i];
        *sum = Some(match *sum {
            Some(acc) => L::add_zero_times(acc, x),
            None => x * L::zero(),
        });
    }

    /// Adds a value.
    #[inline(always)]
    fn add(&mut self, x: L) {
        self.add_to(if self.fused { 3 } else { 0 }, x);
    }

    /// Adds the components of `v`.
    #[inline(always)]
    fn add_vec(&mut self, v: &Vec3<L>) {
        if self.fused {
            self.add_to(0, v.x);
            self.add_to(1, v.y);
            self.add_to(2, v.z);
        } else {
            let zero = L::zero();
            let products = v.x * zero + v.y * zero + v.z * zero;
            self.sums[0] = Some(self.sums[0].map_or(products, |acc| acc + products));
        }
    }

    /// The lanes all of whose values were finite.
    #[inline(always)]
    fn ok(self) -> L::SimdBool {
        let [a, b, c, d] = self.sums;
        let pair = |p: Option<L>, q: Option<L>| match (p, q) {
            (Some(p), Some(q)) => Some(p + q),
            (p, q) => p.or(q),
        };
        let sum = pair(pair(a, b), pair(c, d)).unwrap_or_else(L::zero);
        sum.simd_eq(L::zero())
    }
}

/// The lanes whose inputs the per-contact checked step accepts, as far as the geometry does not
/// show it: finite motion, state and `f_n` (of either sign), a finite `k_n > 0` (`stiffness`,
/// given when the model reads it), finite per-contact `k_t, gamma_t >= 0` when the call
/// gives them, and previous stiffnesses >= 0 in the state when `memory`
/// ([`Model::stiffness_memory`](crate::laws::model::Model::stiffness_memory)). `fused`: see
/// [`FiniteLanes`].
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn inputs_ok<L: Lanes>(
    body1: &Sphere<L>,
    body2: &Sphere<L>,
    force: L,
    stiffness: Option<L>,
    sliding: (Option<L>, Option<L>),
    state: &ContactState<L>,
    memory: bool,
    fused: bool,
) -> L::SimdBool {
    let zero = L::zero();
    let mut finite = FiniteLanes::new(fused);
    finite.add(force);
    finite.add(state.twisting_angle);
    for v in [
        &body1.velocity,
        &body2.velocity,
        &body1.angular_velocity,
        &body2.angular_velocity,
        &state.sliding_spring,
        &state.rolling_spring,
        &state.model_memory,
        &state.previous_normal,
    ] {
        finite.add_vec(v);
    }
    let mut ok = finite.ok();
    if let Some(k) = stiffness {
        ok = ok & k.simd_gt(zero) & (k * zero).simd_eq(zero);
    }
    // Per-contact k_t and gamma_t: finite and >= 0, as the checked step requires.
    for x in [sliding.0, sliding.1].into_iter().flatten() {
        ok = ok & x.simd_ge(zero) & (x * zero).simd_eq(zero);
    }
    if memory {
        let m = &state.model_memory;
        ok = ok & m.x.simd_ge(zero) & m.y.simd_ge(zero) & m.z.simd_ge(zero);
    }
    ok
}

/// The lanes whose loads, new state and (when the model tracks energy) energy terms are
/// finite: the per-contact checked step refuses a step whose energy terms overflow, so the
/// batch does too, although it does not return them. `track_energy` is the model's,
/// decided once per call, so a model that does not track energy tests nothing more. The state
/// fields outside `written`, which the step cannot change, are not tested again: they are as
/// the inputs' test found them, and a lane whose inputs failed is refused whatever its
/// results.
#[inline(always)]
fn results_ok<L: Lanes>(
    track_energy: bool,
    written: WrittenFields,
    out: &StepOutput<L>,
    state: &ContactState<L>,
    fused: bool,
) -> L::SimdBool {
    let loads = &out.loads;
    let mut finite = FiniteLanes::new(fused);
    for v in [&loads.force1, &loads.torque1, &loads.torque2] {
        finite.add_vec(v);
    }
    if written.twisting_angle {
        finite.add(state.twisting_angle);
    }
    for (on, v) in [
        (written.sliding_spring, &state.sliding_spring),
        (written.rolling_spring, &state.rolling_spring),
        (written.model_memory, &state.model_memory),
    ] {
        if on {
            finite.add_vec(v);
        }
    }
    if track_energy {
        for e in out.energy.terms() {
            finite.add(e);
        }
    }
    finite.ok()
}

/// The step input of `L::N` contacts: a material pair's coefficients when the call has a
/// table, and the call's `k_t` and `gamma_t` arrays over them.
#[inline(always)]
fn step_input<L: Lanes>(
    model: &Model,
    force: L,
    stiffness: L,
    sliding: (Option<L>, Option<L>),
    materials: Option<[L; COEFFICIENTS]>,
    dt: f64,
) -> StepInput<L> {
    let mut input = StepInput::new(force, L::from_fn(|_| dt));
    input.normal_stiffness = stiffness;
    if let Some(values) = materials {
        Coefficients::apply(model, values, &mut input);
    }
    if sliding.0.is_some() {
        input.sliding_stiffness = sliding.0;
    }
    if sliding.1.is_some() {
        input.sliding_damping = sliding.1;
    }
    input
}

/// One step of `L::N` contacts: the validation of the per-contact checked step (finite inputs,
/// radii > 0, `d >= eps (R1 + R2)`, a unit normal, `l1, l2 > 0`, finite `f_n` of either sign,
/// `k_n > 0` when the model reads it, finite results), lane-wise, and the generic physics.
#[inline(always)]
fn step_inputs<L: Lanes>(
    model: &Model,
    dt: f64,
    needs_kn: bool,
    given: Given,
    source: &impl LaneSource<L>,
) -> LaneResults<L> {
    debug_assert_eq!(
        <L::Geo as Lanes>::N,
        L::N,
        "the geometry has the lanes of the step"
    );
    let (p1, p2, r1, r2) = source.geometry();
    let g = pair_geometry_unchecked(&p1, &p2, r1, r2, model.geometry);
    let geometry_ok = pair_geometry_valid(&p1, &p2, r1, r2, &g).bitmask();
    let (body1, body2) = source.bodies();
    let (force, stiffness) = source.forces(needs_kn);
    let sliding = source.sliding(given);
    let materials = source.materials(given);
    let mut state = source.state();
    let fused = L::FUSED_PROBE;
    let kn = needs_kn.then_some(stiffness);
    let inputs_ok = inputs_ok(
        &body1,
        &body2,
        force,
        kn,
        sliding,
        &state,
        model.stiffness_memory(),
        fused,
    );
    let out = contact_step_with_geometry(
        model,
        geometry_in::<L>(&g, &g),
        &body1,
        Partner::Sphere(&body2),
        &step_input(model, force, stiffness, sliding, materials, dt),
        &mut state,
    );
    let written = written_fields(model);
    let results_ok = results_ok(model.track_energy, written, &out, &state, fused);
    let l = out.loads;
    LaneResults {
        state,
        force1: l.force1,
        torque1: l.torque1,
        torque2: l.torque2,
        energy: energy_terms(&out.energy),
        valid: geometry_ok & (inputs_ok & results_ok).bitmask() & lane_bits(L::N),
        slips: [
            out.slipped[0].bitmask(),
            out.slipped[1].bitmask(),
            out.slipped[2].bitmask(),
        ],
    }
}

/// The `SLIP_*` bits of lane `k`.
#[inline(always)]
fn slip_bits(slips: &[u64; 3], k: usize) -> u32 {
    let bit = |mask: u64, flag: u32| ((mask >> k) & 1) as u32 * flag;
    bit(slips[0], SLIP_SLIDING) | bit(slips[1], SLIP_ROLLING) | bit(slips[2], SLIP_TWISTING)
}

/// The moving body in slots `at..at + L::N` of a body's rows (its position left at zero).
#[inline(always)]
fn body_at<L: Lanes>(rows: &[Row; BODY_WORDS], at: usize) -> Sphere<L> {
    moving(
        load3(rows3(rows, VELOCITY), at),
        load3(rows3(rows, ANGULAR_VELOCITY), at),
        L::load(&rows[RADIUS][at..]),
    )
}

/// A body in lanes, its position left at zero (the rates and the laws read the geometry).
#[inline(always)]
fn moving<L: Lanes>(velocity: Vec3<L>, angular_velocity: Vec3<L>, radius: L) -> Sphere<L> {
    Sphere {
        position: Vec3::zeros(),
        velocity,
        angular_velocity,
        radius,
    }
}

/// Steps slots `at..at + L::N` of the block, each lane value one load from a row; writes the
/// new state and the loads back into the rows and records the slots' validity and slip bits.
///
/// Its body repeats [`step_inputs`]' sequence (the same helpers, in the same order) instead of
/// calling it: with the results returned through `LaneResults` the AVX-512 kernel measured
/// 41-42 ns per contact in cache against 30 for this form, and with one shared function
/// returning `(valid, state, StepOutput)` the AVX2 kernel measured 37-41 against 35 (full
/// LAMMPS set, edited builds of the bench driver). The compiler's output is sensitive to such
/// shapes: rerun the in-cache benchmark at both SIMD levels after any change here. `fused`:
/// whether the finiteness tests may use fused instructions (see [`FiniteLanes`]).
#[cfg_attr(not(debug_assertions), inline(always))]
#[cfg_attr(debug_assertions, inline)] // one copy in unoptimised builds: see `step_kernel`
#[allow(clippy::too_many_arguments)]
fn step_lanes<L: Lanes>(
    model: &Model,
    dt: f64,
    needs_kn: bool,
    wall: bool,
    given: Given,
    energy: bool,
    fused: bool,
    at: usize,
    b: &mut Block,
) {
    let src = RowsAt { block: b, at };
    let (p1, p2, r1, r2) = LaneSource::<L>::geometry(&src);
    // Body 2: a sphere, or with `wall` (the access's, a constant in each kernel) the wall's
    // motion, from body 2's rows, which hold the wall (its point moved to the origin below).
    let (body1, body2) = LaneSource::<L>::bodies(&src);
    let (g, geometry_ok, wall) = if wall {
        let normal = load3::<L::Geo>(&b.wall_normal, at);
        let (unit, normalisable) = unit_vector_lanes(&normal);
        let mut g = wall_geometry_unchecked(&p1, r1, &p2, &unit, model.geometry);
        let ok = wall_geometry_valid(&p1, r1, &p2, normalisable, &g).bitmask();
        // The step reads the contact point only as `r_c - point` (the wall's material velocity
        // there): taken in the geometry's precision, with the wall's point moved to the origin.
        // In double precision these are the per-contact wall step's bits.
        g.contact_point -= p2;
        let wall = Wall {
            point: Vec3::zeros(),
            normal: conv3::<L>(&unit, &unit),
            velocity: body2.velocity,
            angular_velocity: body2.angular_velocity,
        };
        (g, ok, Some(wall))
    } else {
        let g = pair_geometry_unchecked(&p1, &p2, r1, r2, model.geometry);
        (g, pair_geometry_valid(&p1, &p2, r1, r2, &g).bitmask(), None)
    };
    let (force, stiffness) = LaneSource::<L>::forces(&src, needs_kn);
    let sliding = LaneSource::<L>::sliding(&src, given);
    let materials = LaneSource::<L>::materials(&src, given);
    let mut state = LaneSource::<L>::state(&src);
    let kn = needs_kn.then_some(stiffness);
    let inputs_ok = inputs_ok(
        &body1,
        &body2,
        force,
        kn,
        sliding,
        &state,
        model.stiffness_memory(),
        fused,
    );
    let partner = match &wall {
        Some(w) => Partner::Wall(w),
        None => Partner::Sphere(&body2),
    };
    let out = contact_step_with_geometry(
        model,
        geometry_in::<L>(&g, &g),
        &body1,
        partner,
        &step_input(model, force, stiffness, sliding, materials, dt),
        &mut state,
    );
    let l = &out.loads;
    let written = written_fields(model);
    let results_ok = results_ok(model.track_energy, written, &out, &state, fused);
    let valid = geometry_ok & (inputs_ok & results_ok).bitmask();
    b.valid |= (valid & lane_bits(L::N)) << at;
    // The rows of a field the step cannot change still hold what it read.
    if written.sliding_spring {
        store3(rows3_mut(&mut b.state, 0), at, &state.sliding_spring);
    }
    if written.rolling_spring {
        store3(rows3_mut(&mut b.state, 3), at, &state.rolling_spring);
    }
    if written.twisting_angle {
        state.twisting_angle.store(&mut b.state[6][at..]);
    }
    if written.model_memory {
        store3(rows3_mut(&mut b.state, 7), at, &state.model_memory);
    }
    if written.previous_normal {
        store3(rows3_mut(&mut b.state, 10), at, &state.previous_normal);
    }
    let loads: &mut [Row; 9] = &mut b.loads;
    let (force1, rest) = loads.split_at_mut(3);
    let (torque1, torque2) = rest.split_at_mut(3);
    for (rows, v) in [
        (force1, &l.force1),
        (torque1, &l.torque1),
        (torque2, &l.torque2),
    ] {
        let rows: &mut Rows3 = rows.try_into().expect("three rows");
        store3(rows, at, v);
    }
    let slips = [
        out.slipped[0].bitmask(),
        out.slipped[1].bitmask(),
        out.slipped[2].bitmask(),
    ];
    for k in 0..L::N {
        b.slip[at + k] = slip_bits(&slips, k);
    }
    if energy {
        for (row, e) in b.energy.iter_mut().zip(energy_terms(&out.energy)) {
            e.store(&mut row[at..]);
        }
    }
}

/// Steps contact `c` on its own (one-lane types: staging through rows would only add copies),
/// reading the host's structs and delivering as [`deliver`] does.
#[cfg_attr(not(debug_assertions), inline(always))]
#[cfg_attr(debug_assertions, inline)] // one copy in unoptimised builds: see `step_kernel`
#[allow(clippy::too_many_arguments)]
fn step_one<L: Lanes, A: StepAccess>(
    prefetch: bool,
    access: &mut A,
    model: &Model,
    dt: f64,
    needs_kn: bool,
    c: usize,
    report: &mut BatchReport,
) {
    if prefetch {
        access.touch(c + TOUCH_AHEAD);
        access.touch_in_order(c + TOUCH_AHEAD);
    }
    let (one, two, index_ok) = access.body_refs(c);
    let (one, two): (Sphere<f64>, Sphere<f64>) = (one.sphere(), two.sphere());
    let coefficients = access.sliding_overrides();
    // `Some(None)`: an index out of the table, refused below.
    let material = coefficients.material(c);
    let single = Single {
        body1: one,
        body2: two,
        normal_force: access.normal_force(c),
        normal_stiffness: if needs_kn {
            access.normal_stiffness(c)
        } else {
            1.0
        },
        sliding: coefficients.at(c),
        material: material.flatten().copied(),
        state: access.state_ref(c).load(),
    };
    let material_ok = material.is_none_or(|m| m.is_some());
    let r = step_inputs::<L>(model, dt, needs_kn, Given::of(&coefficients), &single);
    if index_ok && material_ok && r.valid & 1 == 1 {
        let f64s = |v: &Vec3<L>| Vec3::new(v.x.lane(0), v.y.lane(0), v.z.lane(0));
        let arr = |v: &Vec3<L>| [v.x.lane(0), v.y.lane(0), v.z.lane(0)];
        let new = ContactState {
            sliding_spring: f64s(&r.state.sliding_spring),
            rolling_spring: f64s(&r.state.rolling_spring),
            twisting_angle: r.state.twisting_angle.lane(0),
            model_memory: f64s(&r.state.model_memory),
            previous_normal: f64s(&r.state.previous_normal),
        };
        access.state(c).store(&new, slip_bits(&r.slips, 0));
        access.emit(
            c,
            &PairLoads {
                force1: arr(&r.force1),
                torque1: arr(&r.torque1),
                torque2: arr(&r.torque2),
            },
        );
        if let Some(e) = access.energy_out() {
            e[c] = r.energy.map(|e| e.lane(0));
        }
        report.processed += 1;
    } else {
        refuse(access, model, dt, needs_kn, c, report);
    }
}

/// Reports contact `c` as skipped, with the error the per-contact checked step gives for it.
#[cold]
fn refuse<A: StepAccess>(
    access: &A,
    model: &Model,
    dt: f64,
    needs_kn: bool,
    c: usize,
    report: &mut BatchReport,
) {
    report.fail(c, || {
        let bodies = if A::WALL {
            access.wall_contact(c).map(|(s, w)| (s, Body2::Wall(w)))
        } else {
            access.bodies(c).map(|(b1, b2)| (b1, Body2::Sphere(b2)))
        };
        step_error(
            model,
            dt,
            bodies,
            access.normal_force(c),
            if needs_kn {
                access.normal_stiffness(c)
            } else {
                1.0
            },
            access.sliding_overrides().at(c),
            access.sliding_overrides().material(c),
            &access.state_ref(c).load(),
        )
    });
}

/// Writes the state and hands over the loads of every valid contact of the block (slots
/// `0..count`, contacts `c0..`); reports the others. A group of [`GROUP`] valid contacts has
/// its states written by `copy`.
#[cfg_attr(not(debug_assertions), inline(always))]
#[cfg_attr(debug_assertions, inline)] // one copy in unoptimised builds: see `step_kernel`
#[allow(clippy::too_many_arguments)]
fn deliver<A: StepAccess, X: GroupCopy<A::P, A::State>>(
    access: &mut A,
    copy: X,
    model: &Model,
    dt: f64,
    needs_kn: bool,
    c0: usize,
    count: usize,
    b: &Block,
    report: &mut BatchReport,
) {
    let ok = b.valid & b.index_ok & lane_bits(count);
    let mut g = 0;
    while g < count {
        let whole = g + GROUP <= count && (ok >> g) & lane_bits(GROUP) == lane_bits(GROUP);
        if whole {
            let slip: &[u32; GROUP] = b.slip[g..g + GROUP].try_into().expect("a group");
            access.store_group(copy, group(&b.state, g), slip, c0 + g);
            // Every contact of the group is valid: none to report, none to store alone.
            report.processed += GROUP;
            g += GROUP;
            continue;
        }
        for i in g..(g + GROUP).min(count) {
            let c = c0 + i;
            if ok >> i & 1 == 0 {
                refuse(access, model, dt, needs_kn, c, report);
                continue;
            }
            let s = state_from_words(|q| b.state[q][i]);
            access.state(c).store(&s, b.slip[i]);
            report.processed += 1;
        }
        g += GROUP;
    }
    access.emit_block(copy, c0, ok, &b.loads);
    if let Some(e) = access.energy_out() {
        let mut bits = ok;
        while bits != 0 {
            let k = bits.trailing_zeros() as usize;
            e[c0 + k] = std::array::from_fn(|q| b.energy[q][k]);
            bits &= bits - 1;
        }
    }
}

/// Steps every contact of `access` with `model` and time step `dt` (checked by the caller:
/// [`super::check_batch_model`], [`super::check_time_step`]). `L` is the lane type. `copy`
/// moves the groups of contacts between the host's structs and the block (the one-lane
/// kernels do not use it: they read the structs directly). The model's law choices are taken
/// at run time, once per call: one kernel per lane type, access and prefetching choice runs
/// every model.
///
/// **Unoptimised builds** keep the step's large parts out of line: `gather`, `step_lanes`,
/// `step_one`, `deliver` and `laws::step::contact_step_with_geometry` are `#[inline]` with
/// debug assertions on (the unoptimised `dev` and `test` profiles; also the optimised `stress`
/// profile, where LLVM decides), `#[inline(always)]` without (release): without optimisation
/// nothing of an inlined copy is folded away, so rustc compiles one copy per lane type instead
/// of one inside each kernel. The results are the same to the bit: Rust does not contract or
/// reorder floating-point operations, inlined or not.
#[inline(always)]
pub fn step_kernel<L: Lanes, A: StepAccess, X: GroupCopy<A::P, A::State>>(
    model: &Model,
    dt: f64,
    access: &mut A,
    copy: X,
) -> BatchReport {
    const { assert!(BLOCK.is_multiple_of(L::N)) };
    let needs_kn = needs_normal_stiffness(model);
    // Whether to touch the contacts ahead ([`Gather::prefetching`](super::Gather::prefetching)):
    // a run-time choice, tested once per group of contacts.
    let prefetch = access.prefetching();
    // Unfused finiteness tests (see `FiniteLanes`): with the fused ones the double AVX2 kernels
    // took 3-4% more time and the single AVX-512 ones 2-3% less (alternating runs, A, in cache
    // and at 1.2M contacts); the double precision AVX2 kernel is kept the faster.
    let fused = false;
    // A group's states get back only the words the step can change (decided by the model).
    let copy = copy.writing(written_words(written_fields(model)));
    let n = access.len();
    let mut report = BatchReport::default();
    if super::refuse_ungatherable(&*access, n, &mut report) {
        return report;
    }
    // One lane at a time, a pair steps straight from the host's structs; a wall goes through
    // the block as the SIMD kernels do.
    if L::N == 1 && !A::WALL {
        for c in 0..n {
            step_one::<L, A>(prefetch, access, model, dt, needs_kn, c, &mut report);
        }
        return report;
    }
    let sliding = access.sliding_overrides();
    let given = Given::of(&sliding);
    // The energy terms go back only where the call asks for them.
    let energy = model.track_energy && access.energy_out().is_some();
    let mut block = Block::new();
    let mut c0 = 0;
    while c0 < n {
        let count = (n - c0).min(BLOCK);
        gather::<A, X>(prefetch, &*access, copy, c0, count, needs_kn, &mut block);
        block.valid = 0;
        let mut at = 0;
        while at < count {
            step_lanes::<L>(
                model,
                dt,
                needs_kn,
                A::WALL,
                given,
                energy,
                fused,
                at,
                &mut block,
            );
            // What the contacts `TOUCH_AHEAD` further on read in contact order, one lane
            // step's worth after each step: spread among the arithmetic, where the gather issues
            // the scattered rest a group at a time ([`Gather::touch_in_order`]).
            if prefetch {
                for k in 0..L::N {
                    access.touch_in_order(c0 + at + k + TOUCH_AHEAD);
                }
            }
            at += L::N;
        }
        deliver(
            access,
            copy,
            model,
            dt,
            needs_kn,
            c0,
            count,
            &block,
            &mut report,
        );
        c0 += count;
    }
    report
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn state_words_round_trip_in_contact_state_order() {
        let words: [f64; STATE_WORDS] = std::array::from_fn(|q| q as f64 + 0.5);
        let s = state_from_words(|q| words[q]);
        assert_eq!(s.rolling_spring, Vec3::new(3.5, 4.5, 5.5));
        assert_eq!(s.twisting_angle, 6.5);
        assert_eq!(s.previous_normal, Vec3::new(10.5, 11.5, 12.5));
        assert_eq!(state_words(&s), words);
    }

    #[test]
    fn every_group_of_every_row_is_one_aligned_cache_line() {
        use std::mem::{align_of, offset_of};
        assert_eq!(align_of::<Block>(), 64);
        let starts = [
            offset_of!(Block, body1),
            offset_of!(Block, body2),
            offset_of!(Block, normal_force),
            offset_of!(Block, normal_stiffness),
            offset_of!(Block, coefficients),
            offset_of!(Block, state),
            offset_of!(Block, loads),
            offset_of!(Block, energy),
        ];
        // Each field is whole rows, each row whole groups of one line.
        assert_eq!(GROUP * std::mem::size_of::<f64>(), 64);
        assert_eq!(std::mem::size_of::<Row>() % 64, 0);
        for start in starts {
            assert_eq!(start % 64, 0, "a row field at byte {start}");
        }
        let block = Block::new();
        assert_eq!(std::ptr::from_ref(&block.state[3][GROUP]) as usize % 64, 0);
    }

    #[test]
    fn a_group_is_its_slots_of_every_row() {
        let mut rows = [[0.0; BLOCK]; 3];
        for (q, row) in group_mut(&mut rows, GROUP).into_iter().enumerate() {
            row[GROUP - 1] = q as f64 + 1.0;
        }
        assert_eq!([rows[0][2 * GROUP - 1], rows[2][2 * GROUP - 1]], [1.0, 3.0]);
        assert_eq!(rows.iter().flatten().filter(|&&v| v != 0.0).count(), 3);
        assert_eq!(group(&rows, GROUP)[1][GROUP - 1], 2.0);
    }
}
