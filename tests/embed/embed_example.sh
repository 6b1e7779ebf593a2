#!/usr/bin/env bash
# Issue 38: the engine as a CMake package. Installs mbd into a fresh temporary prefix, checks
# find_package(mbd)'s version (0.1 accepted, 1.0 refused), builds examples/embed against the
# prefix alone (CMAKE_PREFIX_PATH, nothing of the source or build tree) and runs it: the period
# of the IFToMM A01 pendulum it prints must be the closed form 4 K(k) / w and its energy drift
# below 1e-8 J (the period to 1e-9 s: the turning points are interpolated where omega is linear in t).
#   embed_example.sh BUILD_DIR SOURCE_DIR [CMAKE_ARGS...]   (the compiler, sanitizer flags)
set -euo pipefail
build_dir=$1
source_dir=$2
shift 2
cmake_args=("$@")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cmake --install "$build_dir" --prefix "$work/prefix" >/dev/null
# the example is copied out of the tree: nothing can reach the sources by a relative path
cp -r "$source_dir/examples/embed" "$work/embed"

# the version file: a request for another major version is refused
mkdir -p "$work/probe"
cat >"$work/probe/CMakeLists.txt" <<'CMAKE'
cmake_minimum_required(VERSION 3.20)
project(probe NONE)
find_package(mbd 1.0 QUIET)
if(mbd_FOUND)
  message(FATAL_ERROR "find_package(mbd 1.0) accepted version ${mbd_VERSION}")
endif()
find_package(mbd 0.1 REQUIRED)
if(NOT TARGET mbd::engine OR NOT TARGET mbd::sdk)
  message(FATAL_ERROR "find_package(mbd) exports no mbd::engine / mbd::sdk")
endif()
file(WRITE "${CMAKE_BINARY_DIR}/version.txt" "${mbd_VERSION}")
CMAKE
cmake -S "$work/probe" -B "$work/probe/build" -DCMAKE_PREFIX_PATH="$work/prefix" >/dev/null
version=$(cat "$work/probe/build/version.txt")
echo "find_package(mbd): version $version, mbd::engine"

cmake -S "$work/embed" -B "$work/embed/build" -DCMAKE_PREFIX_PATH="$work/prefix" -DCMAKE_BUILD_TYPE=Release \
  "${cmake_args[@]}" >/dev/null
cmake --build "$work/embed/build" -j2 >/dev/null
# the plugins and the scene come from the prefix alone: no plugin path, no library path
env -u MBD_PLUGIN_PATH -u LD_LIBRARY_PATH "$work/embed/build/pendulum_period" | tee "$work/out.txt"
grep -q "^mbd engine $version, scene pendulum-a01$" "$work/out.txt"
python3 - "$work/out.txt" <<'PY'
import math, sys
values = dict(line.split()[:2] for line in open(sys.argv[1]) if line.split()[0].endswith(("_s", "_J")))
# pendulum-a01: m = 1 kg, l = 1 m, J = 1e-6 kg m^2 about the bob, g = 9.81, released at rest
# 90 degrees from the downward vertical. Exact period 4 K(k) / w, k = sin(45 deg),
# w^2 = m g l / (J + m l^2); K(k) = pi / (2 AGM(1, sqrt(1 - k^2))).
a, b = 1.0, math.sqrt(1.0 - math.sin(math.pi / 4) ** 2)
for _ in range(30):
    a, b = (a + b) / 2, math.sqrt(a * b)
K = math.pi / (2 * a)
period = 4 * K / math.sqrt(9.81 / 1.000001)
measured, half, drift = float(values["period_s"]), float(values["half_period_s"]), float(values["energy_drift_J"])
print(f"period {measured:.12f} s, closed form {period:.12f} s, difference {measured - period:.2e} s; "
      f"half period {half:.12f} s; energy drift {drift:.2e} J")
assert abs(measured - period) < 1e-9, (measured, period)
assert abs(half - period / 2) < 1e-9, (half, period)
assert drift < 1e-8, drift
PY
