"""Python's results are the mbd command's results: every number of a simulation bit for bit
(planar, spatial and looped scenes, four formulations and four integrators), the same CSV
bytes from to_csv, the statics report of `mbd statics --json`, the efforts of `mbd inverse`;
and, where a closed form exists, the right number."""

import json
import math

import numpy as np
import pytest

import mbd
from conftest import bit_identical, read_csv, run_cli, scene

RUNS = [
    # scene, Python keywords, the same on the command line
    ("bench/chain-5.yaml",  # planar open chain
     dict(formulation="embedding", tol=1e-8, reactions=True, diagnostics=True),
     ["--formulation", "embedding", "--tol", "1e-8", "--reactions", "--diagnostics"], 1.0),
    ("dynamics/heavy-top.yaml",  # spatial: Euler parameters, world angular velocities in the CSV
     dict(formulation="augmented", integrator="rk4", step=1e-3, output_step=5e-3, reactions=True, diagnostics=True),
     ["--formulation", "augmented", "--integrator", "rk4", "--step", "1e-3", "--output-step", "5e-3", "--reactions",
      "--diagnostics"], 0.5),
    ("dynamics/four-bar-spring-damper.yaml",  # planar loop, with the Hamiltonian's H column
     dict(formulation="hamiltonian", reactions=True, diagnostics=True),
     ["--formulation", "hamiltonian", "--reactions", "--diagnostics"], 1.0),
    ("dynamics/rssr-gravity.yaml",  # spatial loop, implicit integrator
     dict(formulation="amalgamated", integrator="cvode", tol=1e-7, output_step=0.01),
     ["--formulation", "amalgamated", "--integrator", "cvode", "--tol", "1e-7", "--output-step", "0.01"], 0.5),
    ("dynamics/pendulum-a01.yaml",  # the 8th-order pair, its rows from the continuous extension
     dict(formulation="augmented", integrator="dop853", tol=1e-9, diagnostics=True),
     ["--formulation", "augmented", "--integrator", "dop853", "--tol", "1e-9", "--diagnostics"], 2.0),
]


@pytest.mark.parametrize("relative, keywords, options, t_end", RUNS, ids=[r[0] for r in RUNS])
def test_simulation_is_the_cli_csv_bit_for_bit(tmp_path, relative, keywords, options, t_end):
    cli_csv = tmp_path / "cli.csv"
    run_cli("simulate", scene(relative), "--t-end", t_end, "-o", cli_csv, "-q", *options)
    header, rows = read_csv(cli_csv)

    result = mbd.load(scene(relative)).simulate(t_end, **keywords)
    assert list(result.columns) == header
    assert bit_identical(result.data, rows)
    for k, name in enumerate(header):
        assert bit_identical(result[name], rows[:, k]), name
    assert result.stats.rows == len(rows)
    assert result.stats.formulation == keywords["formulation"]

    python_csv = tmp_path / "python.csv"
    result.to_csv(python_csv)
    assert python_csv.read_bytes() == cli_csv.read_bytes()


def test_arrays_of_a_simulation_are_its_columns():
    model = mbd.load(scene("bench/chain-5.yaml"))
    result = model.simulate(0.2, formulation="embedding", reactions=True, diagnostics=True)
    assert result.q.shape == (len(result), model.nq) and result.v.shape == (len(result), model.nv)
    # planar: q and v are the CSV's motion columns in body order
    for b, body in enumerate(model.bodies):
        for k, suffix in enumerate(("x", "y", "angle")):
            assert bit_identical(result.q[:, 3 * b + k], result[f"{body}.{suffix}"])
        for k, suffix in enumerate(("vx", "vy", "omega")):
            assert bit_identical(result.v[:, 3 * b + k], result[f"{body}.{suffix}"])
    assert result.reactions.shape == (len(result), len(model.joints), 3)
    assert result.reaction_joints == model.joints
    assert bit_identical(result.reactions[:, 2, 1], result[f"{model.joints[2]}.fy"])
    assert bit_identical(result.energies[:, 0], result["kinetic_energy"])
    assert result.t[0] == 0.0 and result.t[-1] == 0.2 and np.all(np.diff(result.t) > 0)
    # no reactions asked for: none computed, and saying so
    plain = model.simulate(0.2, formulation="embedding")
    assert not hasattr(plain, "reactions") and not hasattr(plain, "energies")
    with pytest.raises(AttributeError, match="reactions=True"):
        plain.reactions


