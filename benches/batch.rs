//! `cargo bench --bench batch`: run time of the batch kernels against hand-written C baselines
//! (each the faster of its loop without and with the library's prefetches), the per-contact C
//! calls and the memory floor, for three physics sets (full, rolltwist, sliding), on two
//! workloads, out of cache (1,200,000 contacts) and in cache (2,000 contacts), and for
//! sphere-wall contacts (group wall, workload A: one per particle, the full set's physics; the
//! per-contact calls and `rsl_batch_step_walls`, whose rows are also set against the full set's
//! `rsl_batch_step` rows of the same precision and SIMD level, per contact of each group).
//!
//! Workload A (the headline): a jittered FCC packing whose particles are spatially sorted as a
//! DEM code keeps them (LAMMPS' atom sort: lexicographic order of small spatial bins), contacts
//! in half-neighbour-list order. Workload B: a cubic packing with randomly permuted particle
//! ids (body 2 of each contact is a random memory access). `bench/bench.c` describes both, the
//! histories, the baselines and every row.
//!
//! The driver `bench/bench.c` is compiled here with the `cc` crate's compiler at
//! `-O3 -march=native` and linked against the `librollslide.a` that cargo built for this bench
//! (release profile). For each size it runs 5 times per workload (A and B alternating); each
//! run's number for a row is the fastest of several timed calls (4 out of cache, 7 in cache),
//! each call starting from the same states. Every ratio (row / baseline of the same physics
//! set, row / memory floor) is computed within one run, and the table reports the median over
//! the runs of the times and of the ratios. Arguments after `--`: `--quick` (one run, 100,000
//! and 2,000 contacts, 3 calls per row) for a smoke test; `--slip=F` (passed to the driver: the
//! fraction of contacts that start beyond each law's limit, default 0.25; the scalar baselines'
//! clip branches are mispredicted in proportion, which the `[noslip]` rows, measured on the same
//! histories with every spring below its limit, bracket); `--set=NAME` (passed to the driver:
//! only the physics set full, rolltwist or sliding, or the group wall, which runs on workload A
//! only; `--quick --set=wall` is the quickest look at the wall rows); `--help`. A full run
//! takes about 4.5 minutes of driver time on a 2-core machine (5 calls per row out of cache took
//! 5 minutes). The table is printed and written to `target/<profile>/bench_table.md`
//! (`target/release/bench_table.md`).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn static_library() -> PathBuf {
    let deps = std::env::current_exe()
        .unwrap()
        .parent()
        .unwrap()
        .to_path_buf();
    [deps.join("librollslide.a"), deps.join("../librollslide.a")]
        .into_iter()
        .filter(|p| p.exists())
        .max_by_key(|p| std::fs::metadata(p).and_then(|m| m.modified()).ok())
        .expect("librollslide.a not found next to the bench binary")
}

fn build_driver() -> PathBuf {
    let out = std::env::current_exe()
        .unwrap()
        .parent()
        .unwrap()
        .join("../bench_driver");
    let compiler = cc::Build::new()
        .target(env!("RSL_BUILD_TARGET"))
        .host(env!("RSL_BUILD_HOST"))
        .opt_level(3)
        .cargo_metadata(false)
        .warnings(false)
        .get_compiler();
    let mut cmd = compiler.to_command();
    cmd.args([
        "-O3",
        "-march=native",
        "-std=c11",
        "-D_POSIX_C_SOURCE=199309L",
        "-Wall",
        "-Wextra",
    ])
    .arg("-I")
    .arg(root().join("include"))
    .arg(root().join("bench/bench.c"))
    .arg(static_library())
    .args([
        "-lgcc_s",
        "-lutil",
        "-lrt",
        "-lpthread",
        "-lm",
        "-ldl",
        "-lc",
    ])
    .arg("-o")
    .arg(&out);
    let status = cmd.status().expect("running the C compiler");
    assert!(status.success(), "compiling bench/bench.c failed");
    out
}

