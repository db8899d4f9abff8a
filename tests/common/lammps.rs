//! The LAMMPS tests' shared part (`tests/lammps_*.rs`): building `lmp_rollslide` once per test
//! process, running it, reading its dumps and logs, and a libtest-mimic runner that reports
//! every test as **ignored, with the reason**, when what it needs is not installed.
//!
//! What they need: LAMMPS (`lmp`, `liblammps-dev`), MPI (`mpirun`, `mpicxx`: `mpi-default-dev
//! openmpi-bin`), `cmake`, and LAMMPS' own source tarball of the installed version (for
//! `neigh_request.h`, which liblammps-dev lacks): `ROLLSLIDE_LAMMPS_SOURCE_TARBALL=<path>`, or
//! Debian's `lammps_*.orig.tar.xz` in `target/tmp/lammps/lammps-source/`, where
//! `apt-get source --download-only lammps` puts it when run there (with deb-src entries in the
//! apt sources; `.ci/run` does both).

use super::linking::{run, shared_cmake_cargo_dir};
use libtest_mimic::{Arguments, Completion, Trial};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

pub fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// The LAMMPS tests' working directory (builds, runs).
pub fn work() -> PathBuf {
    Path::new(env!("CARGO_TARGET_TMPDIR")).join("lammps")
}

pub fn inputs() -> PathBuf {
    root().join("examples/lammps/inputs")
}

fn works(program: &str, arg: &str) -> bool {
    Command::new(program)
        .arg(arg)
        .output()
        .map(|o| o.status.success())
        .unwrap_or(false)
}

/// Debian's source tarball of the installed LAMMPS: the environment's, or the one in the cache.
fn source_tarball() -> Option<PathBuf> {
    if let Some(t) = std::env::var_os("ROLLSLIDE_LAMMPS_SOURCE_TARBALL") {
        return Some(PathBuf::from(t));
    }
    let cache = work().join("lammps-source");
    std::fs::read_dir(&cache)
        .ok()?
        .flatten()
        .map(|e| e.path())
        .find(|p| {
            p.file_name()
                .and_then(|n| n.to_str())
                .is_some_and(|n| n.starts_with("lammps_") && n.ends_with(".orig.tar.xz"))
        })
}

/// What is missing for the LAMMPS tests, empty if nothing.
pub fn missing() -> Vec<&'static str> {
    let mut miss = Vec::new();
    if !works("lmp", "-h") {
        miss.push("lmp (apt-get install lammps)");
    }
    if !Path::new("/usr/include/lammps/pair.h").exists()
        || !Path::new("/usr/lib/x86_64-linux-gnu/cmake/LAMMPS/LAMMPSConfig.cmake").exists()
    {
        miss.push("liblammps-dev");
    }
    if !works("mpirun", "--version") || !works("mpicxx", "--version") {
        miss.push("mpirun and mpicxx (apt-get install mpi-default-dev openmpi-bin)");
    }
    if !works("cmake", "--version") {
        miss.push("cmake");
    }
    if source_tarball().is_none() {
        miss.push(
            "LAMMPS' source tarball for neigh_request.h (with deb-src apt entries: `cd \
             target/tmp/lammps/lammps-source && apt-get source --download-only lammps`, or \
             ROLLSLIDE_LAMMPS_SOURCE_TARBALL=<path>)",
        );
    }
    miss
}

/// `lmp_rollslide`, built once per test process, or why it cannot be.
fn binary() -> &'static Result<PathBuf, String> {
    static BINARY: OnceLock<Result<PathBuf, String>> = OnceLock::new();
    BINARY.get_or_init(|| {
        let miss = missing();
        if !miss.is_empty() {
            return Err(format!("needs {}", miss.join(", ")));
        }
        exclusive();
        Ok(build())
    })
}

