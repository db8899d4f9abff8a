#!/bin/sh
# The whole test suite on a fresh machine: `cargo test` needs cmake and pkg-config for the CMake
# package test (tests/cmake_package.rs), which a fresh machine lacks; install them when missing
# (apt-get, as root or with sudo), then run `cargo test` with any arguments given.
#
#   ./run-tests.sh [cargo test arguments]
set -eu
cd "$(dirname "$0")"
missing=
command -v cmake >/dev/null 2>&1 || missing="$missing cmake"
command -v pkg-config >/dev/null 2>&1 || missing="$missing pkg-config"
if [ -n "$missing" ]; then
  sudo=
  [ "$(id -u)" = 0 ] || sudo=sudo
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends $missing
fi
exec cargo test "$@"
