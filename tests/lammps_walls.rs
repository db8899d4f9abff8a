//! `fix wall/gran/rollslide` inside LAMMPS: flat walls (`xplane`, `yplane`, `zplane`) and a
//! `zcylinder` whose sliding, rolling and twisting come from rollslide
//! (`rsl_contact_step_wall`), with the normal force of stock `fix wall/gran granular`.
//!
//! Scene: `examples/lammps/inputs/in.wall_gran`, spheres on walls and no pair style (the spheres
//! touch the walls only, so each atom's loads are its wall contact's and the body force's):
//! `zplane` (36 spheres on a floor under gravity), `zpair` (the floor and a ceiling at z = 12
//! with 12 more spheres pressed against it), `zcylinder` (48 spheres pressed against the inside
//! of a cylinder of radius 5, circling along it), with random velocities and spins (rolling,
//! sliding, bouncing), the walls still, wiggling along their normal or along the wall, or
//! sheared (a zcylinder `shear x` turns about its axis). Loads are compared atom by atom from
//! `dump custom` files written with 17 digits. Measured values are printed with
//! `cargo test --test lammps_walls -- --nocapture`.
//!
//! Reported as ignored, with the reason, when LAMMPS, MPI, cmake or LAMMPS' source tarball is
//! missing (tests/common/lammps.rs).

mod common;

use common::granular::{normal_by_tangential, parallel_map, Scale, TANGENTIAL};
use common::lammps::{
    assert_loads_agree, compare, lammps, lammps_error, read_dump, rundir, thermo, trial,
    worst_over_mean, worst_relative, Dump,
};
use std::path::Path;

fn main() {
    common::lammps::run_trials(vec![
        trial(
            "flat_walls_match_stock_fix_wall_gran",
            flat_walls_match_stock_fix_wall_gran,
        ),
        trial(
            "zcylinder_lammps_preset_matches_stock",
            zcylinder_lammps_preset_matches_stock,
        ),
        trial(
            "every_tangential_model_on_the_walls_matches_stock",
            every_tangential_model_on_the_walls_matches_stock,
        ),
        trial(
            "every_normal_and_tangential_combination_on_the_walls_matches_stock",
            every_normal_and_tangential_combination_on_the_walls_matches_stock,
        ),
        trial(
            "tangential_models_on_the_walls_across_ranks_and_restart",
            tangential_models_on_the_walls_across_ranks_and_restart,
        ),
        trial(
            "ranks_newton_and_sorting_carry_the_wall_histories",
            ranks_newton_and_sorting_carry_the_wall_histories,
        ),
        trial(
            "restart_continues_the_wall_run",
            restart_continues_the_wall_run,
        ),
        trial(
            "wall_contacts_are_tallied_in_the_energy_budget",
            wall_contacts_are_tallied_in_the_energy_budget,
        ),
        trial(
            "cohesive_walls_match_stock_across_ranks_and_restart",
            cohesive_walls_match_stock_across_ranks_and_restart,
        ),
        trial(
            "bad_wall_arguments_are_lammps_errors",
            bad_wall_arguments_are_lammps_errors,
        ),
    ]);
}

/// One run of in.wall_gran with `np` ranks and the given variables, its dump read back.
fn run(exe: &Path, dir: &Path, np: usize, dump: &str, vars: &[(&str, &str)]) -> Dump {
    let mut all: Vec<(&str, &str)> = vars.to_vec();
    all.push(("dump", dump));
    lammps(exe, dir, np, "in.wall_gran", &all);
    read_dump(&dir.join(dump))
}

/// Runs in.wall_gran with `vars` twice, with stock `fix wall/gran` and with
/// `wall/gran/rollslide ... preset lammps` (dumps named after `tag`), and returns both dumps.
fn stock_and_lammps_preset(
    exe: &Path,
    dir: &Path,
    tag: &str,
    vars: &[(&str, &str)],
) -> (Dump, Dump) {
    let mut stock_vars = vars.to_vec();
    stock_vars.push(("fix", "wall/gran"));
    let stock = run(exe, dir, 1, &format!("stock_{tag}.dump"), &stock_vars);
    let mut ours_vars = vars.to_vec();
    ours_vars.extend([("fix", "wall/gran/rollslide"), ("preset", "lammps")]);
    let ours = run(exe, dir, 1, &format!("lammps_{tag}.dump"), &ours_vars);
    (stock, ours)
}