/// `cargo test` and `cargo test --release`, and the `lammps_*` test programs, share
/// `target/tmp/lammps` (the build, the run directories): a second test process waits here until
/// the first has exited (the lock is released when the process ends).
fn exclusive() {
    static LOCK: OnceLock<std::fs::File> = OnceLock::new();
    LOCK.get_or_init(|| {
        std::fs::create_dir_all(work()).unwrap();
        let file = std::fs::File::create(work().join("lock")).unwrap();
        file.lock().expect("cannot lock target/tmp/lammps/lock");
        file
    });
}

/// Installs rollslide with the repository's CMake build into a prefix, then builds
/// examples/lammps against it (incremental on later runs).
fn build() -> PathBuf {
    let w = work();
    let (rsl_build, prefix, build) = (w.join("rsl-build"), w.join("prefix"), w.join("build"));
    run(Command::new("cmake")
        .arg("-S")
        .arg(root())
        .arg("-B")
        .arg(&rsl_build)
        .arg(format!("-DCMAKE_INSTALL_PREFIX={}", prefix.display()))
        .arg(shared_cmake_cargo_dir())
        .arg("-DROLLSLIDE_BUILD_TESTS=OFF"));
    run(Command::new("cmake")
        .args(["--build"])
        .arg(&rsl_build)
        .args(["-j2"]));
    run(Command::new("cmake").arg("--install").arg(&rsl_build));
    let tarball = source_tarball().expect("checked by missing()");
    run(Command::new("cmake")
        .arg("-S")
        .arg(root().join("examples/lammps"))
        .arg("-B")
        .arg(&build)
        .arg(format!("-DCMAKE_PREFIX_PATH={}", prefix.display()))
        .arg(format!("-DLAMMPS_SOURCE_TARBALL={}", tarball.display()))
        // stock's pair granular and fix wall/gran with DMT's cohesion set, as a reference
        .arg("-DROLLSLIDE_DMT_REFERENCE=ON"));
    run(Command::new("cmake").arg("--build").arg(&build).arg("-j2"));
    let exe = build.join("lmp_rollslide");
    assert!(exe.exists(), "{} was not built", exe.display());
    exe
}

/// A LAMMPS test: `body` gets the `lmp_rollslide` binary and panics on failure. Reported as
/// ignored, with what is missing, when LAMMPS, MPI, cmake or LAMMPS' source are not there
/// (failed instead when `ROLLSLIDE_REQUIRE_LAMMPS` is set, as `.ci/run` sets it).
pub fn trial(name: &str, body: fn(&Path)) -> Trial {
    Trial::ignorable_test(name, move || match binary() {
        Ok(exe) => {
            body(exe);
            Ok(Completion::Completed)
        }
        Err(why) if std::env::var_os("ROLLSLIDE_REQUIRE_LAMMPS").is_some() => {
            Err(format!("ROLLSLIDE_REQUIRE_LAMMPS is set, but this test {why}").into())
        }
        Err(why) => Ok(Completion::ignored_with(why)),
    })
}

/// Runs the trials as `cargo test` runs tests (filters, `--nocapture`, `--test-threads`).
pub fn run_trials(trials: Vec<Trial>) {
    let args = Arguments::from_args();
    libtest_mimic::run(&args, trials).exit();
}

