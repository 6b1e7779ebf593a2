#!/usr/bin/env bash
# `cmake --install` into a fresh prefix, then `import mbd` with only that prefix's package on
# the path (no build tree: run from an empty folder, PYTHONPATH = the prefix's site-packages):
# the package, its extension and libmbd_core come from the prefix, the plugins are found in the
# prefix's lib/mbd/plugins, and a scene given as dicts simulates.
# Arguments: BUILD_DIR PYTHON SITE (the package folder under the prefix, MBD_PYTHON_INSTALL_DIR).
set -euo pipefail
build_dir=$1
python=$2
site=$3
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cmake --install "$build_dir" --prefix "$work/prefix" >/dev/null
test -f "$work/prefix/$site/mbd/__init__.py"
mkdir "$work/empty"
cd "$work/empty"
env -u MBD_PLUGIN_PATH PYTHONPATH="$work/prefix/$site" PYTHONNOUSERSITE=1 PYTHONDONTWRITEBYTECODE=1 \
  "$python" -c "import mbd" 
env -u MBD_PLUGIN_PATH PYTHONPATH="$work/prefix/$site" PYTHONNOUSERSITE=1 PYTHONDONTWRITEBYTECODE=1 \
  PREFIX="$work/prefix" BUILD="$(cd "$build_dir" && pwd)" "$python" - <<'PY'
import os, sys
import mbd, mbd._mbd
prefix, build = os.environ["PREFIX"], os.environ["BUILD"]
assert mbd.__file__.startswith(prefix), mbd.__file__
assert mbd._mbd.__file__.startswith(prefix), mbd._mbd.__file__
assert not any(p.startswith(build) for p in sys.path), sys.path
assert mbd.plugin_path() == [os.path.join(prefix, "lib", "mbd", "plugins")], mbd.plugin_path()
assert {p.type for p in mbd.plugins() if p.kind == "formulation"} >= {"augmented", "embedding"}
pendulum = {"dimension": "planar", "gravity": [0, -9.81],
            "bodies": [{"name": "bob", "mass": 1, "inertia": 1e-6, "position": [1, 0]}],
            "joints": [{"name": "pin", "type": "revolute", "bodies": ["ground", "bob"], "point": [0, 0]}]}
result = mbd.Model.from_dict(pendulum).simulate(0.5)
# the bob stays on its unit circle
assert abs((result["bob.x"] ** 2 + result["bob.y"] ** 2 - 1).max()) < 1e-9
with open("/proc/self/maps") as maps:
    core = [line.split()[-1] for line in maps if "libmbd_core" in line]
assert core and all(path.startswith(prefix) for path in core), core
print(f"import mbd from {os.path.dirname(mbd.__file__)}: {len(mbd.plugins())} plugin types, "
      f"{len(result)} rows simulated")
PY
