//! The per-contact parameters of the batch calls (`rsl_batch_contact_params`), through the C
//! entry points, at every SIMD level, in all three calls that take them:
//! - mixed materials: a model's table of coefficient sets (`rsl_model_set_materials`) and each
//!   contact's index into it (`material`) give every contact the bits of `rsl_contact_step`
//!   with its set's model; a bad index is refused as a bad particle index is, nothing written;
//! - the energy output (`energy`): each stepped contact's terms, bit for bit those of
//!   `rsl_contact_step`; a skipped contact's entry untouched; refused for a model that does not
//!   track energy.

use super::batch::{
    rsl_batch_contact_params, rsl_batch_loads, rsl_batch_options, rsl_batch_report,
    rsl_batch_step_contacts_params, rsl_batch_step_indexed, rsl_batch_step_params,
    RSL_PRECISION_F64, RSL_SIMD_AVX2, RSL_SIMD_AVX512, RSL_SIMD_SCALAR,
};
use super::contact::contact_steps;
use super::contact::{
    rsl_contact_energy, rsl_contact_input, rsl_contact_loads, rsl_contact_state, rsl_contact_step,
    RSL_INPUT_SLIDING_STIFFNESS,
};
use super::model::{
    rsl_model, rsl_model_material_count, rsl_model_set_materials, rsl_model_set_sliding,
    rsl_model_set_twisting, RSL_SLIDING_LINEAR, RSL_TWISTING_SDS,
};
use super::status::{RSL_ERR_INVALID_ARGUMENT, RSL_ERR_MISALIGNED, RSL_OK};
use super::types::{rsl_sphere, rsl_vec3};
use crate::batch::Simd;
use crate::laws::model::{
    Model, Preset, RollingForm, RollingLaw, RollingStiffness, SlidingLaw, Transport, TwistingLaw,
};
use crate::layout::tests::{state_bits, Lcg};

/// The calling thread's last error message.
pub(super) fn last_error() -> String {
    let p = super::status::rsl_last_error_message();
    // SAFETY: the library returns a valid NUL-terminated string, alive until the thread's next
    // failing call.
    unsafe { std::ffi::CStr::from_ptr(p) }
        .to_string_lossy()
        .into_owned()
}

/// A live handle of `model` with this CPU's per-contact steps.
pub(super) fn live(model: Model) -> rsl_model {
    rsl_model::live(model, contact_steps())
}

/// The law sets of the test, one per preset family and rolling law kind: LAMMPS' full set,
/// the objective full set with Marshall twisting, LIGGGHTS' epsd2 (derived rolling stiffness,
/// angle form) and cdt rolling.
pub(super) fn base_models() -> Vec<Model> {
    let mut lammps = Model::with_preset(Preset::Lammps2021);
    lammps.sliding.law = SlidingLaw::Linear;
    (
        lammps.sliding.stiffness,
        lammps.sliding.damping,
        lammps.sliding.friction,
    ) = (2e5, 30.0, 0.5);
    lammps.rolling.law = RollingLaw::Epsd;
    (
        lammps.rolling.stiffness,
        lammps.rolling.damping,
        lammps.rolling.friction,
    ) = (1e5, 10.0, 0.1);
    lammps.twisting.law = TwistingLaw::Sds;
    (lammps.twisting.stiffness, lammps.twisting.damping) = (50.0, 0.5);
    lammps.twisting.friction = 0.05;
    lammps.sliding_transport = Transport::ProjectRescale;
    lammps.rolling_transport = Transport::ProjectRescale;
    let mut marshall = lammps;
    marshall.preset = Preset::Objective;
    marshall.sliding_transport = Transport::Exact;
    marshall.rolling_transport = Transport::Exact;
    marshall.twisting.law = TwistingLaw::Marshall;
    let mut epsd2 = Model::with_preset(Preset::Liggghts38);
    epsd2.sliding = lammps.sliding;
    epsd2.rolling.law = RollingLaw::Epsd;
    epsd2.rolling.form = RollingForm::Angle;
    epsd2.rolling.stiffness_rule = RollingStiffness::Epsd2;
    (epsd2.rolling.damping, epsd2.rolling.friction) = (1e-3, 0.05);
    let mut cdt = epsd2;
    cdt.rolling.law = RollingLaw::Cdt;
    cdt.rolling.form = RollingForm::Length;
    vec![lammps, marshall, epsd2, cdt]
}

