#!/usr/bin/env bash
# Installs mbd into a temporary prefix, builds the SDK's example joint plugin
# out of tree with find_package(mbd), loads it from a scene through
# MBD_PLUGIN_PATH, runs kinematics, and checks the coupling in the output.
set -euo pipefail
build_dir=$1
source_dir=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cmake --install "$build_dir" --prefix "$work/prefix" >/dev/null
cmake -S "$source_dir/sdk/examples/coupler" -B "$work/example" -DCMAKE_PREFIX_PATH="$work/prefix" \
  -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$work/example" -j2 >/dev/null
test -f "$work/example/libmbd_joint_coupler.so"
export MBD_PLUGIN_PATH="$work/example"
"$work/prefix/bin/mbd" plugins | grep -q coupler
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
