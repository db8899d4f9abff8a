//! Batch kernels against the per-contact checked step: every precision and SIMD level, one model
//! per law set and preset family; accumulation into particle arrays; skipping of invalid
//! contacts; decomposition.

mod common;

use common::{full_model, law_set_models, length_form_models, Rng};
use rollslide::batch::dispatch::{run_decompose, run_history_step, run_step, BatchConfig, Simd};
use rollslide::batch::history::{history_layout, words_from_state, HistoryLayout, Record};
use rollslide::batch::states::IndexedGroups;
use rollslide::batch::{
    BatchReport, ContactStates, ContactSteps, Gather, IndexedStates, ModelSliding,
    ParticleDecompose, ParticleSteps, SlidingOverrides, SlidingSource, StepAccess,
    PREFETCH_MIN_BYTES,
};
use rollslide::capi::batch::rsl_batch_loads;
use rollslide::capi::contact::rsl_contact_state;
use rollslide::capi::types::{rsl_decomposition, rsl_sphere, rsl_vec3};
use rollslide::decompose::{decompose_pair, Parts, Sphere};
use rollslide::error::Error;
use rollslide::laws::checked::contact_step_pair;
use rollslide::laws::model::{Model, Preset, RollingLaw, SlidingLaw, Transport};
use rollslide::laws::spring::Storage;
use rollslide::laws::step::{ContactState, StepInput};
use rollslide::GeometryOptions;

fn v(x: rollslide::scalar::Vec3<f64>) -> rsl_vec3 {
    rsl_vec3 {
        x: x.x,
        y: x.y,
        z: x.z,
    }
}

/// One model per law set and preset family ([`law_set_models`]), the LIGGGHTS ones in both
/// rolling forms, one without limits, and three with other options (YADE's preset, viscous
/// rolling with first-order transport, LIGGGHTS' `torsionTorque`), each with a name for messages.
fn models() -> Vec<(Model, String)> {
    let full = full_model(Preset::Objective, Transport::Exact);
    let mut yade = full_model(Preset::Yade2023, Transport::FirstOrder);
    yade.rolling.form = rollslide::laws::model::RollingForm::Angle;
    let mut viscous = full;
    viscous.rolling.law = RollingLaw::Viscous;
    viscous.sliding_transport = Transport::FirstOrder;
    // LIGGGHTS with `torsionTorque on`: EPSD (given stiffness and damping, so that no k_n or
    // masses are needed) acting on the whole relative spin.
    let mut liggghts = Model::with_preset(Preset::Liggghts38);
    liggghts.sliding = full.sliding;
    liggghts.rolling.law = RollingLaw::Epsd;
    liggghts.rolling.stiffness = 50.0;
    liggghts.rolling.damping = 0.2;
    liggghts.rolling.friction = 0.05;
    liggghts.torsion_torque = true;
    liggghts.validate().unwrap();
    // No limits (+inf coefficients): a tensile contact's zero limit force times +inf goes
    // through limit_of's select in every lane. (Before limit_of the product was NaN and, since
    // every clip compares `> limit`, acted as no limit too: this is a regression guard of the
    // lanes agreeing with the per-contact step, not a test that could have caught that NaN.)
    let mut unlimited = full;
    unlimited.sliding.friction = f64::INFINITY;
    unlimited.rolling.friction = f64::INFINITY;
    unlimited.twisting.friction = f64::INFINITY;
    unlimited.validate().unwrap();
    let mut models = law_set_models();
    // The LIGGGHTS models in the length form too (the one that gives each pair of unequal
    // spheres LIGGGHTS' limit from one `mu_r`).
    models.extend(length_form_models());
    models.extend(
        [
            (unlimited, "full/exact without limits"),
            (yade, "full/yade"),
            (viscous, "viscous rolling/first order"),
            (liggghts, "slide+epsd/liggghts torsionTorque"),
        ]
        .map(|(m, name)| (m, name.to_string())),
    );
    models
}

/// Loads (force1, torque1, torque2) of one contact; `None` when the checked step refused it.
type Loads = Option<[rollslide::scalar::Vec3<f64>; 3]>;
/// A predicate on an error.
type ErrorCheck = fn(&Error) -> bool;

struct Scenario {
    particles: Vec<rsl_sphere>,
    pairs: Vec<[u32; 2]>,
    normal_force: Vec<f64>,
    /// `k_n` per contact, read only by the models that need it (LIGGGHTS' cdt).
    normal_stiffness: Vec<f64>,
    states: Vec<rsl_contact_state>,
}

/// Overlapping pairs among `np` particles with random velocities and spins, and half of the
/// contacts carrying a history (a previous normal a little off the current one).
fn scenario(np: usize, nc: usize, seed: u64) -> Scenario {
    let mut rng = Rng::new(seed);
    let mut particles: Vec<rsl_sphere> = (0..np)
        .map(|_| rsl_sphere {
            position: v(rng.vec(10.0)),
            velocity: v(rng.vec(0.5)),
            angular_velocity: v(rng.vec(3.0)),
            radius: rng.uniform(0.8, 1.2),
        })
        .collect();
    let mut pairs = Vec::new();
    for c in 0..nc {
        let i = (rng.next_u64() % np as u64) as u32;
        let mut j = (rng.next_u64() % np as u64) as u32;
        if j == i {
            j = (i + 1) % np as u32;
        }
        // Place j in contact with i (later contacts may move it again: only the final
        // positions matter, and they keep |r_i - r_j| < R_i + R_j for the last pair placed).
        if c % 3 != 0 {
            let (a, b) = (particles[i as usize], particles[j as usize]);
            let n = rng.unit();
            let d = (a.radius + b.radius) * rng.uniform(0.95, 0.999);
            particles[j as usize].position = rsl_vec3 {
                x: a.position.x + d * n.x,
                y: a.position.y + d * n.y,
                z: a.position.z + d * n.z,
            };
        }
        pairs.push([i, j]);
    }
    // A fifth of the contacts pull (tensile f_n): the preset's limit rule runs in every kernel.
    let normal_force = (0..nc).map(|_| rng.uniform(-25.0, 100.0)).collect();
    let states = (0..nc)
        .map(|c| {
            let mut s = rsl_contact_state::default();
            if c % 2 == 0 {
                let [i, j] = pairs[c];
                let (a, b) = (particles[i as usize], particles[j as usize]);
                let d = rollslide::scalar::Vec3::new(
                    b.position.x - a.position.x,
                    b.position.y - a.position.y,
                    b.position.z - a.position.z,
                );
                let n = (d.normalize() + rng.vec(0.01)).normalize();
                s.previous_normal = v(n);
                let t = rng.vec(1e-4);
                s.sliding_spring = v(t - n * t.dot(&n));
                let r = rng.vec(1e-5);
                s.rolling_spring = v(r - n * r.dot(&n));
                s.twisting_angle = rng.uniform(-1e-3, 1e-3);
                // The model memory: the previous stiffnesses of a model that keeps them (the
                // sliding one on either side of the test's k_t, so that rescaled histories shrink
                // in some contacts and not in others); YADE reads it as its off-axis twisting
                // moment; the other models pass it through.
                s.model_memory = rsl_vec3 {
                    x: rng.uniform(0.0, 4e5),
                    y: rng.uniform(0.0, 2e5),
                    z: rng.uniform(0.0, 100.0),
                };
            }
            s
        })
        .collect();
    let normal_stiffness = (0..nc).map(|_| rng.uniform(5e5, 2e6)).collect();
    Scenario {
        particles,
        pairs,
        normal_force,
        normal_stiffness,
        states,
    }
}

