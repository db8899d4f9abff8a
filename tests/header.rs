//! The committed header `include/rollslide.h` must be exactly what cbindgen generates from the
//! sources. Regenerate with `RSL_BLESS_HEADER=1 cargo test --test header`.

use std::path::Path;

#[test]
fn committed_header_matches_cbindgen_output() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let config = cbindgen::Config::from_file(root.join("cbindgen.toml")).expect("cbindgen.toml");
    let bindings = cbindgen::Builder::new()
        .with_crate(root)
        .with_config(config)
        .generate()
        .expect("cbindgen failed to parse the crate");
    let mut generated = Vec::new();
    bindings.write(&mut generated);
    let generated = for_c_readers(String::from_utf8(generated).unwrap());
    let path = root.join("include/rollslide.h");
    if std::env::var_os("RSL_BLESS_HEADER").is_some() {
        std::fs::write(&path, &generated).unwrap();
        return;
    }
    let committed = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        committed == generated,
        "include/rollslide.h is stale: run `RSL_BLESS_HEADER=1 cargo test --test header` and commit it"
    );
}

/// The doc comments are written for both Rust (where an `unsafe fn` documents its contract
/// under `# Safety`, which clippy checks) and C readers: the header names that section in C
/// terms.
fn for_c_readers(header: String) -> String {
    header.replace(
        "// # Safety\n",
        "// Preconditions (the behaviour is undefined if they do not hold):\n",
    )
}

/// No Rust notation reaches the C header: Rust doc sections and links, Rust types, casts and
/// paths, the word itself.
#[test]
fn header_has_no_rust_notation() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let header = std::fs::read_to_string(root.join("include/rollslide.h")).unwrap();
    let rust = [
        "# Safety", "[`", "`]", "Option<", "Vec<", "&mut ", "&self", "::", " as u8", " as i32",
        " as u32", "Some(", "`None`", "Result<", "Rust", "panic", "unwrap", "impl ",
    ];
    let found: Vec<String> = header
        .lines()
        .enumerate()
        .filter(|(_, line)| line.trim_start().starts_with("//"))
        .flat_map(|(i, line)| {
            rust.iter()
                .filter(move |r| line.contains(*r))
                .map(move |r| format!("line {}: `{r}` in {line}", i + 1))
        })
        .collect();
    assert!(
        found.is_empty(),
        "Rust notation in the header:\n{}",
        found.join("\n")
    );
}

#[test]
fn header_version_macros_equal_cargo_version() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let header = std::fs::read_to_string(root.join("include/rollslide.h")).unwrap();
    for (name, value) in [
        ("RSL_VERSION_MAJOR", env!("CARGO_PKG_VERSION_MAJOR")),
        ("RSL_VERSION_MINOR", env!("CARGO_PKG_VERSION_MINOR")),
        ("RSL_VERSION_PATCH", env!("CARGO_PKG_VERSION_PATCH")),
    ] {
        let line = format!("#define {name} {value}\n");
        assert!(header.contains(&line), "header lacks `{}`", line.trim());
    }
}

