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
# says what is missing and exits 0 without them. Takes 19-32 minutes on 2 cores, most of it the
# batch tests under emulation (12 min on the Zen 5 host of docs/performance.md, 28 on the Zen 3
# one); the builds, unoptimised, about 2 minutes. Builds into target/aarch64.
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
cargo test --target "$target" --lib --test batch --test closed_form --test cohesion \
  --test fast_path --test laws --test objectivity --test preset_lammps --test preset_liggghts \
  --test state_swap --test stress "$@"