/// Reorders the contacts of `sc` by body 1 (a stable sort: bodies 2 keep their random order
/// within a run), as a DEM code's neighbour list has them.
fn sort_by_body1(sc: &mut Scenario) {
    let mut order: Vec<usize> = (0..sc.pairs.len()).collect();
    order.sort_by_key(|&c| sc.pairs[c][0]);
    sc.pairs = order.iter().map(|&c| sc.pairs[c]).collect();
    sc.normal_force = order.iter().map(|&c| sc.normal_force[c]).collect();
    sc.normal_stiffness = order.iter().map(|&c| sc.normal_stiffness[c]).collect();
    sc.states = order.iter().map(|&c| sc.states[c]).collect();
}

/// The per-contact copies of body 1 and body 2 that the contact-major call reads.
fn gathered_bodies(sc: &Scenario) -> (Vec<rsl_sphere>, Vec<rsl_sphere>) {
    let body = |k: usize| {
        sc.pairs
            .iter()
            .map(|p| sc.particles[p[k] as usize])
            .collect()
    };
    (body(0), body(1))
}

fn configs() -> Vec<BatchConfig> {
    let mut out = Vec::new();
    for simd in [Simd::Scalar, Simd::Avx2, Simd::Avx512] {
        if !simd.available() {
            eprintln!("note: {simd:?} not available on this CPU, not tested");
            continue;
        }
        for f32 in [false, true] {
            out.push(BatchConfig { f32, simd });
        }
    }
    out
}

/// Per-contact checked steps: the reference loads per contact and new states.
fn reference(model: &Model, sc: &Scenario, dt: f64) -> (Vec<Loads>, Vec<ContactState<f64>>) {
    let mut loads = Vec::new();
    let mut states = Vec::new();
    for (c, [i, j]) in sc.pairs.iter().enumerate() {
        let b1 = Sphere::from(&sc.particles[*i as usize]);
        let b2 = Sphere::from(&sc.particles[*j as usize]);
        let mut s = ContactState::from(&sc.states[c]);
        let mut input = StepInput::new(sc.normal_force[c], dt);
        input.normal_stiffness = sc.normal_stiffness[c];
        let r = contact_step_pair(model, &b1, &b2, &input, &mut s);
        loads.push(
            r.ok()
                .map(|o| [o.loads.force1, o.loads.torque1, o.loads.torque2]),
        );
        states.push(s);
    }
    (loads, states)
}

fn close(a: f64, b: f64, abs: f64, rel: f64) -> bool {
    (a - b).abs() <= abs + rel * b.abs()
}

/// Contact-major batch = per-contact checked step. Double precision: bitwise equal for every
/// SIMD level (no FMA contraction in Rust, sqrt and division correctly rounded, the lanes run
/// the same operations in the same order), checked with tolerance 0. Single precision: within
/// 2e-4 of each quantity's scale over the contacts (f32 epsilon 6e-8 amplified by the
/// cancellation of the branch-rate terms and the clip's normalisation: measured ~1e-5); a
/// spring that stores a load is on the loads' scale (the objective clip resets it to the
/// clipped load less the dashpot's capped share, which cancel to a few f32 epsilons of it).
#[test]
fn contact_major_matches_per_contact_step() {
    let dt = 1e-4;
    for (model, name) in models() {
        let sc = scenario(64, 203, 7);
        let (ref_loads, ref_states) = reference(&model, &sc, dt);
        let (body1, body2) = gathered_bodies(&sc);
        for config in configs() {
            let mut states = sc.states.clone();
            let mut out = vec![rsl_batch_loads::default(); sc.pairs.len()];
            let mut access = ContactSteps {
                energy: None,
                body1: &body1,
                body2: &body2,
                normal_force: &sc.normal_force,
                normal_stiffness: Some(&sc.normal_stiffness),
                states: &mut states,
                out: &mut out,
                sliding: SlidingOverrides::NONE,
            };
            let report = run_step(&model, dt, &mut access, config).unwrap();
            assert_eq!(report.failed, 0, "{config:?}: {:?}", report.first_error);
            let (abs, rel) = if config.f32 { (2e-4, 2e-4) } else { (0.0, 0.0) };
            let scale_f = sc.normal_force.iter().cloned().fold(0.0, f64::max);
            for (c, l) in ref_loads.iter().enumerate() {
                let l = l.expect("valid contact");
                let got = [out[c].force1, out[c].torque1, out[c].torque2];
                for k in 0..3 {
                    for (a, b) in [(got[k].x, l[k].x), (got[k].y, l[k].y), (got[k].z, l[k].z)] {
                        assert!(
                            close(a, b, abs * scale_f, rel),
                            "{config:?} {name} contact {c} load {k}: {a} vs {b}"
                        );
                    }
                }
                let s = ContactState::from(&states[c]);
                let r = &ref_states[c];
                // A spring that stores its load (a force history, YADE's and LIGGGHTS' rolling
                // moment) is compared on the loads' scale.
                let scale_of = |storage: Storage| match storage {
                    Storage::Displacement => 1e-3,
                    Storage::Load => scale_f,
                };
                let springs = [
                    (
                        s.sliding_spring,
                        r.sliding_spring,
                        scale_of(model.sliding.history.storage()),
                    ),
                    (
                        s.rolling_spring,
                        r.rolling_spring,
                        scale_of(model.preset.conventions().rolling_storage),
                    ),
                    (s.previous_normal, r.previous_normal, 1.0),
                ];
                for (a, b, scale) in springs {
                    assert!(
                        (a - b).norm() <= abs * scale + rel * b.norm(),
                        "{config:?} {name} contact {c} state {a} vs {b}"
                    );
                }
                // YADE's twisting "angle" is its moment along the normal.
                let twist_scale = if model.preset.conventions().twist_vector {
                    scale_f
                } else {
                    1e-3
                };
                assert!(close(
                    s.twisting_angle,
                    r.twisting_angle,
                    abs * twist_scale,
                    rel
                ));
            }
        }
    }
}

/// Particle-major: the accumulated forces and torques equal the sums of the per-contact loads
/// (in contact order); the SIMD levels give the same sums as the scalar kernel bitwise in
/// double precision.
#[test]
fn particle_major_accumulates_per_contact_loads() {
    let dt = 1e-4;
    let model = models()[0].0;
    let sc = scenario(50, 300, 11);
    let (ref_loads, _) = reference(&model, &sc, dt);
    let np = sc.particles.len();
    let mut f_ref = vec![rollslide::scalar::Vec3::<f64>::zeros(); np];
    let mut t_ref = f_ref.clone();
    for (c, [i, j]) in sc.pairs.iter().enumerate() {
        let l = ref_loads[c].unwrap();
        f_ref[*i as usize] += l[0];
        f_ref[*j as usize] -= l[0];
        t_ref[*i as usize] += l[1];
        t_ref[*j as usize] += l[2];
    }
    for config in configs() {
        let mut states = sc.states.clone();
        let start = rsl_vec3 {
            x: 1.0,
            y: -2.0,
            z: 0.5,
        };
        let mut force = vec![start; np];
        let mut torque = vec![rsl_vec3::default(); np];
        let mut access = ParticleSteps {
            energy: None,
            particles: &sc.particles,
            pairs: &sc.pairs,
            normal_force: &sc.normal_force,
            normal_stiffness: Some(&sc.normal_stiffness),
            states: &mut states[..],
            force: &mut force,
            torque: &mut torque,
            sliding: ModelSliding,
        };
        access.check().unwrap();
        let report = run_step(&model, dt, &mut access, config).unwrap();
        assert_eq!(report.processed, sc.pairs.len());
        let tol = if config.f32 { 1e-3 } else { 0.0 };
        for p in 0..np {
            let f =
                rollslide::scalar::Vec3::new(force[p].x - 1.0, force[p].y + 2.0, force[p].z - 0.5);
            // Accumulated on top of the initial value: compare the increments (the start value
            // adds one rounding per component, hence the tiny absolute tolerance).
            assert!(
                (f - f_ref[p]).norm() <= tol * 100.0 + 1e-12,
                "{config:?} particle {p}"
            );
            let t = rollslide::scalar::Vec3::new(torque[p].x, torque[p].y, torque[p].z);
            assert!(
                (t - t_ref[p]).norm() <= tol * 100.0,
                "{config:?} particle {p}: {t} vs {}",
                t_ref[p]
            );
        }
    }
}