/// Three material pairs of `base`'s laws: its own coefficients and two others, each value
/// scaled differently (a reached limit in some contacts, not in others).
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

/// Particles in contact pairs (particle-major: contact `c` joins `pairs[2c]`, `pairs[2c+1]`),
/// their normal forces and stiffnesses, and non-zero histories.
struct Contacts {
    particles: Vec<rsl_sphere>,
    pairs: Vec<u32>,
    f_n: Vec<f64>,
    k_n: Vec<f64>,
    states: Vec<rsl_contact_state>,
}

fn contacts(n: usize, rng: &mut Lcg) -> Contacts {
    let mut c = Contacts {
        particles: Vec::new(),
        pairs: Vec::new(),
        f_n: Vec::new(),
        k_n: Vec::new(),
        states: Vec::new(),
    };
    for i in 0..n {
        let (r1, r2) = (rng.uniform(0.5, 1.5), rng.uniform(0.5, 1.5));
        let dir = rng.vec(1.0);
        let len = (dir.x * dir.x + dir.y * dir.y + dir.z * dir.z).sqrt();
        let gap = (r1 + r2) * rng.uniform(0.97, 0.999);
        let p1 = rsl_vec3 {
            x: 4.0 * i as f64,
            y: 0.0,
            z: 0.0,
        };
        let p2 = rsl_vec3 {
            x: p1.x + gap * dir.x / len,
            y: p1.y + gap * dir.y / len,
            z: p1.z + gap * dir.z / len,
        };
        for (p, r) in [(p1, r1), (p2, r2)] {
            c.particles.push(rsl_sphere {
                position: p,
                velocity: rng.vec(0.5),
                angular_velocity: rng.vec(3.0),
                radius: r,
            });
        }
        c.pairs.extend([2 * i as u32, 2 * i as u32 + 1]);
        c.f_n.push(rng.uniform(1.0, 200.0));
        c.k_n.push(rng.uniform(1e4, 1e5));
        c.states.push(rsl_contact_state {
            sliding_spring: rng.vec(1e-4),
            rolling_spring: rng.vec(1e-4),
            ..Default::default()
        });
    }
    c
}

/// `rsl_contact_step` of contact `c` with `model`: status, loads, new state.
fn reference(
    model: &rsl_model,
    c: &Contacts,
    i: usize,
    k_t: Option<f64>,
) -> (i32, rsl_contact_loads, rsl_contact_state) {
    let input = rsl_contact_input {
        normal_force: c.f_n[i],
        dt: 1e-4,
        normal_stiffness: c.k_n[i],
        sliding_stiffness: k_t.unwrap_or(0.0),
        flags: if k_t.is_some() {
            RSL_INPUT_SLIDING_STIFFNESS
        } else {
            0
        },
        ..Default::default()
    };
    let (mut state, mut out) = (c.states[i], rsl_contact_loads::default());
    let (b1, b2) = (
        &c.particles[c.pairs[2 * i] as usize],
        &c.particles[c.pairs[2 * i + 1] as usize],
    );
    // SAFETY: a live handle and locals of the right types; none overlap.
    let status = unsafe { rsl_contact_step(model, b1, b2, &input, &mut state, &mut out) };
    (status, out, state)
}

/// The double-precision option sets of this CPU's SIMD levels.
fn levels() -> Vec<rsl_batch_options> {
    [RSL_SIMD_SCALAR, RSL_SIMD_AVX2, RSL_SIMD_AVX512]
        .into_iter()
        .filter(|&simd| Simd::resolve(simd).is_ok())
        .map(|simd| rsl_batch_options {
            precision: RSL_PRECISION_F64,
            simd,
            flags: 0,
            reserved: 0,
        })
        .collect()
}

fn bits(v: &rsl_vec3) -> [u64; 3] {
    [v.x.to_bits(), v.y.to_bits(), v.z.to_bits()]
}

/// What one batch call left: its status and report, the states (in contact order) and the
/// loads (per particle for the particle-major calls; per contact, as `force1`, `torque1`,
/// `torque2`, for the contact-major one).
struct Run {
    status: i32,
    report: rsl_batch_report,
    states: Vec<rsl_contact_state>,
    loads: Vec<rsl_vec3>,
}

