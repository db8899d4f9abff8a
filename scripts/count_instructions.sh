#!/bin/sh
# Instructions per contact of one benchmark row, split by part: builds the library with line
# tables, links the benchmark driver to it for AVX2 (-march=x86-64-v3), runs the row under
# valgrind's callgrind (exact instruction counts; this host's `perf` has no hardware counters)
# and attributes each executed instruction to a part through its inline chain (addr2line -i),
# as scripts/profile_batch.sh does with time samples.
#
#   scripts/count_instructions.sh [ROW] [SET] [CONTACTS]
#     ROW       a driver row, exactly (default batch_f64_avx2; see bench/bench.c). Valgrind has
#               no AVX-512, so the AVX-512 rows cannot be counted
#     SET       the physics set: full, rolltwist or sliding (default full)
#     CONTACTS  default 2000 (in cache: the kernels that do not prefetch); from about 6,500
#               contacts on, the prefetching kernels run
#
# Prints the instructions per contact of the set's hand-written baseline and of the library's
# code for the row, in total and per part. Needs valgrind (3.19 cannot decode one AVX
# instruction of the per-contact rolling + twisting step) and addr2line.
set -eu
row=${1:-batch_f64_avx2}
set_name=${2:-full}
contacts=${3:-2000}
cd "$(dirname "$0")/.."
target=target/profile-lines
CARGO_PROFILE_RELEASE_DEBUG=line-tables-only CARGO_TARGET_DIR=$target cargo build --release --lib
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
scripts/build_driver.sh $target/release/librollslide.a "$out/driver" x86-64-v3
valgrind --tool=callgrind --dump-instr=yes --callgrind-out-file="$out/cg" \
  "$out/driver" "$contacts" 1 --workload=A --set="$set_name" --only="$row\$" \
  >"$out/rows" 2>"$out/log" || { tail -5 "$out/log" >&2; exit 1; }
grep "^row $set_name" "$out/rows" | grep -v floor || true
python3 - "$out" "$set_name" <<'PY'
import bisect, collections, subprocess, sys
out, set_name = sys.argv[1:]
binary = out + "/driver"
syms = []
nm = subprocess.run(["nm", "-C", binary], capture_output=True, text=True).stdout
for line in nm.splitlines():
    p = line.split(None, 2)
    if len(p) == 3 and p[1] in "tTwW":
        syms.append((int(p[0], 16), p[2]))
syms.sort()
starts = [s for s, _ in syms]
# Self cost per instruction address (positions "instr line"; the cost line after "calls=" is the
# call's inclusive cost, not an instruction of the caller).
cost = collections.Counter()
addr, skip = 0, False
for line in open(out + "/cg"):
    line = line.rstrip("\n")
    if not line:
        continue
    if not (line[0] == "0" or line[0] in "+-*"):
        skip = line.startswith("calls=")
        continue
    p = line.split()
    if len(p) < 3:
        continue
    a = p[0]
    if a.startswith("0x"):
        addr = int(a, 16)
    elif a[0] == "+":
        addr += int(a[1:])
    elif a[0] == "-":
        addr -= int(a[1:])
    if skip:
        skip = False
        continue
    cost[addr] += int(p[2])


def name_of(a):
    return syms[bisect.bisect_right(starts, a) - 1][1]


# Contacts per row: the driver's timeit repeats a call of fewer than 100,000 contacts to step at
# least 200,000 per timed call (one timed call here); the baseline runs twice per set (with and
# without contacts at a limit).
nc = next(int(l.split()[2]) for l in open(out + "/rows") if l.startswith("info contacts"))
per_call = (max(1, 200000 // nc) if nc < 100000 else 1) * nc
# Rows of the library that ran (the per-contact rows run a no-slip twin under the same name).
lib_rows = [l.split()[2] for l in open(out + "/rows")
            if l.startswith("row ") and not l.split()[2].startswith(("baseline", "floor"))]
per_row = per_call * len(lib_rows)
base = sum(c for a, c in cost.items() if name_of(a) == "baseline_" + set_name)
print(f"contacts per row: {per_call}; library rows: {' '.join(lib_rows)}")
print(f"hand-written baseline: {base / (2 * per_call):.1f} instructions per contact")
lib = {a: c for a, c in cost.items()
       if name_of(a).startswith(("rollslide::", "rsl_", "core::", "<rollslide"))}
addrs = sorted(lib)
chains, cur = {}, None
a2l = subprocess.run(["addr2line", "-e", binary, "-i", "-f", "-C", "-a"]
                     + ["%#x" % a for a in addrs], capture_output=True, text=True).stdout
for line in a2l.split("\n"):
    if line.startswith("0x"):
        cur = int(line, 16)
        chains[cur] = []
    elif cur is not None and line:
        chains[cur].append(line)
# The first of these names found on an instruction's inline chain gives its part.
parts_order = [
    ("words_to_rows", "gather: transpositions"), ("pairs_to_rows", "gather: transpositions"),
    ("touch", "gather: prefetches"), ("group_refs", "gather: group references"),
    ("group_refs_by_contact", "gather: group references"),
    ("group_of", "gather: group references"), ("gather", "gather: rest"),
    ("rows_to_words", "delivery: states"), ("store_states", "delivery: states"),
    ("emit_run", "delivery: loads"), ("deliver", "delivery: rest"),
    ("pair_geometry_valid", "checks"), ("inputs_ok", "checks"), ("results_ok", "checks"),
    ("inputs_in_range", "checks"), ("inputs", "checks"), ("outputs", "checks"),
    ("all_set_and_aligned", "checks"),
    ("to_c", "per-contact call: output and state structs"),
    ("store", "per-contact call: output and state structs"),
    ("deliver", "per-contact call: adding the loads"),
    ("transport", "physics: transport"), ("vector_spring", "physics: springs"),
    ("scalar_spring", "physics: springs"),
    ("pair_geometry_unchecked", "geometry"),
    ("contact_step_with_geometry", "physics: rest"),
    ("step_lanes", "block rows and bookkeeping"),
    ("fast_pair_step", "per-contact call: rest"), ("pair_step_with", "per-contact call: rest"),
    ("entered_step", "per-contact call: rest"),
]
parts = collections.Counter()
for a in addrs:
    ch = chains.get(a, [])
    names = [ch[i].split("<")[0].split("::")[-1] for i in range(0, len(ch) - 1, 2)]
    part = "other: " + name_of(a).split("::")[-1][:40]
    for key, label in parts_order:
        if key in names:
            part = label
            break
    parts[part] += lib[a]
total = sum(parts.values())
print(f"library: {total / per_row:.1f} instructions per contact")
for part, c in parts.most_common():
    if c / per_row >= 0.5:
        print(f"  {c / per_row:7.1f}  {part}")
PY
