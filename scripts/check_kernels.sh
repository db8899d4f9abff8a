#!/bin/sh
# Checks that the release library's SIMD batch kernels and per-contact steps are whole: no call
# from a kernel (`batch::dispatch::x86::*`) into the physics, nalgebra, simba or the `core::arch`
# intrinsics, and the per-contact steps as the end of the script says. It also checks that the
# kernels are the ones the source defines (see "The kernels" below).
#
# The x86 kernels get their vector instructions by inlining: the lane types of
# `src/batch/x86/lanes.rs` call `core::arch` intrinsics from plain functions, and an intrinsic
# only becomes its instruction once inlined into a `#[target_feature]` kernel. A physics
# function that the compiler leaves out of line (a closure, a nalgebra method over a lane
# type) is compiled without those features: every intrinsic in it becomes a function call,
# and the kernel runs two to three times slower with the same results (measured when
# nalgebra's `cross` was left out of line: 93 against 45 ns per contact). No test sees that,
# so this check does. It also fails on two helpers once found out of line in the SIMD kernels
# (`core::array::from_fn` building the group's body references, a closure of the block's row
# reader, and one of the gather that prefetched and copied a contact's numbers: a call per
# contact in the prefetching kernels), and on those once found in the indexed-state store
# (`get_disjoint_mut`, `array::map`) or that it could leave there (a function or closure of
# `batch::states`, where `IndexedGroups` is too): each cost a call, and its arguments and results
# through memory, per group of contacts.
#
#   scripts/check_kernels.sh        (builds the release library first; needs objdump)
#   scripts/check_kernels.sh LIB    (checks the release archive LIB, built elsewhere: .ci/run
#                                    gives it the one the CMake build made)
set -eu
cd "$(dirname "$0")/.."
lib=${1:-}
if [ -z "$lib" ]; then
  cargo build --release --lib --quiet
  lib=target/release/librollslide.a