/// One output row of the driver: `row GROUP NAME NS LOADS_DIFF STATE_DIFF FLAGS`.
#[derive(Clone, Debug)]
struct Row {
    group: String,
    name: String,
    ns: f64,
    loads: String,
    state: String,
    flags: String,
}

/// One run of the driver: its `info` lines and its rows in output order.
struct Run {
    info: Vec<String>,
    rows: Vec<Row>,
}

impl Run {
    fn ns(&self, group: &str, name: &str) -> Option<f64> {
        self.rows
            .iter()
            .find(|r| r.group == group && r.name == name)
            .map(|r| r.ns)
    }
}

/// One run of the driver, from a fresh copy of its file (removed after the run).
///
/// The copy is there because of what the code's placement in memory does to a kernel's time: on
/// the Zen 5 host of docs/performance.md, six copies of one driver file, three runs each (A,
/// 1.2M contacts, double AVX-512, full set), gave one copy 23.9-25.4 ns in all three runs, two
/// copies 18.2-18.7 ns in all three, and the other three copies a mix of both. A copy's code
/// sits in its own page-cache pages, so the physical addresses of the kernels follow the file
/// and every run of one file shares them (the suspected link: the L2 cache picks a line's set
/// by physical address). Run from one file, the five runs of an invocation all drew that
/// file's placement, and the median reported it (one invocation gave the full set 22.4 ns,
/// where a copy of the same file under another name took 17.9-18.8 in four runs of four).
/// With a copy per run the median is over five placements.
fn run(exe: &Path, workload: char, contacts: usize, reps: usize, extra: &[String]) -> Run {
    let copy = exe.with_extension(format!("run-{}", std::process::id()));
    std::fs::copy(exe, &copy).expect("copying the bench driver");
    let out = Command::new(&copy)
        .arg(contacts.to_string())
        .arg(reps.to_string())
        .arg(format!("--workload={workload}"))
        .args(extra)
        .output();
    // Removed before any panic below, so that a failed run leaves no copy behind.
    std::fs::remove_file(&copy).expect("removing the copy of the bench driver");
    let out = out.expect("running the bench driver");
    assert!(
        out.status.success(),
        "bench driver (workload {workload}, {contacts} contacts) failed:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8_lossy(&out.stdout).to_string();
    let mut info = Vec::new();
    let mut rows = Vec::new();
    for line in text.lines() {
        if let Some(rest) = line.strip_prefix("info ") {
            info.push(rest.to_string());
            continue;
        }
        let f: Vec<&str> = line.split_whitespace().collect();
        assert!(
            f.len() == 7 && f[0] == "row",
            "unexpected driver output: {line}"
        );
        rows.push(Row {
            group: f[1].to_string(),
            name: f[2].to_string(),
            ns: f[3].parse().expect("ns per contact"),
            loads: f[4].to_string(),
            state: f[5].to_string(),
            flags: f[6].to_string(),
        });
    }
    Run { info, rows }
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(|a, b| a.partial_cmp(b).unwrap());
    v[v.len() / 2]
}

/// Median over the runs of `row / reference of the same run`.
fn median_ratio(runs: &[Run], group: &str, name: &str, reference: &str) -> f64 {
    median(
        runs.iter()
            .map(|r| r.ns(group, name).unwrap() / r.ns(group, reference).unwrap())
            .collect(),
    )
}

/// Suffix of the rows measured on the no-slip histories (compared with `baseline_c[noslip]`).
const NOSLIP: &str = "[noslip]";

/// Rows measured on the indexed layout (each contact's state in place in an array of 1.5
/// states per contact): `rsl_batch_step_indexed` and its own floor and hand-written loops.
fn indexed(name: &str) -> bool {
    ["indexed_", "baseline_c_indexed", "floor_indexed"]
        .iter()
        .any(|p| name.starts_with(p))
}

/// Rows of the group `wall` (sphere-wall contacts, workload A), which has its own baseline and
/// floor: `floor_wall`, `baseline_wall_c`, `percontact_wall_c`, `percontact_wall_unchecked_c`,
/// `batch_wall_<p>_<l>_c` (`rsl_batch_step_walls`).
fn wall(name: &str) -> bool {
    name.contains("_wall")
}

/// The baseline a row is divided by: the one measured on the same histories and layout.
fn reference(name: &str) -> &'static str {
    if wall(name) {
        "baseline_wall_c"
    } else if name.ends_with(NOSLIP) {
        "baseline_c[noslip]"
    } else if indexed(name) {
        "baseline_c_indexed"
    } else {
        "baseline_c"
    }
}

