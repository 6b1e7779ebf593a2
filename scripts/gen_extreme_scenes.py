#!/usr/bin/env python3
"""Generate the parametric scenes of scenes/extreme/ (issue 8: stiff and extreme cases).

Hand-written cases (slider crank, Bricard, spinning bodies, ...) live next to them;
this script writes only the springs, the tiny time scale and the long chains.
Run from the repository root: python3 scripts/gen_extreme_scenes.py
"""
import math
import os

OUT = os.path.join(os.path.dirname(__file__), "..", "scenes", "extreme")


def spring(name, k, m, amplitude, t_end, tol, step, bound, budget=20, quick=None, title=None):
    w = math.sqrt(k / m)
    period = 2 * math.pi / w
    inertia = m * 0.01
    quick = quick or t_end
    title = title or f"A mass on a spring, k = {k:g} N/m"
    text = f"""# {title} (issue 8, extreme cases).
# A block of {m:g} kg slides on a frictionless prismatic guide along x (no gravity); a
# spring (k = {k:g} N/m, no damping, rest length 1 m) joins it to the ground point
# (-1, 0), so the spring is relaxed with the block at x = 0. It starts at x = {amplitude:g} m
# at rest. Closed form (the error oracle): x(t) = {amplitude:g} cos(w t),
# w = sqrt(k / m) = {w:.6g} rad/s (period {period:.6g} s), run for {t_end:g} s
# ({t_end / period:.4g} periods).
# Error measure: max |x - x_exact| over the output times divided by the amplitude.
# Expected outcome: pass with augmented + {'dopri5' if k <= 1e8 else 'cvode'} (relative error <= {bound:g}); explicit
# integrators need a step below 2.8 / w, so dopri5 pays ~w t_end steps; generalized_alpha
# at h = {step:g} s {'resolves the oscillation' if step * w < 0.2 else 'damps the unresolved oscillation (rho_infinity 0.8): inaccurate but stable'}.
name: {name}
dimension: planar
bodies:
  - {{name: block, mass: {m!r}, inertia: {inertia!r}, position: [{amplitude!r}, 0.0]}}
joints:
  - {{name: guide, type: prismatic, bodies: [ground, block], point: [0.0, 0.0], axis: [1.0, 0.0]}}
forces:
  - name: spring
    type: spring_damper
    bodies: [ground, block]
    points: [[-1.0, 0.0], [0.0, 0.0]]
    stiffness: {k!r}
    rest_length: 1.0
expect:
  outcome: pass
  measure: oscillator
  oscillator: {{body: block, amplitude: {amplitude!r}, omega: {w!r}}}
  bound: {bound!r}
  formulation: augmented
  integrator: {'dopri5' if k <= 1e8 else 'cvode'}
  t_end: {t_end!r}
  quick_t_end: {quick!r}
  output_step: {min(t_end / 200, period / 7.3)!r}
  tolerance: {tol!r}
  step: {step!r}
  budget: {budget}
"""
    write_scene(name, text)


def write_scene(name, text):
    with open(os.path.join(OUT, name + ".yaml"), "w") as f:
        f.write(text)


def energy_expectation(bound, t_end, quick, tolerance, step, budget):
    """The `expect:` key of a conservative case: pass with augmented + dopri5 within an energy drift."""
    return f"""expect:
  outcome: pass
  measure: energy
  bound: {bound!r}
  formulation: augmented
  integrator: dopri5
  t_end: {t_end!r}
  quick_t_end: {quick!r}
  tolerance: {tolerance!r}
  step: {step!r}
  budget: {budget}
"""


def chain(name, n, masses, t_end, bound, budget, quick, title, extra=""):
    L = 1.0 / n if n > 10 else 0.5
    lines = []
    for i in range(n):
        m = masses[i % len(masses)]
        lines.append(f"  - {{name: l{i}, mass: {m!r}, inertia: {m * L * L / 12!r}, position: [{(i + 0.5) * L!r}, 0.0]}}")
    joints = [f"  - {{name: j0, type: revolute, bodies: [ground, l0], point: [0.0, 0.0]}}"]
    for i in range(1, n):
        joints.append(f"  - {{name: j{i}, type: revolute, bodies: [l{i - 1}, l{i}], point: [{i * L!r}, 0.0]}}")
    text = f"""# {title} (issue 8, extreme cases).
# A planar chain of {n} uniform links of {L:g} m (I = m L^2 / 12) hanging from the ground by
# revolute joints, g = 9.81 along -y, released at rest from the straight horizontal position.
{extra}# Error measure: the energy drift max |E(t) - E(0)| / max(T + |V|) over the output times
# (E = T + V, no dissipation).
# Expected outcome: pass with augmented + dopri5, energy drift <= {bound:g}.
name: {name}
dimension: planar
gravity: [0, -9.81]
bodies:
""" + "\n".join(lines) + "\njoints:\n" + "\n".join(joints) + "\n" + energy_expectation(
        bound, t_end, quick, 1e-8, 1e-3, budget)
    write_scene(name, text)