/// `rsl_batch_step_params` on `c`'s contacts from their states; zeroed accumulators.
fn step_params(
    model: &rsl_model,
    c: &Contacts,
    params: &rsl_batch_contact_params,
    o: Option<&rsl_batch_options>,
) -> Run {
    let (n, np) = (c.f_n.len(), c.particles.len());
    let mut states = c.states.clone();
    let (mut force, mut torque) = (vec![rsl_vec3::default(); np], vec![rsl_vec3::default(); np]);
    let mut report = rsl_batch_report::default();
    // SAFETY: every array holds what the call reads or writes (`params`' arrays `n` entries);
    // none overlap.
    let status = unsafe {
        rsl_batch_step_params(
            model,
            c.particles.as_ptr(),
            np,
            c.pairs.as_ptr(),
            n,
            c.f_n.as_ptr(),
            c.k_n.as_ptr(),
            params,
            1e-4,
            o.map_or(std::ptr::null(), |o| o as *const _),
            states.as_mut_ptr(),
            force.as_mut_ptr(),
            torque.as_mut_ptr(),
            &mut report,
        )
    };
    force.extend(torque);
    Run {
        status,
        report,
        states,
        loads: force,
    }
}

/// `rsl_batch_step_indexed` on `c`'s contacts, their states in place at every other entry of a
/// host array of `2 n` (the others never touched: checked here).
fn step_indexed(
    model: &rsl_model,
    c: &Contacts,
    params: &rsl_batch_contact_params,
    o: &rsl_batch_options,
) -> Run {
    let (n, np) = (c.f_n.len(), c.particles.len());
    let untouched = rsl_contact_state {
        twisting_angle: 5.0,
        ..Default::default()
    };
    let mut slots = vec![untouched; 2 * n];
    for i in 0..n {
        slots[2 * i + 1] = c.states[i];
    }
    let index: Vec<usize> = (0..n).map(|i| 2 * i + 1).collect();
    let (mut force, mut torque) = (vec![rsl_vec3::default(); np], vec![rsl_vec3::default(); np]);
    let mut report = rsl_batch_report::default();
    // SAFETY: as in `step_params`; `slots` holds `2 n` states, `index` `n` increasing indices.
    let status = unsafe {
        rsl_batch_step_indexed(
            model,
            c.particles.as_ptr(),
            np,
            c.pairs.as_ptr(),
            n,
            c.f_n.as_ptr(),
            c.k_n.as_ptr(),
            params,
            1e-4,
            o,
            slots.as_mut_ptr(),
            2 * n,
            index.as_ptr(),
            force.as_mut_ptr(),
            torque.as_mut_ptr(),
            &mut report,
        )
    };
    for i in 0..n {
        assert_eq!(
            state_bits(&slots[2 * i]),
            state_bits(&untouched),
            "slot {}",
            2 * i
        );
    }
    force.extend(torque);
    Run {
        status,
        report,
        states: (0..n).map(|i| slots[2 * i + 1]).collect(),
        loads: force,
    }
}

/// The value `step_contacts` leaves in the loads of a contact it skips.
const SENTINEL: rsl_vec3 = rsl_vec3 {
    x: 7.0,
    y: 7.0,
    z: 7.0,
};

/// `rsl_batch_step_contacts_params` on `c`'s contacts (bodies gathered per contact); the loads
/// start as `SENTINEL`.
fn step_contacts(
    model: &rsl_model,
    c: &Contacts,
    params: &rsl_batch_contact_params,
    o: &rsl_batch_options,
) -> Run {
    let n = c.f_n.len();
    let body1: Vec<rsl_sphere> = (0..n).map(|i| c.particles[2 * i]).collect();
    let body2: Vec<rsl_sphere> = (0..n).map(|i| c.particles[2 * i + 1]).collect();
    let mut states = c.states.clone();
    let sentinel = rsl_batch_loads {
        force1: SENTINEL,
        torque1: SENTINEL,
        torque2: SENTINEL,
    };
    let mut out = vec![sentinel; n];
    let mut report = rsl_batch_report::default();
    // SAFETY: every array holds `n` elements; none overlap.
    let status = unsafe {
        rsl_batch_step_contacts_params(
            model,
            body1.as_ptr(),
            body2.as_ptr(),
            n,
            c.f_n.as_ptr(),
            c.k_n.as_ptr(),
            params,
            1e-4,
            o,
            states.as_mut_ptr(),
            out.as_mut_ptr(),
            &mut report,
        )
    };
    Run {
        status,
        report,
        states,
        loads: out
            .iter()
            .flat_map(|l| [l.force1, l.torque1, l.torque2])
            .collect(),
    }
}

