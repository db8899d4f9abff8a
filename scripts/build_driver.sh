#!/bin/sh
# Links the benchmark driver (bench/bench.c) to one build of the static library: the compile
# line the measuring scripts share (ab_kernels, placement_sweep, profile_batch,
# count_instructions). `cargo bench --bench batch` compiles the same file with the same
# options through the cc crate.
#
#   scripts/build_driver.sh LIB.a OUT [MARCH, native]
#     MARCH  the -march of the driver (count_instructions.sh uses x86-64-v3: valgrind has no
#            AVX-512). CC picks the compiler (default cc).
#
# -std=c11 keeps GCC from contracting a*b+c into FMAs in the hand-written baselines (rustc
# does not contract either), so the f64 library rows agree with them bit for bit.
set -eu
[ $# -ge 2 ] || { echo "usage: scripts/build_driver.sh LIB.a OUT [MARCH]" >&2; exit 2; }
root=$(cd "$(dirname "$0")/.." && pwd)
${CC:-cc} -O3 -march="${3:-native}" -no-pie -std=c11 -D_POSIX_C_SOURCE=199309L -I"$root/include" \
  "$root/bench/bench.c" "$1" -lgcc_s -lutil -lrt -lpthread -lm -ldl -lc -o "$2"
