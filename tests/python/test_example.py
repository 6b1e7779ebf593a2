"""examples/four_bar_stiffness_sweep.py, the example of docs/python.md, runs and writes its plot."""

import importlib.util

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
