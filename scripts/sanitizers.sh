#!/usr/bin/env bash
# Runs every C test program (c_tests/*.c, the same sources `cargo test` compiles) against the
# static library:
#   1. compiled with -fsanitize=address,undefined -fno-sanitize-recover=all (gcc; clang if
#      CC=clang), every test function run one by one: any ASan or UBSan report fails the run;
#   2. compiled without sanitizers and run under valgrind's memcheck (--error-exitcode,
#      --leak-check=full, definite and indirect leaks are errors), every test function run,
#      against the release library (what hosts link). Valgrind 3.19 (Debian 12) cannot decode
#      every AVX encoding LLVM emits: some AVX2 per-contact steps contain a register-to-register
#      `vmovq` in its 0xD6 form (LLVM's choice when the source is xmm8-15), which valgrind
#      rejects as an illegal opcode although every CPU with AVX runs it. A test stopped by such
#      a decoder gap is run again under valgrind against a library built with
#      `--cfg rollslide_portable_pair_steps` (the same code, but the per-contact steps are the
#      portable build, which valgrind decodes); it passes only if that run is clean, and the
#      report says which tests needed it. Any other failure fails the run. ASan runs the AVX2
#      steps natively (it does not instrument the Rust side).
# The Rust library itself is not instrumented (ASan instruments the C side and intercepts
# malloc/free for both); valgrind checks both sides.
#
# Usage: scripts/sanitizers.sh [--no-valgrind]
# Env: CC (default cc), PROFILE (cargo profile of the library under ASan, default release),
#      VALGRIND_PROFILE (cargo profile of the library under valgrind, default release),
#      LIB (a librollslide.a built elsewhere, for both instead of building one: .ci/run gives the
#      release archive the CMake build made; the portable rerun is still built here).
set -euo pipefail
cd "$(dirname "$0")/.."

CC=${CC:-cc}
PROFILE=${PROFILE:-release}
VALGRIND_PROFILE=${VALGRIND_PROFILE:-release}
run_valgrind=1
[ "${1:-}" = "--no-valgrind" ] && run_valgrind=0

# Builds the static library in cargo profile $1 and prints its path ($LIB when given).
build_lib() {
  if [ -n "${LIB:-}" ]; then
    [ -f "$LIB" ] || { echo "sanitizers: no archive $LIB" >&2; exit 1; }
    echo "$LIB"
  elif [ "$1" = "dev" ]; then
    cargo build --lib >&2
    echo target/debug/librollslide.a
  else
    cargo build --lib --profile "$1" >&2
    echo "target/$1/librollslide.a"
  fi
}
lib=$(build_lib "$PROFILE")
native_libs=(-lgcc_s -lutil -lrt -lpthread -lm -ldl -lc)
out=target/sanitizers
mkdir -p "$out"
sources=(c_tests/*.c)
common=(-std=c11 -Wall -Wextra -Werror -pedantic -g -O1 "-DRSL_SOURCE_DIR=\"$PWD\"" -Iinclude -Ic_tests)

echo "== ASan + UBSan ($CC)"
"$CC" "${common[@]}" -fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer \
  "${sources[@]}" "$lib" "${native_libs[@]}" -o "$out/c_tests_asan"
# detect_leaks: LeakSanitizer too; abort_on_error: a report is a failure even if a test passed.
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:strict_string_checks=1:detect_stack_use_after_return=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
mapfile -t tests < <("$out/c_tests_asan" --list)
failed=0
for t in "${tests[@]}"; do
  if ! "$out/c_tests_asan" "$t" > "$out/asan_$t.log" 2>&1; then
    echo "FAILED under ASan/UBSan: $t"; cat "$out/asan_$t.log"; failed=$((failed + 1))
  elif grep -q "runtime error\|AddressSanitizer\|LeakSanitizer" "$out/asan_$t.log"; then
    echo "sanitizer report: $t"; cat "$out/asan_$t.log"; failed=$((failed + 1))
  fi
done
echo "asan+ubsan: $((${#tests[@]} - failed)) passed, $failed failed"
[ "$failed" -eq 0 ] || exit 1

if [ "$run_valgrind" -eq 1 ]; then
  if ! command -v valgrind > /dev/null; then
    echo "valgrind not installed (apt-get install valgrind)"; exit 1
  fi
  echo "== valgrind memcheck (library ${LIB:-of profile $VALGRIND_PROFILE})"
  vg_lib=$(build_lib "$VALGRIND_PROFILE")
  "$CC" "${common[@]}" "${sources[@]}" "$vg_lib" "${native_libs[@]}" -o "$out/c_tests_plain"
  vg() { # binary test log
    valgrind --quiet --error-exitcode=99 --leak-check=full --errors-for-leak-kinds=definite,indirect \
      "$1" "$2" > "$3" 2>&1
  }
  failed=0
  portable=()
  portable_built=0
  for t in "${tests[@]}"; do
    if vg "$out/c_tests_plain" "$t" "$out/valgrind_$t.log"; then
      continue
    fi
    if grep -q "Illegal opcode" "$out/valgrind_$t.log"; then
      # A decoder gap (header note): the same test on the portable per-contact steps.
      if [ "$portable_built" -eq 0 ]; then  # once per run (a binary of an earlier run is stale)
        RUSTFLAGS="${RUSTFLAGS:-} --cfg rollslide_portable_pair_steps" \
          cargo build --lib --profile "$VALGRIND_PROFILE" --target-dir target/portable-pair-steps >&2
        "$CC" "${common[@]}" "${sources[@]}" \
          "target/portable-pair-steps/$VALGRIND_PROFILE/librollslide.a" "${native_libs[@]}" \
          -o "$out/c_tests_portable_steps"
        portable_built=1
      fi
      if vg "$out/c_tests_portable_steps" "$t" "$out/valgrind_portable_$t.log"; then
        portable+=("$t")
        continue
      fi
      echo "FAILED under valgrind (portable per-contact steps too): $t"
      cat "$out/valgrind_portable_$t.log"
    else
      echo "FAILED under valgrind: $t"; cat "$out/valgrind_$t.log"
    fi
    failed=$((failed + 1))
  done
  if [ ${#portable[@]} -gt 0 ]; then
    echo "valgrind could not decode an AVX2 per-contact step in: ${portable[*]}; those tests ran"
    echo "  clean on the portable per-contact steps (see the note at the top of this script)"
  fi
  echo "valgrind: $((${#tests[@]} - failed)) passed, $failed failed"
  [ "$failed" -eq 0 ] || exit 1
fi
