//! The CMake package end to end, as a user meets it: configures and builds the top-level CMake
//! project (which drives cargo), runs its CTest (the C tests against the static and the shared
//! library), installs it into a fresh prefix, then builds and runs `examples/` as a separate
//! CMake project with `find_package(rollslide CONFIG REQUIRED)`, once with the static and once
//! with the shared library, and builds a C program with `pkg-config`.
//!
//! Needs `cmake` and `pkg-config`: it fails (it does not skip) when they are missing. The CMake
//! build directory is kept under `target/tmp/cmake-package/` so that later runs are incremental.
//!
//! Also pins the system libraries a Rust static library needs (`rustc --print
//! native-static-libs`) against `cmake/native-static-libs.txt`, which the CMake package and the
//! pkg-config files carry, and against the other places that spell them out.

mod common;

use common::linking::{run, shared_cmake_cargo_dir};
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

const INSTALL_HINT: &str = "apt-get install cmake pkg-config";

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn work() -> PathBuf {
    Path::new(env!("CARGO_TARGET_TMPDIR")).join("cmake-package")
}

/// Fails loudly when a tool the test needs is missing.
fn require(tool: &str) {
    let found = Command::new(tool).arg("--version").output().is_ok();
    assert!(
        found,
        "`{tool}` is not installed: the CMake package test needs cmake and pkg-config \
         (`{INSTALL_HINT}`)"
    );
}

/// A command for a program we built: without cargo's LD_LIBRARY_PATH (target/*/deps), so the
/// shared library must be found through the RUNPATH or the LD_LIBRARY_PATH we give.
fn program(path: &Path) -> Command {
    let mut c = Command::new(path);
    c.env_remove("LD_LIBRARY_PATH");
    c
}

/// `readelf -d` lines: the NEEDED libraries, the SONAME and the RUNPATH of an ELF file.
fn dynamic_section(path: &Path) -> String {
    run(Command::new("readelf").arg("-d").arg(path))
}

fn needed(path: &Path) -> Vec<String> {
    dynamic_section(path)
        .lines()
        .filter(|l| l.contains("(NEEDED)"))
        .filter_map(|l| {
            l.split('[')
                .nth(1)
                .map(|s| s.trim_end_matches(']').to_string())
        })
        .collect()
}

/// The names of `c_tests/tests.def`.
fn registered_c_tests() -> Vec<String> {
    std::fs::read_to_string(root().join("c_tests/tests.def"))
        .unwrap()
        .lines()
        .filter_map(|l| l.trim().strip_prefix("RSL_TEST("))
        .map(|l| l.split(')').next().unwrap().trim().to_string())
        .collect()
}

/// The flags of `cmake/native-static-libs.txt`.
fn pinned_native_libs() -> Vec<String> {
    std::fs::read_to_string(root().join("cmake/native-static-libs.txt"))
        .unwrap()
        .split_whitespace()
        .map(str::to_string)
        .collect()
}

fn step(name: &str, start: Instant) {
    eprintln!(
        "cmake_package: {name} done at {:.1} s",
        start.elapsed().as_secs_f64()
    );
}

