#!/usr/bin/env bash
# Runs every C test program (c_tests/*.c, the same sources `cargo test` compiles) against the
# static library:
#   1. compiled with -fsanitize=address,undefined -fno-sanitize-recover=all (gcc; clang if
#      CC=clang), every test function run one by one: any ASan or UBSan report fails the run;
#   2. compiled without sanitizers and run under valgrind's memcheck (--error-exitcode,
#      --leak-check=full, definite and indirect leaks are errors), every test function run.
# The Rust library itself is not instrumented (ASan instruments the C side and intercepts
# malloc/free for both); valgrind checks both sides.
#
# Usage: scripts/sanitizers.sh [--no-valgrind]
# Env: CC (default cc), PROFILE (cargo profile of the library, default release).
set -euo pipefail
cd "$(dirname "$0")/.."

CC=${CC:-cc}
PROFILE=${PROFILE:-release}
run_valgrind=1
[ "${1:-}" = "--no-valgrind" ] && run_valgrind=0

if [ "$PROFILE" = "dev" ]; then
  cargo build --lib
  lib=target/debug/librollslide.a
else
  cargo build --lib --profile "$PROFILE"
  lib=target/$PROFILE/librollslide.a
fi
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
  echo "== valgrind memcheck"
  "$CC" "${common[@]}" "${sources[@]}" "$lib" "${native_libs[@]}" -o "$out/c_tests_plain"
  failed=0
  for t in "${tests[@]}"; do
    if ! valgrind --quiet --error-exitcode=99 --leak-check=full --errors-for-leak-kinds=definite,indirect \
        "$out/c_tests_plain" "$t" > "$out/valgrind_$t.log" 2>&1; then
      echo "FAILED under valgrind: $t"; cat "$out/valgrind_$t.log"; failed=$((failed + 1))
    fi
  done
  echo "valgrind: $((${#tests[@]} - failed)) passed, $failed failed"
  [ "$failed" -eq 0 ] || exit 1
fi
