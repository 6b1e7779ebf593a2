#!/usr/bin/env bash
# Installs mbd into a temporary prefix, builds the SDK's example joint plugin
# out of tree with find_package(mbd), loads it from a scene through
# MBD_PLUGIN_PATH, runs kinematics, and checks the coupling in the output. The package's
# MBD_PLUGIN_DIR must be the installed plugin folder, holding the installed plugin libraries.
set -euo pipefail
build_dir=$1
source_dir=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cmake --install "$build_dir" --prefix "$work/prefix" >/dev/null
# find_package(mbd) in an empty project: MBD_PLUGIN_DIR is an absolute folder under the prefix
# with the standard plugins in it
mkdir -p "$work/probe"
cat >"$work/probe/CMakeLists.txt" <<'CMAKE'
cmake_minimum_required(VERSION 3.16)
project(probe NONE)
find_package(mbd REQUIRED)
file(WRITE "${CMAKE_BINARY_DIR}/plugin_dir.txt" "${MBD_PLUGIN_DIR}")
CMAKE
cmake -S "$work/probe" -B "$work/probe/build" -DCMAKE_PREFIX_PATH="$work/prefix" >/dev/null
plugin_dir=$(cat "$work/probe/build/plugin_dir.txt")
case "$plugin_dir" in
  "$work/prefix"/*) ;;
  *) echo "MBD_PLUGIN_DIR '$plugin_dir' is not under the install prefix $work/prefix" >&2; exit 1 ;;
esac
for lib in libmbd_joint_revolute.so libmbd_joint_distance.so libmbd_force_gravity.so libmbd_formulation_augmented.so; do
  if [ ! -f "$plugin_dir/$lib" ]; then
    echo "MBD_PLUGIN_DIR '$plugin_dir' does not hold the installed plugin $lib" >&2
    ls -la "$plugin_dir" >&2 || true
    exit 1
  fi
done
echo "MBD_PLUGIN_DIR = $plugin_dir: $(ls "$plugin_dir"/libmbd_*.so | wc -l) plugin libraries"
cmake -S "$source_dir/sdk/examples/coupler" -B "$work/example" -DCMAKE_PREFIX_PATH="$work/prefix" \
  -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$work/example" -j2 >/dev/null
test -f "$work/example/libmbd_joint_coupler.so"
export MBD_PLUGIN_PATH="$work/example"
# into a file first: grep -q stops reading at the match, and under pipefail the SIGPIPE mbd then
# gets on its next line would fail the test
"$work/prefix/bin/mbd" plugins > "$work/plugins.txt"
grep -q coupler "$work/plugins.txt"
# its key description: the plugin check needs no --params, and --keys prints the key
"$work/prefix/bin/mbd" plugin check coupler | tee "$work/check.txt"
grep -q "2 checked, 0 failed" "$work/check.txt"
"$work/prefix/bin/mbd" plugins --keys coupler | grep -q '| `ratio` | turns of body b per turn of body a, non-zero | required | `2` |'
"$work/prefix/bin/mbd" kinematics "$source_dir/sdk/examples/coupler/coupler.yaml" --t-end 1 --step 0.25 \
  --output "$work/out.csv"
# theta_b - 0.5 must equal 2 * theta_a, and theta_a = t (driver), at every row
python3 - "$work/out.csv" <<'PY'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
assert len(rows) == 5, len(rows)
for r in rows:
    t, a, b = float(r["t"]), float(r["wheel_a.angle"]), float(r["wheel_b.angle"])
    assert abs(a - t) < 1e-9, (t, a)
    assert abs((b - 0.5) - 2 * a) < 1e-9, (a, b)
print("out-of-tree coupler plugin: %d rows, theta_b - 0.5 = 2 theta_a to 1e-9" % len(rows))
PY
