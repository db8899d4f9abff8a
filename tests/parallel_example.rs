//! `examples/parallel_forces.c` (the force loop of one simulation on several threads) compiled
//! with the `cc` crate against the static library that `cargo test` just built, as
//! `tests/c_tests.rs` compiles the C tests, and run at its default size. The program checks
//! itself (the contact-major pattern bit for bit against the serial step on 1, 2 and 4 threads,
//! the per-thread accumulators within the rounding bound) and exits non-zero on any mismatch;
//! this test fails when it does. Its timings are printed (`-- --nocapture`), never checked.

use std::process::Command;

mod common;
use common::linking::{c_program_command, deps_dir, remove_test_program, root};

/// Runs a command; returns its exit success and its stdout + stderr.
fn run(cmd: &mut Command) -> (bool, String) {
    let out = cmd
        .output()
        .unwrap_or_else(|e| panic!("cannot run {cmd:?}: {e}"));
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    (out.status.success(), text)
}

#[test]
fn parallel_forces_example_is_bitwise_the_serial_step() {
    let work = deps_dir().join("../parallel_example_build");
    std::fs::create_dir_all(&work).unwrap();
    let exe = work.join("parallel_forces");
    let mut cc = c_program_command(
        &[root().join("examples/parallel_forces.c")],
        &["-pthread"],
        &exe,
    );
    let (built, text) = run(&mut cc);
    assert!(
        built,
        "compiling examples/parallel_forces.c failed:\n{text}"
    );

    // The default size (4,000 spheres, 19,386 contacts, 3 steps, 1, 2 and 4 threads).
    let (passed, printed) = run(&mut Command::new(&exe));
    print!("{printed}");
    assert!(passed, "parallel_forces failed:\n{printed}");
    assert!(
        printed.contains("parallel_forces: all checks passed"),
        "{printed}"
    );
    assert!(
        printed.contains("bitwise equal to the serial run for T = 1 2 4"),
        "the contact-major pattern was not checked on 1, 2 and 4 threads:\n{printed}"
    );
    // The memcmp checks can fail: the per-thread accumulators, which add the same loads in
    // another order, change the bits of some sums (the program prints how many).
    let differ: usize = printed
        .lines()
        .find_map(|l| l.split("states bitwise equal; ").nth(1))
        .and_then(|rest| rest.split_whitespace().next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("no count of reordered sums in:\n{printed}"));
    assert!(
        differ > 0,
        "reordering the sums changed no bit: the bitwise comparison proves nothing here"
    );
    remove_test_program(&exe);
}
