//! `rsl_batch_step_walls` through its C entry, against the per-contact
//! `rsl_contact_step_wall_accumulate` (and `rsl_contact_step_wall` for the energy terms) called
//! once per contact in contact order, at every SIMD level of this CPU:
//! - double precision: the accumulated forces and torques, the states and the energy terms bit
//!   for bit (tolerance 0), per-contact `k_t`, `gamma_t` and material pairs included, with the
//!   states in contact order or through a strictly increasing index (untouched slots keep their
//!   bits), for every law set and preset, for counts that fill no whole group or block, for
//!   calls large enough to prefetch, and for wall normals whose square overflows or underflows;
//!   `k_n` read only by the models that need it;
//! - bad input in one contact: the status of the per-contact call, the report's counts and
//!   first index, the refused contacts untouched and every other contact as the per-contact
//!   sequence steps it;
//! - call-level errors: nothing processed, nothing written, the report saying so;
//! - single precision: close to the double results (tolerance justified where it is set).

use super::batch::{
    rsl_batch_contact_params, rsl_batch_options, rsl_batch_report, rsl_batch_step_walls,
    RSL_BATCH_NONE, RSL_PRECISION_F32, RSL_PRECISION_F64, RSL_SIMD_AUTO,
};
use super::contact::{
    rsl_contact_energy, rsl_contact_input, rsl_contact_loads, rsl_contact_state,
    rsl_contact_step_wall, rsl_contact_step_wall_accumulate, RSL_INPUT_SLIDING_DAMPING,
    RSL_INPUT_SLIDING_STIFFNESS,
};
use super::model::{rsl_model, rsl_model_set_materials};
use super::params_tests::{base_models, last_error, live};
use super::status::{
    RSL_ERR_INVALID_ARGUMENT, RSL_ERR_INVALID_HANDLE, RSL_ERR_INVALID_TIME_STEP,
    RSL_ERR_MISALIGNED, RSL_ERR_NULL_POINTER, RSL_OK,
};
use super::types::{rsl_sphere, rsl_vec3, rsl_wall};
use crate::batch::Simd;
use crate::laws::model::{
    Model, Preset, RollingDamping, RollingForm, RollingLaw, RollingStiffness, SlidingLaw,
    Transport, TwistingLaw,
};
use crate::layout::tests::{state_bits, Lcg};
use crate::scalar::Vec3;

/// The time step of every call.
const DT: f64 = 1e-4;

/// `base_models` and each of them tracking energy.
fn all_models() -> Vec<Model> {
    let mut v = base_models();
    let tracked: Vec<Model> = v
        .iter()
        .map(|m| {
            let mut t = *m;
            t.track_energy = true;
            t
        })
        .collect();
    v.extend(tracked);
    v
}

/// More law sets, presets and options, as the pair kernels' tests step them: each subset of
/// the three laws in the objective (exact transport) and LAMMPS (project-rescale) families,
/// Marshall twisting with first-order transports, viscous rolling, YADE_2023 (its vector
/// twisting moment, and with `contact_point_sliding`), LIGGGHTS with `torsion_torque`, its cdt
/// with a rate threshold and epsd2 with a dashpot (angle and length forms), and a set without
/// limits (+inf friction coefficients).
fn more_models() -> Vec<Model> {
    let full = |preset, transport| {
        let mut m = Model::with_preset(preset);
        m.sliding.law = SlidingLaw::Linear;
        (m.sliding.stiffness, m.sliding.damping, m.sliding.friction) = (2e5, 30.0, 0.5);
        m.rolling.law = RollingLaw::Epsd;
        (m.rolling.stiffness, m.rolling.damping, m.rolling.friction) = (1e5, 10.0, 0.1);
        m.twisting.law = TwistingLaw::Sds;
        (
            m.twisting.stiffness,
            m.twisting.damping,
            m.twisting.friction,
        ) = (50.0, 0.5, 0.05);
        m.sliding_transport = transport;
        m.rolling_transport = transport;
        m
    };
    let objective = full(Preset::Objective, Transport::Exact);
    let lammps = full(Preset::Lammps2021, Transport::ProjectRescale);
    let mut models = Vec::new();
    for base in [objective, lammps] {
        for laws in 1..8 {
            let mut m = base;
            if laws & 1 == 0 {
                m.sliding.law = SlidingLaw::None;
            }
            if laws & 2 == 0 {
                m.rolling.law = RollingLaw::None;
            }
            if laws & 4 == 0 {
                m.twisting.law = TwistingLaw::None;
            }
            models.push(m);
        }
    }
    let mut marshall = objective;
    marshall.twisting.law = TwistingLaw::Marshall;
    marshall.sliding_transport = Transport::FirstOrder;
    marshall.rolling_transport = Transport::FirstOrder;
    let mut viscous = objective;
    viscous.rolling.law = RollingLaw::Viscous;
    viscous.sliding_transport = Transport::FirstOrder;
    let mut yade = full(Preset::Yade2023, Transport::FirstOrder);
    yade.rolling.form = RollingForm::Angle;
    let mut yade_contact_point = yade;
    yade_contact_point.contact_point_sliding = true;
    let mut torsion = Model::with_preset(Preset::Liggghts38);
    torsion.sliding = objective.sliding;
    torsion.rolling.law = RollingLaw::Epsd;
    (
        torsion.rolling.stiffness,
        torsion.rolling.damping,
        torsion.rolling.friction,
    ) = (50.0, 0.2, 0.05);
    torsion.torsion_torque = true;
    let mut cdt = Model::with_preset(Preset::Liggghts38);
    cdt.sliding = objective.sliding;
    cdt.rolling.law = RollingLaw::Cdt;
    cdt.rolling.friction = 0.05;
    cdt.rolling.rate_threshold = 1.0;
    let mut epsd2 = Model::with_preset(Preset::Liggghts38);
    epsd2.sliding = objective.sliding;
    epsd2.rolling.law = RollingLaw::Epsd;
    epsd2.rolling.stiffness_rule = RollingStiffness::Epsd2;
    (epsd2.rolling.damping, epsd2.rolling.friction) = (0.2, 0.05);
    let mut unlimited = objective;
    unlimited.sliding.friction = f64::INFINITY;
    unlimited.rolling.friction = f64::INFINITY;
    unlimited.twisting.friction = f64::INFINITY;
    models.extend([
        marshall,
        viscous,
        yade,
        yade_contact_point,
        unlimited,
        torsion,
    ]);
    // Torsion torque needs the angle form; the others in the length form too.
    for m in [cdt, epsd2] {
        models.push(m);
        let mut length = m;
        length.rolling.form = RollingForm::Length;
        length.rolling.friction = 0.1;
        models.push(length);
    }
    for m in &models {
        m.validate().unwrap();
    }
    models
}

/// Three material pairs of `base`'s laws (as `params_tests`' `material_models`): its own
/// coefficients and two others, each value scaled differently.
fn material_models(base: &Model) -> Vec<Model> {
    [1.0, 0.3, 2.5]
        .iter()
        .map(|&f| {
            let mut m = *base;
            m.sliding.stiffness *= f;
            m.sliding.damping *= 2.0 - f / 2.0;
            m.sliding.friction *= f;
            m.rolling.stiffness *= 1.0 / f;
            m.rolling.damping *= f;
            m.rolling.friction *= 1.5 - f / 5.0;
            m.twisting.stiffness *= f;
            m.twisting.damping *= 1.0 / f;
            m.twisting.friction *= f;
            m
        })
        .collect()
}

/// A live handle of `base` with its three material pairs as table, and the pairs' handles.
fn with_materials(base: Model) -> (rsl_model, Vec<rsl_model>) {
    let sets: Vec<rsl_model> = material_models(&base).into_iter().map(live).collect();
    let mut model = live(base);
    let pointers: Vec<*const rsl_model> = sets.iter().map(|s| s as *const _).collect();
    // SAFETY: a live handle and an array of three live handles.
    let status = unsafe { rsl_model_set_materials(&mut model, pointers.as_ptr(), 3) };
    assert_eq!(status, RSL_OK);
    (model, sets)
}

/// `v / |v|` for any finite non-zero `v` (scaled by its largest component first, so that huge
/// and tiny vectors normalise too): where a test wall's surface goes.
fn unit(v: Vec3<f64>) -> Vec3<f64> {
    let largest = v.x.abs().max(v.y.abs()).max(v.z.abs());
    let s = v / largest;
    s / s.norm()
}