/// Stock `fix wall/gran granular` against `fix wall/gran/rollslide ... preset lammps`, same
/// coefficients, one rank: per-atom forces and torques at every one of the first 100 steps
/// agree to 1e-10 relative (measured: below 5e-14), for four law sets (A: hooke, velocity
/// damping, linear_history, rolling sds, twisting sds; B: hertz/material, viscoelastic damping,
/// mindlin with NULL stiffness, twisting marshall; C: tsuji damping; E: hertz, mass_velocity
/// damping, marshall, limit_damping), on a floor and ceiling pair (`zplane 0.0 12.0`) still,
/// wiggling along the normal (`wiggle z`), along the wall (`wiggle x`) and sheared (`shear x`),
/// and on a single floor (`zplane 0.0 NULL`).
///
/// Walls carry no pair order, so stock LAMMPS makes no history sign change here, and the two
/// codes evaluate the same formulas in other orders (a few ulps per contact). 1e-10: the scene
/// amplifies rounding by less than 1e3 over 100 steps (measured: the worst of 77 law, wall and
/// motion combinations was 3.5e-13; below 1e-9 after 2000 steps), while a rule difference
/// (the torque arm, a clip, a transport condition, a coefficient) moves loads by 1e-4 or more:
/// control, the objective preset against stock, above 1e-4 (measured: above 1).
fn flat_walls_match_stock_fix_wall_gran(exe: &Path) {
    let dir = rundir("walls_stock");
    let mut cases: Vec<(&str, &str, &str)> = Vec::new();
    for law in ["A", "B", "C", "E"] {
        for motion in ["none", "wiggle", "wiggle_t", "shear"] {
            cases.push(("zpair", law, motion));
        }
    }
    cases.push(("zplane", "A", "none"));
    let (mut worst_f, mut worst_t) = (0.0f64, 0.0f64);
    for (wall, law, motion) in cases {
        let common = [
            ("wall", wall),
            ("law", law),
            ("motion", motion),
            ("steps", "100"),
            ("dumpevery", "1"),
        ];
        let (stock, ours) =
            stock_and_lammps_preset(exe, &dir, &format!("{wall}_{law}_{motion}"), &common);
        let (f, t) = worst_relative(&stock, &ours);
        println!("{wall} law {law} {motion}: steps 0-100, worst per-atom relative difference force {f:.2e}, torque {t:.2e}");
        assert!(
            f < 1e-10 && t < 1e-10,
            "{wall} law {law} {motion}: wall/gran/rollslide preset lammps differs from stock (force {f:.2e}, torque {t:.2e})"
        );
        worst_f = worst_f.max(f);
        worst_t = worst_t.max(t);
        if law == "A" && motion == "none" && wall == "zpair" {
            let mut objective_vars = common.to_vec();
            objective_vars.extend([("fix", "wall/gran/rollslide"), ("preset", "objective")]);
            let objective = run(exe, &dir, 1, "objective_zpair_A_none.dump", &objective_vars);
            let (f, t) = worst_relative(&stock, &objective);
            println!("control, objective preset vs stock: force {f:.2e}, torque {t:.2e}");
            assert!(
                f.max(t) > 1e-4,
                "the control did not see the objective preset"
            );
        }
    }
    println!("worst over all cases: force {worst_f:.2e}, torque {worst_t:.2e}");
}

/// The cylinder (`zcylinder 5.0`, spheres inside): stock computes the normal force, Marshall's
/// contact radius and the rolling radius with its curved effective radius `R r_w / (R + r_w)`,
/// `r_w = -2 r_c` inside. The fix gives the library the tangent plane at the contact (a flat
/// wall, rolling radius R) with stock's normal force and contact radius, and, for the `lammps`
/// preset, the rolling spring in stock's units (stiffness and damping times s^2, friction times
/// s, s = R_eff / R, the same law in the variable xi / s): per-atom loads at every one of the
/// first 100 steps agree with stock to 1e-10 (measured below 5e-14; tolerance as for the flat
/// walls) for the laws A, B, C and E, the cylinder still, wiggling along its axis and sliding
/// along it (`shear z`). Not compared: `shear x` (the cylinder turning about its axis), where
/// stock adds each atom's surface velocity to the wall velocity of the atoms after it (its
/// `vwall` accumulates over the atom loop), so its loads are not those of a turning cylinder.
fn zcylinder_lammps_preset_matches_stock(exe: &Path) {
    let dir = rundir("walls_cylinder");
    let (mut worst_f, mut worst_t) = (0.0f64, 0.0f64);
    for law in ["A", "B", "C", "E"] {
        for motion in ["none", "wiggle", "shear_z"] {
            let common = [
                ("wall", "zcylinder"),
                ("law", law),
                ("motion", motion),
                ("vbulk", "3"),
                ("steps", "100"),
                ("dumpevery", "1"),
            ];
            let (stock, ours) =
                stock_and_lammps_preset(exe, &dir, &format!("{law}_{motion}"), &common);
            let (f, t) = worst_relative(&stock, &ours);
            println!("zcylinder law {law} {motion}: steps 0-100, worst per-atom relative difference force {f:.2e}, torque {t:.2e}");
            assert!(
                f < 1e-10 && t < 1e-10,
                "zcylinder law {law} {motion}: preset lammps differs from stock (force {f:.2e}, torque {t:.2e})"
            );
            worst_f = worst_f.max(f);
            worst_t = worst_t.max(t);
        }
    }
    println!("worst over all cases: force {worst_f:.2e}, torque {worst_t:.2e}");
}

