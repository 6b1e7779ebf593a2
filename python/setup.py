"""The wheel of the Python module mbd, built by scripts/build-wheel.sh from a staged copy of an
installed build (not from the sources: the extension, libmbd_core and the plugins are built by
CMake first). The staging folder holds this file, VERSION and the package:

    mbd/*.py, mbd/_mbd.*.so        the package and its extension (rpath $ORIGIN/lib)
    mbd/lib/libmbd_core.so.N       the engine, found by the extension through its rpath
    mbd/lib/mbd/plugins/*.so       the plugins, found beside libmbd_core as in an install

The wheel is for the interpreter and the Debian release it was built with: the engine's own
dependencies (SUNDIALS, yaml-cpp, Ipopt, ...) come from Debian's packages."""

import pathlib

from setuptools import setup
from setuptools.dist import Distribution


class BinaryDistribution(Distribution):
    """A wheel tagged for this interpreter and platform (it carries compiled libraries)."""

    def has_ext_modules(self):
        return True


here = pathlib.Path(__file__).resolve().parent
setup(
    name="mbd",
    version=(here / "VERSION").read_text().strip(),
    description="mbd: multibody dynamics with honest numbers (the engine, its plugins and the Python module)",
    packages=["mbd"],
    package_data={"mbd": ["_mbd*.so", "lib/*.so*", "lib/mbd/plugins/*.so"]},
    include_package_data=False,
    python_requires=">=3.9",
    install_requires=["numpy"],
    distclass=BinaryDistribution,
    zip_safe=False,
)