/// Contacts in neighbour-list order (sorted by body 1, runs of the same body 1, bodies 2 that
/// are body 1 of later runs): the particle-major accumulators end bit for bit where the
/// contact-by-contact additions, `force[i] += F; force[j] -= F; torque[i] += M1;
/// torque[j] += M2` in contact order from non-zero start values, put them (double precision,
/// every level). The kernels keep body 1's sums in registers along a run: this is what they
/// must not change.
#[test]
fn particle_major_sums_equal_contact_order_additions_bitwise() {
    let dt = 1e-4;
    let model = models()[0].0;
    let mut sc = scenario(40, 400, 23);
    sort_by_body1(&mut sc);
    let (ref_loads, _) = reference(&model, &sc, dt);
    let np = sc.particles.len();
    let start = |p: usize| rsl_vec3 {
        x: 1.0 + p as f64 / 7.0,
        y: -2.0 / (p as f64 + 3.0),
        z: 0.5 * p as f64,
    };
    let mut f_ref: Vec<rsl_vec3> = (0..np).map(start).collect();
    let mut t_ref: Vec<rsl_vec3> = (0..np).map(|p| start(np - 1 - p)).collect();
    let add = |a: &mut rsl_vec3, b: rollslide::scalar::Vec3<f64>| {
        a.x += b.x;
        a.y += b.y;
        a.z += b.z;
    };
    let mut skipped = 0;
    for (c, [i, j]) in sc.pairs.iter().enumerate() {
        let Some(l) = ref_loads[c] else {
            skipped += 1;
            continue;
        };
        add(&mut f_ref[*i as usize], l[0]);
        add(&mut f_ref[*j as usize], -l[0]);
        add(&mut t_ref[*i as usize], l[1]);
        add(&mut t_ref[*j as usize], l[2]);
    }
    let runs = sc.pairs.windows(2).filter(|w| w[0][0] == w[1][0]).count();
    assert!(
        runs > 300,
        "the scene must have long runs of the same body 1"
    );
    let later_body1 = sc
        .pairs
        .iter()
        .enumerate()
        .filter(|(c, [_, j])| sc.pairs[c + 1..].iter().any(|[i, _]| i == j))
        .count();
    assert!(later_body1 > 100, "bodies 2 must come back as bodies 1");
    let bits = |v: &rsl_vec3| [v.x.to_bits(), v.y.to_bits(), v.z.to_bits()];
    for config in configs().into_iter().filter(|c| !c.f32) {
        let mut states = sc.states.clone();
        let mut force: Vec<rsl_vec3> = (0..np).map(start).collect();
        let mut torque: Vec<rsl_vec3> = (0..np).map(|p| start(np - 1 - p)).collect();
        let mut access = ParticleSteps {
            energy: None,
            particles: &sc.particles,
            pairs: &sc.pairs,
            normal_force: &sc.normal_force,
            normal_stiffness: Some(&sc.normal_stiffness),
            states: &mut states[..],
            force: &mut force,
            torque: &mut torque,
            sliding: ModelSliding,
        };
        let report = run_step(&model, dt, &mut access, config).unwrap();
        assert_eq!(report.processed + skipped, sc.pairs.len());
        for p in 0..np {
            assert_eq!(bits(&force[p]), bits(&f_ref[p]), "{config:?} force {p}");
            assert_eq!(bits(&torque[p]), bits(&t_ref[p]), "{config:?} torque {p}");
        }
    }
}

/// Bits of one result: the particle-major accumulators or contact-major loads, and the states.
type ResultBits = (Vec<[u64; 3]>, Vec<Vec<u64>>);

fn vec3_bits(v: &rsl_vec3) -> [u64; 3] {
    [v.x.to_bits(), v.y.to_bits(), v.z.to_bits()]
}

/// The particle-major step of `sc` in calls of `size` contacts (on the same particles), each
/// checked to prefetch exactly when it is the one call of every contact.
fn particle_major_in_calls<O: SlidingSource>(
    sc: &Scenario,
    model: &Model,
    config: BatchConfig,
    sliding: impl Fn(usize, usize) -> O,
    size: usize,
) -> ResultBits {
    let (nc, np) = (sc.pairs.len(), sc.particles.len());
    let mut states = sc.states.clone();
    let mut force = vec![rsl_vec3::default(); np];
    let mut torque = vec![rsl_vec3::default(); np];
    let mut c0 = 0;
    while c0 < nc {
        let c1 = (c0 + size).min(nc);
        let mut access = ParticleSteps {
            energy: None,
            particles: &sc.particles,
            pairs: &sc.pairs[c0..c1],
            normal_force: &sc.normal_force[c0..c1],
            normal_stiffness: Some(&sc.normal_stiffness[c0..c1]),
            states: &mut states[c0..c1],
            force: &mut force,
            torque: &mut torque,
            sliding: sliding(c0, c1),
        };
        assert_eq!(access.prefetching(), size == nc, "{size} contacts");
        assert_eq!(
            access.footprint() >= PREFETCH_MIN_BYTES,
            access.prefetching()
        );
        let report = run_step(model, 1e-4, &mut access, config).unwrap();
        assert_eq!(report.processed, c1 - c0, "every contact is valid");
        c0 = c1;
    }
    let sums = force.iter().chain(&torque).map(vec3_bits).collect();
    (sums, states.iter().map(state_word_bits).collect())
}

/// The contact-major step of `sc` in calls of `size` contacts; see [`particle_major_in_calls`].
fn contact_major_in_calls<'a>(
    sc: &Scenario,
    model: &Model,
    config: BatchConfig,
    sliding: impl Fn(usize, usize) -> SlidingOverrides<'a>,
    size: usize,
) -> ResultBits {
    let nc = sc.pairs.len();
    let (body1, body2) = gathered_bodies(sc);
    let mut states = sc.states.clone();
    let mut out = vec![rsl_batch_loads::default(); nc];
    let mut c0 = 0;
    while c0 < nc {
        let c1 = (c0 + size).min(nc);
        let mut access = ContactSteps {
            energy: None,
            body1: &body1[c0..c1],
            body2: &body2[c0..c1],
            normal_force: &sc.normal_force[c0..c1],
            normal_stiffness: Some(&sc.normal_stiffness[c0..c1]),
            states: &mut states[c0..c1],
            out: &mut out[c0..c1],
            sliding: sliding(c0, c1),
        };
        assert_eq!(access.prefetching(), size == nc, "{size} contacts");
        let report = run_step(model, 1e-4, &mut access, config).unwrap();
        assert_eq!(report.processed, c1 - c0, "every contact is valid");
        c0 = c1;
    }
    let loads = out
        .iter()
        .flat_map(|l| [l.force1, l.torque1, l.torque2].map(|v| vec3_bits(&v)))
        .collect();
    (loads, states.iter().map(state_word_bits).collect())
}