/// Every tangential model of stock `fix wall/gran granular`: laws N, L, R, F, Q (hertz/material,
/// viscoelastic damping, rolling sds, twisting marshall, with `linear_nohistory`,
/// `linear_history`, `mindlin_rescale NULL`, `mindlin/force NULL`, `mindlin_rescale/force
/// NULL`; law B, `mindlin NULL`, is in the tests above) and P, T, J, K (hooke, velocity
/// damping, rolling sds, twisting sds, with `linear_nohistory`, `mindlin/force`,
/// `mindlin_rescale`, `mindlin_rescale/force`), on the floor and ceiling still, wiggling along
/// their normal (the contacts load and unload with the wall's motion, so the `_rescale` models
/// scale their springs down) and sheared, and inside the cylinder wiggling along its axis: per
/// atom, every one of the first 100 steps, stock and `preset lammps` agree to 1e-10 relative
/// (the tolerance of the tests above, for their reasons). The NULL stiffness is stock's wall
/// formula `E/4 (2 - nu)(1 + nu)` for every model of the mindlin family. Control: stock's law
/// R differs from law B (mindlin) and law Q from law F (mindlin/force) on the wiggling floor and
/// ceiling by more than 1e-6 of the median load at some step (the rescale acts).
fn every_tangential_model_on_the_walls_matches_stock(exe: &Path) {
    let dir = rundir("walls_tangential");
    let (mut worst_f, mut worst_t) = (0.0f64, 0.0f64);
    let mut wiggling = std::collections::BTreeMap::new();
    for law in ["N", "L", "R", "F", "Q", "P", "T", "J", "K", "B"] {
        let (mut law_f, mut law_t) = (0.0f64, 0.0f64);
        for (wall, motion) in [
            ("zpair", "none"),
            ("zpair", "wiggle"),
            ("zpair", "shear"),
            ("zcylinder", "wiggle"),
        ] {
            if law == "B" && (motion != "wiggle" || wall != "zpair") {
                continue; // law B (mindlin): only the control's run
            }
            let vbulk = if wall == "zcylinder" { "3" } else { "0" };
            let common = [
                ("wall", wall),
                ("law", law),
                ("motion", motion),
                ("vbulk", vbulk),
                ("steps", "100"),
                ("dumpevery", "1"),
            ];
            let (stock, ours) =
                stock_and_lammps_preset(exe, &dir, &format!("{wall}_{law}_{motion}"), &common);
            let (f, t) = worst_relative(&stock, &ours);
            assert!(
                f < 1e-10 && t < 1e-10,
                "{wall} law {law} {motion}: wall/gran/rollslide preset lammps differs from stock (force {f:.2e}, torque {t:.2e})"
            );
            law_f = law_f.max(f);
            law_t = law_t.max(t);
            if wall == "zpair" && motion == "wiggle" {
                wiggling.insert(law, stock);
            }
        }
        let scenes = if law == "B" {
            "zpair wiggling"
        } else {
            "zpair still, wiggling, sheared, zcylinder wiggling"
        };
        println!(
            "law {law}: {scenes}, steps 0-100: worst per-atom relative difference force {law_f:.2e}, torque {law_t:.2e}"
        );
        worst_f = worst_f.max(law_f);
        worst_t = worst_t.max(law_t);
    }
    println!("worst over all cases: force {worst_f:.2e}, torque {worst_t:.2e}");
    for (rescaled, plain) in [("R", "B"), ("Q", "F")] {
        let (a, b) = (&wiggling[rescaled], &wiggling[plain]);
        let worst = a
            .iter()
            .map(|(step, rows)| {
                let (f, t) = compare(rows, &b[step]);
                f.over_median.max(t.over_median)
            })
            .fold(0.0, f64::max);
        println!(
            "control, stock law {rescaled} (rescaled) vs law {plain}, wiggling floor and ceiling: {worst:.2e} of the median load at worst"
        );
        assert!(worst > 1e-6, "law {rescaled}: the rescale changed nothing");
    }
}

/// Every normal x tangential combination of stock `fix wall/gran granular` (the 30 of
/// tests/common/granular.rs, each with one damping and one twisting model, rolling sds, at E
/// 1e5, coh 20, mu 0.4), each on one of the walls and motions of the tests above in turn
/// (floor and ceiling still, wiggling along their normal, sheared; the floor wiggling along the
/// wall; the cylinder wiggling and sliding along its axis; each normal model on all six, each
/// tangential model on five; not the turning cylinder, where stock adds its `vwall` over the
/// atoms, see `zcylinder_lammps_preset_matches_stock`): per atom, every one of the first
/// 100 steps, stock and `preset lammps` agree to 1e-10 of the mean load (the tests above
/// bound each atom's difference by 1e-10 of its own load, floored at 1e-3 of the median; that
/// is printed too: up to 2.1e-10, for an atom whose torque is near that floor, with
/// mindlin_rescale/force on the cylinder sliding along its axis, where the difference is 2e-11
/// of the mean load). DMT: stock's wall reads the same uninitialised cohesion as its
/// pair style (lammps_pair's matrix test), so its rows are compared with `fix
/// wall/gran/dmt_reference`, stock's fix compiled from LAMMPS' source with DMT's cohesion set.
fn every_normal_and_tangential_combination_on_the_walls_matches_stock(exe: &Path) {
    let dir = rundir("walls_matrix");
    let scenes = [
        ("zpair", "none"),
        ("zpair", "wiggle"),
        ("zpair", "shear"),
        ("zplane", "wiggle_t"),
        ("zcylinder", "wiggle"),
        ("zcylinder", "shear_z"),
    ];
    let scale = Scale {
        young: 1e5,
        cohesion: 20.0,
        friction: 0.4,
    };
    let laws = normal_by_tangential();
    let cases: Vec<_> = laws
        .iter()
        .enumerate()
        .map(|(k, law)| {
            let (i, j) = (k / TANGENTIAL.len(), k % TANGENTIAL.len());
            (*law, scenes[(i + j) % scenes.len()])
        })
        .collect();
    let results = parallel_map(&cases, 2, |(law, (wall, motion))| {
        let coeffs = law.coeffs(&scale);
        let vbulk = if *wall == "zcylinder" { "3" } else { "0" };
        let tag = format!("{wall}_{motion}_{}", law.tag());
        let stock = law.stock_styles().1;
        let go = |fix: &str, preset: &str, name: &str| {
            run(
                exe,
                &dir,
                1,
                &format!("{name}_{tag}.dump"),
                &[
                    ("wall", wall),
                    ("law", "matrix"),
                    ("coeffs", &coeffs),
                    ("motion", motion),
                    ("vbulk", vbulk),
                    ("steps", "100"),
                    ("dumpevery", "1"),
                    ("fix", fix),
                    ("preset", preset),
                ],
            )
        };
        let (a, b) = (
            go(stock, "lammps", "stock"),
            go("wall/gran/rollslide", "lammps", "lammps"),
        );
        let (f, t) = worst_relative(&a, &b);
        // The largest difference over the mean load (force, torque), at every step.
        let over_mean = a
            .iter()
            .map(|(step, rows)| {
                let (f, t) = worst_over_mean(rows, &b[step]);
                f.max(t)
            })
            .fold(0.0, f64::max);
        (f, t, over_mean)
    });
    let mut failures = Vec::new();
    for ((law, (wall, motion)), (f, t, over_mean)) in cases.iter().zip(results) {
        println!(
            "{:<58} {wall} {motion}: steps 0-100, worst per-atom relative difference force {f:.2e}, torque {t:.2e}; {over_mean:.2e} of the mean load{}",
            law.name(),
            law.stock_note()
        );
        if over_mean >= 1e-10 {
            failures.push(law.name());
        }
    }
    assert!(
        failures.is_empty(),
        "fix wall/gran/rollslide preset lammps differs from stock for {failures:?}"
    );
}

