"""Model.modes() and Model.kinematics() give the numbers of `mbd modes --json` and
`mbd kinematics --output` to the bit (issue 38), and the modes of a pendulum its closed form."""

import json
import math

import numpy as np
import pytest

import mbd
from conftest import Cli, bit_identical, read_csv, run_cli, scene


def same_json(a, b):
    """Equal as JSON values, every float to the bit (== on floats compares them exactly;
    the text of both is also compared by the caller where it matters)."""
    assert type(a) is type(b), (a, b)
    if isinstance(a, dict):
        assert list(a) == list(b)
        for key in a:
            same_json(a[key], b[key])
    elif isinstance(a, list):
        assert len(a) == len(b)
        for x, y in zip(a, b):
            same_json(x, y)
    elif isinstance(a, float):
        assert a.hex() == b.hex(), (a, b)
    else:
        assert a == b


@pytest.mark.parametrize("relative, about", [("dynamics/pendulum-a01.yaml", "statics"),
                                             ("dynamics/four-bar-spring-damper.yaml", "statics"),
                                             ("reference/whipple-bicycle.yaml", "initial")])
def test_modes_equal_the_command_to_the_bit(relative, about):
    # the bicycle: a steady motion with ignorable coordinates and free velocities
    path = scene(relative)
    cli = run_cli("modes", path, "--about", about, "--json")
    expected = json.loads(cli.out)
    result = mbd.load(path).modes(about=about)
    same_json(result.to_dict(), expected)
    assert bit_identical(result.A, np.array(expected["A"], dtype=float).reshape(result.A.shape))
    eigenvalues = np.array([complex(*m["eigenvalue"]) for m in expected["modes"]])
    assert bit_identical(result.eigenvalues.real, eigenvalues.real)
    assert bit_identical(result.eigenvalues.imag, eigenvalues.imag)
    assert result.states == expected["states"] and len(result.modes) == len(expected["modes"])


def test_pendulum_mode_is_the_small_angle_frequency():
    # pendulum-a01: m = 1 kg at l = 1 m, J = 1e-6 kg m^2 about its centre, g = 9.81:
    # omega^2 = m g l / (J + m l^2), undamped
    result = mbd.load(scene("dynamics/pendulum-a01.yaml")).modes()
    assert len(result.modes) == 1 and result.modes[0].kind == "oscillatory"
    assert result.natural_frequencies[0] == pytest.approx(math.sqrt(9.81 / 1.000001), rel=1e-8)
    assert abs(result.damping_ratios[0]) < 1e-10
    assert result.A.shape == (2, 2) and result.B.shape == (2, 0)


@pytest.mark.parametrize("relative", ["four-bar.yaml", "book/slider-crank.yaml"])
def test_kinematics_equals_the_command_to_the_bit(relative, tmp_path):
    path = scene(relative)
    out = tmp_path / "kinematics.csv"
    run_cli("kinematics", path, "--t-end", "1", "--step", "0.01", "--output", out)
    header, rows = read_csv(out)
    result = mbd.load(path).kinematics(1.0, 0.01)
    assert list(result.columns) == header
    assert len(result) == 101
    assert bit_identical(result.data, rows)


def test_kinematics_of_the_driven_crank_follows_its_driver():
    # scenes/four-bar.yaml: its motor turns the crank at a constant rate from its initial angle
    result = mbd.load(scene("four-bar.yaml")).kinematics(0.5, 0.05)
    angle, rate = result["crank.angle"], result["crank.omega"]
    assert np.allclose(np.diff(angle) / 0.05, rate[0], rtol=0, atol=1e-9)
    assert np.allclose(rate, rate[0], rtol=0, atol=1e-9) and rate[0] != 0


def test_bad_arguments_are_named():
    model = mbd.load(scene("four-bar.yaml"))
    with pytest.raises(mbd.InputError, match="step"):
        model.kinematics(1.0, 0.0)
    with pytest.raises(mbd.InputError, match="linear_algebra"):
        model.kinematics(1.0, 0.1, linear_algebra="lu")
    with pytest.raises(mbd.InputError, match="about"):
        mbd.load(scene("dynamics/pendulum-a01.yaml")).modes(about="rest")
    for about in ("statics", "initial"):  # the motor drives the only freedom: nothing to linearise
        with pytest.raises(mbd.LinearisationError, match="no freedom to linearise: the driver 'motor'"):
            model.modes(about=about)
    # released from the horizontal: not at rest, as `mbd modes` says
    with pytest.raises(mbd.LinearisationError, match="not an equilibrium or steady motion"):
        mbd.load(scene("dynamics/pendulum-a01.yaml")).modes(about="initial")


def test_a_statics_that_does_not_converge_gives_no_modes():
    path = scene("dynamics/pendulum-a01.yaml")
    cli = Cli("modes", path, "--statics-iterations", "1", "--json")
    assert cli.code == 1 and "did not converge" in cli.error
    with pytest.raises(mbd.StaticsError, match="no modes: the statics of .*pendulum-a01.yaml did not converge"):
        mbd.load(path).modes(statics_iterations=1)
    with pytest.raises(mbd.InputError, match="statics_iterations"):
        mbd.load(path).modes(statics_iterations=0)
    with pytest.raises(mbd.InputError, match="residual_tolerance"):
        mbd.load(path).modes(residual_tolerance=-1.0)