/// The memory floor a row is divided by: the one of its state layout.
fn floor_of(name: &str) -> &'static str {
    if wall(name) {
        "floor_wall"
    } else if indexed(name) {
        "floor_indexed"
    } else {
        "floor"
    }
}

/// The physics a row computes: its group's set, or what differs (marked with a dagger).
fn physics(row: &Row) -> String {
    if row.name.ends_with(NOSLIP) {
        return format!("{}, no contact at a limit", row.group);
    }
    if let Some(start) = row.name.find('[') {
        let laws = row.name[start + 1..].trim_end_matches(']');
        if row.loads == "-" {
            return format!("{laws} †");
        }
        return format!("{} ({laws})", row.group);
    }
    if let Some(rest) = row.name.strip_prefix("materials") {
        // materials<N>_f64_<l>: the group's laws with a table of N coefficient sets
        let n = rest.split('_').next().unwrap_or("");
        if row.loads == "-" {
            return format!("{}, {n} material sets †", row.group);
        }
        return format!("{}, {n} material set(s)", row.group);
    }
    if row.name.starts_with("decompose") {
        return "decomposition only †".to_string();
    }
    row.group.clone()
}

/// The SIMD level `RSL_SIMD_AUTO` ran for a precision (the suffix of the contact-major row).
fn auto_level(run: &Run, group: &str, precision: &str) -> Option<String> {
    let prefix = format!("contacts_{precision}_");
    run.rows
        .iter()
        .find(|r| r.group == group && r.name.starts_with(&prefix))
        .map(|r| r.name[prefix.len()..].to_string())
}

fn table(runs: &[Run], workload: char, contacts: usize) -> String {
    let mut md = format!(
        "\n### Workload {workload}, {contacts} contacts (median of {} runs)\n\n",
        runs.len()
    );
    for line in &runs[0].info {
        md += &format!("- {line}\n");
    }
    md += "\n| row | physics | ns/contact | / baseline | / floor | max rel. diff, loads \
           | max rel. diff, state |\n|---|---|---:|---:|---:|---:|---:|\n";
    for row in &runs[0].rows {
        let (g, n) = (row.group.as_str(), row.name.as_str());
        let ns = median(runs.iter().map(|r| r.ns(g, n).unwrap()).collect());
        let flags = if row.flags == "0" || row.flags == "-" {
            String::new()
        } else {
            format!(" ({} slip flags differ)", row.flags)
        };
        md += &format!(
            "| {n} | {} | {ns:.2} | {:.2} | {:.2} | {} | {}{flags} |\n",
            physics(row),
            median_ratio(runs, g, n, reference(n)),
            median_ratio(runs, g, n, floor_of(n)),
            row.loads,
            row.state,
        );
    }
    md + &wall_against_pair(runs)
}

/// The pair row a wall batch row is set against: `batch_wall_<p>_<l>_c` (group wall) and
/// `batch_<p>_<l>` (group full: the same physics, `rsl_batch_step`, the same precision and SIMD
/// level).
fn pair_batch_of(wall_row: &str) -> Option<String> {
    let rest = wall_row.strip_prefix("batch_wall_")?.strip_suffix("_c")?;
    Some(format!("batch_{rest}"))
}

