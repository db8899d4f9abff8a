#!/bin/sh
# Re-run every LAMMPS reference case and rebuild lammps_reference.csv, inputs/, params/.
# Needs Debian's lammps (lmp, 29 Sep 2021 update 2) and python3-lammps (fix python/move).
set -e
cd "$(dirname "$0")"
if ! command -v lmp >/dev/null 2>&1 || ! /usr/bin/python3 -c 'import lammps' >/dev/null 2>&1; then
  apt-get update && DEBIAN_FRONTEND=noninteractive apt-get install -y lammps python3-lammps
fi
# use the system python: LAMMPS embeds /usr/lib's libpython and imports the
# lammps module from /usr/lib/python3/dist-packages
/usr/bin/python3 gen_lammps.py "$@"
/usr/bin/python3 check_lammps.py