/// A wall touching `sphere` (overlap 0.1 % to 3 % of its radius) whose outward normal is
/// `normal` (any length; the sphere on its side), its reference point moved along the surface
/// away from the contact point, moving and turning.
fn wall_at(rng: &mut Lcg, sphere: &rsl_sphere, normal: Vec3<f64>) -> rsl_wall {
    let u = unit(normal);
    let depth = sphere.radius * rng.uniform(0.001, 0.03);
    let touch = Vec3::from(sphere.position) - u * (sphere.radius - depth);
    let offset = Vec3::from(rng.vec(1.0));
    let offset = offset - u * offset.dot(&u);
    rsl_wall {
        point: (touch + offset).into(),
        normal: normal.into(),
        velocity: rng.vec(0.5),
        angular_velocity: rng.vec(0.2),
    }
}

/// A persistent history of a contact whose normal (sphere into wall) is `n`: springs tangent
/// to a previous normal a little off `n`, a twisting angle, a model memory (YADE's off-axis
/// twisting moment; the previous stiffnesses, >= 0, of a model that keeps them), slip flags
/// from the last step.
fn history(rng: &mut Lcg, n: Vec3<f64>) -> rsl_contact_state {
    let old = (n + Vec3::from(rng.vec(0.02))).normalize();
    let tangent = |v: rsl_vec3| -> rsl_vec3 {
        let v = Vec3::from(v);
        (v - old * v.dot(&old)).into()
    };
    rsl_contact_state {
        sliding_spring: tangent(rng.vec(5e-4)),
        rolling_spring: tangent(rng.vec(2e-4)),
        twisting_angle: rng.uniform(-1e-2, 1e-2),
        model_memory: {
            let m = rng.vec(0.05);
            rsl_vec3 {
                x: m.x.abs(),
                y: m.y.abs(),
                z: m.z.abs(),
            }
        },
        previous_normal: old.into(),
        slip_flags: rng.below(8) as u32,
        ..Default::default()
    }
}

/// Particles against walls: contact `c` is particle `spheres[c]` against `walls[c]`, with its
/// normal force, stiffnesses, material pair and history; `force` and `torque` are the
/// accumulators' values before the call (non-zero).
#[derive(Clone)]
struct Scene {
    particles: Vec<rsl_sphere>,
    spheres: Vec<u32>,
    walls: Vec<rsl_wall>,
    f_n: Vec<f64>,
    k_n: Vec<f64>,
    k_t: Vec<f64>,
    gamma_t: Vec<f64>,
    material: Vec<u32>,
    states: Vec<rsl_contact_state>,
    force: Vec<rsl_vec3>,
    torque: Vec<rsl_vec3>,
}

impl Scene {
    fn len(&self) -> usize {
        self.spheres.len()
    }

    /// The first `n` contacts (all the particles).
    fn prefix(&self, n: usize) -> Scene {
        Scene {
            particles: self.particles.clone(),
            spheres: self.spheres[..n].to_vec(),
            walls: self.walls[..n].to_vec(),
            f_n: self.f_n[..n].to_vec(),
            k_n: self.k_n[..n].to_vec(),
            k_t: self.k_t[..n].to_vec(),
            gamma_t: self.gamma_t[..n].to_vec(),
            material: self.material[..n].to_vec(),
            states: self.states[..n].to_vec(),
            force: self.force.clone(),
            torque: self.torque.clone(),
        }
    }
}

/// `n_particles` spheres, each touching 2 or 3 walls (a floor, a side wall, a ceiling, each a
/// little tilted, normals of lengths 1, 1e-3, 7.5 or 1e5), one contact in eight tensile. The
/// contacts come particle by particle (`wall_major` false: a particle's contacts next to each
/// other, in the same SIMD group) or wall by wall (all floors, then all sides, then all
/// ceilings).
fn scene(n_particles: usize, wall_major: bool, rng: &mut Lcg) -> Scene {
    let mut s = Scene {
        particles: Vec::new(),
        spheres: Vec::new(),
        walls: Vec::new(),
        f_n: Vec::new(),
        k_n: Vec::new(),
        k_t: Vec::new(),
        gamma_t: Vec::new(),
        material: Vec::new(),
        states: Vec::new(),
        force: Vec::new(),
        torque: Vec::new(),
    };
    let mut contacts = Vec::new();
    for i in 0..n_particles {
        let sphere = rsl_sphere {
            position: rng.vec(20.0),
            velocity: rng.vec(0.5),
            angular_velocity: rng.vec(3.0),
            radius: rng.uniform(0.5, 1.5),
        };
        s.particles.push(sphere);
        s.force.push(rng.vec(10.0));
        s.torque.push(rng.vec(5.0));
        let kinds: Vec<usize> = if rng.below(2) == 0 {
            vec![0, 1, 2]
        } else {
            vec![0, 1 + rng.below(2)]
        };
        for kind in kinds {
            let side = if rng.below(2) == 0 { 1.0 } else { -1.0 };
            let base = [
                Vec3::new(0.0, 0.0, 1.0),
                Vec3::new(side, 0.0, 0.0),
                Vec3::new(0.0, 0.0, -1.0),
            ][kind];
            let u = (base + Vec3::from(rng.vec(0.1))).normalize();
            let length = [1.0, 1e-3, 7.5, 1e5][rng.below(4)];
            let wall = wall_at(rng, &sphere, u * length);
            let f_n = if rng.below(8) == 0 {
                rng.uniform(-40.0, -1.0)
            } else {
                rng.uniform(1.0, 200.0)
            };
            let state = history(rng, -u);
            let values = (
                f_n,
                rng.uniform(1e4, 1e5),
                rng.uniform(5e4, 5e5),
                rng.uniform(5.0, 60.0),
                rng.below(3) as u32,
            );
            contacts.push((kind, i as u32, wall, values, state));
        }
    }
    if wall_major {
        contacts.sort_by_key(|c| c.0);
    }
    for (_, i, wall, (f_n, k_n, k_t, gamma_t, material), state) in contacts {
        s.spheres.push(i);
        s.walls.push(wall);
        s.f_n.push(f_n);
        s.k_n.push(k_n);
        s.k_t.push(k_t);
        s.gamma_t.push(gamma_t);
        s.material.push(material);
        s.states.push(state);
    }
    s
}

/// `s`'s contacts in a random order (the particles and accumulators as they are).
fn shuffled(s: &Scene, rng: &mut Lcg) -> Scene {
    let mut order: Vec<usize> = (0..s.len()).collect();
    for k in (1..order.len()).rev() {
        order.swap(k, rng.below(k + 1));
    }
    let pick = |v: &[f64]| order.iter().map(|&c| v[c]).collect::<Vec<f64>>();
    Scene {
        particles: s.particles.clone(),
        spheres: order.iter().map(|&c| s.spheres[c]).collect(),
        walls: order.iter().map(|&c| s.walls[c]).collect(),
        f_n: pick(&s.f_n),
        k_n: pick(&s.k_n),
        k_t: pick(&s.k_t),
        gamma_t: pick(&s.gamma_t),
        material: order.iter().map(|&c| s.material[c]).collect(),
        states: order.iter().map(|&c| s.states[c]).collect(),
        force: s.force.clone(),
        torque: s.torque.clone(),
    }
}

/// One particle against `n` walls in every direction (each touching it), with histories.
fn crowded_scene(n: usize, rng: &mut Lcg) -> Scene {
    let mut s = scene(1, false, rng).prefix(0);
    let sphere = s.particles[0];
    for _ in 0..n {
        let u = loop {
            let v = Vec3::from(rng.vec(1.0));
            if v.norm() > 0.2 {
                break v.normalize();
            }
        };
        let length = [1.0, 1e-3, 7.5, 1e5][rng.below(4)];
        s.spheres.push(0);
        s.walls.push(wall_at(rng, &sphere, u * length));
        s.f_n.push(rng.uniform(-20.0, 200.0));
        s.k_n.push(rng.uniform(1e4, 1e5));
        s.k_t.push(rng.uniform(5e4, 5e5));
        s.gamma_t.push(rng.uniform(5.0, 60.0));
        s.material.push(rng.below(3) as u32);
        s.states.push(history(rng, -u));
    }
    s
}

/// Which optional arrays a call passes: `normal_stiffness`, `params.sliding_stiffness`,
/// `params.sliding_damping`, `params.material`, `params.energy` (`params` itself NULL when
/// none of its four is).
#[derive(Clone, Copy, Debug, Default)]
struct Arrays {
    k_n: bool,
    k_t: bool,
    gamma_t: bool,
    material: bool,
    energy: bool,
}

impl Arrays {
    fn params(&self) -> bool {
        self.k_t || self.gamma_t || self.material || self.energy
    }
}

/// An energy entry the call must not write (skipped contacts, call-level errors).
const ENERGY_SENTINEL: rsl_contact_energy = rsl_contact_energy {
    elastic_sliding: -3.0,
    elastic_rolling: 0.0,
    elastic_twisting: 0.0,
    dashpot_sliding: 0.0,
    dashpot_rolling: 0.0,
    dashpot_twisting: 0.0,
    slider_sliding: 0.0,
    slider_rolling: 0.0,
    slider_twisting: 0.0,
    transport: 99.0,
    stiffness_change: -7.0,
};

