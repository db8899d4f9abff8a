#!/bin/sh
# Re-run every LIGGGHTS reference case and rebuild liggghts_reference.csv, inputs/, params/.
set -e
cd "$(dirname "$0")"
if ! command -v liggghts >/dev/null 2>&1; then
  apt-get update && DEBIAN_FRONTEND=noninteractive apt-get install -y liggghts
fi
/usr/bin/python3 gen_liggghts.py "$@"