#[test]
fn cmake_build_ctest_install_examples_and_pkg_config() {
    for tool in ["cmake", "ctest", "pkg-config"] {
        require(tool);
    }
    let start = Instant::now();
    let work = work();
    let build = work.join("build");
    let prefix = work.join("prefix");
    std::fs::create_dir_all(&work).unwrap();

    // 1. Configure and build the top-level project (cargo inside, incremental).
    run(Command::new("cmake")
        .arg("-S")
        .arg(root())
        .arg("-B")
        .arg(&build)
        .arg("-DCMAKE_BUILD_TYPE=Release")
        .arg(shared_cmake_cargo_dir()));
    run(Command::new("cmake")
        .arg("--build")
        .arg(&build)
        .args(["--parallel", "2"]));
    step("cmake build (cargo --release inside)", start);

    // 2. CTest: every function of tests.def, against both libraries, plus the registry check.
    let tests = registered_c_tests();
    let listed = run(Command::new("ctest").arg("-N").current_dir(&build));
    let expected = 2 * (tests.len() + 1);
    assert!(
        listed.contains(&format!("Total Tests: {expected}")),
        "ctest should register {expected} tests (2 x ({} in tests.def + 1)):\n{listed}",
        tests.len()
    );
    for name in &tests {
        for kind in ["static", "shared"] {
            assert!(
                listed.contains(&format!("c.{kind}.{name}\n")),
                "no CTest c.{kind}.{name}"
            );
        }
    }
    let ctest = run(Command::new("ctest")
        .args(["--output-on-failure", "-j", "2"])
        .current_dir(&build)
        .env_remove("LD_LIBRARY_PATH"));
    assert!(ctest.contains("100% tests passed"), "{ctest}");
    step("ctest", start);

    // 3. Install into a fresh prefix.
    let _ = std::fs::remove_dir_all(&prefix);
    run(Command::new("cmake")
        .arg("--install")
        .arg(&build)
        .arg("--prefix")
        .arg(&prefix));
    let lib = prefix.join("lib");
    let version = env!("CARGO_PKG_VERSION");
    let major = env!("CARGO_PKG_VERSION_MAJOR");
    let real = format!("librollslide.so.{version}");
    // 0.x: every minor release may break the ABI, so the SONAME carries it (CMakeLists.txt).
    let soname = if major == "0" {
        format!("librollslide.so.0.{}", env!("CARGO_PKG_VERSION_MINOR"))
    } else {
        format!("librollslide.so.{major}")
    };
    assert_eq!(
        std::fs::read_link(lib.join(&soname)).unwrap(),
        Path::new(&real)
    );
    assert_eq!(
        std::fs::read_link(lib.join("librollslide.so")).unwrap(),
        Path::new(&soname)
    );
    assert!(lib.join("librollslide.a").is_file());
    let dynamic = dynamic_section(&lib.join(&real));
    assert!(
        dynamic.contains(&format!("Library soname: [{soname}]")),
        "the installed shared library lacks SONAME {soname}:\n{dynamic}"
    );
    assert_eq!(
        std::fs::read(prefix.join("include/rollslide.h")).unwrap(),
        std::fs::read(root().join("include/rollslide.h")).unwrap(),
        "installed header differs from include/rollslide.h"
    );
    assert_eq!(
        std::fs::read(prefix.join("include/rollslide.hpp")).unwrap(),
        std::fs::read(root().join("include/rollslide.hpp")).unwrap(),
        "installed C++ wrapper differs from include/rollslide.hpp"
    );
    let config =
        std::fs::read_to_string(lib.join("cmake/rollslide/rollslideConfig.cmake")).unwrap();
    let carried: Vec<String> = pinned_native_libs()
        .iter()
        .map(|f| f.trim_start_matches("-l").to_string())
        .collect();
    assert!(
        config.contains(&format!(
            "set(ROLLSLIDE_NATIVE_STATIC_LIBS \"{}\")",
            carried.join(";")
        )),
        "rollslideConfig.cmake does not carry {carried:?}:\n{config}"
    );
    step("install", start);

    // 4. The version file: a consumer asking for another minor version (0.x) is refused.
    let probe = work.join("version-probe");
    let _ = std::fs::remove_dir_all(&probe);
    std::fs::create_dir_all(&probe).unwrap();
    let minor: u32 = env!("CARGO_PKG_VERSION_MINOR").parse().unwrap();
    let wrong = if major == "0" {
        format!("0.{}", minor + 1)
    } else {
        format!("{}.0", major.parse::<u32>().unwrap() + 1)
    };
    std::fs::write(
        probe.join("CMakeLists.txt"),
        format!(
            "cmake_minimum_required(VERSION 3.16)\nproject(p LANGUAGES NONE)\n\
             find_package(rollslide {version} EXACT CONFIG REQUIRED)\n\
             find_package(rollslide {wrong} CONFIG QUIET)\n\
             if(rollslide_FOUND)\n  message(FATAL_ERROR \"{wrong} accepted\")\nendif()\n"
        ),
    )
    .unwrap();
    run(Command::new("cmake")
        .arg("-S")
        .arg(&probe)
        .arg("-B")
        .arg(probe.join("build"))
        .arg(format!("-DCMAKE_PREFIX_PATH={}", prefix.display())));

    // 5. examples/ against the installed package: static, then shared (RUNPATH).
    for (kind, extra) in [
        ("STATIC", "-DROLLSLIDE_USE_STATIC=ON"),
        ("SHARED", "-DROLLSLIDE_USE_STATIC=OFF"),
    ] {
        let dir = work.join(format!("examples-{}", kind.to_lowercase()));
        let _ = std::fs::remove_dir_all(&dir);
        let configured = run(Command::new("cmake")
            .arg("-S")
            .arg(root().join("examples"))
            .arg("-B")
            .arg(&dir)
            .arg(format!("-DCMAKE_PREFIX_PATH={}", prefix.display()))
            .args([
                "-DCMAKE_C_FLAGS=-Werror",
                "-DCMAKE_CXX_FLAGS=-Werror",
                extra,
            ]));
        assert!(
            configured.contains(&format!("rollslide {version} ({kind})")),
            "find_package did not select the {kind} library:\n{configured}"
        );
        run(Command::new("cmake")
            .arg("--build")
            .arg(&dir)
            .args(["--parallel", "2"]));
        for exe in [
            "decompose",
            "decompose_cpp",
            "rolling_pair",
            "rolling_on_wall",
            "calibration",
            "dem_heap",
            "parallel_forces",
        ] {
            let deps = needed(&dir.join(exe));
            let shared = deps.iter().any(|d| d == &soname);
            assert_eq!(
                shared,
                kind == "SHARED",
                "{exe} ({kind}) has NEEDED {deps:?}"
            );
            if kind == "SHARED" {
                let section = dynamic_section(&dir.join(exe));
                assert!(
                    section.contains(&lib.display().to_string()),
                    "{exe}: no RUNPATH to {}:\n{section}",
                    lib.display()
                );
            }
        }
        let ctest = run(Command::new("ctest")
            .arg("--output-on-failure")
            .current_dir(&dir)
            .env_remove("LD_LIBRARY_PATH"));
        assert!(ctest.contains("100% tests passed"), "{ctest}");
        let printed = run(&mut program(&dir.join("decompose")));
        assert!(printed.contains("rolling velocity v_r"), "{printed}");
        step(&format!("examples, {kind}"), start);
    }

    // 6. pkg-config: the shared library (found through LD_LIBRARY_PATH), and the static one.
    let pc_path = lib.join("pkgconfig");
    let pkg_config = |args: &[&str]| -> Vec<String> {
        run(Command::new("pkg-config")
            .args(args)
            .env("PKG_CONFIG_PATH", &pc_path))
        .split_whitespace()
        .map(str::to_string)
        .collect()
    };
    assert_eq!(pkg_config(&["--modversion", "rollslide"]), [version]);
    let private = pkg_config(&["--static", "--libs", "rollslide"]);
    for flag in pinned_native_libs() {
        assert!(
            private.contains(&flag),
            "pkg-config --static --libs rollslide lacks {flag}: {private:?}"
        );
    }
    let source = root().join("examples/decompose.c");
    let pc_dir = work.join("pkg-config");
    std::fs::create_dir_all(&pc_dir).unwrap();
    for (name, args) in [
        ("shared", vec!["--cflags", "--libs", "rollslide"]),
        (
            "static",
            vec!["--static", "--cflags", "--libs", "rollslide-static"],
        ),
    ] {
        let exe = pc_dir.join(format!("decompose_{name}"));
        run(Command::new("cc")
            .args(["-std=c11", "-Wall", "-Wextra", "-Werror", "-pedantic"])
            .arg(&source)
            .args(pkg_config(&args))
            .arg("-o")
            .arg(&exe));
        let deps = needed(&exe);
        assert_eq!(
            deps.contains(&soname),
            name == "shared",
            "decompose_{name} has NEEDED {deps:?}"
        );
        let mut cmd = program(&exe);
        if name == "shared" {
            cmd.env("LD_LIBRARY_PATH", &lib);
        }
        let printed = run(&mut cmd);
        assert!(printed.contains("rolling velocity v_r"), "{printed}");
    }
    step("pkg-config", start);
}