/// Ranks and restart for the tangential models added after those tests (laws N, R, F, Q):
/// the floor and ceiling wiggling along their normal while the spheres move along x through 2
/// subdomains (as below), `lammps` preset; `-np 2` newton on with sorting against one rank at
/// step 3000 to 1e-12 of the median load, and a restart at step 1500 continued to 3000 in a new
/// process against the same two runs in one process to 1e-12 (the tolerances below, for their
/// reasons: equal to the bit unless a history, with the previous step's stiffness that the
/// `_rescale` models keep in it, is lost or garbled).
fn tangential_models_on_the_walls_across_ranks_and_restart(exe: &Path) {
    let dir = rundir("walls_tangential_mpi");
    for law in ["N", "R", "F", "Q"] {
        let base = [
            ("wall", "zpair"),
            ("law", law),
            ("motion", "wiggle"),
            ("preset", "lammps"),
            ("vbulk", "10"),
            ("steps", "3000"),
        ];
        let go = |np: usize, name: &str, extra: &[(&str, &str)]| {
            let mut vars = base.to_vec();
            vars.extend_from_slice(extra);
            run(exe, &dir, np, &format!("{name}_{law}.dump"), &vars)
        };
        let one = go(1, "np1", &[("dumpevery", "3000")]);
        let two = go(
            2,
            "np2",
            &[("dumpevery", "3000"), ("newton", "on"), ("sort", "10")],
        );
        assert_loads_agree(
            &one[&3000],
            &two[&3000],
            1e-12,
            &format!("law {law}: np 2 newton on sort 10 vs np 1, step 3000"),
        );
        let restart = format!("tangential_{law}.restart");
        let mpi = [("newton", "on"), ("sort", "10"), ("dumpevery", "1500")];
        let mut split = mpi.to_vec();
        split.push(("split", "1500"));
        let reference = go(2, "two_runs", &split);
        let mut first = mpi.to_vec();
        first.extend([("restart_at", "1500"), ("restart_file", restart.as_str())]);
        go(2, "first", &first);
        let mut resumed_vars = mpi.to_vec();
        resumed_vars.extend([("from_restart", "1"), ("restart_file", restart.as_str())]);
        let resumed = go(2, "resumed", &resumed_vars);
        assert_loads_agree(
            &reference[&3000],
            &resumed[&3000],
            1e-12,
            &format!("law {law}: restarted at 1500 vs two runs in one process, step 3000"),
        );
    }
}

/// Ranks, newton and sorting: the spheres move as a whole along the walls (at speed 10 along x
/// on the floor and ceiling, split between 2 ranks at x = 12 and across the periodic boundary;
/// at about 8 around the cylinder, split at x = 0) for 3000 steps, so that many atoms change
/// rank with their wall contacts live. `-np 2` with newton on and off, and one rank with atom
/// sorting every 10 steps, give the per-atom loads of one rank without sorting at step 3000 to
/// 1e-12 of the median load, for the objective preset (floor and ceiling wiggling along x; a
/// turning cylinder with law E) and the `lammps` preset (sheared floor and ceiling, law B).
///
/// 1e-12: each atom's loads come from its own wall contact and its body force, computed in the
/// same order whatever rank owns it, so the runs are equal to the bit (measured: 0) unless a
/// history is lost, garbled or given to another atom on the way; a lost history changes the
/// loads at O(1) of the median load (the control of `restart_continues_the_wall_run`).
fn ranks_newton_and_sorting_carry_the_wall_histories(exe: &Path) {
    let dir = rundir("walls_mpi");
    for (wall, law, motion, preset, vbulk) in [
        ("zpair", "A", "wiggle_t", "objective", "10"),
        ("zcylinder", "E", "shear", "objective", "8"),
        ("zpair", "B", "shear", "lammps", "10"),
    ] {
        let go = |np: usize, newton: &str, sort: &str| {
            run(
                exe,
                &dir,
                np,
                &format!("{wall}_{law}_{preset}_np{np}_{newton}_sort{sort}.dump"),
                &[
                    ("wall", wall),
                    ("law", law),
                    ("motion", motion),
                    ("preset", preset),
                    ("vbulk", vbulk),
                    ("newton", newton),
                    ("sort", sort),
                    ("steps", "3000"),
                    ("dumpevery", "3000"),
                ],
            )
        };
        let reference = go(1, "off", "0");
        let (start, end) = (&reference[&0], &reference[&3000]);
        // Atoms on the other rank's side at the end than at the start (columns: id fx fy fz
        // tqx tqy tqz x y z), touching their wall then (a wall torque).
        let side = |r: &Vec<f64>| {
            if wall == "zcylinder" {
                r[7] < 0.0
            } else {
                r[7] < 12.0
            }
        };
        let migrated = start
            .iter()
            .zip(end)
            .filter(|(a, b)| side(a) != side(b) && common::lammps::norm(&b[4..7]) > 0.0)
            .count();
        println!("{wall} law {law} {motion} {preset}: {migrated} of {} atoms changed subdomain and touch their wall at step 3000", end.len());
        assert!(
            migrated >= 10,
            "only {migrated} atoms changed subdomain with their contacts"
        );
        for (np, newton, sort) in [
            (2, "on", "0"),
            (2, "off", "0"),
            (1, "on", "10"),
            (2, "on", "10"),
        ] {
            let other = go(np, newton, sort);
            assert_loads_agree(
                end,
                &other[&3000],
                1e-12,
                &format!(
                    "{wall} law {law} {preset}: np {np} newton {newton} sort {sort}, step 3000"
                ),
            );
        }
    }
}