/// The wall batch rows against the pair batch rows, per contact: the driver gives each row in
/// ns per contact of its own group (the wall group has one contact per particle, about a sixth
/// of the pair group's contacts), so the ratio is of those; median of the same-run ratios.
/// Empty when the run has no wall batch row.
fn wall_against_pair(runs: &[Run]) -> String {
    let mut md = String::new();
    for row in &runs[0].rows {
        let Some(pair) = pair_batch_of(&row.name).filter(|_| row.group == "wall") else {
            continue;
        };
        let name = row.name.as_str();
        let wall_ns = median(runs.iter().map(|r| r.ns("wall", name).unwrap()).collect());
        let (pair_ns, ratio) = if runs.iter().all(|r| r.ns("full", &pair).is_some()) {
            (
                format!(
                    "{:.2}",
                    median(runs.iter().map(|r| r.ns("full", &pair).unwrap()).collect())
                ),
                format!(
                    "{:.2}",
                    median(
                        runs.iter()
                            .map(|r| r.ns("wall", name).unwrap() / r.ns("full", &pair).unwrap())
                            .collect()
                    )
                ),
            )
        } else {
            ("-".to_string(), "-".to_string())
        };
        md += &format!("| {name} | {wall_ns:.2} | {pair} | {pair_ns} | {ratio} |\n");
    }
    if md.is_empty() {
        return md;
    }
    "\nWall batch against pair batch (`rsl_batch_step_walls` in group wall against \
     `rsl_batch_step` in group full, the same physics, precision and SIMD level; each in ns per \
     contact of its own group; \"-\": group full not run):\n\n\
     | wall row | ns/contact | pair row (full) | ns/contact | wall / pair |\n\
     |---|---:|---|---:|---:|\n"
        .to_string()
        + &md
}

fn cpu_info() -> (String, String) {
    let text = std::fs::read_to_string("/proc/cpuinfo").unwrap_or_default();
    let field = |key: &str| {
        text.lines()
            .find(|l| l.starts_with(key))
            .and_then(|l| l.split(':').nth(1))
            .map(|v| v.trim().to_string())
            .unwrap_or_default()
    };
    let model = field("model name");
    let flags = field("flags");
    let have: Vec<String> = ["avx2", "fma", "avx512f"]
        .iter()
        .map(|f| {
            let yes = flags.split_whitespace().any(|x| x == *f);
            format!("{f} {}", if yes { "yes" } else { "no" })
        })
        .collect();
    (model, have.join(", "))
}

fn load_average() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .unwrap_or_default()
        .split_whitespace()
        .take(3)
        .collect::<Vec<_>>()
        .join(" ")
}

/// How the driver's arrays can get 2 MiB pages: the kernel's transparent huge page mode (the
/// bracketed word of `/sys/kernel/mm/transparent_hugepage/enabled`: `always` gives them to
/// every large allocation, `madvise` only to memory the program asks for) and `GLIBC_TUNABLES`
/// as the driver inherits it (`glibc.malloc.hugetlb=1` makes malloc ask). Out of cache they
/// took 1-18% off the rows of workload A and 35-49% off those of B on one host
/// (docs/performance.md, "Huge pages"), so the table says which applied.
fn huge_pages() -> String {
    let mode = std::fs::read_to_string("/sys/kernel/mm/transparent_hugepage/enabled")
        .ok()
        .and_then(|t| {
            let start = t.find('[')?;
            let end = t[start..].find(']')?;
            Some(t[start + 1..start + end].to_string())
        })
        .unwrap_or_else(|| "unknown".to_string());
    let tunables = std::env::var("GLIBC_TUNABLES").unwrap_or_else(|_| "unset".to_string());
    format!("transparent huge pages: {mode}; GLIBC_TUNABLES: {tunables}")
}