def test_spatial_q_and_v_are_the_engines_coordinates():
    # the CSV gives the angular velocity in world axes, v in body axes: w = A(p) wbar
    result = mbd.load(scene("dynamics/heavy-top.yaml")).simulate(0.1, integrator="rk4", step=1e-3)
    e0, e1, e2, e3 = result.q[-1, 3:7]
    A = np.array([[e0**2 + e1**2 - e2**2 - e3**2, 2 * (e1 * e2 - e0 * e3), 2 * (e1 * e3 + e0 * e2)],
                  [2 * (e1 * e2 + e0 * e3), e0**2 - e1**2 + e2**2 - e3**2, 2 * (e2 * e3 - e0 * e1)],
                  [2 * (e1 * e3 - e0 * e2), 2 * (e2 * e3 + e0 * e1), e0**2 - e1**2 - e2**2 + e3**2]])
    world = np.array([result[f"top.w{c}"][-1] for c in "xyz"])
    np.testing.assert_allclose(A @ result.v[-1, 3:6], world, rtol=0, atol=1e-12)
    # steady precession about Z: the horizontal part of w turns, its size and w_z stay
    assert math.hypot(world[0], world[1]) == pytest.approx(50.0, abs=1e-4)
    assert world[2] == pytest.approx(89.16913788781845, abs=1e-4)


def test_unknown_column_lists_near_matches():
    result = mbd.load(scene("dynamics/four-bar-spring-damper.yaml")).simulate(0.05)
    with pytest.raises(KeyError) as error:
        result["crank.angel"]
    assert "'crank.angle'" in str(error.value) and "did you mean" in str(error.value)
    with pytest.raises(KeyError) as error:
        result["zzz"]
    assert "the columns are t, crank.x" in str(error.value)
    assert "crank.angle" in result and "crank.angel" not in result


@pytest.mark.parametrize("relative", ["four-bar.yaml", "statics/pendulum-torque.yaml"])
def test_statics_is_the_cli_json(relative):
    cli = json.loads(run_cli("statics", scene(relative), "--json").out)
    result = mbd.load(scene(relative)).statics()
    assert result.to_dict() == cli
    assert result.converged and result.stability == cli["stability"]
    for b, body in enumerate(mbd.load(scene(relative)).bodies):
        assert result.q[3 * b + 2] == cli["bodies"][body]["angle"]


def test_statics_of_the_pendulum_is_the_closed_form():
    # m g l cos(phi) = M (the scene's header), phi the direction of the mass centre from the pin:
    # the hanging root. l and the offset of phi from the body angle (-0.4) from the scene's
    # rounded position [0.460530, -0.194709].
    l, offset = math.hypot(0.460530, -0.194709), -0.4 - math.atan2(-0.194709, 0.460530)
    result = mbd.load(scene("statics/pendulum-torque.yaml")).statics()
    assert result.bodies["rod"]["angle"] == pytest.approx(-math.acos(2.0 / (9.81 * l)) + offset, abs=1e-9)
    assert result.stability == "stable"
    assert result.reactions["pin"]["fy"] == pytest.approx(9.81, abs=1e-8)  # the pin carries the weight


def test_statics_options_are_the_clis():
    model = mbd.load(scene("statics/pendulum-torque.yaml"))
    cli = json.loads(run_cli("statics", scene("statics/pendulum-torque.yaml"), "--json", "--objective",
                             "virtual-work", "--tolerance", "1e-12").out)
    assert model.statics(objective="virtual-work", tolerance=1e-12).to_dict() == cli
    with pytest.raises(mbd.InputError, match="objective"):
        model.statics(objective="potentail")


PENDULUM = """dimension: planar
gravity: [0, -9.81]
bodies:
  - {name: rod, mass: 1, inertia: 0.08333333333333333, position: [0.46053049700144255, -0.19470917115432526], angle: -0.4}
joints:
  - {name: pin, type: revolute, bodies: [ground, rod], point: [0, 0]}
drivers:
  - {name: swing, joint: pin, motion: {type: harmonic, offset: -0.4, amplitude: 0.3, frequency: 2}}
actuators:
  - {name: motor, joint: pin}
"""


def test_inverse_is_the_cli_csv_and_the_closed_form(tmp_path):
    path = tmp_path / "arm.yaml"
    path.write_text(PENDULUM)
    cli_csv = tmp_path / "cli.csv"
    run_cli("inverse", path, "--t-end", 1, "--step", 0.01, "--reactions", "-o", cli_csv)
    header, rows = read_csv(cli_csv)
    result = mbd.load(path).inverse(1.0, 0.01, reactions=True)
    assert list(result.columns) == header and bit_identical(result.data, rows)
    python_csv = tmp_path / "python.csv"
    result.to_csv(python_csv)
    assert python_csv.read_bytes() == cli_csv.read_bytes()
    # tau = J_O thetaddot + m g l cos(theta), theta = -0.4 + 0.3 sin 2t, J_O = 1/12 + 0.5^2
    t = result.t
    theta, thetaddot = -0.4 + 0.3 * np.sin(2 * t), -1.2 * np.sin(2 * t)
    expected = (1 / 12 + 0.25) * thetaddot + 9.81 * 0.5 * np.cos(theta)
    np.testing.assert_allclose(result.efforts[:, 0], expected, rtol=0, atol=1e-9)
    assert bit_identical(result["motor"], result.efforts[:, 0])
    assert result.reactions.shape == (len(t), 1, 3)
