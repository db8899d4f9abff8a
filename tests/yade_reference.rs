//! The committed YADE reference data (`c_tests/reference/yade_double.csv`, `yade_cohesive.csv`,
//! which the C tests check the library against) is what YADE computes today: the script
//! `c_tests/reference/regenerate.sh` runs Debian's YADE 2023.02a on the cases and
//! `compare_reference.py` compares the result field by field with the committed files (its
//! tolerances are those of the C tests: the same file, regenerated, must match).
//!
//! Reported as ignored, with the reason, when `yade` or `python3` is not installed
//! (`apt-get install yade`); failed instead when `ROLLSLIDE_REQUIRE_YADE` is set, as `.ci/run`
//! sets it.

use libtest_mimic::{Arguments, Completion, Failed, Trial};
use std::path::Path;
use std::process::Command;

fn works(program: &str) -> bool {
    Command::new(program)
        .arg("--version")
        .output()
        .map(|o| o.status.success())
        .unwrap_or(false)
}

fn regenerate_and_compare() -> Result<Completion, Failed> {
    let missing: Vec<&str> = ["yade", "python3"]
        .into_iter()
        .filter(|p| !works(p))
        .collect();
    if !missing.is_empty() {
        let why = format!("needs {} (apt-get install yade)", missing.join(" and "));
        if std::env::var_os("ROLLSLIDE_REQUIRE_YADE").is_some() {
            return Err(format!("ROLLSLIDE_REQUIRE_YADE is set, but this test {why}").into());
        }
        return Ok(Completion::ignored_with(why));
    }
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let here = root.join("c_tests/reference");
    let out = Path::new(env!("CARGO_TARGET_TMPDIR")).join("yade_reference");
    std::fs::create_dir_all(&out).map_err(|e| e.to_string())?;
    let (double, cohesive) = (out.join("yade_double.csv"), out.join("yade_cohesive.csv"));
    let status = Command::new("sh")
        .arg(here.join("regenerate.sh"))
        .arg(&double)
        .arg(&cohesive)
        .status()
        .map_err(|e| e.to_string())?;
    if !status.success() {
        return Err(format!("regenerate.sh failed: {status}").into());
    }
    for (committed, fresh) in [
        ("yade_double.csv", &double),
        ("yade_cohesive.csv", &cohesive),
    ] {
        let o = Command::new("python3")
            .arg(here.join("compare_reference.py"))
            .arg(here.join(committed))
            .arg(fresh)
            .output()
            .map_err(|e| e.to_string())?;
        println!("{committed}: {}", String::from_utf8_lossy(&o.stdout).trim());
        if !o.status.success() {
            return Err(format!(
                "{committed} differs from what YADE computes today:\n{}{}",
                String::from_utf8_lossy(&o.stdout),
                String::from_utf8_lossy(&o.stderr)
            )
            .into());
        }
    }
    Ok(Completion::Completed)
}

fn main() {
    let args = Arguments::from_args();
    let trials = vec![Trial::ignorable_test(
        "committed_yade_reference_is_what_yade_computes",
        regenerate_and_compare,
    )];
    libtest_mimic::run(&args, trials).exit();
}