/// write_restart / read_restart: 1500 steps, a restart file, a new process continuing to 3000
/// (2 ranks, newton on, sorting every 10 steps, the spheres moving through the subdomains).
/// The file carries each atom's wall history and the wiggle's time origin (a global restart
/// value: stock fix wall/gran restarts its wiggle from the restart step).
///
/// Objective preset, law D (no damping), the floor and ceiling wiggling along their normal, and
/// the turning cylinder: the restarted run's loads at step 3000 are the uninterrupted run's to
/// 1e-10 of the median load (measured 0: the setup pass of the restarted run gives the loads of
/// the stored springs, which without damping are the last step's).
///
/// `lammps` preset, law A (damped): compared with the same two runs made in one process (`run
/// 1500` twice), to 1e-12 of the median load (measured 0). Not with the uninterrupted run: a
/// run's setup pass recomputes the damped loads with the full-step velocities (as in stock
/// LAMMPS; measured 1e-6 of the median load at step 3000), see docs/lammps.md.
///
/// Control: the restarted run with the wall fix under another ID (so that it finds neither
/// histories nor time origin in the file) differs by more than 1e-2 of the median load.
fn restart_continues_the_wall_run(exe: &Path) {
    let dir = rundir("walls_restart");
    for (wall, law, preset, motion, vbulk) in [
        ("zpair", "D", "objective", "wiggle", "10"),
        ("zcylinder", "D", "objective", "shear", "8"),
        ("zpair", "A", "lammps", "wiggle", "10"),
    ] {
        let tag = format!("{wall}_{law}_{preset}_{motion}");
        let restart = format!("{tag}.restart");
        let go = |extra: &[(&str, &str)], name: &str| {
            let mut vars = vec![
                ("wall", wall),
                ("law", law),
                ("preset", preset),
                ("motion", motion),
                ("vbulk", vbulk),
                ("newton", "on"),
                ("sort", "10"),
                ("steps", "3000"),
                ("dumpevery", "1500"),
            ];
            vars.extend_from_slice(extra);
            run(exe, &dir, 2, &format!("{name}_{tag}.dump"), &vars)
        };
        let reference = if preset == "objective" {
            go(&[], "uninterrupted")
        } else {
            go(&[("split", "1500")], "two_runs")
        };
        go(
            &[("restart_at", "1500"), ("restart_file", &restart)],
            "first",
        );
        let resumed = go(
            &[("from_restart", "1"), ("restart_file", &restart)],
            "resumed",
        );
        let bound = if preset == "objective" { 1e-10 } else { 1e-12 };
        assert_loads_agree(
            &reference[&3000],
            &resumed[&3000],
            bound,
            &format!("{tag}: restarted at 1500, step 3000"),
        );
        let lost = go(
            &[
                ("from_restart", "1"),
                ("restart_file", &restart),
                ("fixid", "other"),
            ],
            "control",
        );
        let (f, t) = compare(&resumed[&3000], &lost[&3000]);
        println!(
            "   control, the wall fix under another ID: force {:.2e}, torque {:.2e} of the median load",
            f.over_median, t.over_median
        );
        assert!(
            f.over_median.max(t.over_median) > 1e-2,
            "{tag}: the control changed nothing"
        );
    }
}

