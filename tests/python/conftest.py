"""Shared pieces of the Python suite (ctest runs it as python_pytest, with PYTHONPATH at the
build tree's package, MBD_EXECUTABLE the build's mbd command and MBD_SOURCE_DIR the tree)."""

import os
import pathlib
import subprocess

import numpy as np
import pytest

SOURCE = pathlib.Path(os.environ.get("MBD_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
MBD = os.environ.get("MBD_EXECUTABLE", str(SOURCE / "build" / "bin" / "mbd"))


def scene(relative):
    """A scene file of scenes/."""
    return str(SOURCE / "scenes" / relative)


class Cli:
    """The mbd command: its exit code, stdout, and the message after 'mbd: error: '."""

    def __init__(self, *args):
        done = subprocess.run([MBD, *map(str, args)], capture_output=True, text=True, timeout=120)
        self.code, self.out, self.err = done.returncode, done.stdout, done.stderr

    @property
    def error(self):
        lines = [l for l in self.err.splitlines() if l.startswith("mbd: error: ")]
        assert lines, f"mbd printed no error (exit {self.code}): {self.err}"
        return lines[0][len("mbd: error: "):]


def run_cli(*args):
    result = Cli(*args)
    assert result.code == 0, f"mbd {' '.join(map(str, args))} failed: {result.err}"
    return result


def read_csv(path):
    """Header and rows of a CSV mbd wrote; every number read back exactly (17 digits)."""
    with open(path) as f:
        header = f.readline().strip().split(",")
        rows = [[float(x) for x in line.split(",")] for line in f]
    return header, np.array(rows)


def bit_identical(a, b):
    a, b = np.ascontiguousarray(a, dtype=float), np.ascontiguousarray(b, dtype=float)
    return a.shape == b.shape and np.array_equal(a.view(np.uint64), b.view(np.uint64))


@pytest.fixture(autouse=True)
def default_plugin_path():
    """Every test starts and ends with the default plugin path."""
    import mbd
    mbd.set_plugin_path(None)
    yield
    mbd.set_plugin_path(None)
