#!/bin/sh
# The DEM heap demo on a fresh machine: needs cargo and a C compiler (no cmake). Builds the
# library with cargo, compiles examples/dem_heap.c against the static library, runs it: it pours
# 4 heaps (random seeds) for each of 6 values of mu_r, prints the table of the angle of repose
# (mean, sample standard deviation, range and each pour) and writes the SVG plot.
#
#   ./run-demo.sh [OUT.svg]        (default: heap.svg in the current directory)
set -eu
out=${1:-heap.svg}
case $out in /*) ;; *) out=$(pwd)/$out ;; esac
cd "$(dirname "$0")"

cargo build --release --lib
mkdir -p target/demo
cc=${CC:-cc}
# OpenMP, when the compiler has it, runs the cases on all cores.
openmp=
if echo 'int main(void) { return 0; }' | $cc -fopenmp -x c - -o target/demo/openmp-probe 2>/dev/null; then
  openmp=-fopenmp
fi
# The system libraries after the archive are those `rustc --print native-static-libs` lists.
$cc -std=c11 -O2 -Wall -Wextra -pedantic $openmp examples/dem_heap.c -Iinclude \
  target/release/librollslide.a -lgcc_s -lutil -lrt -lpthread -lm -ldl -lc \
  -o target/demo/dem_heap
exec target/demo/dem_heap "$out"
