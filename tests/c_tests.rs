//! Compiles the C test programs of `c_tests/` with the `cc` crate (`-std=c11 -Wall -Wextra
//! -Werror`), links them against the static library that `cargo test` just built, and reports
//! each C test function (listed in `c_tests/tests.def`) as its own test. Also compiles the
//! header as C++, the C++ wrapper's tests (`c_tests/test_wrapper.cpp`) and the C snippet of
//! README.md.

use libtest_mimic::{Arguments, Failed, Trial};
use std::path::{Path, PathBuf};
use std::process::Command;

mod common;
use common::linking::{
    c_program_command, compiler, deps_dir, link_test_program, remove_test_program, root,
};

fn run(mut cmd: Command, what: &str) -> Result<String, String> {
    let out = cmd
        .output()
        .map_err(|e| format!("{what}: cannot run: {e}"))?;
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    if out.status.success() {
        Ok(text)
    } else {
        Err(format!("{what} failed ({}):\n{text}", out.status))
    }
}

/// Compiles C sources into an executable linked against the static library.
fn build_c_program(sources: &[PathBuf], exe: &Path) -> Result<(), String> {
    let extra = [
        format!("-DRSL_SOURCE_DIR=\"{}\"", root().display()),
        "-I".to_string(),
        root().join("c_tests").display().to_string(),
    ];
    let cmd = c_program_command(sources, &extra, exe);
    run(cmd, &format!("compiling {}", exe.display())).map(|_| ())
}

fn c_test_sources() -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(root().join("c_tests"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "c"))
        .collect();
    v.sort();
    v
}

/// The ```c (`fence` "c") or ```cpp block of README.md right after a marker `<!-- compiled by
/// tests/c_tests.rs -->`.
fn readme_snippet(fence: &str) -> String {
    let readme = std::fs::read_to_string(root().join("README.md")).unwrap();
    let opening = format!("```{fence}\n");
    readme
        .split("<!-- compiled by tests/c_tests.rs -->")
        .skip(1)
        .find_map(|after| after.trim_start().strip_prefix(opening.as_str()))
        .map(|body| body.split("```").next().unwrap().to_string())
        .unwrap_or_else(|| panic!("README.md has no marked ```{fence} block"))
}

/// README's C++ snippet (a statement sequence on `body1`, `body2`, `input`) inside a program
/// that gives it two touching spheres and an input, and checks the loads it returns.
fn readme_cpp_program() -> String {
    format!(
        "#include \"rollslide.hpp\"\n#include <cstdio>\n\
         static rsl_contact_loads snippet(const rsl_sphere &body1, const rsl_sphere &body2,\n\
                                          const rsl_contact_input &input) {{\n{}\n\
         return loads;\n}}\n\
         int main() {{\n\
         rsl_sphere a = {{{{0, 0, 0}}, {{0, 0.1, 0}}, {{0, 0, 1}}, 0.5}};\n\
         rsl_sphere b = {{{{0.99, 0, 0}}, {{0, 0, 0}}, {{0, 0, 0}}, 0.5}};\n\
         rsl_contact_input in = rsl_contact_input();\n\
         in.normal_force = 10.0; in.dt = 1e-4;\n\
         rsl_contact_loads l = snippet(a, b, in);\n\
         std::printf(\"force on body 1 %g %g %g\\n\", l.force1.x, l.force1.y, l.force1.z);\n\
         return l.force1.x == -10.0 && l.force1.y < 0.0 ? 0 : 1;\n}}\n",
        readme_snippet("cpp")
    )
}

