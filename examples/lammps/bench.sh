#!/usr/bin/env bash
# Pair time per contact inside LAMMPS: stock `pair_style granular` against
# `granular/rollslide lammps` (and `objective`), same input, same pair_coeff, one rank, newton
# off (both use the same half/size/newtoff neighbour list), read from LAMMPS' own timer
# breakdown (the "Pair" row, seconds) and divided by steps x mean contacts (coordination number
# from compute contact/atom, averaged over the thermo rows, times atoms / 2).
#
#   examples/lammps/bench.sh <lmp_rollslide> [cells per side, 24] [steps, 1000] [repeats, 3]
#
# Input: examples/lammps/inputs/in.packing, law A (hooke, velocity damping, linear_history,
# rolling sds, twisting sds) and law B (hertz/material, viscoelastic damping, mindlin, twisting
# marshall: the sliding dashpot and stiffness change per contact, passed to the batch call as
# per-contact arrays); both run rsl_batch_step_params (contacts between owned atoms) and
# rsl_batch_step_contacts_params (contacts with a ghost atom) per chunk. Prints a
# Markdown table (medians of the repeats) and the CPU.
#
# Atom types (a second table): law A with 1 atom type and with 3 (in.packing's `types`: types
# at random, so that the type pair changes along the neighbour list, and a pair_coeff per type
# pair, same laws), stock `granular` and `granular/rollslide lammps`, with thermo output every
# 50 steps and every step (`thermo 1`: in.packing's thermo_style has `press`, so LAMMPS asks
# for the virial every step, and the style then steps every contact through
# rsl_batch_step_contacts_params, which gives each pair's force for the tally).
# Energy (a third table): law A and law B, `granular/rollslide lammps`, without and with
# `compute rollslide/energy` (in.packing's `energy 1`: the models track energy, the style
# collects every contact's energy terms and tallies them per atom).
# ROWS (environment): `laws` (the first table), `types` (the second), `energy` (the third) or
# `all` (default: the first two).
set -euo pipefail
exe=$(realpath "$1")
n=${2:-24}
steps=${3:-1000}
reps=${4:-3}
rows=${ROWS:-all}
input=$(cd "$(dirname "$0")/inputs" && pwd)/in.packing
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
atoms=$((n * n * n))

median() { sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }

echo "CPU: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//'), $(nproc) cores;" \
     "$atoms atoms, $steps steps, median of $reps runs"
echo
# Runs one row `reps` times: sets t (Pair time, s), ns (per contact) and contacts, medians.
measure() {
  local pair=$1 preset=$2 law=$3 types=$4 thermo=$5 energy=${6:-0} times=() per=() one
  for _ in $(seq "$reps"); do
    (cd "$tmp" && "$exe" -in "$input" -log log -screen none -var pair "$pair" -var preset "$preset" \
       -var law "$law" -var n "$n" -var steps "$steps" -var thermo "$thermo" -var types "$types" \
       -var energy "$energy")
    one=$(awk -F'|' '/^Pair /{gsub(/ /, "", $3); print $3}' "$tmp/log")
    contacts=$(awk -v atoms="$atoms" '/^Step /{on=1; next} /^Loop time/{on=0} on && NF >= 6 {s += $4; k++}
                END {printf "%.0f", s / k * atoms / 2}' "$tmp/log")
    times+=("$one")
    per+=("$(awk -v t="$one" -v c="$contacts" -v s="$steps" 'BEGIN {printf "%.2f", t / (s * c) * 1e9}')")
  done
  t=$(printf '%s\n' "${times[@]}" | median)
  ns=$(printf '%s\n' "${per[@]}" | median)
}

if [ "$rows" = all ] || [ "$rows" = laws ]; then
  echo "| law | pair style | Pair time (s) | contacts | ns per contact | / granular |"
  echo "|---|---|---:|---:|---:|---:|"
  for law in A B; do
    base=""
    for style in "granular|" "granular/rollslide|lammps" "granular/rollslide|objective"; do
      pair=${style%|*}
      preset=${style#*|}
      measure "$pair" "$preset" "$law" 1 50
      [ -z "$base" ] && base=$ns
      ratio=$(awk -v a="$ns" -v b="$base" 'BEGIN {printf "%.2f", a / b}')
      echo "| $law | $pair $preset | $t | $contacts | $ns | $ratio |"
    done
  done
  echo
fi

if [ "$rows" = all ] || [ "$rows" = types ]; then
  echo "| law | types | thermo | pair style | Pair time (s) | contacts | ns per contact | / granular |"
  echo "|---|---:|---:|---|---:|---:|---:|---:|"
  for thermo in 50 1; do
    for types in 1 3; do
      base=""
      for style in "granular|" "granular/rollslide|lammps"; do
        pair=${style%|*}
        preset=${style#*|}
        measure "$pair" "$preset" A "$types" "$thermo"
        [ -z "$base" ] && base=$ns
        ratio=$(awk -v a="$ns" -v b="$base" 'BEGIN {printf "%.2f", a / b}')
        echo "| A | $types | $thermo | $pair $preset | $t | $contacts | $ns | $ratio |"
      done
    done
  done
fi

if [ "$rows" = energy ]; then
  echo "| law | compute rollslide/energy | Pair time (s) | contacts | ns per contact | / without |"
  echo "|---|---|---:|---:|---:|---:|"
  for law in A B; do
    base=""
    for energy in 0 1; do
      measure granular/rollslide lammps "$law" 1 50 "$energy"
      [ -z "$base" ] && base=$ns
      ratio=$(awk -v a="$ns" -v b="$base" 'BEGIN {printf "%.2f", a / b}')
      echo "| $law | $([ "$energy" = 1 ] && echo yes || echo no) | $t | $contacts | $ns | $ratio |"
    done
  done
fi