/// Calls of at least `PREFETCH_MIN_BYTES` run the kernels that prefetch, smaller ones the
/// kernels that do not (two instantiations of the same code). The same contacts stepped in one
/// large call and in calls of 1,000 give the same bits, in both precisions, at every level, for
/// every model, particle-major (the accumulated sums) and contact-major (the loads), and the
/// same states; with the model's sliding coefficients and with per-contact `k_t` and
/// `gamma_t` (which the gather copies group by group, a partial group at each call's end).
#[test]
fn calls_with_and_without_prefetching_give_the_same_bits() {
    let chunk = 1000;
    // 9,003 contacts among 400 particles: 1.2 MB particle-major, 3.2 MB contact-major; a call
    // of 1,000 contacts stays well below. 9,003 and 1,000 are not multiples of the group of 8.
    let mut sc = scenario(400, 9003, 31);
    sort_by_body1(&mut sc);
    let nc = sc.pairs.len();
    assert_eq!(nc % 8, 3, "a partial group at the end");
    let mut rng = Rng::new(5);
    let k_t: Vec<f64> = (0..nc).map(|_| rng.uniform(0.0, 4e4)).collect();
    let gamma_t: Vec<f64> = (0..nc).map(|_| rng.uniform(0.0, 20.0)).collect();
    let overrides = |c0: usize, c1: usize| SlidingOverrides {
        stiffness: Some(&k_t[c0..c1]),
        damping: Some(&gamma_t[c0..c1]),
        materials: None,
    };
    // One call's results, after checking that the calls of `chunk` gave the same.
    let same = |[one, chunks]: [ResultBits; 2], what: String| {
        assert!(
            one == chunks,
            "{what}: one call and calls of {chunk} differ"
        );
        one
    };
    let mut differ = 0;
    for (model, _) in models() {
        for config in configs() {
            let what = |layout: &str, k: &str| format!("{layout}{k}, {config:?}, {model:?}");
            let k = ", per-contact k_t and gamma_t";
            let none = |_, _| SlidingOverrides::NONE;
            let sizes = [nc, chunk];
            let particle = |n| particle_major_in_calls(&sc, &model, config, |_, _| ModelSliding, n);
            let plain = same(sizes.map(particle), what("particle-major", ""));
            let particle_k = |n| particle_major_in_calls(&sc, &model, config, overrides, n);
            differ += usize::from(same(sizes.map(particle_k), what("particle-major", k)) != plain);
            let contact = |n| contact_major_in_calls(&sc, &model, config, none, n);
            same(sizes.map(contact), what("contact-major", ""));
            let contact_k = |n| contact_major_in_calls(&sc, &model, config, overrides, n);
            same(sizes.map(contact_k), what("contact-major", k));
        }
    }
    // The per-contact coefficients reach the results (for the models with a sliding law).
    assert!(differ > 0, "per-contact k_t and gamma_t changed no result");
}

/// Many steps of an evolving scene: scalar and SIMD kernels keep identical histories (double),
/// and the single-precision histories stay within 1e-4 relative of the double ones.
#[test]
fn repeated_steps_scalar_and_simd_agree() {
    let dt = 1e-4;
    let model = models()[1].0;
    let sc = scenario(40, 120, 3);
    let run = |config: BatchConfig| {
        let mut states = sc.states.clone();
        let mut particles = sc.particles.clone();
        for step in 0..200 {
            let mut force = vec![rsl_vec3::default(); particles.len()];
            let mut torque = force.clone();
            let mut access = ParticleSteps {
                energy: None,
                particles: &particles,
                pairs: &sc.pairs,
                normal_force: &sc.normal_force,
                normal_stiffness: Some(&sc.normal_stiffness),
                states: &mut states[..],
                force: &mut force,
                torque: &mut torque,
                sliding: ModelSliding,
            };
            let report = run_step(&model, dt, &mut access, config).unwrap();
            assert_eq!(report.failed, 0, "step {step}");
            // Move the particles rigidly a little so the normals turn.
            for p in particles.iter_mut() {
                p.position.x += p.velocity.x * dt;
                p.position.y += p.velocity.y * dt;
                p.position.z += p.velocity.z * dt;
            }
        }
        states
    };
    let scalar = run(BatchConfig {
        f32: false,
        simd: Simd::Scalar,
    });
    for config in configs() {
        let got = run(config);
        for (c, (a, b)) in got.iter().zip(&scalar).enumerate() {
            let (a, b) = (ContactState::from(a), ContactState::from(b));
            let tol = if config.f32 {
                1e-4 * b.sliding_spring.norm().max(1e-6)
            } else {
                0.0
            };
            assert!(
                (a.sliding_spring - b.sliding_spring).norm() <= tol,
                "{config:?} contact {c}: {} vs {}",
                a.sliding_spring,
                b.sliding_spring
            );
        }
    }
}

/// Invalid contacts are skipped in one pass: their state and loads are untouched, every other
/// contact is processed, and the report names the first failure with the per-contact error.
#[test]
fn invalid_contacts_are_skipped_and_reported() {
    let dt = 1e-4;
    let model = models()[0].0;
    let mut sc = scenario(30, 100, 5);
    let np = sc.particles.len() as u32;
    // Contact 13: index out of range; 20: NaN normal force; 41: NaN state;
    // 57: coincident centres (i == j); 80: infinite velocity of a private particle.
    sc.pairs[13] = [np + 5, 0];
    sc.normal_force[20] = f64::NAN;
    sc.states[41].sliding_spring.y = f64::NAN;
    sc.pairs[57] = [3, 3];
    sc.particles.push(rsl_sphere {
        position: sc.particles[0].position,
        velocity: rsl_vec3 {
            x: f64::INFINITY,
            y: 0.0,
            z: 0.0,
        },
        angular_velocity: rsl_vec3::default(),
        radius: 1.0,
    });
    sc.pairs[80] = [np, 1];
    let bad = [13usize, 20, 41, 57, 80];
    let body = |c: usize, k: usize| {
        sc.particles
            .get(sc.pairs[c][k] as usize)
            .copied()
            .unwrap_or_default()
    };
    let body1: Vec<rsl_sphere> = (0..sc.pairs.len()).map(|c| body(c, 0)).collect();
    let body2: Vec<rsl_sphere> = (0..sc.pairs.len()).map(|c| body(c, 1)).collect();
    for config in configs() {
        let mut states = sc.states.clone();
        let sentinel = rsl_batch_loads {
            force1: rsl_vec3 {
                x: 7.0,
                y: 7.0,
                z: 7.0,
            },
            ..Default::default()
        };
        let mut out = vec![sentinel; sc.pairs.len()];
        let mut access = ParticleSteps {
            energy: None,
            particles: &sc.particles,
            pairs: &sc.pairs,
            normal_force: &sc.normal_force,
            normal_stiffness: Some(&sc.normal_stiffness),
            states: &mut states[..],
            force: &mut vec![rsl_vec3::default(); sc.particles.len()],
            torque: &mut vec![rsl_vec3::default(); sc.particles.len()],
            sliding: ModelSliding,
        };
        let report = run_step(&model, dt, &mut access, config).unwrap();
        assert_eq!(report.failed, bad.len(), "{config:?}");
        assert_eq!(report.processed, sc.pairs.len() - bad.len());
        assert_eq!(report.first_failed, Some(13));
        assert!(matches!(
            report.first_error,
            Some(Error::InvalidArgument(_))
        ));
        for c in bad {
            assert_eq!(
                format!("{:?}", states[c]),
                format!("{:?}", sc.states[c]),
                "state of bad contact {c} changed"
            );
        }
        for c in [0usize, 14, 99] {
            assert_ne!(states[c], sc.states[c], "valid contact {c} not stepped");
        }

        // Contact-major: same skipping; outputs of bad contacts untouched.
        let mut states = sc.states.clone();
        let mut access = ContactSteps {
            energy: None,
            body1: &body1,
            body2: &body2,
            normal_force: &sc.normal_force,
            normal_stiffness: Some(&sc.normal_stiffness),
            states: &mut states,
            out: &mut out,
            sliding: SlidingOverrides::NONE,
        };
        let report = run_step(&model, dt, &mut access, config).unwrap();
        // Contact 13's default (zero-radius) body fails as an invalid radius here.
        assert_eq!(report.failed, bad.len(), "{config:?}");
        assert_eq!(report.first_failed, Some(13));
        assert!(matches!(report.first_error, Some(Error::InvalidRadius(_))));
        for c in bad {
            assert_eq!(out[c], sentinel);
        }
        assert_ne!(out[0], sentinel);
    }
    // The per-contact errors of the others, one at a time.
    let cases: [(usize, ErrorCheck); 4] = [
        (20, |e| *e == Error::NonFinite("normal force")),
        (41, |e| matches!(e, Error::NonFinite(_))),
        (57, |e| *e == Error::CoincidentCentres),
        (80, |e| matches!(e, Error::NonFinite(_))),
    ];
    for (c, is) in cases {
        let pairs = [sc.pairs[c]];
        let mut states = [sc.states[c]];
        let mut access = ParticleSteps {
            energy: None,
            particles: &sc.particles,
            pairs: &pairs,
            normal_force: &sc.normal_force[c..c + 1],
            normal_stiffness: Some(&sc.normal_stiffness[c..c + 1]),
            states: &mut states[..],
            force: &mut vec![rsl_vec3::default(); sc.particles.len()],
            torque: &mut vec![rsl_vec3::default(); sc.particles.len()],
            sliding: ModelSliding,
        };
        let report = run_step(&model, dt, &mut access, configs()[0]).unwrap();
        assert!(
            is(report.first_error.as_ref().unwrap()),
            "contact {c}: {:?}",
            report.first_error
        );
    }
}