fn all_bits(v: &[rsl_vec3]) -> Vec<u64> {
    v.iter().flat_map(bits).collect()
}

#[test]
fn each_contact_steps_as_its_material_pairs_model_bit_for_bit() {
    let mut rng = Lcg(11);
    let n = 101; // three blocks and a part, so that groups mix whole and partial ones
    for base in base_models() {
        let sets: Vec<rsl_model> = material_models(&base).into_iter().map(live).collect();
        let mut model = live(base);
        let pointers: Vec<*const rsl_model> = sets.iter().map(|s| s as *const _).collect();
        // SAFETY: a live handle and an array of three live handles.
        let status = unsafe { rsl_model_set_materials(&mut model, pointers.as_ptr(), 3) };
        assert_eq!(status, RSL_OK);
        let c = contacts(n, &mut rng);
        // Random sets, with two indices out of range (3 and u32::MAX).
        let mut material: Vec<u32> = (0..n).map(|_| (rng.next() * 3.0) as u32).collect();
        let bad = [17usize, 64];
        material[bad[0]] = 3;
        material[bad[1]] = u32::MAX;
        let k_t: Vec<f64> = (0..n).map(|_| rng.uniform(5e4, 5e5)).collect();
        for with_k_t in [false, true] {
            let want: Vec<_> = (0..n)
                .map(|i| {
                    let set = sets.get(material[i] as usize).unwrap_or(&sets[0]);
                    reference(set, &c, i, with_k_t.then_some(k_t[i]))
                })
                .collect();
            for (i, w) in want.iter().enumerate() {
                assert_eq!(w.0, RSL_OK, "reference step of contact {i}");
            }
            let params = rsl_batch_contact_params {
                sliding_stiffness: if with_k_t {
                    k_t.as_ptr()
                } else {
                    std::ptr::null()
                },
                sliding_damping: std::ptr::null(),
                material: material.as_ptr(),
                energy: std::ptr::null_mut(),
            };
            for o in levels() {
                let what = format!("{base:?} k_t {with_k_t} {o:?}");
                let check = |r: &Run| {
                    assert_eq!(r.status, RSL_ERR_INVALID_ARGUMENT, "{what}");
                    assert_eq!(r.report.failed, 2, "{what}");
                    assert_eq!(r.report.processed, n as u64 - 2, "{what}");
                    assert_eq!(r.report.first_failed, bad[0] as u64, "{what}");
                    assert_eq!(r.report.first_status, RSL_ERR_INVALID_ARGUMENT, "{what}");
                };
                // Particle-major, states in contact order; loads: forces, then torques.
                let np = c.particles.len();
                let p = step_params(&model, &c, &params, Some(&o));
                check(&p);
                let (force, torque) = p.loads.split_at(np);
                for (i, (_, l, s)) in want.iter().enumerate() {
                    let (b1, b2) = (2 * i, 2 * i + 1);
                    if bad.contains(&i) {
                        assert_eq!(state_bits(&p.states[i]), state_bits(&c.states[i]), "{what}");
                        for q in [b1, b2] {
                            assert_eq!(bits(&force[q]), [0; 3], "{what}: {i} wrote a force");
                            assert_eq!(bits(&torque[q]), [0; 3], "{what}: {i} wrote a torque");
                        }
                        continue;
                    }
                    assert_eq!(state_bits(&p.states[i]), state_bits(s), "{what}: state {i}");
                    assert_eq!(bits(&force[b1]), bits(&l.force1), "{what}: force {i}");
                    assert_eq!(bits(&torque[b1]), bits(&l.torque1), "{what}: torque1 {i}");
                    assert_eq!(bits(&torque[b2]), bits(&l.torque2), "{what}: torque2 {i}");
                    // Body 2 received -F1 (added to zero).
                    let minus = rsl_vec3 {
                        x: -l.force1.x,
                        y: -l.force1.y,
                        z: -l.force1.z,
                    };
                    assert_eq!(bits(&force[b2]), bits(&minus), "{what}: force2 {i}");
                }
                // Histories where the host keeps them: the same bits.
                let x = step_indexed(&model, &c, &params, &o);
                check(&x);
                let states = |r: &Run| r.states.iter().map(state_bits).collect::<Vec<_>>();
                assert_eq!(states(&x), states(&p), "{what}: indexed states");
                assert_eq!(
                    all_bits(&x.loads),
                    all_bits(&p.loads),
                    "{what}: indexed loads"
                );
                // Contact-major.
                let k = step_contacts(&model, &c, &params, &o);
                check(&k);
                for i in 0..n {
                    let loads = &k.loads[3 * i..3 * i + 3];
                    if bad.contains(&i) {
                        assert_eq!(all_bits(loads), all_bits(&[SENTINEL; 3]), "{what}");
                        assert_eq!(state_bits(&k.states[i]), state_bits(&c.states[i]));
                        continue;
                    }
                    let (_, l, s) = &want[i];
                    assert_eq!(state_bits(&k.states[i]), state_bits(s), "{what}: state {i}");
                    let want = [l.force1, l.torque1, l.torque2];
                    assert_eq!(all_bits(loads), all_bits(&want), "{what}: loads {i}");
                }
            }
        }
        // The sets do differ: some contact's loads change with its material.
        let mut other = material.clone();
        for m in other.iter_mut() {
            *m = m.wrapping_add(1) % 3;
        }
        let differs = (0..n).filter(|i| !bad.contains(i)).any(|i| {
            let a = reference(&sets[material[i] as usize], &c, i, None);
            let b = reference(&sets[other[i] as usize], &c, i, None);
            bits(&a.1.force1) != bits(&b.1.force1) || bits(&a.1.torque1) != bits(&b.1.torque1)
        });
        assert!(differs, "{base:?}: the material sets give the same loads");
    }
}

