// Forwards the target and host triples to the integration tests, which compile the C tests
// with the `cc` crate outside a build script (cc needs to know the target there).
fn main() {
    for var in ["TARGET", "HOST"] {
        let value = std::env::var(var).unwrap_or_default();
        println!("cargo:rustc-env=RSL_BUILD_{var}={value}");
    }
    println!("cargo:rerun-if-changed=build.rs");
}