/// Call-level errors: bad time step, model refused by the batch.
#[test]
fn call_level_errors_process_nothing() {
    let model = models()[0].0;
    let sc = scenario(10, 10, 1);
    let mut states = sc.states.clone();
    let mut force = vec![rsl_vec3::default(); 10];
    let mut torque = force.clone();
    let mut access = ParticleSteps {
        energy: None,
        particles: &sc.particles,
        pairs: &sc.pairs,
        normal_force: &sc.normal_force,
        normal_stiffness: Some(&sc.normal_stiffness),
        states: &mut states[..],
        force: &mut force,
        torque: &mut torque,
        sliding: ModelSliding,
    };
    let config = configs()[0];
    assert_eq!(
        run_step(&model, 0.0, &mut access, config).unwrap_err(),
        Error::InvalidTimeStep
    );
    let mut ratio = model;
    ratio.rolling.damping_rule = rollslide::laws::model::RollingDamping::Ratio;
    assert!(run_step(&ratio, 1e-4, &mut access, config).is_err());
    assert_eq!(states, sc.states);
}

/// Decomposition batches equal `decompose_pair` (double: bitwise; single: rates within 1e-5 of
/// their scale, geometry bitwise since it is computed in double), invalid contacts skipped.
#[test]
fn decompose_batch_matches_decompose_pair() {
    let mut sc = scenario(40, 150, 9);
    sc.pairs[7] = [2, 2];
    for options in [
        GeometryOptions::default(),
        GeometryOptions {
            branch_rule: rollslide::BranchRule::Radii,
            rolling_radius: rollslide::RollingRadiusRule::Effective,
        },
    ] {
        for config in configs() {
            let mut out = vec![rsl_decomposition::default(); sc.pairs.len()];
            let mut access = ParticleDecompose {
                particles: &sc.particles,
                pairs: &sc.pairs,
                out: &mut out,
            };
            let report = run_decompose(options, Parts::ALL, &mut access, config).unwrap();
            assert_eq!(report.failed, 1);
            assert_eq!(report.first_failed, Some(7));
            assert_eq!(report.first_error, Some(Error::CoincidentCentres));
            assert_eq!(out[7], rsl_decomposition::default());
            for (c, [i, j]) in sc.pairs.iter().enumerate().filter(|(c, _)| *c != 7) {
                let d = decompose_pair(
                    &Sphere::from(&sc.particles[*i as usize]),
                    &Sphere::from(&sc.particles[*j as usize]),
                    options,
                    Parts::ALL,
                )
                .unwrap();
                let want = rsl_decomposition::from(&d);
                let got = out[c];
                assert_eq!(got.normal, want.normal);
                assert_eq!(got.overlap, want.overlap);
                assert_eq!(got.branch1, want.branch1);
                let tol = if config.f32 { 1e-5 * 30.0 } else { 0.0 };
                for (a, b) in [
                    (got.sliding_velocity, want.sliding_velocity),
                    (got.rolling_velocity, want.rolling_velocity),
                    (got.tumbling, want.tumbling),
                    (got.objective_velocity1, want.objective_velocity1),
                ] {
                    for (x, y) in [(a.x, b.x), (a.y, b.y), (a.z, b.z)] {
                        assert!((x - y).abs() <= tol, "{config:?} contact {c}: {x} vs {y}");
                    }
                }
                assert!((got.twisting_rate - want.twisting_rate).abs() <= tol);
            }
        }
    }
}

/// A contact whose centre distance is so small that its square underflows (found by fuzzing
/// the scalar path) is refused by every kernel, as `decompose_pair` refuses it, and the other
/// contacts of the batch are stepped.
#[test]
fn underflowing_centre_distance_is_refused_in_every_kernel() {
    let dt = 1e-4;
    let model = models()[0].0;
    let sc = scenario(30, 17, 9);
    let body = |c: usize, k: usize| sc.particles[sc.pairs[c][k] as usize];
    let mut body1: Vec<rsl_sphere> = (0..sc.pairs.len()).map(|c| body(c, 0)).collect();
    let mut body2: Vec<rsl_sphere> = (0..sc.pairs.len()).map(|c| body(c, 1)).collect();
    let tiny = 9;
    body1[tiny] = rsl_sphere {
        radius: 0.6e-160,
        ..Default::default()
    };
    body2[tiny] = rsl_sphere {
        position: rsl_vec3 {
            x: 1e-160,
            y: 0.0,
            z: 0.0,
        },
        radius: 0.6e-160,
        ..Default::default()
    };
    for config in configs() {
        let mut states = sc.states.clone();
        let mut out = vec![rsl_batch_loads::default(); sc.pairs.len()];
        let mut access = ContactSteps {
            energy: None,
            body1: &body1,
            body2: &body2,
            normal_force: &sc.normal_force,
            normal_stiffness: Some(&sc.normal_stiffness),
            states: &mut states,
            out: &mut out,
            sliding: SlidingOverrides::NONE,
        };
        let report = run_step(&model, dt, &mut access, config).unwrap();
        assert_eq!(report.failed, 1, "{config:?}");
        assert_eq!(report.first_failed, Some(tiny), "{config:?}");
        assert!(matches!(
            report.first_error,
            Some(Error::InvalidArgument(_))
        ));
        assert_eq!(states[tiny], sc.states[tiny]);
        assert_eq!(report.processed, sc.pairs.len() - 1);
    }
}

