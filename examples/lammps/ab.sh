#!/usr/bin/env bash
# Before/after comparison of two builds of lmp_rollslide: runs them alternately ROUNDS times on
# the packing of bench.sh (law A and law B, `lammps` preset, one rank) and prints the median Pair
# time of each and their ratio (after / before). Single runs move by several percent on a shared
# machine; alternating runs close in time show a change of a few percent.
#
#   examples/lammps/ab.sh <lmp before> <lmp after> [rounds, 5] [cells per side, 24] [steps, 1000]
#
# Keep the first binary before rebuilding: cp build-lammps/lmp_rollslide /tmp/lmp_before.
# PRESET (environment): the style's mode, `lammps` (default) or `objective`.
# To compare two builds of the library under one lmp_rollslide, give as <lmp before> a script
# that runs it with LD_LIBRARY_PATH set to a directory holding the other librollslide.so.0.2:
#   printf '#!/bin/sh\nLD_LIBRARY_PATH=/tmp/old exec %s "$@"\n' "$PWD/build-lammps/lmp_rollslide" > /tmp/lmp_old
set -euo pipefail
before=$(realpath "$1")
after=$(realpath "$2")
preset=${PRESET:-lammps}
rounds=${3:-5}
n=${4:-24}
steps=${5:-1000}
input=$(cd "$(dirname "$0")/inputs" && pwd)/in.packing
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cd "$tmp"
for _ in $(seq "$rounds"); do
  for side in before after; do
    exe=${!side}
    for law in A B; do
      "$exe" -in "$input" -log log -screen none -var pair granular/rollslide -var preset "$preset" \
        -var law "$law" -var n "$n" -var steps "$steps" -var thermo 50
      echo "$side $law $(awk -F'|' '/^Pair /{gsub(/ /, "", $3); print $3}' log)"
    done
  done
done >runs
python3 - runs <<'PY'
import collections, statistics, sys
v = collections.defaultdict(list)
for line in open(sys.argv[1]):
    side, law, t = line.split()
    v[law, side].append(float(t))
for law in "AB":
    b, a = statistics.median(v[law, "before"]), statistics.median(v[law, "after"])
    print(f"law {law}: Pair time before {b:.3f} s, after {a:.3f} s, ratio {a / b:.3f} "
          f"(medians of {len(v[law, 'before'])})")
PY