/// A directory of its own for one test's runs.
pub fn rundir(name: &str) -> PathBuf {
    let d = work().join("runs").join(name);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The command that runs `exe` with `np` MPI ranks (`mpirun` beyond one), to which the caller
/// adds LAMMPS' arguments.
pub fn command(exe: &Path, np: usize) -> Command {
    if np == 1 {
        // One rank: Open MPI's singleton start without its runtime daemon (about 0.1 s of the
        // 0.4 s a short run takes here; the tests make about 1500 runs).
        let mut c = Command::new(exe);
        c.env("OMPI_MCA_ess_singleton_isolated", "1");
        return c;
    }
    let mut c = Command::new("mpirun");
    c.args([
        "--allow-run-as-root",
        "--oversubscribe",
        "-np",
        &np.to_string(),
    ])
    .arg(exe);
    c
}

/// Runs `lmp_rollslide` (stock LAMMPS' styles included) on `input` (a file of
/// examples/lammps/inputs) with `np` MPI ranks in `dir`; `vars` are `-var` pairs. Returns the log.
pub fn lammps(exe: &Path, dir: &Path, np: usize, input: &str, vars: &[(&str, &str)]) -> String {
    let log = dir.join(format!("log.{}", vars_tag(vars)));
    let mut cmd = command(exe, np);
    cmd.current_dir(dir)
        .arg("-in")
        .arg(inputs().join(input))
        .arg("-log")
        .arg(&log)
        .args(["-screen", "none"]);
    for (k, v) in vars {
        cmd.args(["-var", k, v]);
    }
    run(&mut cmd);
    std::fs::read_to_string(&log).unwrap()
}

/// Runs `lmp_rollslide` on `input` with `np` ranks in `dir` and `args` (`-var` pairs and the
/// like), expecting a LAMMPS error: returns its `ERROR` line. Fails if there is none, or if the
/// program ended by a signal (a crash) rather than with an exit status (error->all /
/// MPI_Abort).
pub fn lammps_error(exe: &Path, dir: &Path, np: usize, input: &str, args: &[&str]) -> String {
    let out = command(exe, np)
        .current_dir(dir)
        .arg("-in")
        .arg(inputs().join(input))
        .args(["-log", "none"])
        .args(args)
        .output()
        .unwrap();
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    let error = text
        .lines()
        .find(|l| l.starts_with("ERROR"))
        .unwrap_or_else(|| panic!("no LAMMPS error for {args:?}:\n{text}"))
        .to_string();
    assert!(out.status.code().is_some(), "crashed: {:?}", out.status);
    error
}

/// The log's name for a run's variables: all of them, or (beyond 200 characters: file names
/// end at 255) their first 180 characters and a hash of the whole.
fn vars_tag(vars: &[(&str, &str)]) -> String {
    use std::hash::{Hash, Hasher};
    let tag = vars
        .iter()
        .map(|(k, v)| format!("{k}-{v}"))
        .collect::<Vec<_>>()
        .join("_")
        .replace(['/', ' '], "");
    if tag.len() <= 200 {
        return tag;
    }
    let mut hasher = std::collections::hash_map::DefaultHasher::new();
    tag.hash(&mut hasher);
    let cut = (0..=180).rev().find(|&i| tag.is_char_boundary(i)).unwrap();
    format!("{}-{:016x}", &tag[..cut], hasher.finish())
}

/// A `dump custom` file: per step, the rows sorted by atom ID.
pub type Dump = BTreeMap<u64, Vec<Vec<f64>>>;

pub fn read_dump(path: &Path) -> Dump {
    let text = std::fs::read_to_string(path)
        .unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
    let lines: Vec<&str> = text.lines().collect();
    let mut out = Dump::new();
    let mut k = 0;
    while k < lines.len() {
        if lines[k].starts_with("ITEM: TIMESTEP") {
            let step: u64 = lines[k + 1].trim().parse().unwrap();
            let n: usize = lines[k + 3].trim().parse().unwrap();
            let mut a = k + 4;
            while !lines[a].starts_with("ITEM: ATOMS") {
                a += 1;
            }
            let rows = lines[a + 1..a + 1 + n]
                .iter()
                .map(|l| l.split_whitespace().map(|x| x.parse().unwrap()).collect())
                .collect();
            out.insert(step, rows);
            k = a + 1 + n;
        } else {
            k += 1;
        }
    }
    out
}

pub fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

pub fn diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y) * (x - y))
        .sum::<f64>()
        .sqrt()
}

pub fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(|a, b| a.partial_cmp(b).unwrap());
    v[v.len() / 2]
}

