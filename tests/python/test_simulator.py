"""mbd.Simulator (issue 38): stepping, the state as numpy, inputs, a Python user force, events
and bad input. Oracles: a built-in spring-damper (the user force computes the same law), the
A01 pendulum's closed form, the engine's own whole run (simulate) for events."""

import math
import traceback

import numpy as np
import pytest

import mbd
from conftest import scene


def pair(spring):
    """Two free planar bodies (no gravity), with or without a spring-damper between their centres."""
    d = {"name": "pair", "dimension": "planar", "gravity": [0, 0], "bodies": [
        {"name": "a", "mass": 1.5, "inertia": 0.2, "position": [0, 0], "velocity": [0.3, -0.2],
         "angular_velocity": 1},
        {"name": "b", "mass": 0.7, "inertia": 0.1, "position": [1.2, 0.4], "velocity": [-0.5, 0.6]}]}
    if spring:
        d["forces"] = [{"name": "s", "type": "spring_damper", "bodies": ["a", "b"], "stiffness": 40,
                        "damping": 0.8, "rest_length": 1}]
    return mbd.Model.from_dict(d)


def spring_damper_forces(q, v):
    """f = k (l - l0) + c ldot along u, tension pulling a towards b (book Sec. 5.4): per body (fx, fy, torque)."""
    d, dv = q[3:5] - q[0:2], v[3:5] - v[0:2]
    l = math.hypot(d[0], d[1])
    u = d / l
    f = 40.0 * (l - 1.0) + 0.8 * float(u @ dv)
    return np.array([[f * u[0], f * u[1], 0.0], [-f * u[0], -f * u[1], 0.0]])


@pytest.mark.parametrize("kind", ["generalized", "bodies"])
def test_a_python_user_force_reproduces_a_built_in_spring_damper(kind):
    builtin = mbd.Simulator(pair(True), integrator="rk4", step=1e-3, t_end=2.0)
    user = mbd.Simulator(pair(False), integrator="rk4", step=1e-3, t_end=2.0)
    calls = []

    def force(t, q, v):
        calls.append(t)
        rows = spring_damper_forces(q, v)
        return rows if kind == "bodies" else rows.ravel()

    user.set_user_force(force, kind=kind)
    builtin.advance_to(2.0)
    user.advance_to(2.0)
    assert len(calls) >= 4 * 2000  # four stages per rk4 step
    assert np.max(np.abs(builtin.q - user.q)) < 1e-12
    assert np.max(np.abs(builtin.v - user.v)) < 1e-12
    assert np.max(np.abs(builtin.v - pair(True).initial_state()[1])) > 0.1  # the spring acted


def test_spatial_body_moments_are_in_world_axes():
    """A free spatial body turned 90 degrees about z, pushed by a world moment about x: its
    body-frame spin grows about its own -y axis (world x is body -y) at M / I."""
    model = mbd.Model.from_dict({"name": "top", "dimension": "spatial", "gravity": [0, 0, 0], "bodies": [
        {"name": "b", "mass": 2.0, "inertia": [0.5, 0.5, 0.5], "position": [0, 0, 0],
         "orientation": {"axis": [0, 0, 1], "angle": math.pi / 2}}]})
    sim = mbd.Simulator(model, integrator="rk4", step=1e-3, t_end=0.1)
    sim.set_user_force(lambda t, q, v: np.array([[0, 0, 0, 0.25, 0, 0]]), kind="bodies")
    sim.advance_to(0.1)
    _, w = sim.body_state("b")
    # spinning about one principal axis of a sphere-like body: omega = M t / I, no gyroscopic term
    assert w[3:] == pytest.approx([0.0, -0.25 * 0.1 / 0.5, 0.0], abs=1e-12)


def test_step_advance_and_the_state_as_numpy():
    model = mbd.load(scene("dynamics/pendulum-a01.yaml"))
    sim = mbd.Simulator(model, integrator="dopri5", tol=1e-8)
    view = sim.q
    assert not view.flags.writeable
    with pytest.raises(ValueError):
        view[0] = 1.0
    t, q0, v0 = sim.state()
    assert t == 0.0 and q0.shape == (model.nq,) and v0.shape == (model.nv,)
    for _ in range(20):
        before = sim.time
        sim.step()
        assert sim.time > before
    assert sim.stats["steps"] == 20
    # the view follows the state (no copy made), the copy from state() does not
    assert np.shares_memory(view, sim.q)
    assert np.array_equal(view, sim.q) and not np.array_equal(view, q0)
    sim.advance_to(0.7)
    assert sim.time == pytest.approx(0.7, abs=1e-15)
    # reset() returns to the scene's start
    sim.reset()
    assert sim.time == 0.0 and np.array_equal(sim.q, q0)


def test_advance_to_continues_the_run():
    """1000 advance_to calls land on the whole run of simulate() within its tolerance."""
    model = mbd.load(scene("dynamics/pendulum-a01.yaml"))
    whole = model.simulate(1.0, integrator="dopri5", tol=1e-9)
    sim = mbd.Simulator(model, integrator="dopri5", tol=1e-9, t_end=1.0)
    for k in range(1, 1001):
        sim.advance_to(k / 1000)
    assert np.max(np.abs(sim.q - whole.q[-1])) < 1e-7
    assert np.max(np.abs(sim.v - whole.v[-1])) < 1e-7


