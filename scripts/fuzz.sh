#!/usr/bin/env bash
# Bounded fuzzing of the C entry points (fuzz/, cargo-fuzz + libFuzzer, AddressSanitizer on the
# Rust code and debug assertions on). Each target starts from its committed seeds
# (fuzz/corpus/<target>/seed-*, made by fuzz/make_seeds.py) and runs for FUZZ_SECONDS
# (default 30); any panic, abort, sanitizer report or failed invariant (see
# fuzz/fuzz_targets/common.rs) fails the run, and libFuzzer leaves the input in
# fuzz/artifacts/<target>/. New corpus entries go to a scratch directory, not to the tree.
#
# cargo-fuzz needs nightly-only rustc flags (-Zsanitizer...): with the stable toolchain,
# RUSTC_BOOTSTRAP=1 unlocks them (no other toolchain can be fetched here).
#
# RUSTFLAGS in the environment reach the build (cargo-fuzz appends them to its own flags).
#
# Usage: scripts/fuzz.sh [target...]     Env: FUZZ_SECONDS, FUZZ_NICE (default 19), RUSTFLAGS
set -euo pipefail
cd "$(dirname "$0")/../fuzz"
seconds=${FUZZ_SECONDS:-30}
nice_level=${FUZZ_NICE:-19}
command -v cargo-fuzz > /dev/null 2>&1 || cargo install cargo-fuzz --locked
export RUSTC_BOOTSTRAP=1
targets=("$@")
[ ${#targets[@]} -gt 0 ] || mapfile -t targets < <(cargo fuzz list)
nice -n "$nice_level" cargo fuzz build -O --debug-assertions
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
for t in "${targets[@]}"; do
  mkdir -p "$scratch/$t"
  echo "== fuzz $t for ${seconds}s"
  # -timeout: one input taking > 10 s is a hang; -rss_limit_mb: 2 GiB.
  nice -n "$nice_level" cargo fuzz run -O --debug-assertions "$t" "$scratch/$t" "corpus/$t" -- \
    -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
    > "$scratch/$t.log" 2>&1 || { tail -60 "$scratch/$t.log"; echo "fuzz $t FAILED"; exit 1; }
  grep -E "stat::(number_of_executed_units|average_exec_per_sec|new_units_added|peak_rss_mb)" \
    "$scratch/$t.log" | sed "s/^/  $t /"
done
echo "fuzz: ${#targets[@]} targets, no crash"