#[test]
fn a_table_takes_sets_of_the_models_laws_only_and_setters_keep_it_for_values() {
    let base = base_models()[0];
    let mut model = live(base);
    let mut other_laws = base;
    other_laws.twisting.law = TwistingLaw::None;
    let mut other_transport = base;
    other_transport.rolling_transport = Transport::Exact;
    let good: Vec<rsl_model> = material_models(&base).into_iter().map(live).collect();
    let count = |m: &rsl_model| {
        let mut n = 99;
        // SAFETY: a live handle and a local.
        assert_eq!(unsafe { rsl_model_material_count(m, &mut n) }, RSL_OK);
        n
    };
    let set = |m: &mut rsl_model, sets: &[*const rsl_model]| {
        // SAFETY: a live handle; `sets` holds `sets.len()` pointers (live or NULL).
        unsafe { rsl_model_set_materials(m, sets.as_ptr(), sets.len()) }
    };
    let good_ptrs: Vec<*const rsl_model> = good.iter().map(|m| m as *const _).collect();
    assert_eq!(set(&mut model, &good_ptrs), RSL_OK);
    assert_eq!(count(&model), 3);
    // Refused, the table unchanged: other laws, another transport, a NULL set.
    for bad in [live(other_laws), live(other_transport)] {
        let sets = [good_ptrs[0], &bad as *const rsl_model];
        assert_eq!(set(&mut model, &sets), RSL_ERR_INVALID_ARGUMENT);
        assert_eq!(count(&model), 3);
    }
    let sets = [good_ptrs[0], std::ptr::null()];
    assert_eq!(set(&mut model, &sets), RSL_ERR_INVALID_ARGUMENT);
    assert_eq!(count(&model), 3);
    // A misaligned set: the message names the element, not the model.
    let misaligned = (good_ptrs[1] as usize + 1) as *const rsl_model;
    let sets = [good_ptrs[0], good_ptrs[2], misaligned];
    assert_eq!(set(&mut model, &sets), RSL_ERR_MISALIGNED);
    assert_eq!(last_error(), "misaligned pointer: sets[2]");
    assert_eq!(count(&model), 3);
    // A setter that changes values keeps the table; one that changes a law removes it.
    // SAFETY: a live handle, used by this thread only.
    unsafe {
        assert_eq!(
            rsl_model_set_sliding(&mut model, RSL_SLIDING_LINEAR, 3e5, 20.0, 0.4),
            RSL_OK
        );
        assert_eq!(count(&model), 3);
        assert_eq!(
            rsl_model_set_twisting(&mut model, RSL_TWISTING_SDS, 10.0, 0.1, 0.02),
            RSL_OK
        );
        assert_eq!(count(&model), 3);
    }
    // SAFETY: as above.
    unsafe {
        assert_eq!(
            super::model::rsl_model_set_twisting(&mut model, 0, 0.0, 0.0, 0.0),
            RSL_OK
        );
    }
    assert_eq!(model.model.twisting.law, TwistingLaw::None);
    assert_eq!(count(&model), 0);
    // n = 0 removes a table (NULL allowed).
    assert_eq!(set(&mut model, &[]), RSL_OK);
    // SAFETY: a live handle; NULL with n = 0.
    assert_eq!(
        unsafe { rsl_model_set_materials(&mut model, std::ptr::null(), 0) },
        RSL_OK
    );
    assert_eq!(count(&model), 0);
}