def spatial_chain(name, n, t_end, bound, budget, quick):
    """n rods of 1/n m on spherical joints, hanging from the ground, released horizontal."""
    L = 1.0 / n
    m = 1.0
    axial, transverse = 1e-6 * m * L * L, m * L * L / 12
    bodies = [f"  - {{name: l{i}, mass: {m!r}, inertia: [{axial!r}, {transverse!r}, {transverse!r}], "
              f"position: [{(i + 0.5) * L!r}, 0.0, 0.0]}}" for i in range(n)]
    bodies[-1] = bodies[-1].replace("position:", f"velocity: [0.0, 1.0, 0.0], angular_velocity: [0.0, 0.0, {2.0 / L!r}], position:")
    joints = ["  - {name: j0, type: spherical, bodies: [ground, l0], point: [0.0, 0.0, 0.0]}"]
    joints += [f"  - {{name: j{i}, type: spherical, bodies: [l{i - 1}, l{i}], point: [{i * L!r}, 0.0, 0.0]}}"
               for i in range(1, n)]
    text = f"""# A spatial chain of {n} links on spherical joints (issue 8, extreme cases).
# {n} uniform rods of {L:g} m and 1 kg (transverse inertia m L^2 / 12, axial inertia 1e-6 of
# that: nearly singular about each rod's axis) hang from the ground by spherical joints,
# g = 9.81 along -z; released from the straight horizontal position along x with the last rod
# swinging sideways (1 m/s along y at its centre, turning about its joint), so that the motion
# is fully spatial.
# Error measure: the energy drift max |E(t) - E(0)| / max(T + |V|) over the output times.
# Expected outcome: pass with augmented + dopri5, energy drift <= {bound:g}.
name: {name}
dimension: spatial
gravity: [0, 0, -9.81]
bodies:
""" + "\n".join(bodies) + "\njoints:\n" + "\n".join(joints) + "\n" + energy_expectation(
        bound, t_end, quick, 1e-10, 1e-4, budget)
    write_scene(name, text)


if __name__ == "__main__":
    os.makedirs(OUT, exist_ok=True)
    spring("spring-k1e2", 1e2, 1.0, 1e-3, 10.0, 1e-10, 1e-3, 1e-4, quick=2.0)
    spring("spring-k1e4", 1e4, 1.0, 1e-3, 1.0, 1e-10, 1e-4, 1e-4, quick=0.5)
    spring("spring-k1e6", 1e6, 1.0, 1e-3, 0.1, 1e-10, 1e-5, 1e-4, quick=0.05)
    spring("spring-k1e8", 1e8, 1.0, 1e-3, 0.05, 1e-10, 1e-6, 1e-4, quick=0.01)
    spring("spring-k1e10", 1e10, 1.0, 1e-3, 0.005, 1e-10, 1e-7, 1e-2, quick=0.001)
    # a 1e-4 s period: w = 2 pi 1e4 rad/s, tiny mass and amplitude
    w = 2 * math.pi * 1e4
    spring("tiny-time-scale", 1e-3 * w * w, 1e-3, 1e-6, 1e-3, 1e-10, 1e-6, 1e-4,
           title="A 1e-4 s oscillation: a 1 g block with an amplitude of 1 micrometre")
    chain("mass-ratio-chain", 4, [1.0, 1e-6, 1.0, 1e6], 2.0, 1e-5, 30, 0.5,
          "Mass ratios 1e-6 and 1e6 in one chain",
          "# Masses 1, 1e-6, 1, 1e6 kg along the chain: neighbouring ratios 1e-6 and 1e6 (1e12 overall).\n")
    chain("chain-200", 200, [1.0], 1.0, 1e-4, 20, 0.05,
          "A long chain of 200 links")
    chain("chain-1000", 1000, [1.0], 0.2, 1e-4, 30, 0.005,
          "A long chain of 1,000 links")
    spatial_chain("spatial-chain-50", 50, 1.0, 1e-6, 15, 0.1)