fi
[ -f "$lib" ] || { echo "check_kernels: no archive $lib" >&2; exit 1; }
# In the archive's objects a call's target is its relocation (-r), on the line after the call.
out=$(objdump -dr --no-show-raw-insn -C "$lib" | awk '
  /^[0-9a-f]+ <.*>:$/ { inside = ($0 ~ /batch::dispatch::x86::/); name = $0; call = 0; next }
  inside && /\tcall/ { call = 1; next }
  inside && call && /R_X86_64_/ {
    call = 0
    # The target of the call: demangled or (for section-relative targets) mangled. Only its path
    # is tested, not the generic arguments of a demangled instance (`f::<...>`): a kernel
    # calls the cold, deliberately out-of-line `batch::group_refs_by_contact` for the
    # last, partial group, and where the kernels and it lie in different codegen units its
    # name carries the access type (`batch::states::IndexedGroups`) among them.
    match($0, /R_X86_64_[A-Z0-9_]+[ \t]+/)
    target = substr($0, RSTART + RLENGTH)
    path = target
    sub(/::<.*/, "", path)
    if (path ~ /core_arch|nalgebra|simba|x86::lanes|3x865lanes|rollslide::(scalar|laws|geometry|loads|decompose)|9rollslide(6scalar|4laws|8geometry|5loads|9decompose)/ ||
        path ~ /core::array|4core5array|RowsAt|block::gather|5block6gather|get_disjoint_mut|batch::states|5batch6states/)
      print name " calls " target
    next
  }
  { call = 0 }' | sort | uniq -c)
# Defined functions only: an object file that calls a kernel of another codegen unit lists it
# as undefined.
kernels=$(objdump -t -C "$lib" | grep ' F ' | grep -c 'batch::dispatch::x86::' || true)
if [ "$kernels" -eq 0 ]; then
  echo "check_kernels: no x86 kernel found in $lib" >&2
  exit 1
fi
# The kernels (src/batch/dispatch.rs, module `x86`): one step kernel per SIMD level (AVX2, AVX-512),
# precision (`avx2_f64`, `avx2_f32`, `avx512_f64`, `avx512_f32`) and access type `A`
# (`<A: CAccess>`), which takes the model's law decisions and the prefetching choice at run
# time: no compile-time parameter besides the access type. The access types `run_step` is instantiated
# with (STEP_ACCESS): particle-major with the states in an array (rsl_batch_step, _params) or in
# place (rsl_batch_step_indexed), each with the model's sliding coefficients or per-contact ones
# (4); packed histories (rsl_batch_step_history), one per record layout: 7, 10 or 13 words from
# word 0 with a sliding law, 4, 7 or 10 from word 3 without (6); contact-major
# (rsl_batch_step_contacts, _params: 1); sphere-wall contacts (rsl_batch_step_walls: 1, the
# states in order or in place chosen at run time). The decomposition has one kernel per level
# (`decompose_avx2`, `decompose_avx512`: the precision is a run-time argument), access type
# (particle- or contact-major: DECOMPOSE_ACCESS) and prefetching choice (`<const P: bool, A>`).
# Each of the six families must be there, with at most one instance per access type (two for
# the decomposition): fewer is fine (LLVM may fold identical instances into one), more means
# another compile-time parameter (or a new access type: then update the count here). Where the
# symbols carry their generic arguments (v0 mangling), a decomposition kernel's first must be
# the prefetching choice (`true` or `false`).
STEP_ACCESS=12
DECOMPOSE_ACCESS=2
families=$(objdump -t -C "$lib" | awk -v step_max="$STEP_ACCESS" \
    -v decompose_max=$((2 * DECOMPOSE_ACCESS)) '
  BEGIN {
    n = split("avx2_double::avx2_f64 avx2_single::avx2_f32 avx512_double::avx512_f64 " \
              "avx512_single::avx512_f32 decompose::decompose_avx2 decompose::decompose_avx512",
              family, " ")
    for (i = 1; i <= n; i++) count[family[i]] = 0
  }
  / F / && /batch::dispatch::x86::/ {
    name = $0
    sub(/^[^\t]*\t[0-9a-f]+[ \t]+/, "", name)   # after the section and the size
    sub(/^\.hidden[ \t]+/, "", name)
    for (i = 1; i <= n; i++) {
      key = "batch::dispatch::x86::" family[i]
      at = index(name, key)
      if (at == 0) continue
      rest = substr(name, at + length(key))
      sub(/^::h[0-9a-f]+/, "", rest)              # a hash, where the demangler shows it
      sub(/^\.llvm\..*/, "", rest)                # a ThinLTO suffix
      if (rest == "") { count[family[i]]++; break }
      if (substr(rest, 1, 3) == "::<") {        # v0 mangling: the generic arguments
        count[family[i]]++
        if (family[i] ~ /^decompose/ && rest !~ /^::<(true|false),/) print "parameter " name
      }
      break                                     # anything else is not a kernel (a closure)
    }
  }
  END {
    for (i = 1; i <= n; i++) {
      max = family[i] ~ /^decompose/ ? decompose_max : step_max
      c = count[family[i]]
      if (c == 0) print "missing " family[i]
      else if (c > max) print "extra " family[i] " " c " instances, at most " max
      else print "ok " family[i] " " c
    }
  }')
bad=$(echo "$families" | grep -v '^ok ' || true)
if [ -n "$bad" ]; then
  echo "check_kernels: the kernels in $lib are not the ones of src/batch/dispatch.rs (see the script):" >&2
  echo "$bad" | head -20 >&2
  exit 1
fi
if [ -n "$out" ]; then
  echo "check_kernels: physics left out of line in the SIMD kernels (see the script's header):" >&2
  echo "$out" | head -20 >&2
  exit 1
fi
# The per-contact steps (`capi::contact::[unchecked_][wall_]{out,accumulate}_step_{avx2,portable}`:
# pair and wall, checked and unchecked) call nothing but their cold checked path: the physics,
# the finiteness tests and the panic boundary all inlined (a `guard_status` left out of line
# took the whole step behind two calls: 1.4-1.7x the time). And the eight entries reach them by
# a jump (a tail call with the same arguments), not by a call.
steps=$(objdump -dr --no-show-raw-insn -C "$lib" | awk '
  /^[0-9a-f]+ <.*>:$/ {
    step = ($0 ~ /capi::contact::(unchecked_)?(wall_)?(out|accumulate)_step_(avx2|portable)>/)
    entry = ($0 ~ /<rsl_contact_step(_wall)?(_accumulate)?(_unchecked)?>:/)
    if (entry) { name = $0; entries++ ; jumps[name] = 0 }
    sname = $0; call = 0; next
  }
  entry && /\tjmp +\*%/ && jumps[name] == 0 { jumps[name] = 1 }
  entry && /\tcall +\*/ && !/\*0x0\(%rip\)/ { jumps[name] = -1 }
  step && /\tcall/ { call = 1; next }
  step && call && /R_X86_64_/ {
    call = 0
    if ($NF !~ /contact::(wall_)?(out|accumulate)_step_guarded/) print sname " calls " $NF
    next
  }
  { call = 0 }
  END {
    for (n in jumps) if (jumps[n] != 1) print n " calls the handle step instead of jumping to it"
    if (entries != 8) print entries " per-contact entries found, 8 expected"
  }' | sort | uniq -c)
if [ -n "$steps" ]; then
  echo "check_kernels: a per-contact step is not whole (see the script):" >&2
  echo "$steps" | head -20 >&2
  exit 1
fi
echo "check_kernels: $kernels x86 kernel symbols, none calls out of line into the physics or the intrinsics"
echo "check_kernels: instances per kernel: $(echo "$families" | awk '{printf "%s%s %s", sep, $2, $3; sep = ", "}')"
echo "check_kernels: the per-contact steps call only their checked path; the eight entries jump to them"