fn main() {
    if std::env::args().any(|a| a == "--help" || a == "-h") {
        println!(
            "cargo bench --bench batch [-- [--quick] [--slip=F] [--set=NAME]]\n  \
             --quick     one run per workload, 100,000 and 2,000 contacts, 3 calls per row\n  \
             --slip=F    fraction of contacts starting beyond each law's limit (default 0.25)\n  \
             --set=NAME  only the physics set full, rolltwist or sliding, or the group wall \
             (sphere-wall contacts; workload A only)\n\
             The rows are described at the top of bench/bench.c."
        );
        return;
    }
    let quick = std::env::args().any(|a| a == "--quick");
    // `--slip=F` and `--set=NAME` are passed to the driver (fraction of contacts beyond each
    // law's limit; only one physics set or the group wall).
    let extra: Vec<String> = std::env::args()
        .filter(|a| a.starts_with("--slip=") || a.starts_with("--set="))
        .collect();
    let only_set = extra
        .iter()
        .find_map(|a| a.strip_prefix("--set="))
        .map(str::to_string);
    let exe = build_driver();
    let (cpu, simd) = cpu_info();
    let load_start = load_average();
    let pages = huge_pages();
    println!("CPU: {cpu}; {simd}; {pages}; load average (1, 5, 15 min) at start: {load_start}");
    let sizes: &[(usize, usize)] = if quick {
        &[(100_000, 3), (2_000, 3)]
    } else {
        // 4 calls per row out of cache (not 5) keeps a full run near 4 minutes on 2 cores
        &[(1_200_000, 4), (2_000, 7)]
    };
    let runs = if quick { 1 } else { 5 };
    // The group wall runs on workload A only.
    let workloads: &[char] = if only_set.as_deref() == Some("wall") {
        &['A']
    } else {
        &['A', 'B']
    };
    let started = Instant::now();
    let mut results: BTreeMap<(char, usize), Vec<Run>> = BTreeMap::new();
    for &(n, reps) in sizes {
        for r in 0..runs {
            for &w in workloads {
                eprintln!(
                    "[{:6.1} s] workload {w}, {n} contacts, run {}/{runs}",
                    started.elapsed().as_secs_f64(),
                    r + 1
                );
                results
                    .entry((w, n))
                    .or_default()
                    .push(run(&exe, w, n, reps, &extra));
            }
        }
    }
    let elapsed = started.elapsed().as_secs_f64();
    let load_end = load_average();

    let title = format!(
        "{}{}",
        if quick { " (--quick smoke test)" } else { "" },
        extra.iter().map(|a| format!(" ({a})")).collect::<String>()
    );
    let mut md = format!(
        "## rollslide batch benchmark{}\n\nCPU: {cpu}; {simd}; {pages}. Load average (1, 5, 15 min): \
         {load_start} at the start, {load_end} at the end; driver runs took {elapsed:.0} s.\n\n\
         Each run's number for a row is the fastest of several timed calls ({}); every ratio is \
         taken within one run (row / the baseline of the same physics set, row / the floor \
         measured with that set), then the median over {runs} run(s) is reported, as is the \
         median of the times. Workload A: particles spatially sorted (LAMMPS atom sort), \
         half neighbour list; workload B: particle ids randomly permuted. A random quarter of \
         the contacts (driver option --slip) starts beyond each law's limit (the info lines give \
         the fractions measured); the scalar baselines mispredict their clip branches on them. \
         Each set's baseline is the faster of its hand-written loop without and with the \
         library's prefetches (rows baseline_c_plain and baseline_c_prefetch). The indexed \
         rows (each state in place in an array of 1.5 per contact) are divided by the floor \
         and the baseline measured on that layout (floor_indexed, baseline_c_indexed). \
         Rows marked [noslip] (\"no slip\" in the summary) run on the same histories with every \
         spring below its limit (no clip taken: the baselines' best case) and are divided by \
         the baseline on those histories. The group wall (workload A: one sphere-wall contact \
         per particle, the full set's physics) is divided by its own baseline and floor \
         (baseline_wall_c, floor_wall); its batch rows (rsl_batch_step_walls) are also set \
         against group full's rsl_batch_step rows of the same precision and SIMD level, per \
         contact of each group (the table after each workload A table). The rows are described \
         at the top of `bench/bench.c`. † different physics from the group's baseline (ratio \
         given for cost only). Diffs: max |difference| from the baseline relative to the \
         largest baseline component (loads: per-particle forces and torques; state: springs, \
         twisting angle, normal).\n",
        title,
        sizes
            .iter()
            .map(|(n, reps)| format!("{reps} calls at {n} contacts"))
            .collect::<Vec<_>>()
            .join(", ")
    );

    // Summary: the main kernels against the baseline of the same physics set (left out when
    // --set ran none of the sets).
    let summary_start = md.len();
    let mut summarised = false;
    md += "\n### Summary: median of same-run ratios to the hand-written C baseline of the same \
           physics\n\n| physics | kernel |";
    let mut columns = Vec::new();
    for &w in workloads {
        for &(n, _) in sizes {
            md += &format!(" {w}, {n} |");
            columns.push((w, n));
        }
    }
    md += "\n|---|---|";
    md += &"---:|".repeat(columns.len());
    md += "\n";
    for group in ["full", "rolltwist", "sliding"] {
        // a set left out with --set
        if !results
            .values()
            .any(|rs| rs[0].rows.iter().any(|r| r.group == group))
        {
            continue;
        }
        summarised = true;
        let first = &results[&columns[0]][0];
        let l64 = auto_level(first, group, "f64").unwrap_or_default();
        let l32 = auto_level(first, group, "f32").unwrap_or_default();
        let kernels = [
            (
                "baseline_c".to_string(),
                "C baseline: ns/contact".to_string(),
            ),
            ("floor".to_string(), "memory floor".to_string()),
            (
                format!("batch_f64_{l64}"),
                format!("batch f64 {l64} (auto)"),
            ),
            (
                format!("batch_f32_{l32}"),
                format!("batch f32 {l32} (auto)"),
            ),
            (
                format!("history_f64_{l64}"),
                format!("packed histories f64 {l64} (auto)"),
            ),
            (
                format!("history_f32_{l32}"),
                format!("packed histories f32 {l32} (auto)"),
            ),
            (
                "baseline_c_indexed".to_string(),
                "histories in place: C baseline: ns/contact".to_string(),
            ),
            (
                "floor_indexed".to_string(),
                "histories in place: memory floor".to_string(),
            ),
            (
                format!("indexed_f64_{l64}"),
                format!("histories in place (indexed) f64 {l64} (auto)"),
            ),
            (
                "percontact_acc_c".to_string(),
                "rsl_contact_step_accumulate".to_string(),
            ),
            (
                "percontact_c".to_string(),
                "rsl_contact_step + host adds".to_string(),
            ),
            (
                format!("baseline_c{NOSLIP}"),
                "no slip: C baseline: ns/contact".to_string(),
            ),
            (
                format!("batch_f64_{l64}{NOSLIP}"),
                format!("no slip: batch f64 {l64} (auto)"),
            ),
            (
                format!("batch_f32_{l32}{NOSLIP}"),
                format!("no slip: batch f32 {l32} (auto)"),
            ),
            (
                format!("percontact_acc_c{NOSLIP}"),
                "no slip: rsl_contact_step_accumulate".to_string(),
            ),
        ];
        for (name, label) in kernels {
            md += &format!("| {group} | {label} |");
            for key in &columns {
                let rs = &results[key];
                let cell = if rs[0].ns(group, &name).is_none() {
                    "-".to_string()
                } else if name.starts_with("baseline_c") {
                    format!(
                        "{:.1}",
                        median(rs.iter().map(|r| r.ns(group, &name).unwrap()).collect())
                    )
                } else {
                    format!("{:.2}", median_ratio(rs, group, &name, reference(&name)))
                };
                md += &format!(" {cell} |");
            }
            md += "\n";
        }
    }
    if !summarised {
        md.truncate(summary_start);
    }

    for &w in workloads {
        for &(n, _) in sizes {
            md += &table(&results[&(w, n)], w, n);
        }
    }
    println!("{md}");
    // target/<profile>/bench_table.md (the bench binary is target/<profile>/deps/batch-*)
    let path = std::env::current_exe()
        .unwrap()
        .parent()
        .and_then(Path::parent)
        .unwrap()
        .join("bench_table.md");
    std::fs::write(&path, &md).unwrap();
    println!("table written to {}", path.display());
}
