"""examples/four_bar_stiffness_sweep.py, the example of docs/python.md, runs and writes its plot."""

import importlib.util
import math
import re

import pytest

from conftest import SOURCE


def test_the_stiffness_sweep_example_writes_its_plot(tmp_path):
    spec = importlib.util.spec_from_file_location("sweep", SOURCE / "examples" / "four_bar_stiffness_sweep.py")
    sweep = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(sweep)
    output = tmp_path / "sweep.png"
    results = sweep.main(["--points", "3", "--t-end", "0.3", "--output", str(output)])
    assert output.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert [round(k) for k, _, _ in results] == [50, 500, 5000]
    for k, motion, equilibrium in results:
        assert motion.t[-1] == 0.3 and equilibrium.converged and equilibrium.stability == "stable"


def test_the_example_reports_every_angle_one_way(tmp_path, capsys):
    """Issue 41: the equilibrium angle was printed unwrapped and plotted wrapped. Every angle the
    example reports is in degrees in (-180, 180]."""
    spec = importlib.util.spec_from_file_location("sweep", SOURCE / "examples" / "four_bar_stiffness_sweep.py")
    sweep = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(sweep)
    assert sweep.degrees_wrapped(1.5 * math.pi) == pytest.approx(-90.0)
    assert sweep.degrees_wrapped(-math.pi) == 180.0 and sweep.degrees_wrapped(math.pi) == 180.0
    assert sweep.degrees_wrapped(-7 * math.pi / 4) == pytest.approx(45.0)
    sweep.main(["--points", "3", "--t-end", "0.3", "--output", str(tmp_path / "sweep.png")])
    printed = [line for line in capsys.readouterr().out.splitlines() if line.startswith("k = ")]
    assert len(printed) == 3
    for line in printed:
        angles = [float(a) for a in re.findall(r"(-?\d+\.\d+) deg", line)]
        assert len(angles) == 2 and all(-180.0 < a <= 180.0 for a in angles), line
