#!/usr/bin/env bash
# What the rollslide pair style, walls and energy compute cost in a whole LAMMPS run: the heap
# of examples/lammps/inputs/in.heap (1200 spheres poured onto a floor in a box of three plane
# wall fixes, then settling; `-var preset lammps`, so that stock and rollslide compute the same
# laws), one rank, LAMMPS' own timer breakdown (Pair, Modify: the integration, gravity,
# fix pour and the three wall fixes) and loop time, each summed over the input's runs, for:
#   stock      pair granular + fix wall/gran granular
#   walls      pair granular/rollslide + fix wall/gran granular (stock walls)
#   rollslide  pair granular/rollslide + fix wall/gran/rollslide
#   energy     the same + compute rollslide/energy
# The rows run in alternation, REPEATS times; prints a Markdown table of the medians, with the
# ratios to the stock row (and, for energy, to rollslide), and the CPU.
#
#   examples/lammps/heap_cost.sh <lmp_rollslide> [repeats, 3] [settle time, 10]
set -euo pipefail
exe=$(realpath "$1")
reps=${2:-3}
settle=${3:-10}
input=$(cd "$(dirname "$0")/inputs" && pwd)/in.heap
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
rows=(stock walls rollslide energy)
declare -A vars=(
  [stock]="-var pair stock -var walls stock -var energy 0"
  [walls]="-var walls stock -var energy 0"
  [rollslide]="-var walls rollslide -var energy 0"
  [energy]="-var walls rollslide -var energy 1"
)
median() { sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }
for r in $(seq "$reps"); do
  for row in "${rows[@]}"; do
    # shellcheck disable=SC2086
    (cd "$tmp" && "$exe" -in "$input" -var preset lammps -var settle "$settle" ${vars[$row]} \
      -log none -screen "$row.$r.out" >/dev/null)
    awk -v row="$row" '
      /^Loop time of/ { loop += $4 }
      /^Pair +\|/ { pair += $3 }
      /^Modify +\|/ { modify += $3 }
      END { printf "%s %.4f %.4f %.4f\n", row, pair, modify, loop }' "$tmp/$row.$r.out" \
      >> "$tmp/times"
  done
done
col() { awk -v row="$1" -v k="$2" '$1 == row { print $k }' "$tmp/times" | median; }
echo "| run | Pair (s) | Modify (s) | loop (s) | Pair / stock | Modify / stock | loop / stock |"
echo "|---|---:|---:|---:|---:|---:|---:|"
for row in "${rows[@]}"; do
  p=$(col "$row" 2) m=$(col "$row" 3) l=$(col "$row" 4)
  ps=$(col stock 2) ms=$(col stock 3) ls=$(col stock 4)
  awk -v row="$row" -v p="$p" -v m="$m" -v l="$l" -v ps="$ps" -v ms="$ms" -v ls="$ls" \
    'BEGIN { printf "| %s | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f |\n", row, p, m, l, p / ps, m / ms, l / ls }'
done
pr=$(col rollslide 2) pe=$(col energy 2) lr=$(col rollslide 4) le=$(col energy 4)
awk -v pr="$pr" -v pe="$pe" -v lr="$lr" -v le="$le" \
  'BEGIN { printf "\nenergy compute: Pair %.2fx, loop %.2fx the rollslide row\n", pe / pr, le / lr }'
echo "CPU: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), $reps alternating runs, medians"