fn main() {
    let args = Arguments::from_args();
    let work = deps_dir().join("../c_tests_build");
    std::fs::create_dir_all(&work).unwrap();
    let exe = work.join("c_tests");
    let built = build_c_program(&c_test_sources(), &exe);

    let mut trials = Vec::new();
    match &built {
        Ok(()) => {
            let list = run(
                {
                    let mut c = Command::new(&exe);
                    c.arg("--list");
                    c
                },
                "c_tests --list",
            )
            .expect("listing the C tests");
            let show = args.nocapture;
            for name in list.lines().map(str::to_owned) {
                let exe = exe.clone();
                trials.push(Trial::test(format!("c::{name}"), move || {
                    let mut c = Command::new(&exe);
                    c.arg(&name);
                    let printed = run(c, &name).map_err(Failed::from)?;
                    if show {
                        print!("{printed}");
                    }
                    Ok(())
                }));
            }
        }
        Err(e) => {
            let e = e.clone();
            trials.push(Trial::test("c::build", move || Err(Failed::from(e))));
        }
    }

    let work2 = work.clone();
    trials.push(Trial::test("header_compiles_as_cpp", move || {
        let src = work2.join("header_cxx.cpp");
        std::fs::write(
            &src,
            // A host's own names that an unprefixed header name would clash with (the
            // header once declared `enum Scene { Generic, ... }`, `MAX_LANES`, `SLIP_*`).
            "#include \"rollslide.h\"\n#include <cstring>\n\
             enum Scene { Generic, FullExact };\n\
             static const int MAX_LANES = 4, SLIP_SLIDING = 8, SLIP_ROLLING = 16;\n\
             int main() { rsl_vec3 v = {1.0, 2.0, 3.0}; (void)v;\n\
             Scene s = FullExact;\n\
             if (s == Generic || MAX_LANES + SLIP_SLIDING + SLIP_ROLLING != 28) return 2;\n\
             return std::strlen(rsl_version()) > 0 ? 0 : 1; }\n",
        )
        .unwrap();
        let out = work2.join("header_cxx");
        let mut cmd = compiler(true).to_command();
        cmd.args(["-std=c++11", "-Wall", "-Wextra", "-Werror", "-pedantic"])
            .arg("-I")
            .arg(root().join("include"))
            .arg(&src);
        link_test_program(&mut cmd, &out);
        run(cmd, "compiling the header as C++")?;
        run(Command::new(&out), "running the C++ program")?;
        remove_test_program(&out);
        Ok(())
    }));

    // The C++ wrapper: C++11 and C++17, g++ (the cc crate's C++ compiler) and clang++ where it
    // is installed (`.ci/run` installs it).
    let clang = Command::new("clang++").arg("--version").output().is_ok();
    for (name, std) in [
        ("cpp_wrapper_cxx11", "c++11"),
        ("cpp_wrapper_cxx17", "c++17"),
    ] {
        for use_clang in [false, true] {
            let work4 = work.clone();
            let label = format!("{name}_{}", if use_clang { "clang" } else { "gcc" });
            // Without clang++ its trials are listed as ignored (run them with
            // `--include-ignored` to see the error).
            let trial = Trial::test(label.clone(), move || {
                if use_clang && !clang {
                    return Err("clang++ is not installed (apt-get install clang)".into());
                }
                let exe = work4.join(&label);
                let mut cmd = if use_clang {
                    Command::new("clang++")
                } else {
                    compiler(true).to_command()
                };
                cmd.arg(format!("-std={std}"))
                    .args(["-O1", "-Wall", "-Wextra", "-Werror", "-pedantic"])
                    .arg("-I")
                    .arg(root().join("include"))
                    .arg(root().join("c_tests/test_wrapper.cpp"));
                link_test_program(&mut cmd, &exe);
                run(cmd, &format!("compiling rollslide.hpp's test ({label})"))?;
                let printed = run(Command::new(&exe), &label)?;
                if !printed.contains("all checks passed") {
                    return Err(format!("{label} printed:\n{printed}").into());
                }
                remove_test_program(&exe);
                Ok(())
            });
            trials.push(trial.with_ignored_flag(use_clang && !clang));
        }
    }

    let work3 = work.clone();
    trials.push(Trial::test(
        "readme_c_snippet_compiles_and_runs",
        move || {
            let src = work3.join("readme_snippet.c");
            std::fs::write(&src, readme_snippet("c")).unwrap();
            let out = work3.join("readme_snippet");
            build_c_program(&[src], &out)?;
            let printed = run(Command::new(&out), "running the README snippet")?;
            if !printed.contains("rolling velocity") {
                return Err(format!("README snippet printed unexpected output:\n{printed}").into());
            }
            remove_test_program(&out);
            Ok(())
        },
    ));

    let work4 = work.clone();
    trials.push(Trial::test(
        "readme_cpp_snippet_compiles_and_runs",
        move || {
            let src = work4.join("readme_snippet.cpp");
            std::fs::write(&src, readme_cpp_program()).unwrap();
            let out = work4.join("readme_snippet_cpp");
            let mut cmd = compiler(true).to_command();
            cmd.args(["-std=c++11", "-Wall", "-Wextra", "-Werror"])
                .arg("-I")
                .arg(root().join("include"))
                .arg(&src);
            link_test_program(&mut cmd, &out);
            run(cmd, "compiling README's C++ snippet")?;
            run(Command::new(&out), "running README's C++ snippet")?;
            remove_test_program(&out);
            Ok(())
        },
    ));

    let conclusion = libtest_mimic::run(&args, trials);
    // The C tests' program stays after a failure, to be rerun by hand (it has no line tables).
    if !conclusion.has_failed() {
        remove_test_program(&exe);
    }
    conclusion.exit();
}
