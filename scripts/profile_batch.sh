#!/bin/sh
# Where the batch step kernel spends its time: builds the library with line tables, links the
# benchmark driver to it, samples one kernel with `perf record -e cpu-clock` and attributes each
# sample to a part of `src/batch/block.rs` through its inline chain (addr2line -i).
#
#   scripts/profile_batch.sh [ROW] [WORKLOAD] [CONTACTS]
#     ROW       the driver row to profile (default batch_f64_avx512; see bench/bench.c)
#     WORKLOAD  A or B (default A); CONTACTS (default 1200000)
#   REPS (environment, default 6): timed calls per row; SET (environment): only that physics set
#   of the driver (full, rolltwist or sliding; default every set)
#
# Needs perf and addr2line (binutils). Prints the share of the kernel's samples per part, then
# the share that lands on instructions addressing the stack frame (rows and spilled values), in
# all and per part, and the size of the hottest kernel's hot code. The gathering's line also says
# how much of it is the prefetches of the contacts ahead (the prefetch instructions and the
# index loads and address arithmetic that feed them; none in calls that fit in cache); the
# lines the contacts ahead read in contact order are touched after each lane step instead
# (Gather::touch_in_order), and have a line of their own.
set -eu
row=${1:-batch_f64_avx512}
workload=${2:-A}
contacts=${3:-1200000}
cd "$(dirname "$0")/.."
target=target/profile-lines
CARGO_PROFILE_RELEASE_DEBUG=line-tables-only CARGO_TARGET_DIR=$target cargo build --release --lib
out=$(mktemp -d)
scripts/build_driver.sh $target/release/librollslide.a "$out/driver"
perf record -q -e cpu-clock -o "$out/perf.data" \
  "$out/driver" "$contacts" ${REPS:-6} --workload="$workload" --only="$row" \
  ${SET:+--set="$SET"} >/dev/null
# The kernels are named after their level and precision (x86::avx512_f64, scalar_f32...).
case $row in
  *f32_avx512*) sym=avx512_f32 ;; *f32_avx2*) sym=avx2_f32 ;; *f32_scalar*) sym=scalar_f32 ;;
  *avx2*) sym=avx2_f64 ;; *scalar*) sym=scalar_f64 ;; *) sym=avx512_f64 ;;
esac
perf script -i "$out/perf.data" -F ip,sym 2>/dev/null | awk -v s="$sym" '$0 ~ s {print $1}' |
  sort | uniq -c >"$out/ips"
awk '{print "0x" $2}' "$out/ips" | addr2line -e "$out/driver" -i -f -C -a >"$out/lines"
python3 - "$out/ips" "$out/lines" "$out/parts" <<'EOF'
import collections, sys
counts = {int(a, 16): int(c) for c, a in (l.split() for l in open(sys.argv[1]))}
where = open(sys.argv[3], "w")
blocks, cur = [], None
for line in open(sys.argv[2]):
    line = line.rstrip("\n")
    if line.startswith("0x"):
        cur = [int(line, 16), []]
        blocks.append(cur)
    else:
        cur[1].append(line)
parts = collections.Counter()
prefetches = 0
for addr, lines in blocks:
    names = [lines[i].split("<")[0].split("::")[-1] for i in range(0, len(lines) - 1, 2)]
    part = "other"
    for name in ("gather", "deliver", "step_lanes", "step_one"):
        if name in names:
            part = name
            break
    if part == "gather" and "touch" in names:
        prefetches += counts.get(addr, 0)
    if part == "other" and "touch_in_order" in names:
        part = "prefetches in contact order, after each lane step"
    if part in ("step_lanes", "step_one"):
        if "contact_step_with_geometry" in names:
            part = "physics"
        elif "pair_geometry_unchecked" in names or "pair_geometry_valid" in names:
            part = "geometry and its validity"
        elif "inputs_ok" in names or "results_ok" in names:
            part = "finiteness probes"
        else:
            part = "row loads and stores" if part == "step_lanes" else "reading the structs"
    parts[part] += counts.get(addr, 0)
    print(f"{addr:#x} {part}", file=where)
total = sum(parts.values()) or 1
for part, n in parts.most_common():
    print(f"{100 * n / total:5.1f}%  {part}")
    if part == "gather":
        print(f"{100 * prefetches / total:5.1f}%    of which the prefetches of the contacts ahead")
print(f"({total} samples)")
EOF
# How much of the kernel's time goes to instructions that address the stack frame (the block's
# rows, and the SIMD values LLVM spills between the physics' steps), in the kernel function
# with the most samples: its disassembly, and the samples that land on such instructions.
hot=$(awk '{print $2}' "$out/ips" | python3 -c '
import subprocess, sys
ips = [int(l, 16) for l in sys.stdin.read().split()]
syms = []
for l in subprocess.run(["nm", "-S", sys.argv[1]], capture_output=True, text=True).stdout.splitlines():
    f = l.split()
    if len(f) == 4 and sys.argv[2] in f[3]:
        syms.append((int(f[0], 16), int(f[1], 16)))
s, z = max(syms, key=lambda t: sum(t[0] <= a < t[0] + t[1] for a in ips))
print(f"{s:#x} {s + z:#x}")' "$out/driver" "$sym")
set -- $hot
objdump -d --no-show-raw-insn -M intel --start-address="$1" --stop-address="$2" "$out/driver" \
  >"$out/hot.s"
python3 - "$out/ips" "$out/hot.s" "$out/parts" <<'EOF'
import collections, re, sys
counts = {int(a, 16): int(c) for c, a in (l.split() for l in open(sys.argv[1]))}
part_of = {int(a, 16): p for a, p in (l.rstrip("\n").split(" ", 1) for l in open(sys.argv[3]))}
insns = {}
for line in open(sys.argv[2]):
    m = re.match(r"\s+([0-9a-f]+):\s+(.*)", line)
    if m:
        insns[int(m.group(1), 16)] = m.group(2)
def stack(t):
    return "rsp" in t or "rbp" in t
hits = {a: c for a, c in counts.items() if a in insns}
total = sum(hits.values()) or 1
on_stack = sum(c for a, c in hits.items() if stack(insns[a]))
print(f"hottest kernel: {len(insns)} instructions, {sum(map(stack, insns.values()))} address the stack;")
print(f"{100 * on_stack / total:.1f}% of its samples land on those; by part (share of the")
print("kernel's samples on the part's stack accesses, and of the part's own samples):")
mine, spilled = collections.Counter(), collections.Counter()
for a, c in hits.items():
    mine[part_of.get(a, "other")] += c
    if stack(insns[a]):
        spilled[part_of.get(a, "other")] += c
for part, n in spilled.most_common():
    print(f"  {100 * n / total:5.1f}%  {part} ({100 * n / mine[part]:.0f}% of its samples)")
# Its hot code: the instructions in the 64-byte lines that have samples (a lower bound of what
# runs; with the lines next to those, a closer estimate), to set against the loop size at which
# this core's front end slows down (bench/code_size.c measures it).
lines = {a // 64 for a in hits}
near = {l + d for l in lines for d in (-1, 0, 1)}
print(f"hot code: {sum(a // 64 in lines for a in insns)} instructions in the {len(lines)} lines "
      f"with samples, {sum(a // 64 in near for a in insns)} with the lines next to them")
EOF
rm -rf "$out"