def test_events_are_reported_as_they_happen():
    model = mbd.load(scene("examples/force-joint-stop.yaml"))
    sim = mbd.Simulator(model, integrator="dopri5", tol=1e-9, t_end=3.0)
    told = []
    sim.on_event(lambda e: told.append((e, sim.time)))
    for k in range(1, 301):
        start = sim.time
        sim.advance_to(0.01 * k)
        for event, _ in told:
            if event["time"] >= start:
                assert event["time"] <= sim.time
    assert told and len(told) == len(sim.events)
    assert told[0][0]["force"] == "stop"
    assert told[0][0] == sim.events[0]


CART_POLE = {"name": "cart-pole", "dimension": "planar", "gravity": [0, -9.81], "bodies": [
    {"name": "cart", "mass": 1.0, "inertia": 0.01, "position": [0, 0]},
    {"name": "pole", "mass": 0.1, "inertia": 0.1 / 12, "position": [0, 0.5], "angle": math.pi / 2}],
    "joints": [{"name": "rail", "type": "prismatic", "bodies": ["ground", "cart"], "point": [0, 0], "axis": [1, 0]},
               {"name": "pin", "type": "revolute", "bodies": ["cart", "pole"], "point": [0, 0]}],
    "forces": [{"name": "push", "type": "point_force", "body": "cart", "force": [{"type": "input", "name": "force"}, 0]}]}


def test_bad_input_is_a_clear_error_and_the_simulator_stays_usable():
    model = mbd.Model.from_dict(CART_POLE)
    sim = mbd.Simulator(model, integrator="dopri5", tol=1e-8)
    assert sim.input_names == ["force"]
    with pytest.raises(mbd.InputError, match="its inputs are: force"):
        sim.set_input("forse", 1.0)
    with pytest.raises(mbd.InputError, match="finite"):
        sim.set_input("force", float("nan"))
    with pytest.raises(mbd.InputError, match="needs 6 coordinates and 6 velocities, got 5"):
        sim.reset(np.zeros(5))
    bad = sim.q.copy()
    bad[1] = np.nan
    with pytest.raises(mbd.InputError, match="finite"):
        sim.reset(bad)
    with pytest.raises(mbd.InputError, match="its bodies are: cart, pole"):
        sim.body_state("poll")
    with pytest.raises(mbd.InputError, match="not before the current time"):
        sim.advance_to(-1.0)
    sim.set_input("force", 1.0)
    sim.advance_to(0.1)
    t_good, q_good, v_good = sim.state()

    # a callback returning the wrong shape
    sim.set_user_force(lambda t, q, v: np.zeros(3))
    with pytest.raises(mbd.DynamicsError, match=r"returned shape \(3,\); it must return 6 generalized forces"):
        sim.step()
    assert sim.time == t_good and np.array_equal(sim.q, q_good)
    with pytest.raises(mbd.DynamicsError, match=r"call reset\(\)"):
        sim.step()
    sim.set_user_force(lambda t, q, v: None)
    with pytest.raises(mbd.DynamicsError, match="returned None"):
        sim.reset(q_good, v_good)  # the restart evaluates the force at once
    sim.set_user_force(None)
    sim.reset(q_good, v_good)

    # a callback that raises: the Python exception is the cause, with its traceback
    def controller_offline(t, q, v):
        raise RuntimeError("controller offline")

    sim.set_user_force(controller_offline)
    with pytest.raises(mbd.DynamicsError, match="raised RuntimeError: controller offline") as raised:
        sim.advance_to(0.2)
    cause = raised.value.__cause__
    assert isinstance(cause, RuntimeError)
    assert "controller_offline" in "".join(traceback.format_tb(cause.__traceback__))
    assert sim.time == t_good and np.array_equal(sim.v, v_good)
    with pytest.raises(mbd.DynamicsError, match=r"call reset\(\)"):
        sim.advance_to(0.2)
    # usable again after a reset, with the state as it was
    sim.set_user_force(None)
    sim.reset(q_good, v_good)
    sim.advance_to(0.2)
    assert sim.time == pytest.approx(0.2, abs=1e-15)
    assert sim.input("force") == 1.0
    with pytest.raises(mbd.InputError, match="kind"):
        sim.set_user_force(controller_offline, kind="joints")
    with pytest.raises(mbd.InputError, match="callable"):
        sim.set_user_force(3.0)


def test_a_written_state_is_assembled():
    sim = mbd.Simulator(mbd.Model.from_dict(CART_POLE), integrator="dopri5", tol=1e-10)
    q, v = sim.body_state("cart")
    q[1] = 0.3  # off the rail
    sim.set_body_state("cart", q, v)
    assert sim.body_state("cart")[0][1] == pytest.approx(0.0, abs=1e-8)


def test_a_joint_state_is_read_and_written_onto_the_constraints():
    sim = mbd.Simulator(mbd.Model.from_dict(CART_POLE), integrator="dopri5", tol=1e-10)
    sim.set_input("force", 2.0)
    sim.advance_to(0.3)
    x, xdot = sim.joint_state("rail")
    assert x == pytest.approx(sim.q[0], abs=1e-12) and xdot == pytest.approx(sim.v[0], abs=1e-12)
    pole = math.pi / 2 - 0.2  # the pin's angle is the pole's body angle less the cart's, which stays 0
    sim.set_joint_state("pin", pole, 0.7)
    angle, rate = sim.joint_state("pin")
    assert angle == pytest.approx(pole, abs=1e-10) and rate == pytest.approx(0.7, abs=1e-10)
    assert sim.q[5] == pytest.approx(pole, abs=1e-10)
    assert sim.q[3] - sim.q[0] == pytest.approx(0.5 * math.cos(pole), abs=1e-10)
    with pytest.raises(mbd.InputError, match="its joints are: rail, pin"):
        sim.joint_state("pinn")