/// A state slot the call must not touch (past the contacts, or not indexed).
fn spare_state() -> rsl_contact_state {
    rsl_contact_state {
        sliding_spring: rsl_vec3 {
            x: 1.0,
            y: -2.0,
            z: 3.0,
        },
        twisting_angle: 5.0,
        slip_flags: 6,
        reserved: 9,
        ..Default::default()
    }
}

/// What the per-contact calls give, contact by contact in contact order.
struct Want {
    /// Each contact's status.
    status: Vec<i32>,
    /// Each contact's state after its step (before it, where refused).
    states: Vec<rsl_contact_state>,
    /// The accumulators after every contact.
    force: Vec<rsl_vec3>,
    torque: Vec<rsl_vec3>,
    /// Each stepped contact's energy terms (`ENERGY_SENTINEL` where refused).
    energy: Vec<rsl_contact_energy>,
}

impl Want {
    fn first_failed(&self) -> Option<usize> {
        self.status.iter().position(|&s| s != RSL_OK)
    }
    fn failed(&self) -> usize {
        self.status.iter().filter(|&&s| s != RSL_OK).count()
    }
}

/// The per-contact sequence for `s`'s contacts: `rsl_contact_step_wall_accumulate` on the
/// accumulators in contact order, with `normal_stiffness` set when the model reads it (the
/// batch reads `k_n` only then), `RSL_INPUT_SLIDING_STIFFNESS` / `RSL_INPUT_SLIDING_DAMPING`
/// when `a` passes those arrays, the material pair's handle (`sets`) when it passes
/// `material`; a contact whose particle or material index is out of range is refused with
/// `RSL_ERR_INVALID_ARGUMENT` (what the batch documents). The energy terms come from
/// `rsl_contact_step_wall` on the same input, whose status and state are checked to be the
/// accumulating call's.
fn reference(model: &rsl_model, sets: &[rsl_model], s: &Scene, a: Arrays) -> Want {
    let n = s.len();
    let mut w = Want {
        status: Vec::with_capacity(n),
        states: s.states.clone(),
        force: s.force.clone(),
        torque: s.torque.clone(),
        energy: vec![ENERGY_SENTINEL; n],
    };
    let needs_kn = model.model.needs_normal_stiffness();
    for c in 0..n {
        let handle = if a.material {
            match sets.get(s.material[c] as usize) {
                Some(h) => h,
                None => {
                    w.status.push(RSL_ERR_INVALID_ARGUMENT);
                    continue;
                }
            }
        } else {
            model
        };
        let i = s.spheres[c] as usize;
        let Some(sphere) = s.particles.get(i) else {
            w.status.push(RSL_ERR_INVALID_ARGUMENT);
            continue;
        };
        let mut flags = 0;
        if a.k_t {
            flags |= RSL_INPUT_SLIDING_STIFFNESS;
        }
        if a.gamma_t {
            flags |= RSL_INPUT_SLIDING_DAMPING;
        }
        let input = rsl_contact_input {
            normal_force: s.f_n[c],
            dt: DT,
            normal_stiffness: if needs_kn { s.k_n[c] } else { 0.0 },
            sliding_stiffness: if a.k_t { s.k_t[c] } else { 0.0 },
            sliding_damping: if a.gamma_t { s.gamma_t[c] } else { 0.0 },
            flags,
            ..Default::default()
        };
        let before = w.states[c];
        // SAFETY: a live handle and locals of the right types; none overlap.
        let status = unsafe {
            rsl_contact_step_wall_accumulate(
                handle,
                sphere,
                &s.walls[c],
                &input,
                &mut w.states[c],
                &mut w.force[i],
                &mut w.torque[i],
            )
        };
        w.status.push(status);
        if a.energy {
            let (mut state, mut out) = (before, rsl_contact_loads::default());
            // SAFETY: as above.
            let out_status = unsafe {
                rsl_contact_step_wall(handle, sphere, &s.walls[c], &input, &mut state, &mut out)
            };
            assert_eq!(out_status, status, "contact {c}: the two per-contact calls");
            assert_eq!(state_bits(&state), state_bits(&w.states[c]), "contact {c}");
            if status == RSL_OK {
                w.energy[c] = out.energy;
            }
        }
    }
    w
}

/// Where the call finds the states: `states[c]` in an array of `n + spare` (`state_index`
/// NULL); `states[index[c]]` with strictly increasing indices leaving gaps of 0, 1 and 2
/// slots in an array with 2 more slots past the last index (`Indexed`); or with the indices
/// 0, 2, 4, ... in an array that ends at the last one (`IndexedTight`).
#[derive(Clone, Copy, Debug)]
enum Layout {
    Ordered { spare: usize },
    Indexed,
    IndexedTight,
}

/// The two layouts of the larger tests: states in contact order, and in place through an index.
const TWO_LAYOUTS: [Layout; 2] = [Layout::Ordered { spare: 0 }, Layout::Indexed];

const LAYOUTS: [Layout; 4] = [
    Layout::Ordered { spare: 0 },
    Layout::Ordered { spare: 5 },
    Layout::Indexed,
    Layout::IndexedTight,
];

/// What one batch call left.
struct Got {
    status: i32,
    report: rsl_batch_report,
    /// States in contact order.
    states: Vec<rsl_contact_state>,
    force: Vec<rsl_vec3>,
    torque: Vec<rsl_vec3>,
    /// The energy output (`ENERGY_SENTINEL` everywhere when not passed).
    energy: Vec<rsl_contact_energy>,
}

/// `rsl_batch_step_walls` on `s`'s contacts with the arrays `a`, options `o` (NULL for
/// `None`) and the state layout `layout`; asserts that the state slots it does not own kept
/// their bits.
fn run(
    model: &rsl_model,
    s: &Scene,
    a: Arrays,
    o: Option<&rsl_batch_options>,
    layout: Layout,
) -> Got {
    run_with_report(model, s, a, o, layout, true)
}

/// As [`run`], with `report` NULL when `with_report` is false.
fn run_with_report(
    model: &rsl_model,
    s: &Scene,
    a: Arrays,
    o: Option<&rsl_batch_options>,
    layout: Layout,
    with_report: bool,
) -> Got {
    let n = s.len();
    let np = s.particles.len();
    let (index, n_states): (Vec<usize>, usize) = match layout {
        Layout::Ordered { spare } => (Vec::new(), n + spare),
        Layout::Indexed => {
            let index: Vec<usize> = (0..n).map(|c| 3 * c + 1 + c % 3).collect();
            let n_states = index.last().map_or(0, |&l| l + 3);
            (index, n_states)
        }
        Layout::IndexedTight => ((0..n).map(|c| 2 * c).collect(), (2 * n).saturating_sub(1)),
    };
    let slot = |c: usize| match layout {
        Layout::Ordered { .. } => c,
        Layout::Indexed | Layout::IndexedTight => index[c],
    };
    let mut slots = vec![spare_state(); n_states];
    for c in 0..n {
        slots[slot(c)] = s.states[c];
    }
    let (mut force, mut torque) = (s.force.clone(), s.torque.clone());
    let mut energy = vec![ENERGY_SENTINEL; n];
    let params = rsl_batch_contact_params {
        sliding_stiffness: if a.k_t {
            s.k_t.as_ptr()
        } else {
            std::ptr::null()
        },
        sliding_damping: if a.gamma_t {
            s.gamma_t.as_ptr()
        } else {
            std::ptr::null()
        },
        material: if a.material {
            s.material.as_ptr()
        } else {
            std::ptr::null()
        },
        energy: if a.energy {
            energy.as_mut_ptr()
        } else {
            std::ptr::null_mut()
        },
    };
    let mut report = rsl_batch_report {
        processed: 77,
        failed: 77,
        first_failed: 77,
        first_status: 77,
        simd: 77,
        reserved: 77,
    };
    // SAFETY: every array holds what the call reads or writes (`slots` `n_states` states,
    // `index` `n` increasing indices below it, the per-contact arrays `n` entries, the
    // per-particle ones `np`); none of the written ones overlap anything.
    let status = unsafe {
        rsl_batch_step_walls(
            model,
            s.particles.as_ptr(),
            np,
            s.spheres.as_ptr(),
            s.walls.as_ptr(),
            n,
            s.f_n.as_ptr(),
            if a.k_n {
                s.k_n.as_ptr()
            } else {
                std::ptr::null()
            },
            if a.params() {
                &params
            } else {
                std::ptr::null()
            },
            DT,
            o.map_or(std::ptr::null(), |o| o as *const _),
            slots.as_mut_ptr(),
            n_states,
            if !matches!(layout, Layout::Ordered { .. }) {
                index.as_ptr()
            } else {
                std::ptr::null()
            },
            force.as_mut_ptr(),
            torque.as_mut_ptr(),
            if with_report {
                &mut report
            } else {
                std::ptr::null_mut()
            },
        )
    };
    let owned: Vec<usize> = (0..n).map(slot).collect();
    let mut is_owned = vec![false; n_states];
    for &k in &owned {
        is_owned[k] = true;
    }
    for (k, st) in slots.iter().enumerate() {
        if !is_owned[k] {
            assert_eq!(
                state_bits(st),
                state_bits(&spare_state()),
                "{layout:?}: slot {k} (no contact's) was written"
            );
        }
    }
    Got {
        status,
        report,
        states: owned.iter().map(|&k| slots[k]).collect(),
        force,
        torque,
        energy,
    }
}