/// The libraries rustc says a static library needs, for an empty crate (std's needs; this crate's
/// dependencies add none: the examples link the real library with exactly the pinned list).
fn rustc_native_static_libs() -> Vec<String> {
    let dir = work().join("native-static-libs");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("probe.rs"), "pub fn probe() {}\n").unwrap();
    let rustc = std::env::var("RUSTC").unwrap_or_else(|_| "rustc".to_string());
    let text = run(Command::new(rustc)
        .args(["--crate-type", "staticlib", "--crate-name", "probe"])
        .args(["--print", "native-static-libs", "-o"])
        .arg(dir.join("libprobe.a"))
        .arg(dir.join("probe.rs")));
    let line = text
        .lines()
        .find_map(|l| l.split("native-static-libs:").nth(1))
        .unwrap_or_else(|| panic!("rustc printed no native-static-libs:\n{text}"));
    line.split_whitespace().map(str::to_string).collect()
}

#[test]
fn native_static_libs_are_pinned() {
    let printed = rustc_native_static_libs();
    let pinned: BTreeSet<String> = pinned_native_libs().into_iter().collect();
    let missing: Vec<&String> = printed.iter().filter(|l| !pinned.contains(*l)).collect();
    assert!(
        missing.is_empty(),
        "`rustc --print native-static-libs` now asks for {missing:?} (all: {printed:?}); add \
         them to cmake/native-static-libs.txt (the CMake package and the pkg-config files), \
         the cc line of README.md and run-demo.sh (the tests read the file)"
    );
    // The other places that spell the list out must carry all of it too.
    for file in ["README.md", "run-demo.sh"] {
        let text = std::fs::read_to_string(root().join(file)).unwrap();
        for flag in &pinned {
            assert!(
                text.contains(&format!("\"{flag}\"")) || text.contains(&format!(" {flag}")),
                "{file} does not link {flag} (cmake/native-static-libs.txt lists it)"
            );
        }
    }
}
