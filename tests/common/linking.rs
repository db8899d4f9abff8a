//! Building C and C++ programs against the static library `cargo test` just built (the C tests,
//! the examples the tests run).
#![allow(dead_code)]

use std::path::{Path, PathBuf};

/// The repository root.
pub fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// The directory of this test binary (target/<profile>/deps), where cargo put the library.
pub fn deps_dir() -> PathBuf {
    std::env::current_exe()
        .unwrap()
        .parent()
        .unwrap()
        .to_path_buf()
}

/// The freshest `librollslide.a` of this profile.
pub fn static_library() -> PathBuf {
    let deps = deps_dir();
    let candidates = [deps.join("librollslide.a"), deps.join("../librollslide.a")];
    candidates
        .into_iter()
        .filter(|p| p.exists())
        .max_by_key(|p| std::fs::metadata(p).and_then(|m| m.modified()).ok())
        .expect("librollslide.a not found next to the test binary; run through `cargo test`")
}

/// The system libraries a Rust static library needs, as the CMake package and the pkg-config
/// files pin them (`cmake/native-static-libs.txt`; `tests/cmake_package.rs` checks the list
/// against `rustc --print native-static-libs`).
pub fn native_libs() -> Vec<String> {
    std::fs::read_to_string(root().join("cmake/native-static-libs.txt"))
        .unwrap()
        .split_whitespace()
        .map(str::to_string)
        .collect()
}

/// Linker flags for every test program linked against the unoptimised static library:
/// `--gc-sections` drops the functions the program cannot reach and `-S` (`--strip-debug`) the
/// library's line tables. Unoptimised, a C test program that steps a batch held 811 MB of
/// machine code (the batch kernels, most of it) and 1.21 GB in all; with these flags it is
/// 0.48 GB and links in 2.4 s instead of 5.8. The C test programs of one `cargo test` once
/// filled 9.2 GB, and the disk of the CI machine ran out.
pub fn test_program_link_flags() -> [&'static str; 2] {
    ["-Wl,--gc-sections", "-Wl,-S"]
}

/// Removes a test program once it has run and passed (a failed one stays, to be rerun by hand):
/// each is about 0.5 GB (see [`test_program_link_flags`]).
pub fn remove_test_program(exe: &Path) {
    // A program that is already gone (or never built) is fine.
    let _ = std::fs::remove_file(exe);
}

/// The C (or C++) compiler the `cc` crate picks for this target, flags left to the caller.
pub fn compiler(cpp: bool) -> cc::Tool {
    cc::Build::new()
        .cpp(cpp)
        .target(env!("RSL_BUILD_TARGET"))
        .host(env!("RSL_BUILD_HOST"))
        .opt_level(1)
        .cargo_metadata(false)
        .warnings(false)
        .get_compiler()
}

/// Appends to a compile command what every test program links with: the static library, the
/// system libraries it needs ([`native_libs`]), [`test_program_link_flags`], and `-o exe`.
pub fn link_test_program<'a>(
    cmd: &'a mut std::process::Command,
    exe: &Path,
) -> &'a mut std::process::Command {
    cmd.arg(static_library())
        .args(native_libs())
        .args(test_program_link_flags())
        .arg("-o")
        .arg(exe)
}

/// The command that builds the C test program `exe` from the C11 `sources`: the strict flags
/// every C program of the tests compiles with (`-std=c11 -Wall -Wextra -Werror -pedantic`), the
/// repository's `include/`, then `extra` (defines, include directories, `-pthread`), linked as
/// [`link_test_program`] links. The C tests and the examples the tests run all build through
/// it, so that they cannot drift apart on the flags.
pub fn c_program_command<S: AsRef<std::ffi::OsStr>>(
    sources: &[PathBuf],
    extra: &[S],
    exe: &Path,
) -> std::process::Command {
    let mut cmd = compiler(false).to_command();
    cmd.args(["-std=c11", "-Wall", "-Wextra", "-Werror", "-pedantic"])
        .arg("-I")
        .arg(root().join("include"))
        .args(extra)
        .args(sources);
    link_test_program(&mut cmd, exe);
    cmd
}

/// Runs a command; panics with its whole output when it fails. Returns stdout + stderr.
pub fn run(cmd: &mut std::process::Command) -> String {
    let shown = format!("{cmd:?}");
    let out = cmd
        .output()
        .unwrap_or_else(|e| panic!("cannot run {shown}: {e}"));
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        out.status.success(),
        "{shown} failed ({}):\n{text}",
        out.status
    );
    text
}

/// `-DROLLSLIDE_CARGO_TARGET_DIR=...` for a test that configures the repository's CMake build:
/// the tests that do (`cmake_package` and the `lammps_*` tests) share one cargo target
/// directory, so the release library they all build (the same `cargo rustc` command) is
/// compiled once per change, not once per test (about a minute each). `cargo test` runs the
/// test binaries one after another, and cargo's own lock orders any overlap.
pub fn shared_cmake_cargo_dir() -> String {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("cmake-cargo");
    format!("-DROLLSLIDE_CARGO_TARGET_DIR={}", dir.display())
}