fn vec_bits(v: &[rsl_vec3]) -> Vec<[u64; 3]> {
    v.iter()
        .map(|v| [v.x.to_bits(), v.y.to_bits(), v.z.to_bits()])
        .collect()
}

fn energy_terms(e: &rsl_contact_energy) -> [f64; 11] {
    [
        e.elastic_sliding,
        e.elastic_rolling,
        e.elastic_twisting,
        e.dashpot_sliding,
        e.dashpot_rolling,
        e.dashpot_twisting,
        e.slider_sliding,
        e.slider_rolling,
        e.slider_twisting,
        e.transport,
        e.stiffness_change,
    ]
}

fn energy_bits(e: &rsl_contact_energy) -> [u64; 11] {
    energy_terms(e).map(f64::to_bits)
}

/// The report the batch owes for `w`'s statuses, `simd` the level that ran.
fn expected_report(w: &Want, simd: u32) -> rsl_batch_report {
    let first = w.first_failed();
    rsl_batch_report {
        processed: (w.status.len() - w.failed()) as u64,
        failed: w.failed() as u64,
        first_failed: first.map_or(RSL_BATCH_NONE, |c| c as u64),
        first_status: first.map_or(RSL_OK, |c| w.status[c]),
        simd,
        reserved: 0,
    }
}

/// Asserts that the batch left `w`'s results bit for bit: status, report, states, accumulators
/// and (when `energy`) the energy entries.
fn assert_bits(g: &Got, w: &Want, simd: u32, energy: bool, what: &str) {
    let report = expected_report(w, simd);
    assert_eq!(g.status, report.first_status, "{what}: status");
    assert_eq!(g.report, report, "{what}: report");
    for c in 0..w.status.len() {
        assert_eq!(
            state_bits(&g.states[c]),
            state_bits(&w.states[c]),
            "{what}: state of contact {c} (per-contact status {}): {:?} vs {:?}",
            w.status[c],
            g.states[c],
            w.states[c]
        );
    }
    let (gf, wf) = (vec_bits(&g.force), vec_bits(&w.force));
    for i in 0..wf.len() {
        assert_eq!(
            gf[i], wf[i],
            "{what}: force on particle {i}: {:?} vs {:?}",
            g.force[i], w.force[i]
        );
    }
    let (gt, wt) = (vec_bits(&g.torque), vec_bits(&w.torque));
    for i in 0..wt.len() {
        assert_eq!(
            gt[i], wt[i],
            "{what}: torque on particle {i}: {:?} vs {:?}",
            g.torque[i], w.torque[i]
        );
    }
    for c in 0..w.status.len() {
        let want = if energy {
            &w.energy[c]
        } else {
            &ENERGY_SENTINEL
        };
        assert_eq!(
            energy_bits(&g.energy[c]),
            energy_bits(want),
            "{what}: energy of contact {c}: {:?} vs {:?}",
            g.energy[c],
            want
        );
    }
}

/// This CPU's SIMD levels.
fn levels() -> Vec<Simd> {
    [Simd::Scalar, Simd::Avx2, Simd::Avx512]
        .into_iter()
        .filter(|s| s.available())
        .collect()
}

fn options(simd: Simd, precision: u32) -> rsl_batch_options {
    rsl_batch_options {
        precision,
        simd: simd.code(),
        flags: 0,
        reserved: 0,
    }
}

/// The batch call at every double-precision level this CPU has, in each of `layouts`, against
/// the per-contact sequence `w` (bit for bit); returns the number of contacts compared.
fn assert_every_kernel(
    model: &rsl_model,
    s: &Scene,
    a: Arrays,
    w: &Want,
    layouts: &[Layout],
    what: &str,
) -> usize {
    let mut checked = 0;
    for simd in levels() {
        let o = options(simd, RSL_PRECISION_F64);
        for &layout in layouts {
            let g = run(model, s, a, Some(&o), layout);
            assert_bits(
                &g,
                w,
                simd.code(),
                a.energy,
                &format!("{what} {simd:?} {layout:?}"),
            );
            checked += s.len();
        }
    }
    checked
}

/// The array sets of the double-precision comparison for `model`: `k_n` NULL where the model
/// does not read it, per-contact `k_t` and `gamma_t` alone and together, material pairs with and
/// without `k_t` (which wins over the pair's), and the energy output where the model tracks it.
fn array_sets(model: &Model) -> Vec<Arrays> {
    let needs_kn = model.needs_normal_stiffness();
    let plain = Arrays {
        k_n: true,
        ..Default::default()
    };
    let mut v = vec![
        plain,
        Arrays { k_t: true, ..plain },
        Arrays {
            gamma_t: true,
            ..plain
        },
        Arrays {
            k_t: true,
            gamma_t: true,
            ..plain
        },
        Arrays {
            material: true,
            ..plain
        },
        Arrays {
            material: true,
            k_t: true,
            gamma_t: true,
            ..plain
        },
    ];
    if !needs_kn {
        v.push(Arrays::default());
        v.push(Arrays {
            k_t: true,
            ..Default::default()
        });
    }
    if model.track_energy {
        let with_energy: Vec<Arrays> = v.iter().map(|a| Arrays { energy: true, ..*a }).collect();
        v.extend(with_energy);
    }
    v
}

/// Test 1. Several hundred contacts of about 100 particles, 2-3 walls each (tensile normal
/// forces, normals of lengths 1e-3 to 1e5, non-zero histories and accumulators), ordered by
/// particle, by wall and at random: for every law set (energy tracking on and off), every array
/// set, every SIMD level and every state layout, the double-precision batch gives the
/// per-contact sequence's accumulators, states and energy terms bit for bit; NULL options (the
/// best level) and a NULL report too.
#[test]
fn walls_step_as_the_per_contact_accumulating_call_bit_for_bit() {
    let mut rng = Lcg(2024);
    let mut contacts_checked = 0;
    for base in all_models() {
        let (model, sets) = with_materials(base);
        for order in ["particle", "wall", "random"] {
            let s = scene(100, order == "wall", &mut rng);
            let s = if order == "random" {
                shuffled(&s, &mut rng)
            } else {
                s
            };
            assert!(s.len() >= 200, "{} contacts", s.len());
            assert!(s.f_n.iter().any(|&f| f < 0.0), "no tensile contact");
            for a in array_sets(&base) {
                let w = reference(&model, &sets, &s, a);
                for (c, &st) in w.status.iter().enumerate() {
                    assert_eq!(
                        st, RSL_OK,
                        "{base:?} {a:?}: per-contact step of contact {c}"
                    );
                }
                if a.energy {
                    assert!(w
                        .energy
                        .iter()
                        .any(|e| e.elastic_sliding > 0.0 && e.dashpot_sliding > 0.0));
                }
                let what = format!("{base:?} {order} order {a:?}");
                contacts_checked += assert_every_kernel(&model, &s, a, &w, &LAYOUTS, &what);
                // Default options: the best level; no report.
                let what = format!("{base:?} {order} order {a:?} NULL options");
                let g = run(&model, &s, a, None, Layout::Ordered { spare: 0 });
                assert_bits(&g, &w, Simd::best().code(), a.energy, &what);
                let auto = rsl_batch_options {
                    simd: RSL_SIMD_AUTO,
                    ..options(Simd::Scalar, RSL_PRECISION_F64)
                };
                let mut g = run_with_report(&model, &s, a, Some(&auto), Layout::Indexed, false);
                g.report = expected_report(&w, Simd::best().code());
                assert_bits(&g, &w, Simd::best().code(), a.energy, &what);
            }
            // The material pairs and the per-contact coefficients do change the loads.
            let plain = reference(&model, &sets, &s, array_sets(&base)[0]);
            for a in [
                Arrays {
                    k_t: true,
                    k_n: true,
                    ..Default::default()
                },
                Arrays {
                    material: true,
                    k_n: true,
                    ..Default::default()
                },
            ] {
                let other = reference(&model, &sets, &s, a);
                assert_ne!(vec_bits(&plain.force), vec_bits(&other.force), "{a:?}");
            }
        }
    }
    assert!(contacts_checked > 0);
}