/// The file-scope identifiers a header declares: macro names, struct and enum tags, typedef
/// names, enumeration constants and function names (a small scanner for the shapes cbindgen
/// writes; comments are skipped).
fn file_scope_identifiers(header: &str) -> Vec<String> {
    let ident = |s: &str| -> String {
        s.chars()
            .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
            .collect()
    };
    let mut names = Vec::new();
    let mut depth = 0i32;
    let mut in_enum = false;
    for line in header.lines() {
        let code = line.split("//").next().unwrap_or("").trim();
        if code.is_empty() || code.starts_with("/*") || code.starts_with('*') {
            continue;
        }
        if let Some(rest) = code.strip_prefix("#define ") {
            names.push(ident(rest));
            continue;
        }
        if code.starts_with('#') || code == "extern \"C\" {" || code.starts_with("} //") {
            continue;
        }
        if depth == 0 {
            for keyword in ["struct ", "enum ", "union "] {
                if let Some(at) = code.find(keyword) {
                    let tag = ident(&code[at + keyword.len()..]);
                    if !tag.is_empty() {
                        names.push(tag);
                    }
                    if keyword == "enum " && code.ends_with('{') {
                        in_enum = true;
                    }
                }
            }
            if let Some(open) = code.find('(') {
                // A function declaration: the identifier just before the first '('.
                let before = code[..open].trim_end();
                let start = before
                    .rfind(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
                    .map_or(0, |i| i + 1);
                names.push(before[start..].to_string());
            }
        } else if depth == 1 && code.starts_with('}') {
            // `} name;` closes a typedef.
            let name = ident(code.trim_start_matches('}').trim());
            if !name.is_empty() {
                names.push(name);
            }
        } else if in_enum {
            let name = ident(code);
            if !name.is_empty() {
                names.push(name);
            }
        }
        depth += code.matches('{').count() as i32 - code.matches('}').count() as i32;
        if depth == 0 {
            in_enum = false;
        }
    }
    names.retain(|n| !n.is_empty());
    names
}

fn prefixed(name: &str) -> bool {
    ["rsl_", "RSL_", "ROLLSLIDE_"]
        .iter()
        .any(|p| name.starts_with(p))
}

/// Every identifier the header puts in an includer's file scope carries the library's prefix,
/// so that no name of the host's own (an `enum Scene { Generic }`, an `int MAX_LANES`) can
/// clash with it.
#[test]
fn every_file_scope_identifier_of_the_header_is_prefixed() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let header = std::fs::read_to_string(root.join("include/rollslide.h")).unwrap();
    let names = file_scope_identifiers(&header);
    // The scanner sees each kind of declaration (else this test could not fail).
    for expected in [
        "ROLLSLIDE_H",
        "RSL_OK",
        "rsl_sphere",
        "rsl_contact_state",
        "rsl_batch_step",
        "rsl_model_new",
    ] {
        assert!(
            names.iter().any(|n| n == expected),
            "scanner missed {expected}"
        );
    }
    let bad: Vec<&String> = names.iter().filter(|n| !prefixed(n)).collect();
    assert!(bad.is_empty(), "unprefixed file-scope identifiers: {bad:?}");
}

/// The scanner flags the leaks it is there to catch.
#[test]
fn the_identifier_scanner_flags_unprefixed_names() {
    let leaky = "#define MAX_LANES 8\n\
                 // A comment with Generic in it.\n\
                 enum Scene {\n  Generic,\n  FullExact = 1,\n};\n\
                 typedef struct rsl_ok {\n  double x;\n} rsl_ok;\n\
                 typedef struct Inner {\n  int32_t y;\n} Outer;\n\
                 int32_t rsl_fine(const struct rsl_ok *a);\n\
                 void leak(void);\n";
    let names = file_scope_identifiers(leaky);
    let bad: Vec<&str> = names
        .iter()
        .map(String::as_str)
        .filter(|n| !prefixed(n))
        .collect();
    assert_eq!(
        bad,
        [
            "MAX_LANES",
            "Scene",
            "Generic",
            "FullExact",
            "Inner",
            "Outer",
            "leak"
        ]
    );
    assert!(names.iter().any(|n| n == "rsl_fine"));
}

/// The header's documentation only cites files a user has: every `*.md` it names exists in the
/// repository (it once cited the team's specification files, which are not shipped).
#[test]
fn header_cites_only_files_in_the_repository() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let header = std::fs::read_to_string(root.join("include/rollslide.h")).unwrap();
    for word in header.split(|c: char| c.is_whitespace() || "()`,;:".contains(c)) {
        let word = word.trim_end_matches('.');
        if word.ends_with(".md") {
            assert!(
                root.join(word).is_file(),
                "the header cites {word}, which is not in the repository"
            );
        }
    }
}
