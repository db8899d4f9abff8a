#!/bin/sh
# The library on a second architecture: builds it for aarch64-unknown-linux-gnu (where the batch
# calls have no SIMD level: `RSL_SIMD_AUTO` gives the one-lane kernel), checks that the build is
# free of warnings there (clippy, every target), and runs the Rust tests that need neither a C
# compiler at run time nor an external program under qemu's user-mode emulator: the unit tests,
# the batch equalities, the closed forms, objectivity, the laws, the LAMMPS and LIGGGHTS
# references, cohesion, the fast path, state swaps and the stress runs.
#
#   scripts/aarch64.sh [cargo test arguments]
#
# Needs the rustup target `aarch64-unknown-linux-gnu`, the cross linker `aarch64-linux-gnu-gcc`
# (Debian: gcc-aarch64-linux-gnu, libc6-dev-arm64-cross) and `qemu-aarch64` (Debian: qemu-user);
# says what is missing and exits 0 without them. Builds into target/aarch64.
#
# The tests run in the optimised `stress` profile (opt-level 3, with the debug assertions and
# overflow checks of the `test` profile): optimised code, as an aarch64 user runs it, with every
# check the unoptimised tests have; unoptimised code is what x86-64's `cargo test` runs. On the
# 2-core Zen 3 host of docs/performance.md, the same day: unoptimised, the script took 1,332 s,
# of which the batch test under emulation 1,193 s (1,680 s on a slower day); in this profile
# 184-189 s (clippy 26 s, the optimised build of the tests 2m04s, all the tests 35 s, the batch
# test 30-31 s).
set -eu
cd "$(dirname "$0")/.."
target=aarch64-unknown-linux-gnu
missing=
rustup target list --installed 2>/dev/null | grep -qx "$target" || missing="$missing rustup-target:$target"
command -v aarch64-linux-gnu-gcc >/dev/null 2>&1 || missing="$missing aarch64-linux-gnu-gcc"
command -v qemu-aarch64 >/dev/null 2>&1 || missing="$missing qemu-aarch64"
if [ -n "$missing" ]; then
  echo "scripts/aarch64.sh: skipped, missing:$missing"
  exit 0
fi
export CARGO_TARGET_DIR=target/aarch64
export CARGO_TARGET_AARCH64_UNKNOWN_LINUX_GNU_LINKER=aarch64-linux-gnu-gcc
export CARGO_TARGET_AARCH64_UNKNOWN_LINUX_GNU_RUNNER="qemu-aarch64 -L /usr/aarch64-linux-gnu"
export CC_aarch64_unknown_linux_gnu=aarch64-linux-gnu-gcc
cargo clippy --target "$target" --all-targets -- -D warnings
cargo test --profile stress --target "$target" --lib --test batch --test closed_form --test cohesion \
  --test fast_path --test laws --test objectivity --test preset_lammps --test preset_liggghts \
  --test state_swap --test stress "$@"