/// Test 1d. `normal_stiffness` is read only by the models that need it: for the others an array
/// of NaN (or NULL) gives the bits of the per-contact call without `k_n`; for cdt, which reads
/// it, the same NaN refuses every contact (`RSL_ERR_NON_FINITE`), nothing written.
#[test]
fn normal_stiffness_is_read_only_by_the_models_that_need_it() {
    let mut rng = Lcg(57);
    let models = base_models();
    for base in models {
        let (model, sets) = with_materials(base);
        let mut s = scene(30, false, &mut rng);
        s.k_n.iter_mut().for_each(|k| *k = f64::NAN);
        let a = Arrays {
            k_n: true,
            ..Default::default()
        };
        let w = reference(&model, &sets, &s, a);
        if base.needs_normal_stiffness() {
            assert!(w
                .status
                .iter()
                .all(|&st| st == super::status::RSL_ERR_NON_FINITE));
        } else {
            assert!(w.status.iter().all(|&st| st == RSL_OK));
        }
        for simd in levels() {
            for precision in [RSL_PRECISION_F64, RSL_PRECISION_F32] {
                let o = options(simd, precision);
                let what = format!("{base:?} {simd:?} precision {precision}");
                let g = run(&model, &s, a, Some(&o), Layout::Ordered { spare: 0 });
                if precision == RSL_PRECISION_F64 || base.needs_normal_stiffness() {
                    assert_bits(&g, &w, simd.code(), false, &what);
                } else {
                    assert_eq!(g.report, expected_report(&w, simd.code()), "{what}");
                }
            }
        }
    }
}

/// Test 1b. Calls large enough to prefetch (their arrays over `PREFETCH_MIN_BYTES`: about 6000
/// contacts of 2500 particles) give the per-contact sequence's bits too, each level, both
/// layouts.
#[test]
fn large_calls_that_prefetch_step_as_the_per_contact_call() {
    let mut rng = Lcg(8128);
    let models = base_models();
    let mut cdt = models[3];
    cdt.track_energy = true;
    for base in [models[0], cdt] {
        let (model, sets) = with_materials(base);
        let s = scene(2500, false, &mut rng);
        let bytes = std::mem::size_of_val(&s.walls[..]) + std::mem::size_of_val(&s.states[..]);
        assert!(bytes > crate::batch::PREFETCH_MIN_BYTES, "{bytes} bytes");
        let a = Arrays {
            k_n: true,
            k_t: true,
            energy: base.track_energy,
            ..Default::default()
        };
        let w = reference(&model, &sets, &s, a);
        assert!(w.status.iter().all(|&st| st == RSL_OK));
        let what = format!("{base:?} {a:?} large");
        assert_every_kernel(&model, &s, a, &w, &TWO_LAYOUTS, &what);
    }
}

/// Test 1c. Every law set, preset and option of [`more_models`] (each also tracking energy):
/// the batch gives the per-contact sequence's bits, with and without per-contact `k_t` and
/// `gamma_t`, each level, both layouts.
#[test]
fn every_law_set_and_preset_steps_walls_as_the_per_contact_call() {
    let mut rng = Lcg(1729);
    for plain in more_models() {
        let mut tracked = plain;
        tracked.track_energy = true;
        for base in [plain, tracked] {
            let (model, sets) = with_materials(base);
            let s = scene(40, true, &mut rng);
            for a in [
                Arrays {
                    k_n: true,
                    energy: base.track_energy,
                    ..Default::default()
                },
                Arrays {
                    k_n: true,
                    k_t: true,
                    gamma_t: true,
                    material: true,
                    energy: base.track_energy,
                },
            ] {
                let w = reference(&model, &sets, &s, a);
                for (c, &st) in w.status.iter().enumerate() {
                    assert_eq!(
                        st, RSL_OK,
                        "{base:?} {a:?}: per-contact step of contact {c}"
                    );
                }
                assert_every_kernel(&model, &s, a, &w, &TWO_LAYOUTS, &format!("{base:?} {a:?}"));
            }
        }
    }
}

/// Test 2. Counts that fill no whole group of 8 or block of 32 (1, 7, 9, 31, 33, 65, 100; 0
/// too), and one particle against 37 walls (every lane of a group adding to the same
/// accumulators): the partial groups and blocks give the per-contact sequence's bits, each
/// layout, each level.
#[test]
fn partial_groups_and_blocks_step_as_the_per_contact_call() {
    let mut rng = Lcg(77);
    for base in all_models() {
        let (model, sets) = with_materials(base);
        let full = scene(50, false, &mut rng);
        assert!(full.len() >= 100);
        // One particle against 37 walls all around it: every contact adds to the same
        // accumulators, 8 or 16 of them in each group.
        let crowded = crowded_scene(37, &mut rng);
        let scenes = [0, 1, 7, 9, 31, 33, 65, 100]
            .map(|n| (format!("n {n}"), full.prefix(n)))
            .into_iter()
            .chain([("one particle, 37 walls".to_string(), crowded)]);
        for (n, s) in scenes {
            for a in [
                Arrays {
                    k_n: true,
                    ..Default::default()
                },
                Arrays {
                    k_n: true,
                    k_t: true,
                    gamma_t: true,
                    energy: base.track_energy,
                    ..Default::default()
                },
            ] {
                let w = reference(&model, &sets, &s, a);
                assert!(w.status.iter().all(|&st| st == RSL_OK));
                assert_every_kernel(&model, &s, a, &w, &LAYOUTS, &format!("{base:?} {n} {a:?}"));
            }
        }
    }
}

/// Test 3. Wall normals whose square overflows or underflows (lengths 1e200, 1e-200, 1e300,
/// 1e-300, around the limits 1.3e154 and 1.5e-154, components of 1e308 or subnormal), mixed
/// with plain ones in the same groups and filling whole groups alone: the per-contact call
/// accepts them (it normalises them rescaled), and the batch gives its bits.
#[test]
fn normals_whose_square_overflows_or_underflows_give_the_per_contact_bits() {
    let mut rng = Lcg(31);
    let lengths = [
        1e200, 1e-200, 1e300, 1e-300, 1.4e154, 1.4e-154, 1e-160, 1e160,
    ];
    let vectors = [
        Vec3::new(0.0, 0.0, 5e-324),
        Vec3::new(1e-310, -3e-311, 2e-310),
        Vec3::new(1e308, 1e308, 0.0),
        Vec3::new(-1e308, 3e307, 1.7e308),
        Vec3::new(2e-320, 2e-320, 2e-320),
        Vec3::new(1e200, 1e-200, 0.0),
    ];
    for base in all_models() {
        let (model, sets) = with_materials(base);
        // Every other contact, then every contact, with an extreme normal.
        for every in [2, 1] {
            let mut s = scene(40, false, &mut rng);
            for c in (0..s.len()).step_by(every) {
                let sphere = s.particles[s.spheres[c] as usize];
                let k = rng.below(lengths.len() + vectors.len());
                let normal = if k < lengths.len() {
                    unit(Vec3::from(s.walls[c].normal)) * lengths[k]
                } else {
                    vectors[k - lengths.len()]
                };
                s.walls[c] = wall_at(&mut rng, &sphere, normal);
                let n = -unit(normal);
                s.states[c] = history(&mut rng, n);
            }
            for a in [
                Arrays {
                    k_n: true,
                    ..Default::default()
                },
                Arrays {
                    k_n: true,
                    k_t: true,
                    energy: base.track_energy,
                    ..Default::default()
                },
            ] {
                let w = reference(&model, &sets, &s, a);
                for (c, &st) in w.status.iter().enumerate() {
                    assert_eq!(
                        st, RSL_OK,
                        "{base:?}: per-contact step of contact {c}, normal {:?}",
                        s.walls[c].normal
                    );
                }
                let what = format!("{base:?} every {every} {a:?}");
                assert_every_kernel(&model, &s, a, &w, &LAYOUTS, &what);
            }
        }
    }
}

/// Number of doubles [`poke`] reaches.
const POKED_DOUBLES: usize = 39;

