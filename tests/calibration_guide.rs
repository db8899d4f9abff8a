//! docs/calibration.md quotes the output of examples/calibration.c. This test compiles the
//! program against the static library that `cargo test` built, as tests/c_tests.rs does (the
//! `cc` crate, `-std=c11 -Wall -Wextra -Werror -pedantic`, the system libraries pinned in
//! cmake/native-static-libs.txt), runs it (it exits non-zero when one of its own physics checks
//! fails), and fails if the guide's output block is not exactly what the program printed, or if
//! the prose of the guide's worked examples quotes a number the program did not print.

use std::process::Command;
use std::sync::OnceLock;

mod common;
use common::linking::{c_program_command, deps_dir, remove_test_program, root};

/// The line before the guide's ```text block that holds the program's output.
const MARKER: &str =
    "<!-- output of examples/calibration.c, checked by tests/calibration_guide.rs -->";

/// The section of the guide whose prose may quote only numbers the program printed.
const SECTION: &str = "## Worked examples";

fn run(mut cmd: Command, what: &str) -> Result<String, String> {
    let out = cmd
        .output()
        .map_err(|e| format!("{what}: cannot run: {e}"))?;
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    if out.status.success() {
        Ok(stdout)
    } else {
        Err(format!(
            "{what} failed ({}):\n{stdout}{}",
            out.status,
            String::from_utf8_lossy(&out.stderr)
        ))
    }
}

/// Compiles and runs examples/calibration.c once; its standard output.
fn program_output() -> &'static Result<String, String> {
    static OUTPUT: OnceLock<Result<String, String>> = OnceLock::new();
    OUTPUT.get_or_init(|| {
        let work = deps_dir().join("../calibration_guide_build");
        std::fs::create_dir_all(&work).unwrap();
        let exe = work.join("calibration");
        let cmd = c_program_command(
            &[root().join("examples/calibration.c")],
            &[] as &[&str],
            &exe,
        );
        run(cmd, "compiling examples/calibration.c")?;
        let output = run(Command::new(&exe), "running examples/calibration.c")?;
        remove_test_program(&exe);
        Ok(output)
    })
}

fn guide() -> String {
    std::fs::read_to_string(root().join("docs/calibration.md")).unwrap()
}

/// The ```text block that follows the marker line, without its fences.
fn output_block(guide: &str) -> Option<&str> {
    let after = guide.split_once(&format!("{MARKER}\n"))?.1;
    let body = after.strip_prefix("```text\n")?;
    let end = body.find("\n```")?;
    Some(&body[..end + 1])
}

/// The text of the section headed `heading`, up to the next `## ` heading.
fn section<'a>(guide: &'a str, heading: &str) -> Option<&'a str> {
    let start = guide.find(&format!("\n{heading}\n"))? + 1;
    let rest = &guide[start + heading.len()..];
    let end = rest.find("\n## ").map_or(rest.len(), |i| i + 1);
    Some(&guide[start..start + heading.len() + end])
}

/// The numbers written in `text`: a digit not preceded by a letter, digit, `_` or `.`, then
/// digits and dots, and an exponent (`e-06`, `E+10`) if one follows; a trailing dot (the end
/// of a sentence) is dropped. Signs are left out.
fn numbers_in(text: &str) -> Vec<String> {
    let chars: Vec<char> = text.chars().collect();
    let mut found = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        let starts = chars[i].is_ascii_digit()
            && (i == 0 || !(chars[i - 1].is_alphanumeric() || "_.".contains(chars[i - 1])));
        if !starts {
            i += 1;
            continue;
        }
        let mut j = i;
        while j < chars.len() && (chars[j].is_ascii_digit() || chars[j] == '.') {
            j += 1;
        }
        if j < chars.len() && "eE".contains(chars[j]) {
            let mut k = j + 1;
            if k < chars.len() && "+-".contains(chars[k]) {
                k += 1;
            }
            if k < chars.len() && chars[k].is_ascii_digit() {
                while k < chars.len() && chars[k].is_ascii_digit() {
                    k += 1;
                }
                j = k;
            }
        }
        let number: String = chars[i..j].iter().collect();
        found.push(number.trim_end_matches('.').to_string());
        i = j;
    }
    found
}

/// The numbers of `prose` that `output` does not contain.
fn unprinted_numbers(prose: &str, output: &str) -> Vec<String> {
    numbers_in(prose)
        .into_iter()
        .filter(|n| !output.contains(n.as_str()))
        .collect()
}

#[test]
fn calibration_example_runs_and_passes_its_checks() {
    let output = program_output().as_ref().unwrap_or_else(|e| panic!("{e}"));
    assert!(
        output.ends_with("all checks passed\n"),
        "examples/calibration.c printed:\n{output}"
    );
}

#[test]
fn guide_block_is_the_program_output() {
    let output = program_output().as_ref().unwrap_or_else(|e| panic!("{e}"));
    let guide = guide();
    let block = output_block(&guide).unwrap_or_else(|| {
        panic!("docs/calibration.md lacks the line `{MARKER}` followed by a ```text block")
    });
    if block != output {
        let first = block
            .lines()
            .zip(output.lines())
            .position(|(a, b)| a != b)
            .unwrap_or(block.lines().count().min(output.lines().count()));
        panic!(
            "docs/calibration.md's output block differs from what examples/calibration.c prints, \
             from line {} on (guide: {:?}, program: {:?}); paste the program's output:\n{output}",
            first + 1,
            block.lines().nth(first),
            output.lines().nth(first)
        );
    }
}

#[test]
fn guide_prose_quotes_only_printed_numbers() {
    let output = program_output().as_ref().unwrap_or_else(|e| panic!("{e}"));
    let guide = guide();
    let text = section(&guide, SECTION)
        .unwrap_or_else(|| panic!("docs/calibration.md lacks the section `{SECTION}`"));
    let block = output_block(&guide).expect("no output block");
    assert!(
        text.contains(block),
        "the output block is not in `{SECTION}`"
    );
    let prose = text.replacen(block, "", 1);
    let missing = unprinted_numbers(&prose, output);
    assert!(
        missing.is_empty(),
        "`{SECTION}` of docs/calibration.md quotes numbers examples/calibration.c does not print: \
         {missing:?}"
    );
}

/// The helpers find what they are there to find (else the tests above could not fail).
#[test]
fn the_checks_flag_what_they_should() {
    assert_eq!(
        numbers_in("k_n = 1.153e+06 N/m, R_r^2, l1 and 0.1897 rad. Step 7855 (of 2e-3)."),
        ["1.153e+06", "2", "0.1897", "7855", "2e-3"]
    );
    let printed = "k_n = 1.153e+06 N/m\nslipping from step 7855\n";
    assert!(unprinted_numbers("k_n is 1.153e+06 N/m, step 7855", printed).is_empty());
    assert_eq!(
        unprinted_numbers("k_n is 1.154e+06 N/m", printed),
        ["1.154e+06"]
    );
    let doc = format!(
        "# T\n\n{SECTION}\n\nSee:\n\n{MARKER}\n```text\nline 1\nline 2\n```\n\nAfter.\n\n## Next\n"
    );
    assert_eq!(output_block(&doc), Some("line 1\nline 2\n"));
    let text = section(&doc, SECTION).unwrap();
    assert!(
        text.starts_with(SECTION) && text.trim_end().ends_with("After.") && !text.contains("Next")
    );
}