/// The particle-major call on packed histories (`rsl_batch_step_history`'s kernels) against the
/// call on full states, with the fields a record does not keep set to zero: the same report,
/// and bit for bit the same loads and new record words, for every model (and so every record
/// layout: with and without the sliding spring), precision and SIMD level (the
/// records fill the block's rows with exactly the values the states do). A non-finite word in
/// a record is skipped as in a state.
#[test]
fn packed_histories_step_as_full_states() {
    let dt = 1e-4;
    let mut layouts = Vec::new();
    let mut all = models();
    // The YADE and LIGGGHTS models without a sliding law too: the layouts without the sliding
    // spring, YADE's (10 words from word 3) and LIGGGHTS' (4 words from word 3, which the LAMMPS
    // models without sliding also have).
    for (model, name) in models() {
        if matches!(model.preset, Preset::Yade2023 | Preset::Liggghts38) {
            let mut no_sliding = model;
            no_sliding.sliding.law = SlidingLaw::None;
            all.push((no_sliding, format!("{name} without sliding")));
        }
    }
    for (model, name) in all {
        let layout = history_layout(&model);
        if !layouts.contains(&layout) {
            layouts.push(layout);
        }
        let end = layout.first + layout.words;
        let mut sc = scenario(40, 150, 21);
        sc.states[7].rolling_spring.x = f64::NAN;
        sc.states[30].twisting_angle = f64::INFINITY;
        for s in sc.states.iter_mut() {
            if end < 13 {
                s.model_memory = rsl_vec3::default();
            }
            if end < 10 {
                s.previous_normal = rsl_vec3::default();
            }
            if layout.first > 0 {
                s.sliding_spring = rsl_vec3::default();
            }
        }
        for config in configs() {
            let np = sc.particles.len();
            let mut states = sc.states.clone();
            let (mut force, mut torque) =
                (vec![rsl_vec3::default(); np], vec![rsl_vec3::default(); np]);
            let mut access = ParticleSteps {
                energy: None,
                particles: &sc.particles,
                pairs: &sc.pairs,
                normal_force: &sc.normal_force,
                normal_stiffness: Some(&sc.normal_stiffness),
                states: &mut states[..],
                force: &mut force,
                torque: &mut torque,
                sliding: ModelSliding,
            };
            let full = run_step(&model, dt, &mut access, config).unwrap();
            let packed = match (layout.first, end) {
                (0, 7) => step_packed::<7, 0>(&model, dt, &sc, config),
                (0, 10) => step_packed::<10, 0>(&model, dt, &sc, config),
                (0, _) => step_packed::<13, 0>(&model, dt, &sc, config),
                (_, 7) => step_packed::<4, 3>(&model, dt, &sc, config),
                (_, 10) => step_packed::<7, 3>(&model, dt, &sc, config),
                _ => step_packed::<10, 3>(&model, dt, &sc, config),
            };
            let what = format!("{name} {layout:?} {config:?}");
            assert_eq!(
                format!("{:?}", packed.report),
                format!("{full:?}"),
                "{what}"
            );
            assert_eq!(full.failed, 2, "{what}: contacts 7 and 30 skipped");
            let bits = |v: &[rsl_vec3]| -> Vec<[u64; 3]> {
                v.iter()
                    .map(|v| [v.x.to_bits(), v.y.to_bits(), v.z.to_bits()])
                    .collect()
            };
            assert_eq!(bits(&packed.force), bits(&force), "{what}: forces");
            assert_eq!(bits(&packed.torque), bits(&torque), "{what}: torques");
            for (c, record) in packed.records.iter().enumerate() {
                let mut expected = vec![0.0; layout.words];
                assert!(words_from_state(
                    &ContactState::from(&states[c]),
                    layout,
                    &mut expected
                ));
                let b = |r: &[f64]| r.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
                assert_eq!(b(record), b(&expected), "{what}: record {c}");
            }
        }
    }
    layouts.sort_by_key(|l| (l.first, l.words));
    assert_eq!(layouts, HistoryLayout::ALL, "every record layout is tested");
}

/// What [`step_packed`] returns.
struct Packed {
    report: rollslide::batch::BatchReport,
    force: Vec<rsl_vec3>,
    torque: Vec<rsl_vec3>,
    records: Vec<Vec<f64>>,
}

/// Steps `sc` with its states packed into `W`-word records from full-layout word `F`.
fn step_packed<const W: usize, const F: usize>(
    model: &Model,
    dt: f64,
    sc: &Scenario,
    config: BatchConfig,
) -> Packed {
    let np = sc.particles.len();
    let mut records: Vec<Record<W, F>> = sc
        .states
        .iter()
        .map(|s| Record::from_state(&ContactState::from(s)))
        .collect();
    let (mut force, mut torque) = (vec![rsl_vec3::default(); np], vec![rsl_vec3::default(); np]);
    let mut access = ParticleSteps {
        energy: None,
        particles: &sc.particles,
        pairs: &sc.pairs,
        normal_force: &sc.normal_force,
        normal_stiffness: Some(&sc.normal_stiffness),
        states: &mut records[..],
        force: &mut force,
        torque: &mut torque,
        sliding: ModelSliding,
    };
    let report = run_history_step(model, dt, &mut access, config).unwrap();
    Packed {
        report,
        force,
        torque,
        records: records.iter().map(|r| r.0.to_vec()).collect(),
    }
}

/// Per-contact sliding stiffness and damping (contact-major, `SlidingOverrides`) against the
/// per-contact checked step with the same overrides: bit for bit in double precision at every
/// level for every model (1e-4 of the scale in single); a contact with a negative or
/// non-finite `k_t` or `gamma_t` is skipped with the checked step's error and its state and
/// loads untouched. Each array is tested alone and with the other.
#[test]
fn per_contact_sliding_coefficients_match_the_checked_step() {
    let dt = 1e-4;
    let sc = scenario(40, 150, 31);
    let mut rng = Rng::new(7);
    let n = sc.pairs.len();
    let mut k_t: Vec<f64> = (0..n).map(|_| rng.uniform(0.0, 4e4)).collect();
    let mut gamma_t: Vec<f64> = (0..n).map(|_| rng.uniform(0.0, 20.0)).collect();
    k_t[11] = -1.0;
    k_t[12] = f64::NAN;
    gamma_t[40] = f64::INFINITY;
    gamma_t[41] = -0.5;
    let body = |c: usize, k: usize| sc.particles[sc.pairs[c][k] as usize];
    let body1: Vec<rsl_sphere> = (0..n).map(|c| body(c, 0)).collect();
    let body2: Vec<rsl_sphere> = (0..n).map(|c| body(c, 1)).collect();
    let mut tested = 0;
    for (model, name) in models() {
        for (use_k, use_g) in [(true, false), (false, true), (true, true)] {
            let sliding = SlidingOverrides {
                stiffness: use_k.then_some(&k_t[..]),
                damping: use_g.then_some(&gamma_t[..]),
                materials: None,
            };
            // Reference: the checked step with the same overrides.
            let mut expected = Vec::new();
            let mut first_error = None;
            for c in 0..n {
                let mut input = StepInput::new(sc.normal_force[c], dt);
                input.normal_stiffness = sc.normal_stiffness[c];
                (input.sliding_stiffness, input.sliding_damping) = sliding.at(c);
                let mut s = ContactState::from(&sc.states[c]);
                let r = contact_step_pair(
                    &model,
                    &Sphere::from(&body1[c]),
                    &Sphere::from(&body2[c]),
                    &input,
                    &mut s,
                );
                if let Err(e) = &r {
                    first_error.get_or_insert((c, e.clone()));
                }
                expected.push(r.ok().map(|o| (o.loads, s)));
            }
            for config in configs() {
                let what = format!("{name} {config:?} k_t {use_k} gamma_t {use_g}");
                let mut states = sc.states.clone();
                let mut out = vec![rsl_batch_loads::default(); n];
                let mut access = ContactSteps {
                    energy: None,
                    body1: &body1,
                    body2: &body2,
                    normal_force: &sc.normal_force,
                    normal_stiffness: Some(&sc.normal_stiffness),
                    states: &mut states,
                    out: &mut out,
                    sliding,
                };
                access.check().unwrap();
                let report = run_step(&model, dt, &mut access, config).unwrap();
                let (c0, e0) = first_error.clone().unwrap();
                assert_eq!(report.first_failed, Some(c0), "{what}");
                assert_eq!(report.first_error, Some(e0), "{what}");
                let bad = expected.iter().filter(|e| e.is_none()).count();
                assert_eq!((report.failed, report.processed), (bad, n - bad), "{what}");
                for c in 0..n {
                    let Some((loads, state)) = &expected[c] else {
                        assert_eq!(out[c], rsl_batch_loads::default(), "{what}: {c} written");
                        assert_eq!(states[c], sc.states[c], "{what}: {c} state written");
                        continue;
                    };
                    let got = [out[c].force1, out[c].torque1, out[c].torque2];
                    let want = [loads.force1, loads.torque1, loads.torque2];
                    for (g, w) in got.iter().zip(want) {
                        for (a, b) in [(g.x, w.x), (g.y, w.y), (g.z, w.z)] {
                            if config.f32 {
                                assert!(close(a, b, 1e-4, 1e-4), "{what}: {c}: {a} vs {b}");
                            } else {
                                assert_eq!(a.to_bits(), b.to_bits(), "{what}: contact {c}");
                            }
                        }
                    }
                    if !config.f32 {
                        assert_eq!(ContactState::from(&states[c]), *state, "{what}: {c}");
                    }
                }
                tested += 1;
            }
        }
    }
    assert!(tested > 0);
}