/// Double `field` of contact `c`: its wall (0-11: point, normal, velocity, angular velocity),
/// its sphere (12-21: position, velocity, angular velocity, radius; shared with the particle's
/// other contacts), `f_n` (22), `k_t` (23), `gamma_t` (24), `k_n` (25), its state (26-38:
/// sliding spring, rolling spring, twisting angle, model memory, previous normal).
fn poke(s: &mut Scene, c: usize, field: usize) -> &mut f64 {
    fn vec(v: &mut rsl_vec3, i: usize) -> &mut f64 {
        [&mut v.x, &mut v.y, &mut v.z].into_iter().nth(i).unwrap()
    }
    match field {
        0..=11 => {
            let w = &mut s.walls[c];
            let v = [
                &mut w.point,
                &mut w.normal,
                &mut w.velocity,
                &mut w.angular_velocity,
            ]
            .into_iter()
            .nth(field / 3)
            .unwrap();
            vec(v, field % 3)
        }
        12..=21 => {
            let p = &mut s.particles[s.spheres[c] as usize];
            match field - 12 {
                i @ 0..=2 => vec(&mut p.position, i),
                i @ 3..=5 => vec(&mut p.velocity, i - 3),
                i @ 6..=8 => vec(&mut p.angular_velocity, i - 6),
                _ => &mut p.radius,
            }
        }
        22 => &mut s.f_n[c],
        23 => &mut s.k_t[c],
        24 => &mut s.gamma_t[c],
        25 => &mut s.k_n[c],
        _ => {
            let st = &mut s.states[c];
            match field - 26 {
                i @ 0..=2 => vec(&mut st.sliding_spring, i),
                i @ 3..=5 => vec(&mut st.rolling_spring, i - 3),
                6 => &mut st.twisting_angle,
                i @ 7..=9 => vec(&mut st.model_memory, i - 7),
                i => vec(&mut st.previous_normal, i - 10),
            }
        }
    }
}

/// Test 4. Bad input in one contact in the middle of a batch (40 contacts of 16 particles, a
/// particle's contacts side by side): each double of its wall, sphere (shared with its
/// particle's other contacts), `f_n`, `k_t`, `gamma_t`, `k_n` (for the models that read it) and
/// state set to NaN, +-inf, 0, -0, -1, 1e200, 1e-200, +-f64::MAX and the least subnormal; its
/// wall normal all zero (+0 or -0) or the least subnormal along one axis; its particle index
/// out of range (`n_particles`, `u32::MAX`); its material index out of range. In double
/// precision the batch returns the status the per-contact sequence gives its first refused
/// contact (`RSL_OK` where all accept), the report counts the refused contacts and gives the
/// first, the refused contacts keep their state and energy entry and add nothing, and every
/// other contact has the sequence's bits. In single precision, for the refusals that do not
/// depend on the precision (NaN, +-inf, indices, zero normal), the same status, report and
/// untouched contacts.
#[test]
fn bad_input_in_one_contact_is_refused_as_the_per_contact_call_refuses_it() {
    let mut rng = Lcg(4242);
    let values = [
        f64::NAN,
        f64::INFINITY,
        f64::NEG_INFINITY,
        0.0,
        -1.0,
        1e200,
        1e-200,
        f64::MAX,
        -f64::MAX,
        5e-324,
        -0.0,
    ];
    let mut refused = 0;
    let mut cases = 0;
    let mut f32_cases = 0;
    let mut models = base_models();
    for k in [1, 3] {
        let mut tracked = models[k];
        tracked.track_energy = true;
        models.push(tracked);
    }
    for base in models {
        let (model, sets) = with_materials(base);
        let clean = scene(16, false, &mut rng);
        let m = clean.len() / 2;
        assert!(clean.len() >= 33, "{} contacts", clean.len());
        let needs_kn = base.needs_normal_stiffness();
        let with_params = Arrays {
            k_n: true,
            k_t: true,
            gamma_t: true,
            energy: base.track_energy,
            ..Default::default()
        };
        let plain = Arrays {
            k_n: needs_kn,
            ..Default::default()
        };
        let mut bad_cases: Vec<(String, Scene, Arrays)> = Vec::new();
        for field in 0..POKED_DOUBLES {
            if field == 25 && !needs_kn {
                continue; // k_n is not read (documented): nothing to refuse
            }
            for x in values {
                let mut s = clean.clone();
                *poke(&mut s, m, field) = x;
                let what = format!("double {field} of contact {m} = {x:e}");
                if !(23..=25).contains(&field) {
                    bad_cases.push((what.clone(), s.clone(), plain));
                }
                bad_cases.push((what, s, with_params));
            }
        }
        for (name, normal) in [
            ("zero normal", Vec3::new(0.0, 0.0, 0.0)),
            ("subnormal normal", Vec3::new(0.0, 0.0, 5e-324)),
            ("negative zero normal", Vec3::new(-0.0, 0.0, -0.0)),
        ] {
            let mut s = clean.clone();
            s.walls[m].normal = normal.into();
            bad_cases.push((name.to_string(), s, with_params));
        }
        for index in [clean.particles.len() as u32, u32::MAX] {
            let mut s = clean.clone();
            s.spheres[m] = index;
            bad_cases.push((format!("sphere index {index}"), s.clone(), plain));
            bad_cases.push((format!("sphere index {index}"), s, with_params));
        }
        for index in [3, u32::MAX] {
            let mut s = clean.clone();
            s.material[m] = index;
            let a = Arrays {
                material: true,
                ..with_params
            };
            bad_cases.push((format!("material index {index}"), s, a));
        }
        for (what, s, a) in &bad_cases {
            let w = reference(&model, &sets, s, *a);
            if w.failed() > 0 {
                refused += 1;
            }
            cases += 1;
            for simd in levels() {
                let o = options(simd, RSL_PRECISION_F64);
                for layout in [Layout::Ordered { spare: 1 }, Layout::Indexed] {
                    let what = format!("{base:?} {what} {a:?} {simd:?} {layout:?}");
                    let g = run(&model, s, *a, Some(&o), layout);
                    assert_bits(&g, &w, simd.code(), a.energy, &what);
                    if w.status[m] != RSL_OK {
                        assert_eq!(
                            state_bits(&g.states[m]),
                            state_bits(&s.states[m]),
                            "{what}: the refused contact's state"
                        );
                    }
                }
                // Single precision refuses the same contacts where the refusal does not
                // depend on the precision (non-finite values, bad indices, a zero normal):
                // same status and report, the refused contacts untouched.
                let same_in_f32 = what.contains("NaN")
                    || what.contains("inf")
                    || what.contains("index")
                    || what.contains("zero normal");
                if same_in_f32 {
                    let o = options(simd, RSL_PRECISION_F32);
                    let what = format!("{base:?} {what} {a:?} {simd:?} f32");
                    let g = run(&model, s, *a, Some(&o), Layout::Indexed);
                    let report = expected_report(&w, simd.code());
                    assert_eq!(g.status, report.first_status, "{what}: status");
                    assert_eq!(g.report, report, "{what}: report");
                    for (c, &st) in w.status.iter().enumerate() {
                        if st != RSL_OK {
                            assert_eq!(
                                state_bits(&g.states[c]),
                                state_bits(&s.states[c]),
                                "{what}: refused contact {c}'s state"
                            );
                            assert_eq!(
                                energy_bits(&g.energy[c]),
                                energy_bits(&ENERGY_SENTINEL),
                                "{what}: refused contact {c}'s energy"
                            );
                        }
                    }
                    f32_cases += 1;
                }
            }
        }
    }
    assert!(f32_cases > 0);
    // NaN and +-inf are refused in every double (3 of the 11 values), and a few more.
    assert!(
        refused * 11 > cases * 3,
        "only {refused} of {cases} cases refused"
    );
}

/// The report of a call-level error with status `status`.
fn refused_report(status: i32) -> rsl_batch_report {
    rsl_batch_report {
        processed: 0,
        failed: 0,
        first_failed: RSL_BATCH_NONE,
        first_status: status,
        simd: 0,
        reserved: 0,
    }
}

/// The raw arguments of one `rsl_batch_step_walls` call.
#[derive(Clone, Copy)]
struct Call {
    model: *const rsl_model,
    particles: *const rsl_sphere,
    n_particles: usize,
    spheres: *const u32,
    walls: *const rsl_wall,
    n_contacts: usize,
    normal_force: *const f64,
    normal_stiffness: *const f64,
    params: *const rsl_batch_contact_params,
    dt: f64,
    options: *const rsl_batch_options,
    states: *mut rsl_contact_state,
    n_states: usize,
    state_index: *const usize,
    force: *mut rsl_vec3,
    torque: *mut rsl_vec3,
    report: *mut rsl_batch_report,
}

impl Call {
    /// # Safety
    /// The pointers as `rsl_batch_step_walls` needs them (or NULL / misaligned on purpose).
    unsafe fn run(&self) -> i32 {
        // SAFETY: forwarded contract.
        unsafe {
            rsl_batch_step_walls(
                self.model,
                self.particles,
                self.n_particles,
                self.spheres,
                self.walls,
                self.n_contacts,
                self.normal_force,
                self.normal_stiffness,
                self.params,
                self.dt,
                self.options,
                self.states,
                self.n_states,
                self.state_index,
                self.force,
                self.torque,
                self.report,
            )
        }
    }
}

