#!/usr/bin/env bash
# Installs every Debian package mbd needs to build, test and benchmark.
# Idempotent; run as root (or with sudo available) on Debian 12.
set -euo pipefail
packages=(
  build-essential cmake pkg-config
  ccache  # a compiler cache (CMakeLists.txt, MBD_CCACHE): rebuilds compile only what changed
  lld  # the linker of every build tree (CMakeLists.txt, MBD_LLD; docs/ci.md)
  procps  # pgrep: .ci/run stops its background builds when a phase fails
  libeigen3-dev libboost-dev libboost-filesystem-dev
  libyaml-cpp-dev libsuitesparse-dev libcli11-dev nlohmann-json3-dev
  coinor-libipopt-dev libsundials-dev
  libgtest-dev
  python3 python3-numpy
  python3-dev pybind11-dev python3-pytest  # the Python module (python/, docs/python.md) and its tests
  python3-venv python3-pip python3-setuptools python3-wheel  # the wheel and its venv test (scripts/build-wheel.sh, docs/python.md)
  python3-nbconvert python3-ipykernel  # the notebook of the wheel test, executed headless
  python3-matplotlib
  libsimbody-dev libmujoco-dev  # the bench peers (bench/peers/, docs/benchmarks.md)
  clang libclang-rt-dev  # libFuzzer (scripts/fuzz.sh, run by CI through scripts/fuzz-ci.sh)
  libtinygltf-dev libassimp-dev chromium   # animation export and its browser test (issue 15)
  libhdf5-dev libopenmpi-dev openmpi-bin  # mbd sweep: its HDF5 results file and its MPI ranks (issue 18)
  libmujoco-samples liburdfdom-dev libconsole-bridge-dev libtinyxml-dev  # model import (import/, docs/import.md; MJCF through libmujoco-dev)
  libsdformat-dev  # SDF import (import/src/sdf_reader.cpp, docs/import.md)
  libdart-dev libdart-utils-urdf-dev  # DART, which runs the same URDF robots (tests/test_dart_agreement.cpp, docs/import.md)
  libfcl-dev  # collision detection of the `collision:` shapes (plugins/forces/collision_contact)
  universal-ctags  # the size limits of the source (scripts/check-sizes.sh, tests/test_source_sizes.cpp)
)
# node and npm (the viewer's three.js bundle and its tests): Debian's unless a node is there
command -v node > /dev/null || packages+=(nodejs)
command -v npm > /dev/null || packages+=(npm)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
else
  SUDO=""
  [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -qq
  $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
  echo "install-deps: installed ${missing[*]}"
fi

# The viewer's npm packages (three, esbuild, puppeteer-core, gltf-validator), exactly as
# viewer/package-lock.json pins them, into viewer/node_modules (not committed).
viewer="$(cd "$(dirname "$0")/../viewer" && pwd)"
if [ ! -f "$viewer/node_modules/.package-lock.json" ] || [ "$viewer/package-lock.json" -nt "$viewer/node_modules/.package-lock.json" ]; then
  (cd "$viewer" && npm ci --no-audit --no-fund --prefer-offline > /dev/null)
  echo "install-deps: npm packages of viewer/ installed"
fi