fn energy_bits(e: &rsl_contact_energy) -> [u64; 11] {
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
    .map(f64::to_bits)
}

#[test]
fn the_batch_calls_return_each_contacts_energy_terms_bit_for_bit() {
    let mut rng = Lcg(5);
    let n = 75;
    for base in base_models() {
        let mut tracked = base;
        tracked.track_energy = true;
        let model = live(tracked);
        let mut c = contacts(n, &mut rng);
        // One contact with a non-finite normal force: skipped, its entry untouched.
        let skipped = 40;
        c.f_n[skipped] = f64::NAN;
        let want: Vec<_> = (0..n).map(|i| reference(&model, &c, i, None)).collect();
        let sentinel = rsl_contact_energy {
            transport: 99.0,
            ..Default::default()
        };
        let with_energy = |energy: &mut Vec<rsl_contact_energy>| rsl_batch_contact_params {
            sliding_stiffness: std::ptr::null(),
            sliding_damping: std::ptr::null(),
            material: std::ptr::null(),
            energy: energy.as_mut_ptr(),
        };
        let energy_of = |e: &[rsl_contact_energy]| e.iter().map(energy_bits).collect::<Vec<_>>();
        for o in levels() {
            let what = format!("{base:?} {o:?}");
            let check = |r: &Run| {
                assert_eq!(r.status, want[skipped].0, "{what}");
                assert_eq!(
                    (r.report.failed, r.report.first_failed),
                    (1, skipped as u64)
                );
            };
            // Particle-major.
            let mut energy = vec![sentinel; n];
            check(&step_params(
                &model,
                &c,
                &with_energy(&mut energy),
                Some(&o),
            ));
            for i in 0..n {
                if i == skipped {
                    assert_eq!(energy_bits(&energy[i]), energy_bits(&sentinel), "{what}");
                } else {
                    assert_eq!(want[i].0, RSL_OK);
                    let e = &want[i].1.energy;
                    assert_eq!(energy_bits(&energy[i]), energy_bits(e), "{what}: {i}");
                }
            }
            // The terms are not all zero: the laws store and dissipate energy.
            assert!(energy
                .iter()
                .any(|e| e.elastic_sliding > 0.0 || e.slider_rolling > 0.0));
            // Histories where the host keeps them, and contact-major: the same entries.
            let mut indexed = vec![sentinel; n];
            check(&step_indexed(&model, &c, &with_energy(&mut indexed), &o));
            assert_eq!(energy_of(&indexed), energy_of(&energy), "{what}: indexed");
            let mut contacts = vec![sentinel; n];
            check(&step_contacts(&model, &c, &with_energy(&mut contacts), &o));
            assert_eq!(
                energy_of(&contacts),
                energy_of(&energy),
                "{what}: contact-major"
            );
        }
        // A model that does not track energy: refused, nothing processed or written.
        let plain = live(base);
        let mut energy = vec![sentinel; n];
        let r = step_params(&plain, &c, &with_energy(&mut energy), None);
        assert_eq!(r.status, RSL_ERR_INVALID_ARGUMENT);
        assert_eq!((r.report.processed, r.report.failed), (0, 0));
        assert!(energy
            .iter()
            .all(|e| energy_bits(e) == energy_bits(&sentinel)));
        assert!(r.loads.iter().all(|f| bits(f) == [0; 3]));
        let states = |v: &[rsl_contact_state]| v.iter().map(state_bits).collect::<Vec<_>>();
        assert_eq!(states(&r.states), states(&c.states));
    }
}
