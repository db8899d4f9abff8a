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
    let generated = String::from_utf8(generated).unwrap();
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
