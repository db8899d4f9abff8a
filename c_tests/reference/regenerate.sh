#!/bin/sh
# Regenerate the YADE double-precision references: c_tests/reference/yade_double.csv (cases.json)
# and c_tests/reference/yade_cohesive.csv (cohesive_cases.json: CohFrict with cohesion)
#   sh c_tests/reference/regenerate.sh [OUT.csv [OUT_COHESIVE.csv]]
# Installs Debian's yade (2023.02a) with apt-get if `yade` is missing. Headless.
set -eu
HERE=$(cd "$(dirname "$0")" && pwd)
OUT=${1:-"$HERE/yade_double.csv"}
OUT_COHESIVE=${2:-"$HERE/yade_cohesive.csv"}
if ! command -v yade >/dev/null 2>&1; then
    SUDO=""
    if [ "$(id -u)" != "0" ]; then SUDO="sudo"; fi
    $SUDO apt-get update
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y --no-install-recommends yade
fi
# no display needed: -n (no GUI), and keep Qt from looking for an X server
export QT_QPA_PLATFORM=offscreen
export OMP_NUM_THREADS=1
unset DISPLAY || true
cd "$HERE"
yade -n -x "$HERE/yade_reference.py" "$OUT"
echo "regenerate.sh: wrote $OUT"
yade -n -x "$HERE/yade_reference.py" "$OUT_COHESIVE" "$HERE/cohesive_cases.json"
echo "regenerate.sh: wrote $OUT_COHESIVE"
