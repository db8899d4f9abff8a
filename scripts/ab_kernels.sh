#!/usr/bin/env bash
# Before/after comparison of two builds of the library on the benchmark driver (bench/bench.c):
# links the driver to each static library, runs them alternately ROUNDS times (each run from a
# fresh copy of its driver's file), and prints the median ns per contact of every row for both
# and their ratio (after / before). Alternating runs close in time are what shows a change of a
# few percent on a host where single runs of a row scatter by more.
#
#   [REPS=N] scripts/ab_kernels.sh BEFORE.a AFTER.a [CONTACTS, 1200000] [ROUNDS, 5] [ROW SUBSTRING] [driver options...]
#
# Build the two libraries with separate target directories, e.g.
#   git stash; cargo build --release --lib; cp target/release/librollslide.a /tmp/before.a; git stash pop
#   cargo build --release --lib; scripts/ab_kernels.sh /tmp/before.a target/release/librollslide.a 2000 5 batch_f
# Driver options pass through (--workload=B, --slip=0, --level=avx2 for the contacts_ rows).
# At 1.2M contacts a kernel's time moves by 10-20% with where the stack lies modulo 4 KB, which
# address-space randomisation changes at every run (scripts/placement_sweep.sh measures the
# spread): that is why the rounds alternate and the medians are compared.
# MALLOC_MMAP_THRESHOLD_=4000000000 in the environment places the driver's arrays differently,
# another placement to check against.
# The memory floors and the hand-written loops are printed too: the same code on both sides
# when only the library differs, so their ratios show how much the host moved between runs.
# Besides the medians' ratio it prints the ratios of the lower quartiles and of the minima: on a
# shared virtual machine whose runs of one binary fall into a fast and a slow mode (up to 1.7x
# apart), the fast mode is what compares the code.
# AFTER_ENV (environment): variables set for the after side's runs only, e.g. to compare one
# library with and without huge pages for the host's arrays:
#   AFTER_ENV=GLIBC_TUNABLES=glibc.malloc.hugetlb=1 scripts/ab_kernels.sh L.a L.a 1200000 5 ''
# REPS (environment, default 3) is the number of timed calls per row and run, of which the
# driver reports the fastest. On the 2-core Zen 3 virtual machine of docs/performance.md the
# slow mode comes and goes while a process runs (the SIMD rows more than the hand-written
# loops; with address-space randomisation off, one stack offset gave both modes), so more
# calls per run find the fast one: in cache, six runs of 40 calls gave the double AVX2 full
# set 52.8-56.4 ns per contact in five of them (74.0 in one), where six runs of 3 calls gave
# 59.7-105.8. With REPS=15 in cache (6-8 rounds) the minima of the hand-written loops, the
# same code on both sides, differed by at most 3%.
set -euo pipefail
before=$1
after=$2
contacts=${3:-1200000}
rounds=${4:-5}
only=${5:-}
shift $(( $# < 5 ? $# : 5 ))
cd "$(dirname "$0")/.."
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
for side in before after; do
  lib=${!side}
  scripts/build_driver.sh "$lib" "$tmp/$side"
done
for _ in $(seq "$rounds"); do
  for side in before after; do
    extra=()
    if [ "$side" = after ] && [ -n "${AFTER_ENV:-}" ]; then
      read -ra extra <<<"$AFTER_ENV"
    fi
    # Each run from a fresh copy of the driver's file: the code's placement in memory comes
    # with the file's page-cache pages, and every run of one file shares them (docs/performance.md,
    # "Where the driver's file lies"); a copy per run draws a new placement each time.
    cp "$tmp/$side" "$tmp/run"
    env "${extra[@]}" "$tmp/run" "$contacts" "${REPS:-3}" --workload=A --only="$only" "$@" 2>&1 |
      awk -v s="$side" '/^row/ {print s, $2 ":" $3, $4}'
    rm -f "$tmp/run"
  done
done >"$tmp/runs"
python3 - "$tmp/runs" <<'PY'
import collections, statistics, sys
v = collections.defaultdict(list)
for line in open(sys.argv[1]):
    side, row, ns = line.split()
    v[(row, side)].append(float(ns))
def quartile(x):
    return sorted(x)[(len(x) - 1) // 4]
for row in sorted({r for r, _ in v}):
    b, a = v.get((row, "before")), v.get((row, "after"))
    if b and a:
        mb, ma = statistics.median(b), statistics.median(a)
        print(f"{row:48s} before {mb:7.2f}  after {ma:7.2f}  ratio {ma / mb:.3f}"
              f"  lower quartile {quartile(a) / quartile(b):.3f}  min {min(a) / min(b):.3f}"
              f"  (n={len(b)})")
PY