/// Test 5. Call-level errors process nothing and write nothing (states, accumulators, energy
/// entries keep their bits), and the report says so (`processed = failed = 0`, no first
/// contact, the call's status): NULL arrays (particles with `n_particles > 0`, spheres, walls,
/// normal forces, `k_n` for a model that reads it, states, accumulators, model), a dead handle,
/// misaligned arrays, `state_index` not strictly increasing or out of range, `n_states` below
/// `n_contacts` without an index, bad options, bad time steps, an energy output for a model
/// that does not track energy, a damping-ratio rolling model. Then the edge cases that are no
/// call-level error: no contact at all (NULL everywhere), and contacts without particles (each
/// refused as an index out of range).
#[test]
fn call_level_errors_process_nothing_and_write_nothing() {
    let mut rng = Lcg(9);
    let models = base_models();
    let (lammps, cdt) = (models[0], models[3]);
    assert!(cdt.needs_normal_stiffness() && !lammps.needs_normal_stiffness());
    let s = scene(8, false, &mut rng);
    let n = s.len();
    let np = s.particles.len();
    let o = options(Simd::Scalar, RSL_PRECISION_F64);
    let model = live(lammps);
    let cdt_model = live(cdt);
    let mut ratio = lammps;
    ratio.rolling.damping_rule = RollingDamping::Ratio;
    ratio.rolling.damping = 0.3;
    let ratio_model = live(ratio);
    let mut tracked = lammps;
    tracked.track_energy = true;
    let tracked_model = live(tracked);
    // Every call writes into these; each case starts from the same values.
    let n_states = 2 * n + 2;
    let index: Vec<usize> = (0..n).map(|c| 2 * c + 1).collect();
    let mut slots: Vec<rsl_contact_state> = (0..n_states)
        .map(|k| {
            if k % 2 == 1 && k / 2 < n {
                s.states[k / 2]
            } else {
                spare_state()
            }
        })
        .collect();
    let (mut force, mut torque) = (s.force.clone(), s.torque.clone());
    let mut energy = vec![ENERGY_SENTINEL; n];
    let mut report = rsl_batch_report::default();
    let initial = (
        slots.iter().map(state_bits).collect::<Vec<_>>(),
        vec_bits(&force),
        vec_bits(&torque),
        energy.iter().map(energy_bits).collect::<Vec<_>>(),
    );
    let bad_index_sets: Vec<Vec<usize>> = vec![
        {
            let mut v = index.clone();
            v[5] = v[4]; // equal neighbours
            v
        },
        {
            let mut v = index.clone();
            v.swap(3, 4); // decreasing
            v
        },
        {
            let mut v = index.clone();
            v[n - 1] = n_states; // out of range
            v
        },
        {
            let mut v = index.clone();
            v[n - 1] = usize::MAX;
            v
        },
    ];
    let bad_options = [
        rsl_batch_options { precision: 2, ..o },
        rsl_batch_options { simd: 9, ..o },
        rsl_batch_options { flags: 1, ..o },
    ];
    let energy_params = rsl_batch_contact_params {
        sliding_stiffness: std::ptr::null(),
        sliding_damping: std::ptr::null(),
        material: std::ptr::null(),
        energy: energy.as_mut_ptr(),
    };
    let plain = Call {
        model: &model,
        particles: s.particles.as_ptr(),
        n_particles: np,
        spheres: s.spheres.as_ptr(),
        walls: s.walls.as_ptr(),
        n_contacts: n,
        normal_force: s.f_n.as_ptr(),
        normal_stiffness: s.k_n.as_ptr(),
        params: std::ptr::null(),
        dt: DT,
        options: &o,
        states: slots.as_mut_ptr(),
        n_states,
        state_index: index.as_ptr(),
        force: force.as_mut_ptr(),
        torque: torque.as_mut_ptr(),
        report: &mut report,
    };
    let misaligned = |p: usize| p + 4;
    let mut cases: Vec<(String, Call, i32)> = vec![
        (
            "NULL particles".into(),
            Call {
                particles: std::ptr::null(),
                ..plain
            },
            RSL_ERR_NULL_POINTER,
        ),
        (
            "NULL spheres".into(),
            Call {
                spheres: std::ptr::null(),
                ..plain
            },
            RSL_ERR_NULL_POINTER,
        ),
        (
            "NULL walls".into(),
            Call {
                walls: std::ptr::null(),
                ..plain
            },
            RSL_ERR_NULL_POINTER,
        ),
        (
            "NULL normal_force".into(),
            Call {
                normal_force: std::ptr::null(),
                ..plain
            },
            RSL_ERR_NULL_POINTER,
        ),
        (
            "NULL k_n for cdt".into(),
            Call {
                model: &cdt_model,
                normal_stiffness: std::ptr::null(),
                ..plain
            },
            RSL_ERR_NULL_POINTER,
        ),
        (
            "NULL states".into(),
            Call {
                states: std::ptr::null_mut(),
                ..plain
            },
            RSL_ERR_NULL_POINTER,
        ),
        (
            "NULL force".into(),
            Call {
                force: std::ptr::null_mut(),
                ..plain
            },
            RSL_ERR_NULL_POINTER,
        ),
        (
            "NULL torque".into(),
            Call {
                torque: std::ptr::null_mut(),
                ..plain
            },
            RSL_ERR_NULL_POINTER,
        ),
        (
            "NULL model".into(),
            Call {
                model: std::ptr::null(),
                ..plain
            },
            RSL_ERR_NULL_POINTER,
        ),
        (
            "misaligned walls".into(),
            Call {
                walls: misaligned(s.walls.as_ptr() as usize) as *const rsl_wall,
                ..plain
            },
            RSL_ERR_MISALIGNED,
        ),
        (
            "misaligned state_index".into(),
            Call {
                state_index: misaligned(index.as_ptr() as usize) as *const usize,
                ..plain
            },
            RSL_ERR_MISALIGNED,
        ),
        (
            "n_states below n_contacts, no index".into(),
            Call {
                state_index: std::ptr::null(),
                n_states: n - 1,
                ..plain
            },
            RSL_ERR_INVALID_ARGUMENT,
        ),
        (
            "energy output, model without tracking".into(),
            Call {
                params: &energy_params,
                ..plain
            },
            RSL_ERR_INVALID_ARGUMENT,
        ),
        (
            "damping-ratio rolling".into(),
            Call {
                model: &ratio_model,
                ..plain
            },
            RSL_ERR_INVALID_ARGUMENT,
        ),
    ];
    for (k, bad) in bad_index_sets.iter().enumerate() {
        cases.push((
            format!("state_index {k}"),
            Call {
                state_index: bad.as_ptr(),
                ..plain
            },
            RSL_ERR_INVALID_ARGUMENT,
        ));
    }
    for bad in &bad_options {
        cases.push((
            format!("options {bad:?}"),
            Call {
                options: bad,
                ..plain
            },
            RSL_ERR_INVALID_ARGUMENT,
        ));
    }
    for dt in [0.0, -1e-4, f64::NAN, f64::INFINITY] {
        cases.push((
            format!("dt {dt}"),
            Call { dt, ..plain },
            RSL_ERR_INVALID_TIME_STEP,
        ));
    }
    // A tracking model with energy output and the same errors: the energy entries stay too.
    cases.push((
        "tracked, NULL walls".into(),
        Call {
            model: &tracked_model,
            params: &energy_params,
            walls: std::ptr::null(),
            ..plain
        },
        RSL_ERR_NULL_POINTER,
    ));
    cases.push((
        "tracked, bad index".into(),
        Call {
            model: &tracked_model,
            params: &energy_params,
            state_index: bad_index_sets[0].as_ptr(),
            ..plain
        },
        RSL_ERR_INVALID_ARGUMENT,
    ));
    for (what, call, status) in &cases {
        // SAFETY: every pointer is NULL, misaligned on purpose, or holds what the call reads or
        // writes; the call refuses before touching the arrays.
        let got = unsafe { call.run() };
        assert_eq!(got, *status, "{what}: status ({})", last_error());
        assert_eq!(report, refused_report(*status), "{what}: report");
        let now = (
            slots.iter().map(state_bits).collect::<Vec<_>>(),
            vec_bits(&force),
            vec_bits(&torque),
            energy.iter().map(energy_bits).collect::<Vec<_>>(),
        );
        assert!(now == initial, "{what}: something was written");
        if what.starts_with("n_states") {
            assert!(last_error().contains("n_states"), "{}", last_error());
        }
    }
    // A dead handle.
    let mut dead = live(lammps);
    dead.magic = 0;
    // SAFETY: as above (the handle is read, found dead).
    let status = unsafe {
        Call {
            model: &dead,
            ..plain
        }
        .run()
    };
    assert_eq!(status, RSL_ERR_INVALID_HANDLE);
    assert_eq!(report, refused_report(RSL_ERR_INVALID_HANDLE));
    // No contact: NULL arrays are fine, nothing written, RSL_OK.
    let empty = Call {
        spheres: std::ptr::null(),
        walls: std::ptr::null(),
        n_contacts: 0,
        normal_force: std::ptr::null(),
        normal_stiffness: std::ptr::null(),
        states: std::ptr::null_mut(),
        n_states: 0,
        state_index: std::ptr::null(),
        ..plain
    };
    // SAFETY: as above.
    let status = unsafe { empty.run() };
    assert_eq!(status, RSL_OK);
    assert_eq!(
        report,
        rsl_batch_report {
            simd: Simd::Scalar.code(),
            ..refused_report(RSL_OK)
        }
    );
    assert_eq!(vec_bits(&force), initial.1);
    assert_eq!(vec_bits(&torque), initial.2);
    // Contacts but no particle: each contact's index is out of range; nothing written.
    let no_particles = Call {
        particles: std::ptr::null(),
        n_particles: 0,
        force: std::ptr::null_mut(),
        torque: std::ptr::null_mut(),
        ..plain
    };
    for simd in levels() {
        let o = options(simd, RSL_PRECISION_F64);
        // SAFETY: as above.
        let status = unsafe {
            Call {
                options: &o,
                ..no_particles
            }
            .run()
        };
        assert_eq!(status, RSL_ERR_INVALID_ARGUMENT, "{simd:?}");
        assert_eq!(
            report,
            rsl_batch_report {
                processed: 0,
                failed: n as u64,
                first_failed: 0,
                first_status: RSL_ERR_INVALID_ARGUMENT,
                simd: simd.code(),
                reserved: 0,
            },
            "{simd:?}"
        );
        assert_eq!(
            slots.iter().map(state_bits).collect::<Vec<_>>(),
            initial.0,
            "{simd:?}"
        );
    }
    // The call every case above spoils in one argument is a valid one: it steps every contact
    // (the tracking model's too, with its energy output).
    for call in [
        plain,
        Call {
            model: &tracked_model,
            params: &energy_params,
            ..plain
        },
    ] {
        // SAFETY: every pointer holds what the call reads or writes; none overlap.
        let status = unsafe { call.run() };
        assert_eq!(status, RSL_OK, "{}", last_error());
        assert_eq!(
            report,
            rsl_batch_report {
                processed: n as u64,
                simd: Simd::Scalar.code(),
                ..refused_report(RSL_OK)
            }
        );
    }
    assert_ne!(vec_bits(&force), initial.1);
    assert!(energy
        .iter()
        .all(|e| energy_bits(e) != energy_bits(&ENERGY_SENTINEL)));
}