/// With `compute rollslide/energy`, the wall fix tallies its contacts (the `wall` columns): the
/// budget `dE_kin + dE_rot + dE_pot + dE_elastic + E_dissipated - E_transport -
/// E_stiffness_change` (the last 0 for these linear laws) over 0.4 time
/// units (E_pot: the gravity's, or the radial push's) closes to the time-integration error,
/// which falls in proportion to dt:
/// - the normal force alone (`tangential linear_history 0 0 0`, the fix's own terms: the normal
///   dashpot's dissipation and the normal spring's energy), floor and ceiling: residual below
///   1e-2 of the dissipated energy at dt = 2e-4 (measured 3.5e-3) and four times smaller at
///   dt = 5e-5 (bound: 0.35 times);
/// - the whole law A on the cylinder (sliding, rolling and twisting from the library, fast
///   slip: `k v dt` near `mu f_n`): residual below 1e-3 of the dissipated energy at dt = 2e-4
///   (measured 4.0e-5: 0.0027 of 67.7) and four times smaller at dt = 5e-5 (bound 0.35 times).
///
/// Then ranks: the floor and ceiling moving along x through 2 subdomains (`-np 2`, newton on,
/// sorting) give the one-rank run's dissipated and elastic energies to 1e-12 (measured 0: each
/// contact is tallied once, by its atom's owner, and its springs' last energies move with it).
fn wall_contacts_are_tallied_in_the_energy_budget(exe: &Path) {
    let dir = rundir("walls_energy");
    // Thermo columns with energy 1: step ke rke mean|torque| epot transport dissipated elastic
    // stiffness-change.
    let budget = |rows: &[Vec<f64>]| {
        let e = |r: &[f64]| r[1] + r[2] + r[4] + r[7];
        let (a, b) = (&rows[0], rows.last().unwrap());
        let dissipated = b[6] - a[6];
        (
            e(b) - e(a) + dissipated - (b[5] - a[5]) - (b[8] - a[8]),
            dissipated,
        )
    };
    let go = |np: usize, dt: &str, extra: &[(&str, &str)]| {
        let steps = format!("{}", (0.4 / dt.parse::<f64>().unwrap()).round() as u64);
        let mut vars = vec![
            ("energy", "1"),
            ("dt", dt),
            ("steps", steps.as_str()),
            ("thermo", steps.as_str()),
        ];
        vars.extend_from_slice(extra);
        thermo(&lammps(exe, &dir, np, "in.wall_gran", &vars))
    };
    let normal_only = [
        ("wall", "zpair"),
        ("custom", "1"),
        (
            "fixargs",
            "granular hooke 2e4 20 damping velocity tangential linear_history 0 0 0 zplane 0.0 12.0 preset objective",
        ),
    ];
    let (r1, d1) = budget(&go(1, "2e-4", &normal_only));
    let (r2, d2) = budget(&go(1, "5e-5", &normal_only));
    println!("normal force only: residual {r1:.3e} of {d1:.4} dissipated at dt 2e-4, {r2:.3e} of {d2:.4} at 5e-5");
    assert!(
        d1 > 0.1 && r1.abs() < 1e-2 * d1,
        "normal force only: residual {r1:.3e}"
    );
    assert!(
        r2.abs() < 0.35 * r1.abs(),
        "normal force only: residual does not fall with dt"
    );
    let law_a = [("wall", "zcylinder"), ("law", "A"), ("vbulk", "3")];
    let (r1, d1) = budget(&go(1, "2e-4", &law_a));
    let (r2, d2) = budget(&go(1, "5e-5", &law_a));
    println!("law A, cylinder: residual {r1:.4} of {d1:.4} dissipated at dt 2e-4, {r2:.4} of {d2:.4} at 5e-5");
    assert!(
        d1 > 1.0 && r1.abs() < 1e-3 * d1,
        "law A: residual {r1:.3e} of {d1:.3e}"
    );
    assert!(
        r2.abs() < 0.35 * r1.abs(),
        "law A: residual does not fall with dt"
    );

    let moving = [
        ("wall", "zpair"),
        ("law", "A"),
        ("motion", "wiggle_t"),
        ("vbulk", "10"),
    ];
    let one = go(1, "2e-4", &moving);
    let mut two_vars = moving.to_vec();
    two_vars.extend([("newton", "on"), ("sort", "10")]);
    let two = go(2, "2e-4", &two_vars);
    let (a, b) = (one.last().unwrap(), two.last().unwrap());
    for (k, name) in [
        (5, "transport"),
        (6, "dissipated"),
        (7, "elastic"),
        (8, "stiffness change"),
    ] {
        let d = (a[k] - b[k]).abs();
        println!("np 2 vs np 1, {name}: {:.6e} vs {:.6e}", a[k], b[k]);
        assert!(
            d <= 1e-12 * a[6].abs().max(1.0),
            "np 2 {name} differs by {d:.2e}"
        );
    }
}

