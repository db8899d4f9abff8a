#!/usr/bin/env bash
# Dissipation by mechanism, and the angle of repose, against a parameter of the heap: pours the
# heap of examples/lammps/inputs/in.heap once for each value (2 MPI ranks), then draws what
# `compute rollslide/energy` counted into one SVG and prints its tables (Markdown).
#
#   examples/lammps/heap.sh [--sweep mu_r|coh] <lmp_rollslide> [OUT.svg] [values]
#
# --sweep mu_r (the default): rolling friction, values 0 0.05 0.1 0.2 0.4, OUT
#   docs/heap_dissipation.svg; the law is in.heap's default (hooke) unless HEAP_VARS sets
#   another (HEAP_VARS="law hertz_mindlin": docs/heap_hertz_mindlin.svg).
# --sweep coh: JKR's surface energy at in.heap's mu_r (0.1), law jkr unless HEAP_VARS sets
#   one, values 0 0.25 0.5 1 2, OUT docs/heap_jkr.svg; the SVG adds the angle of repose.
# Extra `-var` settings of in.heap go in HEAP_VARS (e.g. HEAP_VARS="n 600 settle 10" for a
# quicker look); HEAP_RUNS=DIR keeps the runs' logs and final positions in DIR. The angle of
# repose is measured from the final positions (heap_plot.py says how); a mode's total (dashpot
# and friction) below -1e-9 of the dissipated energy is flagged by a `heap_plot: warning` line.
set -euo pipefail
sweep=mu_r
if [ "${1:-}" = --sweep ]; then
  sweep=${2:?--sweep needs mu_r or coh}
  shift 2
fi
case $sweep in
  mu_r) default_values=(0 0.05 0.1 0.2 0.4) ;;
  coh) default_values=(0 0.25 0.5 1 2) ;;
  *) echo "heap.sh: --sweep mu_r or --sweep coh, not $sweep" >&2; exit 2 ;;
esac
exe=$(realpath "${1:?usage: heap.sh [--sweep mu_r|coh] <lmp_rollslide> [OUT.svg] [values]}")
here=$(cd "$(dirname "$0")" && pwd)
vars=()
law=hooke
if [ -n "${HEAP_VARS:-}" ]; then
  set -f  # no globbing of the words (e.g. a `*`)
  # shellcheck disable=SC2206
  words=($HEAP_VARS)
  set +f
  for ((k = 0; k + 1 < ${#words[@]}; k += 2)); do
    vars+=(-var "${words[k]}" "${words[k + 1]}")
    [ "${words[k]}" != law ] || law=${words[k + 1]}
  done
fi
if [ "$sweep" = coh ] && [ "$law" = hooke ]; then
  law=jkr
  vars+=(-var law jkr)
fi
case $sweep/$law in
  mu_r/hooke) default_out=heap_dissipation.svg ;;
  coh/jkr) default_out=heap_jkr.svg ;;
  *) default_out=heap_$law.svg ;;
esac
out=$(realpath -m "${2:-$here/../../docs/$default_out}")
shift $(($# < 2 ? $# : 2))
values=("$@")
[ ${#values[@]} -gt 0 ] || values=("${default_values[@]}")
if [ -n "${HEAP_RUNS:-}" ]; then
  runs=$(realpath -m "$HEAP_RUNS")  # logs and final positions kept there
  mkdir -p "$runs"
else
  runs=$(mktemp -d)
  trap 'rm -rf "$runs"' EXIT
fi
logs=()
sweep_start=$(date +%s)
for v in "${values[@]}"; do
  log="$runs/log.$sweep-$v"
  start=$(date +%s)
  (cd "$runs" && mpirun --allow-run-as-root -np 2 "$exe" -in "$here/inputs/in.heap" \
    -var "$sweep" "$v" "${vars[@]}" -var dump 1 -var dumpfile "$runs/dump.$sweep-$v" \
    -log "$log" -screen none)
  echo "$sweep $v: $(($(date +%s) - start)) s" >&2
  logs+=("$log")
done
echo "sweep ($law, ${#values[@]} runs): $(($(date +%s) - sweep_start)) s" >&2
python3 "$here/heap_plot.py" "$out" "${logs[@]}"
echo "wrote $out" >&2
