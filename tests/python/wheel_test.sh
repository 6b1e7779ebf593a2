#!/usr/bin/env bash
# Issue 38: the wheel. Builds it from the build tree (scripts/build-wheel.sh, no network),
# installs it with `pip install --no-index` into a fresh venv of Debian's python3 (numpy from
# Debian through --system-site-packages), and with no PYTHONPATH, LD_LIBRARY_PATH or
# MBD_PLUGIN_PATH: runs a pendulum against its closed forms, then executes a notebook headless
# with nbconvert and checks that its output holds the viewer's page.
#   wheel_test.sh BUILD_DIR SOURCE_DIR PYTHON
set -euo pipefail
build_dir=$1
source_dir=$2
python=$3
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
wheel=$(bash "$source_dir/scripts/build-wheel.sh" "$build_dir" "$work/dist" "$python")
echo "wheel: $(basename "$wheel"), $(du -k "$wheel" | cut -f1) kB"
# --without-pip: Debian's pip, seen through --system-site-packages, installs into the venv
# (ensurepip's own copy of pip would take most of the test's time)
"$python" -m venv --system-site-packages --without-pip "$work/venv"
"$work/venv/bin/python" -m pip install --no-index --disable-pip-version-check --quiet "$wheel"
test -d "$work/venv/lib/python3"*/site-packages/mbd  # installed into the venv, not elsewhere
clean=(env -u PYTHONPATH -u LD_LIBRARY_PATH -u MBD_PLUGIN_PATH -u PYTHONHOME)
cd "$work"  # nothing of the tree on sys.path

"${clean[@]}" "$work/venv/bin/python" - "$source_dir/scenes/dynamics/pendulum-a01.yaml" "$work/venv" <<'PY'
import math, os, sys
import mbd
scene, venv = sys.argv[1], os.path.realpath(sys.argv[2])
# the package, its engine and its plugins are the wheel's, in the venv
assert os.path.realpath(mbd.__file__).startswith(venv), mbd.__file__
plugins = mbd.plugin_path()
assert os.path.realpath(plugins[0]).startswith(venv), plugins
assert any(p.type == "revolute" and p.usable for p in mbd.plugins())
model = mbd.load(scene)
# pendulum-a01: 1 kg at 1 m, J = 1e-6 kg m^2, g = 9.81, released at rest from the horizontal.
# Energy: T + V stays 0 (V = 0 at the pivot's height); the bob's speed at the bottom is sqrt(2 g l)
# scaled by the compound inertia: m v^2 / 2 (1 + J / (m l^2)) = m g l.
result = model.simulate(1.0, integrator="dop853", tol=1e-11, output_step=1e-3, diagnostics=True)
energy = result["kinetic_energy"] + result["potential_energy"]
bottom = abs(result["bob.x"]).argmin()
speed = math.hypot(result["bob.vx"][bottom], result["bob.vy"][bottom])
speed_exact = math.sqrt(2 * 9.81 / 1.000001)
print(f"venv: mbd {mbd.__version__} from {os.path.dirname(mbd.__file__)}; {len(mbd.plugins())} plugin types")
print(f"pendulum: max |T + V| = {abs(energy).max():.2e} J; speed at the bottom {speed:.9f} m/s "
      f"(closed form {speed_exact:.9f}, bob.x there {result['bob.x'][bottom]:.1e})")
assert abs(energy).max() < 1e-8
# the sample nearest the bottom is within 0.5 ms of it, where the speed is largest: it differs
# by at most (1/2) |d2v/dt2| (0.5 ms)^2, |d2v/dt2| = v w^2 < 44 m/s^3 there: 6e-6 m/s
assert abs(speed - speed_exact) < 1e-5, (speed, speed_exact)
modes = model.modes()
omega = math.sqrt(9.81 / 1.000001)
print(f"modes: omega_n = {modes.natural_frequencies[0]!r} rad/s, closed form {omega!r}")
assert abs(modes.natural_frequencies[0] - omega) < 1e-8 * omega
PY

# A notebook executed headless: the kernel is the venv's interpreter (its own kernelspec)
export JUPYTER_CONFIG_DIR="$work/jupyter/config" JUPYTER_DATA_DIR="$work/jupyter/data" \
  JUPYTER_RUNTIME_DIR="$work/jupyter/runtime" IPYTHONDIR="$work/ipython"
"${clean[@]}" "$work/venv/bin/python" -m ipykernel install --prefix "$work/venv" --name mbd-wheel >/dev/null 2>&1
"$python" - "$work/pendulum.ipynb" "$source_dir/scenes/dynamics/pendulum-a01.yaml" <<'PY'
import sys
import nbformat
notebook = nbformat.v4.new_notebook()
notebook.cells = [
    nbformat.v4.new_code_cell(f"import mbd\nmodel = mbd.load({sys.argv[2]!r})"),
    nbformat.v4.new_code_cell("result = model.simulate(1.0, output_step=0.01)\nresult"),
]
nbformat.write(notebook, sys.argv[1])
PY
"${clean[@]}" "$work/venv/bin/python" -m nbconvert --to notebook --execute \
  --ExecutePreprocessor.kernel_name=mbd-wheel --ExecutePreprocessor.timeout=60 \
  --output executed.ipynb "$work/pendulum.ipynb" 2>"$work/nbconvert.log" || { cat "$work/nbconvert.log" >&2; exit 1; }
"$python" - "$work/executed.ipynb" <<'PY'
import html, re, sys
import nbformat
notebook = nbformat.read(sys.argv[1], as_version=4)
shown = [o["data"]["text/html"] for o in notebook.cells[1].outputs if "text/html" in o.get("data", {})]
assert len(shown) == 1, notebook.cells[1].outputs
page = html.unescape(re.fullmatch(r'<iframe class="mbd-viewer" srcdoc="([^"]*)"[^>]*></iframe>', shown[0], re.S).group(1))
assert page.startswith("<!DOCTYPE html>"), page[:80]
assert '<script id="mbd-scene" type="application/json">{"name":"pendulum-a01"' in page
assert '"rows":101' in page and '<script id="mbd-motion" type="text/plain">' in page
print(f"notebook: executed headless, its output holds the viewer page ({len(page)} characters, 101 rows)")
PY
