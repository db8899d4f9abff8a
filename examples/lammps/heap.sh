#!/usr/bin/env bash
# Dissipation by mechanism against rolling friction: pours the heap of
# examples/lammps/inputs/in.heap once for each mu_r (2 MPI ranks), then draws what
# `compute rollslide/energy` counted into one SVG and prints its table (Markdown).
#
#   examples/lammps/heap.sh <lmp_rollslide> [OUT.svg, docs/heap_dissipation.svg] [mu_r values]
#
# Default mu_r values: 0 0.05 0.1 0.2 0.4. Extra `-var` settings of in.heap go in HEAP_VARS
# (e.g. HEAP_VARS="n 600 settle 5000" for a quicker look).
set -euo pipefail
exe=$(realpath "$1")
here=$(cd "$(dirname "$0")" && pwd)
out=$(realpath -m "${2:-$here/../../docs/heap_dissipation.svg}")
shift $(($# < 2 ? $# : 2))
values=("$@")
[ ${#values[@]} -gt 0 ] || values=(0 0.05 0.1 0.2 0.4)
runs=$(mktemp -d)
trap 'rm -rf "$runs"' EXIT
vars=()
if [ -n "${HEAP_VARS:-}" ]; then
  set -- $HEAP_VARS
  while [ $# -ge 2 ]; do vars+=(-var "$1" "$2"); shift 2; done
fi
logs=()
for mu in "${values[@]}"; do
  log="$runs/log.mu_r-$mu"
  start=$(date +%s)
  (cd "$runs" && mpirun --allow-run-as-root -np 2 "$exe" -in "$here/inputs/in.heap" \
    -var mu_r "$mu" "${vars[@]}" -log "$log" -screen none)
  echo "mu_r $mu: $(($(date +%s) - start)) s" >&2
  logs+=("$log")
done
python3 "$here/heap_plot.py" "$out" "${logs[@]}"
echo "wrote $out" >&2