/// Per-contact sliding coefficients in the particle-major step (`ParticleSteps` with
/// `SlidingOverrides`) against the contact-major step with the same overrides (checked against
/// the per-contact step above): the same report, the same new states, and accumulators equal to
/// the contact-major loads added in contact order (`force[i] += F1`, `force[j] -= F1`,
/// `torque[i] += M1`, `torque[j] += M2`), bit for bit in double precision at every level and
/// model (1e-4 of the scale in single, whose kernels differ in their lane counts).
#[test]
fn particle_major_sliding_coefficients_match_the_contact_major_step() {
    let dt = 1e-4;
    let sc = scenario(40, 150, 33);
    let mut rng = Rng::new(9);
    let n = sc.pairs.len();
    let np = sc.particles.len();
    let mut k_t: Vec<f64> = (0..n).map(|_| rng.uniform(0.0, 4e4)).collect();
    let mut gamma_t: Vec<f64> = (0..n).map(|_| rng.uniform(0.0, 20.0)).collect();
    k_t[17] = -1.0;
    gamma_t[50] = f64::NAN;
    let body = |c: usize, k: usize| sc.particles[sc.pairs[c][k] as usize];
    let body1: Vec<rsl_sphere> = (0..n).map(|c| body(c, 0)).collect();
    let body2: Vec<rsl_sphere> = (0..n).map(|c| body(c, 1)).collect();
    let start = rsl_vec3 {
        x: 0.25,
        y: -1.0,
        z: 2.0,
    };
    let mut tested = 0;
    for (model, name) in models() {
        for (use_k, use_g) in [(true, false), (false, true), (true, true)] {
            let sliding = SlidingOverrides {
                stiffness: use_k.then_some(&k_t[..]),
                damping: use_g.then_some(&gamma_t[..]),
                materials: None,
            };
            for config in configs() {
                let what = format!("{name} {config:?} k_t {use_k} gamma_t {use_g}");
                let mut want_states = sc.states.clone();
                let mut out = vec![rsl_batch_loads::default(); n];
                let mut contacts = ContactSteps {
                    energy: None,
                    body1: &body1,
                    body2: &body2,
                    normal_force: &sc.normal_force,
                    normal_stiffness: Some(&sc.normal_stiffness),
                    states: &mut want_states,
                    out: &mut out,
                    sliding,
                };
                let want = run_step(&model, dt, &mut contacts, config).unwrap();
                let skipped = out
                    .iter()
                    .filter(|l| **l == rsl_batch_loads::default())
                    .count();
                assert_eq!(
                    skipped, want.failed,
                    "{what}: only the skipped have no loads"
                );
                let (mut want_force, mut want_torque) = (vec![start; np], vec![start; np]);
                for (l, pair) in out.iter().zip(&sc.pairs) {
                    if *l == rsl_batch_loads::default() {
                        continue; // skipped (a processed contact has non-zero loads here)
                    }
                    let [i, j] = pair.map(|p| p as usize);
                    let add = |a: &mut rsl_vec3, b: rsl_vec3, s: f64| {
                        (a.x, a.y, a.z) = (a.x + s * b.x, a.y + s * b.y, a.z + s * b.z);
                    };
                    add(&mut want_force[i], l.force1, 1.0);
                    add(&mut want_force[j], l.force1, -1.0);
                    add(&mut want_torque[i], l.torque1, 1.0);
                    add(&mut want_torque[j], l.torque2, 1.0);
                }
                let mut states = sc.states.clone();
                let (mut force, mut torque) = (vec![start; np], vec![start; np]);
                let mut access = ParticleSteps {
                    energy: None,
                    particles: &sc.particles,
                    pairs: &sc.pairs,
                    normal_force: &sc.normal_force,
                    normal_stiffness: Some(&sc.normal_stiffness),
                    states: &mut states[..],
                    force: &mut force,
                    torque: &mut torque,
                    sliding,
                };
                access.check().unwrap();
                let got = run_step(&model, dt, &mut access, config).unwrap();
                assert_eq!(got.first_failed, want.first_failed, "{what}");
                assert_eq!(got.first_error, want.first_error, "{what}");
                assert_eq!(
                    (got.failed, got.processed),
                    (want.failed, want.processed),
                    "{what}"
                );
                assert!(got.failed >= 1, "{what}: the bad coefficients are skipped");
                for p in 0..np {
                    for (g, w) in [(force[p], want_force[p]), (torque[p], want_torque[p])] {
                        for (a, b) in [(g.x, w.x), (g.y, w.y), (g.z, w.z)] {
                            if config.f32 {
                                assert!(close(a, b, 1e-4, 1e-4), "{what}: {p}: {a} vs {b}");
                            } else {
                                assert_eq!(a.to_bits(), b.to_bits(), "{what}: particle {p}");
                            }
                        }
                    }
                }
                if !config.f32 {
                    assert_eq!(states, want_states, "{what}");
                }
                tested += 1;
            }
        }
    }
    assert!(tested > 0);
}

/// A particle-major call counts at most two particles per contact toward the prefetch threshold
/// (and their force and torque): a chunk of a large scene, passed with the scene's whole particle
/// array, runs the kernels without prefetches, the whole scene in one call the prefetching ones.
#[test]
fn chunks_of_a_large_scene_count_only_the_particles_they_reach() {
    let sc = scenario(20_000, 12_000, 41);
    let np = sc.particles.len();
    assert!(
        size_of_val(&sc.particles[..]) > PREFETCH_MIN_BYTES,
        "a large particle array"
    );
    let mut states = sc.states.clone();
    let (mut force, mut torque) = (vec![rsl_vec3::default(); np], vec![rsl_vec3::default(); np]);
    for (contacts, prefetches) in [(sc.pairs.len(), true), (512, false)] {
        let access = ParticleSteps {
            energy: None,
            particles: &sc.particles,
            pairs: &sc.pairs[..contacts],
            normal_force: &sc.normal_force[..contacts],
            normal_stiffness: Some(&sc.normal_stiffness[..contacts]),
            states: &mut states[..contacts],
            force: &mut force,
            torque: &mut torque,
            sliding: ModelSliding,
        };
        assert_eq!(access.prefetching(), prefetches, "{contacts} contacts");
        let decompose = ParticleDecompose {
            particles: &sc.particles,
            pairs: &sc.pairs[..contacts],
            out: &mut vec![rsl_decomposition::default(); contacts][..],
        };
        assert_eq!(decompose.prefetching(), prefetches, "{contacts} contacts");
    }
}

/// The bits of every word of a state, slip flags included (NaN compares equal to itself).
fn state_word_bits(s: &rsl_contact_state) -> Vec<u64> {
    let c = ContactState::from(s);
    let mut b: Vec<u64> = [
        c.sliding_spring,
        c.rolling_spring,
        c.model_memory,
        c.previous_normal,
    ]
    .iter()
    .flat_map(|v| [v.x, v.y, v.z])
    .map(f64::to_bits)
    .collect();
    b.push(c.twisting_angle.to_bits());
    b.push(u64::from(s.slip_flags));
    b
}