/// Largest `|got - want| / scale` over the components, with `scale` the largest `|want|`
/// component (1 where all are 0, where the difference must then be below 1).
fn relative_error(got: &[f64], want: &[f64]) -> f64 {
    let scale = want.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let scale = if scale > 0.0 { scale } else { 1.0 };
    got.iter()
        .zip(want)
        .fold(0.0f64, |m, (g, w)| m.max((g - w).abs() / scale))
}

/// The values of one part of a state.
type StatePart = fn(&rsl_contact_state) -> Vec<f64>;

fn flat(v: &[rsl_vec3]) -> Vec<f64> {
    v.iter().flat_map(|v| [v.x, v.y, v.z]).collect()
}

/// Single precision's tolerance, as a fraction of each quantity's scale over the call (its
/// largest magnitude: the load sums added to the particles, each spring's components, the
/// twisting angles and off-axis parts, the previous normals; for the energy terms the largest
/// term of the call, since the transport term is 0 to rounding, 1e-17, in double and single
/// rounding of the energies in single). The f32 kernels take the geometry in double and the
/// rates, history updates, clips and loads in single: f32 epsilon (6e-8) amplified by the
/// cancellations in the relative velocities, the spring updates and the load sums on a
/// particle. Measured over these scenes (every law set, array set, SIMD level and layout; the
/// three levels give the same largest errors): at most 7.4e-7 (the rolling springs), 4.3e-7
/// (the energy terms), 2.6e-7 (the sliding springs), 2.1e-7 (the twisting angles), 1.5e-7
/// (the loads), 3e-8 (the normals), 0 (the off-axis parts, carried). 1e-5 leaves a margin of
/// more than 13 and is 20 times tighter than the 2e-4 that tests/batch.rs allows the pair
/// kernels.
const F32_TOLERANCE: f64 = 1e-5;

/// Test 6. Single precision at each level: the same contacts stepped (none refused), with
/// loads, states and energy terms within `F32_TOLERANCE` of their scale of the double
/// per-contact results, and slip flags equal; histories in contact order and indexed, normals
/// from 1e-200 to 1e200.
#[test]
fn single_precision_is_close_to_the_double_per_contact_results() {
    let mut rng = Lcg(606);
    let mut worst: f64 = 0.0;
    for base in all_models() {
        let (model, sets) = with_materials(base);
        let mut s = scene(100, true, &mut rng);
        for c in (0..s.len()).step_by(7) {
            let u = unit(Vec3::from(s.walls[c].normal));
            s.walls[c].normal = (u * [1e200, 1e-200][c % 2]).into();
        }
        for a in [
            Arrays {
                k_n: true,
                ..Default::default()
            },
            Arrays {
                k_n: true,
                k_t: true,
                gamma_t: true,
                material: true,
                energy: base.track_energy,
            },
        ] {
            let w = reference(&model, &sets, &s, a);
            assert!(w.status.iter().all(|&st| st == RSL_OK));
            let load_sums = |f: &[rsl_vec3], f0: &[rsl_vec3]| -> Vec<f64> {
                flat(f).iter().zip(flat(f0)).map(|(x, x0)| x - x0).collect()
            };
            for simd in levels() {
                let o = options(simd, RSL_PRECISION_F32);
                for layout in [Layout::Ordered { spare: 0 }, Layout::Indexed] {
                    let what = format!("{base:?} {a:?} {simd:?} {layout:?} f32");
                    let g = run(&model, &s, a, Some(&o), layout);
                    assert_eq!(g.status, RSL_OK, "{what}");
                    assert_eq!(g.report, expected_report(&w, simd.code()), "{what}");
                    let mut errors = vec![
                        (
                            "force",
                            relative_error(
                                &load_sums(&g.force, &s.force),
                                &load_sums(&w.force, &s.force),
                            ),
                        ),
                        (
                            "torque",
                            relative_error(
                                &load_sums(&g.torque, &s.torque),
                                &load_sums(&w.torque, &s.torque),
                            ),
                        ),
                    ];
                    let field = |st: &[rsl_contact_state], f: StatePart| {
                        st.iter().flat_map(f).collect::<Vec<f64>>()
                    };
                    let parts: [(&str, StatePart); 5] = [
                        ("sliding spring", |s| {
                            let v = s.sliding_spring;
                            vec![v.x, v.y, v.z]
                        }),
                        ("rolling spring", |s| {
                            let v = s.rolling_spring;
                            vec![v.x, v.y, v.z]
                        }),
                        ("twisting angle", |s| vec![s.twisting_angle]),
                        ("model memory", |s| {
                            let v = s.model_memory;
                            vec![v.x, v.y, v.z]
                        }),
                        ("previous normal", |s| {
                            let v = s.previous_normal;
                            vec![v.x, v.y, v.z]
                        }),
                    ];
                    for (name, f) in parts {
                        errors.push((
                            name,
                            relative_error(&field(&g.states, f), &field(&w.states, f)),
                        ));
                    }
                    if a.energy {
                        // Every term against the largest term of the call: the transport
                        // term is 0 to rounding (1e-17) in double, and single rounding
                        // (6e-8 of the energies) in single.
                        let terms = |e: &[rsl_contact_energy], t: usize| -> Vec<f64> {
                            e.iter().map(|e| energy_terms(e)[t]).collect()
                        };
                        let scale = w
                            .energy
                            .iter()
                            .flat_map(energy_terms)
                            .fold(0.0f64, |m, x| m.max(x.abs()));
                        assert!(scale > 0.0, "{what}");
                        for t in 0..10 {
                            let e = terms(&g.energy, t)
                                .iter()
                                .zip(terms(&w.energy, t))
                                .fold(0.0f64, |m, (x, y)| m.max((x - y).abs() / scale));
                            errors.push(("energy", e));
                        }
                    }
                    for (name, e) in errors {
                        worst = worst.max(e);
                        assert!(
                            e <= F32_TOLERANCE,
                            "{what}: {name} off by {e:e} of its scale"
                        );
                    }
                    let slips = |st: &[rsl_contact_state]| -> Vec<u32> {
                        st.iter().map(|s| s.slip_flags).collect()
                    };
                    assert_eq!(slips(&g.states), slips(&w.states), "{what}: slip flags");
                }
            }
        }
    }
    eprintln!("single precision: largest error {worst:e} of the scale");
}
