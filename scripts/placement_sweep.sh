#!/usr/bin/env bash
# How much a kernel's time depends on where the process's stack lies modulo 4 KB.
#
# At 1.2M contacts the same driver binary, on the same data, gives batch rows that differ by
# 10-20% between two invocations. Address-space randomisation (ASLR) is what changes between
# them: with it off (`setarch -R`) a binary's times mostly repeat, and moving the stack alone
# (by padding the environment, which sits above it) moves them by that much again. This script
# links the benchmark driver (bench/bench.c) to one build of the library, switches ASLR off,
# runs the driver once per stack offset (PADS offsets spread evenly over 4 KB, each a multiple
# of 64 bytes, the alignment of the kernels' block), and prints for each row the min / median
# / max over the offsets of its ns per contact and of its ratio to the hand-written loop of
# the same run.
#
#   scripts/placement_sweep.sh LIB.a [CONTACTS, 1200000] [PADS, 32] [driver options...]
#
# e.g. scripts/placement_sweep.sh target/release/librollslide.a 1200000 32 --set=full --only=_avx
# Needs `setarch` (util-linux). The offsets are the same on every invocation, so two builds
# swept with the same PADS meet the same stack positions (not the same frame layouts: each
# build's kernels lay out their frames differently).
set -euo pipefail
lib=$1
contacts=${2:-1200000}
pads=${3:-32}
shift $(( $# < 3 ? $# : 3 ))
command -v setarch >/dev/null || { echo "placement_sweep: needs setarch (util-linux)" >&2; exit 1; }
cd "$(dirname "$0")/.."
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
scripts/build_driver.sh "$lib" "$tmp/driver"
step=$(( (4096 / pads + 63) / 64 * 64 ))
for k in $(seq 0 $((pads - 1))); do
  pad=$(( (k * step) % 4096 ))
  filler=$(head -c "$pad" /dev/zero | tr '\0' x)
  if ! STACK_PAD="$filler" setarch "$(uname -m)" -R "$tmp/driver" "$contacts" 3 --workload=A "$@" \
    >"$tmp/out" 2>&1; then
    cat "$tmp/out" >&2
    exit 1
  fi
  awk -v p="$pad" '/^row/ && $3 !~ /^floor/ {print p, $2, $3, $4}' "$tmp/out"
done >"$tmp/runs"
python3 - "$tmp/runs" "$step" <<'PY'
import collections, statistics, sys
ns = collections.defaultdict(dict)
for line in open(sys.argv[1]):
    pad, group, row, t = line.split()
    ns[(group, row)][int(pad)] = float(t)
if not ns:
    sys.exit("placement_sweep: the driver printed no row (check the driver options)")
def spread(v):
    return f"{min(v):7.3f} {statistics.median(v):7.3f} {max(v):7.3f}"
print(f"{'row':58s} {'ns min / median / max':>23s}   {'/ loop min / median / max':>23s}")
for (group, row), by_pad in ns.items():
    base = ns.get((group, "baseline_c" + ("[noslip]" if "[noslip]" in row else "")), {})
    ratios = [t / base[p] for p, t in by_pad.items() if p in base]
    print(f"{group + ':' + row:58s} {spread(list(by_pad.values()))}   "
          + (spread(ratios) if ratios else ""))
print(f"({len(next(iter(ns.values())))} stack offsets, {sys.argv[2]}-byte steps)")
PY