/// Bad arguments are LAMMPS errors with a message naming what is wrong, never a crash: an
/// unknown or unsupported wall style, a cylinder radius that is not positive, missing
/// coefficients (`linear_nohistory`'s), a NULL stiffness of the mindlin family without
/// hertz/material (naming the model), an unknown tangential model, an unknown keyword, the interaction styles and keywords outside the subset,
/// coefficients the library refuses (its message), and a contact the library refuses (an atom
/// with velocity 1e308, whose loads overflow), which names the atom, the fix and the wall, on
/// one rank and on the second of two.
fn bad_wall_arguments_are_lammps_errors(exe: &Path) {
    let dir = rundir("walls_bad");
    let ok = "hooke 1e4 0 tangential linear_history 1e4 0 0.5";
    let g = |rest: &str| format!("granular {ok} {rest}");
    let cases: Vec<(usize, String, &str, &str, &str)> = vec![
        // (ranks, fix arguments, wall scene, bad atom, expected text)
        (1, g("xcylinder 5.0"), "zplane", "0", "wall style 'xcylinder' is not supported"),
        (1, g("region box"), "zplane", "0", "wall style 'region' is not supported"),
        (1, g("zcylinder -5.0"), "zcylinder", "0", "zcylinder radius must be > 0 (got -5.0)"),
        (1, g("zcylinder"), "zcylinder", "0", "zcylinder needs its radius"),
        (
            1,
            "granular hooke 1e4 tangential linear_history 1e4 0 0.5 zplane 0.0 NULL".into(),
            "zplane",
            "0",
            "instead of 'tangential'",
        ),
        (
            1,
            "granular hooke 1e4 0 zplane 0.0 NULL".into(),
            "zplane",
            "0",
            "a normal model and a tangential model are required",
        ),
        (1, g("zplane 0.0"), "zplane", "0", "zplane needs lo and hi"),
        (1, g(""), "zplane", "0", "a wall style (xplane, yplane, zplane or zcylinder) must follow"),
        (1, g("zplane 0.0 NULL fancy 1"), "zplane", "0", "unknown keyword 'fancy'"),
        (1, g("zplane 0.0 NULL contacts"), "zplane", "0", "keyword 'contacts' is not supported"),
        (1, g("zplane 0.0 NULL preset yade"), "zplane", "0", "unknown preset 'yade'"),
        (1, g("cutoff 1.0 zplane 0.0 NULL"), "zplane", "0", "keyword 'cutoff' is not supported"),
        (
            1,
            "granular hertz/fancy 1e4 0 0.3 1 tangential linear_history 1e4 0 0.5 zplane 0.0 NULL".into(),
            "zplane",
            "0",
            "keyword 'hertz/fancy' is not supported",
        ),
        (
            1,
            "granular jkr 1e5 0 0.3 tangential linear_history 1e4 0 0.5 zplane 0.0 NULL".into(),
            "zplane",
            "0",
            "'jkr' needs E, eta_n, nu and coh (got 'tangential' for coh)",
        ),
        (
            1,
            "granular jkr 1e5 0 0.3 1 tangential linear_history 1e4 0 0.5 limit_damping zplane 0.0 NULL".into(),
            "zplane",
            "0",
            "limit_damping cannot be used with the jkr normal model",
        ),
        (
            1,
            "granular dmt 1e5 0 0.3 1 tangential linear_history 1e4 0 0.5 limit_damping zplane 0.0 NULL".into(),
            "zplane",
            "0",
            "limit_damping cannot be used with the dmt normal model",
        ),
        (
            1,
            "hooke/history 1e4 NULL 0 NULL 0.5 0 zplane 0.0 NULL".into(),
            "zplane",
            "0",
            "interaction style 'hooke/history' is not supported",
        ),
        (
            1,
            g("zplane 0.0 NULL wiggle z 0.1 1.0 shear x 1.0"),
            "zplane",
            "0",
            "wiggle and shear cannot be used together",
        ),
        (1, g("zplane 0.0 NULL shear z 1.0"), "zplane", "0", "shear must be along the wall"),
        (1, g("xplane 0.0 10.0"), "zplane", "0", "xplane wall in a periodic dimension"),
        (
            1,
            "granular hooke 1e4 0 tangential mindlin_rescale NULL 0 0.5 zplane 0.0 NULL".into(),
            "zplane",
            "0",
            "tangential mindlin_rescale NULL (the stiffness from the material) needs the hertz/material normal model",
        ),
        (
            1,
            "granular hertz 1e4 0 tangential mindlin_rescale/force NULL 0 0.5 zplane 0.0 NULL".into(),
            "zplane",
            "0",
            "tangential mindlin_rescale/force NULL (the stiffness from the material) needs the hertz/material normal model",
        ),
        (
            1,
            "granular hooke 1e4 0 tangential linear_nohistory 0.5".into(),
            "zplane",
            "0",
            "not enough parameters for 'linear_nohistory'",
        ),
        (
            1,
            "granular hooke 1e4 0 tangential mindlin/force NULL 0 0.5 zplane 0.0 NULL".into(),
            "zplane",
            "0",
            "tangential mindlin/force NULL (the stiffness from the material) needs the hertz/material normal model",
        ),
        (
            1,
            "granular hooke 1e4 0 tangential mindlin_fancy 1e4 0 0.5 zplane 0.0 NULL".into(),
            "zplane",
            "0",
            "tangential model 'mindlin_fancy' is not supported",
        ),
        (
            1,
            format!("granular {ok} rolling sds -1 1 1 zplane 0.0 NULL"),
            "zplane",
            "0",
            "rolling stiffness = -1",
        ),
        (
            1,
            g("zplane 0.0 NULL"),
            "zplane",
            "5",
            "fix walls wall/gran/rollslide: rsl_batch_step_walls failed for atom 5 and the wall zplane lo: non-finite",
        ),
        (
            2,
            g("zplane 0.0 NULL preset lammps"),
            "zplane",
            "31",
            "failed for atom 31 and the wall zplane lo: non-finite",
        ),
    ];
    for (np, args, wall, bad, want) in &cases {
        let args = [
            "-var", "steps", "2", "-var", "wall", wall, "-var", "badatom", bad, "-var", "custom",
            "1", "-var", "fixargs", args,
        ];
        let error = lammps_error(exe, &dir, *np, "in.wall_gran", &args);
        println!("{error}");
        assert!(error.contains(want), "expected '{want}' in: {error}");
    }
}

/// The JKR necks of an in.wall_gran floor run (zplane 0.0 NULL, gravity 10, density 1; atom k's
/// diameter 0.8 + 0.4 frac(0.618... k)): the atom-steps with the atom apart from the floor
/// (z > its radius) and a wall force on it (its force is not its weight alone), and the atoms.
fn wall_necks(dump: &Dump) -> (usize, usize) {
    let mut steps = 0;
    let mut atoms = std::collections::BTreeSet::new();
    for rows in dump.values() {
        for r in rows {
            let id = r[0];
            let u = (id * 0.6180339887498949).fract();
            let radius = 0.5 * (0.8 + 0.4 * u);
            let weight = 10.0 * 4.0 / 3.0 * std::f64::consts::PI * radius.powi(3);
            if r[9] > radius && (r[3] + weight).abs() > 1e-9 * weight {
                steps += 1;
                atoms.insert(id as u64);
            }
        }
    }
    (steps, atoms.len())
}