/// One particle-major step of `sc` (time step 1e-4) with its states in `states` and, when
/// given, per-contact `k_t`: the report, whether the kernel prefetched, the forces and torques
/// (from a non-zero start).
fn step_with_states<St: ContactStates<Slot = rsl_contact_state>>(
    model: &Model,
    config: BatchConfig,
    sc: &Scenario,
    states: St,
    k_t: Option<&[f64]>,
) -> (BatchReport, bool, Vec<rsl_vec3>, Vec<rsl_vec3>) {
    let start = rsl_vec3 {
        x: 1.0,
        y: -2.0,
        z: 0.5,
    };
    let np = sc.particles.len();
    let (mut force, mut torque) = (vec![start; np], vec![start; np]);
    macro_rules! step {
        ($sliding:expr) => {{
            let mut access = ParticleSteps {
                energy: None,
                particles: &sc.particles,
                pairs: &sc.pairs,
                normal_force: &sc.normal_force,
                normal_stiffness: Some(&sc.normal_stiffness),
                states,
                force: &mut force,
                torque: &mut torque,
                sliding: $sliding,
            };
            access.check().unwrap();
            let prefetched = access.prefetching();
            let report = run_step(model, 1e-4, &mut access, config).unwrap();
            (report, prefetched)
        }};
    }
    let (report, prefetched) = match k_t {
        Some(k) => step!(SlidingOverrides {
            stiffness: Some(k),
            damping: None,
            materials: None,
        }),
        None => step!(ModelSliding),
    };
    (report, prefetched, force, torque)
}

/// States kept in the host's array (one slot per neighbour-list entry, about a third of them
/// touching) and stepped through an index per contact ([`IndexedStates`]) give the bits of the
/// same call on a buffer of the touching contacts' states: loads, states, report, in every
/// kernel and precision, with and without per-contact sliding coefficients, with and without
/// prefetching; so do the C layer's [`IndexedGroups`] (what `rsl_batch_step_indexed` steps,
/// with unchecked group addresses). The slots not indexed hold NaN (a read would refuse the
/// contact) and keep it.
#[test]
fn indexed_states_step_as_a_buffer_of_states() {
    let mut rng = Rng::new(77);
    // 150 contacts run the kernels without prefetches; 12,000 (1.4 MB of states and indices
    // alone) the prefetching ones.
    for (nc, every_model) in [(150, true), (12_000, false)] {
        let mut sc = scenario(nc / 3 + 10, nc, 41 + nc as u64);
        sort_by_body1(&mut sc);
        let mut index = Vec::with_capacity(nc);
        let mut next = 0;
        for _ in 0..nc {
            next += 1 + (rng.next_u64() % 4) as usize;
            index.push(next);
        }
        let n_slots = next + 3;
        let untouched = rsl_contact_state {
            twisting_angle: f64::NAN,
            rolling_spring: rsl_vec3 {
                x: 0.0,
                y: f64::NAN,
                z: 0.0,
            },
            ..Default::default()
        };
        let k_t: Vec<f64> = (0..nc).map(|_| rng.uniform(0.0, 4e4)).collect();
        let mut tested = 0;
        for (m, (model, name)) in models().into_iter().enumerate() {
            if !every_model && m % 4 != 0 {
                continue;
            }
            for config in configs() {
                for with_kt in [false, true] {
                    let what = format!("{nc} {name} {config:?} k_t {with_kt}");
                    let k_t = with_kt.then_some(&k_t[..]);
                    let mut buffer = sc.states.clone();
                    let want = step_with_states(&model, config, &sc, &mut buffer[..], k_t);
                    // The core's `IndexedStates`, and the C layer's wrapper of it (what
                    // `rsl_batch_step_indexed` steps).
                    for grouped in [false, true] {
                        let what = format!("{what} grouped {grouped}");
                        let mut slots = vec![untouched; n_slots];
                        for (c, &i) in index.iter().enumerate() {
                            slots[i] = sc.states[c];
                        }
                        let states = IndexedStates::new(&mut slots, &index).unwrap();
                        let got = if grouped {
                            step_with_states(&model, config, &sc, IndexedGroups::from(states), k_t)
                        } else {
                            step_with_states(&model, config, &sc, states, k_t)
                        };
                        assert_eq!(got.1, nc > 1000, "{what}: prefetching as intended");
                        assert_eq!(got.1, want.1, "{what}");
                        assert_eq!(
                            (got.0.processed, got.0.failed, got.0.first_failed),
                            (want.0.processed, want.0.failed, want.0.first_failed),
                            "{what}"
                        );
                        assert_eq!(got.0.first_error, want.0.first_error, "{what}");
                        assert!(want.0.processed > nc / 2, "{what}: most contacts step");
                        let bits = |v: &[rsl_vec3]| -> Vec<u64> {
                            v.iter()
                                .flat_map(|v| [v.x, v.y, v.z])
                                .map(f64::to_bits)
                                .collect()
                        };
                        assert_eq!(bits(&got.2), bits(&want.2), "{what}: force");
                        assert_eq!(bits(&got.3), bits(&want.3), "{what}: torque");
                        let mut next = 0;
                        for (s, slot) in slots.iter().enumerate() {
                            if index.get(next) == Some(&s) {
                                assert_eq!(
                                    state_word_bits(slot),
                                    state_word_bits(&buffer[next]),
                                    "{what}: contact {next}"
                                );
                                next += 1;
                            } else {
                                assert_eq!(
                                    state_word_bits(slot),
                                    state_word_bits(&untouched),
                                    "{what}: slot {s} is not a contact's"
                                );
                            }
                        }
                        tested += 1;
                    }
                }
            }
        }
        assert!(tested > 0);
    }
}

/// Indices that repeat, fall or point past the slots are refused before anything is read.
#[test]
fn indexed_states_refuse_bad_indices() {
    let mut slots = vec![rsl_contact_state::default(); 6];
    for bad in [&[0, 2, 2][..], &[3, 1], &[1, 6]] {
        assert!(matches!(
            IndexedStates::new(&mut slots, bad),
            Err(Error::InvalidArgument(_))
        ));
    }
    let states = IndexedStates::new(&mut slots, &[0, 5]).unwrap();
    let sc = scenario(4, 3, 1);
    let (mut force, mut torque) = (vec![rsl_vec3::default(); 4], vec![rsl_vec3::default(); 4]);
    let access = ParticleSteps {
        energy: None,
        particles: &sc.particles,
        pairs: &sc.pairs,
        normal_force: &sc.normal_force,
        normal_stiffness: Some(&sc.normal_stiffness),
        states,
        force: &mut force,
        torque: &mut torque,
        sliding: ModelSliding,
    };
    assert!(access.check().is_err(), "two indices for three contacts");
}

/// A block's index test: true exactly when the largest particle index of the contacts asked
/// about is below the particle count, whatever lies outside the range asked about.
#[test]
fn a_blocks_indices_are_in_range_exactly_when_its_largest_is() {
    let particles = vec![rsl_sphere::default(); 5];
    let pairs = [[0u32, 4], [4, 1], [5, 0], [2, 3], [1, u32::MAX]];
    let (mut force, mut torque) = (vec![rsl_vec3::default(); 5], vec![rsl_vec3::default(); 5]);
    let mut states = vec![rsl_contact_state::default(); pairs.len()];
    let access = ParticleSteps {
        energy: None,
        particles: &particles,
        pairs: &pairs,
        normal_force: &[0.0; 5],
        normal_stiffness: None,
        states: &mut states[..],
        force: &mut force,
        torque: &mut torque,
        sliding: ModelSliding,
    };
    // (first, n, expected): index 4 is the last particle, 5 and u32::MAX are past it.
    for (first, n, expected) in [
        (0, 2, true),
        (0, 3, false),
        (2, 1, false),
        (3, 1, true),
        (3, 2, false),
        (4, 1, false),
    ] {
        assert_eq!(
            access.indices_in_range(first, n),
            expected,
            "contacts {first}..{}",
            first + n
        );
    }
}
