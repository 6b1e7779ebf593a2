"""Issue 38's acceptance in Python: an LQR cart-pole closed through mbd.Simulator.set_input
every 10 ms (zero-order hold) from a 5-degree start. Oracles computed here: the LQR gain from
a hand linearisation (Riccati equation by the Hamiltonian matrix's stable subspace, residual
checked), and the same closed loop integrated here by RK4 on Lagrange's equations of the
cart-pole written by hand (tests/test_simulator.cpp does the same in C++)."""

import math

import numpy as np

import mbd

M, m, L, G = 1.0, 0.1, 1.0, 9.81  # cart, pole (uniform rod pinned at its end), length, gravity
LC, I_PIN = 0.5 * L, m * L * L / 3.0
THETA0, PERIOD = math.radians(5.0), 0.01


def cart_pole(force):
    """The scene: theta is the pole from upright, positive towards +x (body angle pi/2 - theta)."""
    return mbd.Model.from_dict({
        "name": "cart-pole", "dimension": "planar", "gravity": [0, -G],
        "bodies": [{"name": "cart", "mass": M, "inertia": 0.01, "position": [0, 0]},
                   {"name": "pole", "mass": m, "inertia": m * L * L / 12,
                    "position": [LC * math.sin(THETA0), LC * math.cos(THETA0)], "angle": math.pi / 2 - THETA0}],
        "joints": [{"name": "rail", "type": "prismatic", "bodies": ["ground", "cart"], "point": [0, 0], "axis": [1, 0]},
                   {"name": "pin", "type": "revolute", "bodies": ["cart", "pole"], "point": [0, 0]}],
        "forces": [{"name": "push", "type": "point_force", "body": "cart", "force": [force, 0]}]})


def cart_pole_state(q, v):
    """(x, theta, xdot, thetadot) of the scene's coordinates."""
    return np.array([q[0], math.pi / 2 - q[5], v[0], -v[5]])


def rate(s, F):
    """Lagrange's equations (T = 1/2 (M+m) xd^2 + m lc cos(th) xd thd + 1/2 I thd^2, V = m g lc cos(th)):
    (M + m) xdd + m lc cos(th) thdd - m lc sin(th) thd^2 = F;  m lc cos(th) xdd + I thdd - m g lc sin(th) = 0."""
    x, th, xd, thd = s
    c, sn = math.cos(th), math.sin(th)
    a11, a12, a22 = M + m, m * LC * c, I_PIN
    b1, b2 = F + m * LC * sn * thd * thd, m * G * LC * sn
    det = a11 * a22 - a12 * a12
    return (xd, thd, (a22 * b1 - a12 * b2) / det, (a11 * b2 - a12 * b1) / det)


def lqr_gain():
    """K of F = -K s for Q = diag(1, 10, 1, 1), R = 0.1, at upright."""
    Mm = np.array([[M + m, m * LC], [m * LC, I_PIN]])
    Minv = np.linalg.inv(Mm)
    A = np.zeros((4, 4))
    A[0, 2] = A[1, 3] = 1.0
    A[2:, 1] = Minv @ [0.0, m * G * LC]
    B = np.zeros((4, 1))
    B[2:, 0] = Minv @ [1.0, 0.0]
    Q, R = np.diag([1.0, 10.0, 1.0, 1.0]), 0.1
    H = np.block([[A, -B @ B.T / R], [-Q, -A.T]])
    w, U = np.linalg.eig(H)
    stable = U[:, w.real < 0]
    assert stable.shape[1] == 4
    X = np.real(stable[4:] @ np.linalg.inv(stable[:4]))
    residual = A.T @ X + X @ A - X @ B @ B.T @ X / R + Q
    assert np.max(np.abs(residual)) < 1e-9
    return (B.T @ X / R).ravel()


def oracle_angles(K, periods, compare):
    """The closed loop integrated here: RK4 at 1e-4 s, the force held over each period."""
    s = (0.0, THETA0, 0.0, 0.0)
    h, angles = PERIOD / 100, {}
    for k in range(periods):
        F = -float(K @ s)
        for _ in range(100):
            k1 = rate(s, F)
            k2 = rate([a + 0.5 * h * b for a, b in zip(s, k1)], F)
            k3 = rate([a + 0.5 * h * b for a, b in zip(s, k2)], F)
            k4 = rate([a + h * b for a, b in zip(s, k3)], F)
            s = tuple(a + h / 6 * (b1 + 2 * b2 + 2 * b3 + b4) for a, b1, b2, b3, b4 in zip(s, k1, k2, k3, k4))
        if k + 1 in compare:
            angles[k + 1] = s[1]
    return angles


def test_lqr_cart_pole_through_set_input_matches_the_closed_loop():
    K = lqr_gain()
    sim = mbd.Simulator(cart_pole({"type": "input", "name": "force"}), integrator="dopri5", tol=1e-11, t_end=10.0)
    assert sim.input_names == ["force"]
    assert cart_pole_state(sim.q, sim.v)[1] == __import__("pytest").approx(THETA0, abs=1e-12)
    compare = {50, 100, 200, 500}
    angles, forces, worst_after_2s = {}, [], 0.0
    for k in range(1000):
        F = -float(K @ cart_pole_state(sim.q, sim.v))
        sim.set_input("force", F)
        forces.append(F)
        sim.advance_to((k + 1) * PERIOD)
        theta = cart_pole_state(sim.q, sim.v)[1]
        if k + 1 in compare:
            angles[k + 1] = theta
        if sim.time >= 2.0 - 1e-12:
            worst_after_2s = max(worst_after_2s, abs(theta))
    assert abs(sim.time - 10.0) < 1e-12
    assert worst_after_2s < math.radians(1.0)
    assert abs(forces[0]) > 0.1  # the controller acted
    oracle = oracle_angles(K, 500, compare)
    for k in sorted(compare):
        assert abs(angles[k] - oracle[k]) < 1e-6, f"t = {k * PERIOD}: {angles[k]} vs {oracle[k]}"


def test_the_recorded_inputs_replayed_through_simulate_give_the_closed_loop():
    """The forces set every 10 ms, replayed as a piecewise-constant time function through a whole
    model.simulate: its steps end on the table's times (docs/integrators.md, "Breakpoints"), so
    with rk4 it takes the stepped run's steps with its values, to 1e-10 rad at 0.5, 1, 2 and 5 s."""
    K = lqr_gain()
    sim = mbd.Simulator(cart_pole({"type": "input", "name": "force"}), integrator="rk4", step=1e-3, t_end=5.0)
    forces, angles = [], {}
    for k in range(500):
        forces.append(-float(K @ cart_pole_state(sim.q, sim.v)))
        sim.set_input("force", forces[-1])
        sim.advance_to((k + 1) * PERIOD)
        angles[k + 1] = cart_pole_state(sim.q, sim.v)[1]
    table = [[k * PERIOD, f] for k, f in enumerate(forces)]
    result = cart_pole({"type": "steps", "table": table}).simulate(5.0, integrator="rk4", step=1e-3, output_step=0.5)
    for k in (50, 100, 200, 500):
        row = int(round(k * PERIOD / 0.5))
        replayed = cart_pole_state(result.q[row], result.v[row])[1]
        assert abs(replayed - angles[k]) < 1e-10, f"t = {k * PERIOD}: {replayed} vs {angles[k]}"