/// Worst per-atom differences of force (columns 1-3) and torque (4-6) at one step: relative
/// to the atom's own load (floored at 1e-3 of the median load, for the few atoms whose contact
/// loads cancel), and the largest difference over the median load.
pub struct Worst {
    pub relative: f64,
    pub over_median: f64,
}

pub fn compare(a: &[Vec<f64>], b: &[Vec<f64>]) -> (Worst, Worst) {
    assert_eq!(a.len(), b.len(), "different atom counts");
    let mut out = Vec::new();
    for cols in [1..4, 4..7] {
        let med = median(a.iter().map(|r| norm(&r[cols.clone()])).collect());
        let mut w = Worst {
            relative: 0.0,
            over_median: 0.0,
        };
        for (ra, rb) in a.iter().zip(b) {
            assert_eq!(ra[0], rb[0], "atom IDs differ");
            let d = diff(&ra[cols.clone()], &rb[cols.clone()]);
            let own = norm(&ra[cols.clone()]).max(1e-3 * med);
            w.relative = w.relative.max(d / own);
            w.over_median = w.over_median.max(d / med);
        }
        out.push(w);
    }
    let t = out.pop().unwrap();
    (out.pop().unwrap(), t)
}

/// The largest per-atom difference of force (columns 1-3) and of torque (4-6) at one step, over
/// the mean load of `a` (0 where the two are equal, even with no load at all).
pub fn worst_over_mean(a: &[Vec<f64>], b: &[Vec<f64>]) -> (f64, f64) {
    assert_eq!(a.len(), b.len(), "different atom counts");
    let worst = |cols: std::ops::Range<usize>| {
        let mean = a.iter().map(|r| norm(&r[cols.clone()])).sum::<f64>() / a.len() as f64;
        a.iter()
            .zip(b)
            .map(|(x, y)| {
                let d = diff(&x[cols.clone()], &y[cols.clone()]);
                if d == 0.0 {
                    0.0
                } else {
                    d / mean
                }
            })
            .fold(0.0, f64::max)
    };
    (worst(1..4), worst(4..7))
}

/// Worst per-atom relative differences (force, torque) over every step both dumps hold.
pub fn worst_relative(a: &Dump, b: &Dump) -> (f64, f64) {
    let (mut wf, mut wt) = (0.0f64, 0.0f64);
    assert_eq!(a.len(), b.len(), "the dumps hold different steps");
    for (step, rows) in a {
        let (f, t) = compare(rows, &b[step]);
        wf = wf.max(f.relative);
        wt = wt.max(t.relative);
    }
    (wf, wt)
}

/// Asserts that two runs' loads at one step (dump rows) differ by less than `bound` of the median
/// load, force and torque, and prints the measured differences under `what`.
pub fn assert_loads_agree(a: &[Vec<f64>], b: &[Vec<f64>], bound: f64, what: &str) {
    let (f, t) = compare(a, b);
    println!(
        "{what}: worst difference / median load: force {:.2e}, torque {:.2e}",
        f.over_median, t.over_median
    );
    assert!(
        f.over_median < bound && t.over_median < bound,
        "{what}: force {:.2e}, torque {:.2e} of the median load (bound {bound:e})",
        f.over_median,
        t.over_median
    );
}

/// Thermo rows of a log (all numeric columns of its thermo_style), from every run in it.
pub fn thermo(log: &str) -> Vec<Vec<f64>> {
    let mut rows = Vec::new();
    let mut inside = false;
    for line in log.lines() {
        if line.starts_with("Step ") || line.trim_start().starts_with("Step ") {
            inside = true;
            continue;
        }
        if line.starts_with("Loop time") {
            inside = false;
        }
        if inside {
            if let Ok(r) = line
                .split_whitespace()
                .map(|x| x.parse::<f64>())
                .collect::<Result<Vec<_>, _>>()
            {
                rows.push(r);
            }
        }
    }
    rows
}
