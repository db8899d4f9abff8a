//! `cargo bench --bench batch`: run time of the batch kernels against a hand-written C
//! baseline, the per-contact C call and the memory floor, on 1,000,000 contacts (out of cache)
//! and 2,000 contacts (in cache).
//!
//! The driver `bench/bench.c` is compiled here with the `cc` crate's compiler at
//! `-O3 -march=native` and linked against the `librollslide.a` that cargo built for this bench
//! (release profile); it is run 3 times per size and the table reports the median of the 3
//! runs (each run's number is the minimum over several timed calls, each call starting from
//! the same states). Arguments after `--`: `--quick` (one run, smaller sizes) for a smoke test.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;

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

fn run(exe: &Path, contacts: usize, reps: usize) -> (String, BTreeMap<String, (f64, String)>) {
    let out = Command::new(exe)
        .arg(contacts.to_string())
        .arg(reps.to_string())
        .output()
        .expect("running the bench driver");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8_lossy(&out.stdout).to_string();
    let mut rows = BTreeMap::new();
    let mut header = String::new();
    for line in text.lines() {
        let f: Vec<&str> = line.split_whitespace().collect();
        if f[0] == "contacts" {
            header = line.to_string();
            continue;
        }
        rows.insert(f[0].to_string(), (f[1].parse().unwrap(), f[2].to_string()));
    }
    (header, rows)
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(|a, b| a.partial_cmp(b).unwrap());
    v[v.len() / 2]
}

fn main() {
    let quick = std::env::args().any(|a| a == "--quick");
    let exe = build_driver();
    let cpu = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("model name"))
                .map(|l| l.split(':').nth(1).unwrap().trim().to_string())
        })
        .unwrap_or_default();
    let load = std::fs::read_to_string("/proc/loadavg").unwrap_or_default();
    println!("CPU: {cpu}; load average at start: {}", load.trim());
    let sizes: &[(usize, usize)] = if quick {
        &[(100_000, 3), (2_000, 3)]
    } else {
        &[(1_000_000, 5), (2_000, 15)]
    };
    let runs = if quick { 1 } else { 3 };
    let mut md = String::new();
    for &(n, reps) in sizes {
        let mut all: Vec<BTreeMap<String, (f64, String)>> = Vec::new();
        let mut header = String::new();
        for _ in 0..runs {
            let (h, rows) = run(&exe, n, reps);
            header = h;
            all.push(rows);
        }
        let keys: Vec<String> = all[0].keys().cloned().collect();
        let med: BTreeMap<String, f64> = keys
            .iter()
            .map(|k| (k.clone(), median(all.iter().map(|r| r[k].0).collect())))
            .collect();
        let base = med["baseline_c"];
        let floor = med["floor"];
        md += &format!(
            "\n{header} (median of {runs} runs)\n\n| kernel | ns/contact | / C baseline | / memory floor | max rel. diff vs baseline |\n|---|---:|---:|---:|---:|\n"
        );
        let mut order: Vec<&String> = keys.iter().collect();
        let rank = |k: &str| -> usize {
            [
                "baseline_c",
                "floor",
                "percontact_c",
                "percontact_acc_c",
                "batch_f64",
                "contacts_f64",
                "batch_f32",
                "contacts_f32",
                "decompose",
            ]
            .iter()
            .position(|p| k.starts_with(p))
            .unwrap_or(99)
        };
        order.sort_by_key(|k| (rank(k), k.to_string()));
        for k in order {
            let t = med[k];
            md += &format!(
                "| {k} | {t:.2} | {:.2} | {:.2} | {} |\n",
                t / base,
                t / floor,
                all[0][k].1
            );
        }
    }
    println!("{md}");
    let path = std::env::current_exe()
        .unwrap()
        .parent()
        .unwrap()
        .join("../bench_table.md");
    std::fs::write(&path, &md).unwrap();
    println!("table written to {}", path.display());
}
