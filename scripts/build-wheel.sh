#!/usr/bin/env bash
# Builds the wheel of the Python module from a CMake build (docs/python.md, "A wheel"), with
# Debian's packaging tools and no network:
#   scripts/build-wheel.sh BUILD_DIR OUT_DIR [PYTHON]
# BUILD_DIR must have mbd_core, mbd_plugins, mbd and mbd_python built. The build is installed
# into a temporary prefix, the package, libmbd_core and the plugins are staged as
# python/setup.py describes, and `pip wheel --no-build-isolation --no-index` makes the wheel
# (python3-pip, python3-setuptools, python3-wheel). Prints the wheel's path.
set -euo pipefail
build_dir=$(realpath "$1")
out_dir=$2
python=${3:-/usr/bin/python3}
source_dir=$(cd "$(dirname "$0")/.." && pwd)
stage=$(mktemp -d)
trap 'rm -rf "$stage"' EXIT

cmake --install "$build_dir" --prefix "$stage/prefix" >/dev/null
site=$(grep '^MBD_PYTHON_INSTALL_DIR:' "$build_dir/CMakeCache.txt" | cut -d= -f2)
version=$(grep '^CMAKE_PROJECT_VERSION:' "$build_dir/CMakeCache.txt" | cut -d= -f2)
libdir=$(grep '^CMAKE_INSTALL_LIBDIR:' "$build_dir/CMakeCache.txt" | cut -d= -f2)
mkdir -p "$stage/wheel/mbd/lib/mbd/plugins"
cp "$stage/prefix/$site/mbd/"*.py "$stage/prefix/$site/mbd/"_mbd*.so "$stage/wheel/mbd/"
# libmbd_core under its soname (a wheel holds no symbolic links), the name the extension asks for
soname=$(objdump -p "$stage/prefix/$libdir/libmbd_core.so" | awk '$1 == "SONAME" {print $2}')
cp -L "$stage/prefix/$libdir/$soname" "$stage/wheel/mbd/lib/$soname"
cp "$stage/prefix/$libdir/mbd/plugins/"*.so "$stage/wheel/mbd/lib/mbd/plugins/"
cp "$source_dir/python/setup.py" "$stage/wheel/"
echo "$version" > "$stage/wheel/VERSION"

mkdir -p "$out_dir"
"$python" -m pip wheel --no-build-isolation --no-index --no-deps --disable-pip-version-check --quiet \
  --wheel-dir "$out_dir" "$stage/wheel" >&2
ls "$out_dir"/mbd-"$version"-*.whl