/// The cohesive normal models on a wall: stock `fix wall/gran granular` against `fix
/// wall/gran/rollslide ... preset lammps`, one rank, in.wall_gran's floor (`zplane 0.0 NULL`,
/// 36 spheres landing, bouncing and leaving), 1000 steps, per-atom forces and torques at every
/// step to 1e-10 relative: JKR (law W: mindlin NULL, X: linear_history; viscoelastic damping,
/// rolling sds, twisting marshall; coh 1), whose contacts hold beyond touching until the
/// pull-off distance of stock's wall (computed from the atom's radius as a = (9 pi coh R /
/// (4 E))^(1/3), its formula) with a per-atom touch flag, the contact radius JKR's a (Mindlin,
/// Marshall) and the limits LAMMPS' |F_ne + 2 F_pulloff| (per contact: these contacts step one
/// at a time); necks beyond touching counted from the dump (atoms above the floor with a wall
/// force), asserted > 0. DMT (law V: linear_nohistory with mu_s 1e3, no rolling or twisting:
/// stock's wall, as its pair style, limits DMT's friction with an uninitialised cohesion).
/// Control: stock with coh 0 differs by more than 1e-3 of the median load somewhere in the run.
/// Law W on the cylinder too (stock's cylinder holds no neck beyond touching). Then law W across
/// ranks (np 2, newton on, sorting every 10 steps, against one rank) and
/// through a restart at step 500 (against the two runs in one process), loads at step 1000 to
/// 1e-12 of the median load: the touch flag (the atom's wall side) moves with the atom and into
/// the restart file.
fn cohesive_walls_match_stock_across_ranks_and_restart(exe: &Path) {
    let dir = rundir("walls_cohesive");
    for (law, what, cmu) in [
        ("W", "jkr, mindlin, rolling sds, marshall", "0.4"),
        ("X", "jkr, linear_history, rolling sds, marshall", "0.4"),
        ("V", "dmt, linear_nohistory mu_s 1e3", "1e3"),
    ] {
        let vars = [
            ("wall", "zplane"),
            ("law", law),
            ("coh", "1"),
            ("cmu", cmu),
            ("steps", "1000"),
            ("dumpevery", "1"),
        ];
        let (stock, ours) = stock_and_lammps_preset(exe, &dir, &format!("cohesive_{law}"), &vars);
        let (f, t) = worst_relative(&stock, &ours);
        let mut control_vars = vars.to_vec();
        control_vars[2] = ("coh", "0");
        control_vars.push(("fix", "wall/gran"));
        let control = run(
            exe,
            &dir,
            1,
            &format!("stock_coh0_{law}.dump"),
            &control_vars,
        );
        let control_worst = stock
            .iter()
            .map(|(step, rows)| {
                let (cf, ct) = compare(rows, &control[step]);
                cf.over_median.max(ct.over_median)
            })
            .fold(0.0f64, f64::max);
        let (neck_steps, neck_atoms) = wall_necks(&ours);
        println!(
            "law {law} ({what}), coh 1: steps 0-1000, worst per-atom relative difference force {f:.2e}, torque {t:.2e}; control coh 0: {control_worst:.2e} of the median load; necks beyond touching: {neck_atoms} atoms, {neck_steps} atom-steps"
        );
        assert!(
            f < 1e-10 && t < 1e-10,
            "law {law}: wall/gran/rollslide preset lammps differs from stock (force {f:.2e}, torque {t:.2e})"
        );
        assert!(
            control_worst > 1e-3,
            "law {law}: the cohesion changed nothing"
        );
        if law != "V" {
            assert!(neck_steps > 0, "law {law}: no neck beyond touching");
        }
    }
    // The cylinder (stock's finds no contact beyond touching; its pull-off distance, negative
    // for the larger spheres, delays their contacts).
    let (stock, ours) = stock_and_lammps_preset(
        exe,
        &dir,
        "cohesive_W_zcylinder",
        &[
            ("wall", "zcylinder"),
            ("law", "W"),
            ("coh", "1"),
            ("steps", "1000"),
            ("dumpevery", "1"),
        ],
    );
    let (f, t) = worst_relative(&stock, &ours);
    println!("law W on the cylinder, coh 1: steps 0-1000, worst per-atom relative difference force {f:.2e}, torque {t:.2e}");
    assert!(
        f < 1e-10 && t < 1e-10,
        "law W on the cylinder: wall/gran/rollslide preset lammps differs from stock (force {f:.2e}, torque {t:.2e})"
    );
    let base = [
        ("wall", "zplane"),
        ("law", "W"),
        ("coh", "1"),
        ("preset", "lammps"),
        ("vbulk", "10"),
        ("steps", "1000"),
    ];
    let go = |np: usize, name: &str, extra: &[(&str, &str)]| {
        let mut vars = base.to_vec();
        vars.extend_from_slice(extra);
        run(exe, &dir, np, &format!("{name}_W.dump"), &vars)
    };
    let one = go(1, "np1", &[("dumpevery", "1000")]);
    let two = go(
        2,
        "np2",
        &[("dumpevery", "1000"), ("newton", "on"), ("sort", "10")],
    );
    let (neck_steps, _) = wall_necks(&go(1, "np1_every", &[("dumpevery", "1")]));
    println!("law W, vbulk 10: necks beyond touching over the run: {neck_steps} atom-steps");
    assert!(neck_steps > 0, "law W, vbulk 10: no neck beyond touching");
    assert_loads_agree(
        &one[&1000],
        &two[&1000],
        1e-12,
        "law W (jkr): np 2 newton on sort 10 vs np 1, step 1000",
    );
    let mpi = [("newton", "on"), ("sort", "10"), ("dumpevery", "500")];
    let mut split = mpi.to_vec();
    split.push(("split", "500"));
    let reference = go(2, "two_runs", &split);
    let mut first = mpi.to_vec();
    first.extend([
        ("restart_at", "500"),
        ("restart_file", "cohesive_W.restart"),
    ]);
    go(2, "first", &first);
    let mut resumed_vars = mpi.to_vec();
    resumed_vars.extend([
        ("from_restart", "1"),
        ("restart_file", "cohesive_W.restart"),
    ]);
    let resumed = go(2, "resumed", &resumed_vars);
    assert_loads_agree(
        &reference[&1000],
        &resumed[&1000],
        1e-12,
        "law W (jkr): restarted at 500 vs two runs in one process, step 1000",
    );
}
