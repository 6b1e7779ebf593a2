#!/usr/bin/env bash
# Installs every Debian package mbd needs to build, test and benchmark.
# Idempotent; run as root (or with sudo available) on Debian 12.
set -euo pipefail
packages=(
  build-essential cmake pkg-config
  libeigen3-dev libboost-dev libboost-filesystem-dev
  libyaml-cpp-dev libsuitesparse-dev libcli11-dev
  coinor-libipopt-dev libsundials-dev
  libgtest-dev
  python3 python3-numpy
  python3-matplotlib
  libsimbody-dev libmujoco-dev  # the bench peers (bench/peers/, docs/benchmarks.md)
  clang libclang-rt-dev  # libFuzzer (scripts/fuzz.sh, run by CI through scripts/fuzz-ci.sh)
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi
SUDO=""
[ "$(id -u)" -ne 0 ] && SUDO="sudo"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
echo "install-deps: installed ${missing[*]}"
