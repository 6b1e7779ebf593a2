#!/usr/bin/env python3
"""A stiffness sweep of the four-bar with a spring-damper (scenes/dynamics/four-bar-spring-damper.yaml):
for each spring stiffness, the free damped motion of the crank and the stable static
equilibrium nearest the scene's configuration, computed in parallel threads over changed
models of one scene, and plotted. Every angle it prints or plots is in degrees in (-180, 180]. (The linkage has more than one stable equilibrium: with a
stiff spring the nearest one is on another branch, and the motion, started at 5 rad/s, need
not settle in the nearest one.)

    PYTHONPATH=build/python /usr/bin/python3 examples/four_bar_stiffness_sweep.py --output sweep.png
"""

import argparse
import concurrent.futures
import os
import pathlib
import sys

import numpy as np

import mbd

SCENE = pathlib.Path(__file__).resolve().parents[1] / "scenes" / "dynamics" / "four-bar-spring-damper.yaml"


def study(model, stiffness, t_end):
    """The motion and the equilibrium of the four-bar with this spring stiffness [N/m]."""
    changed = model.with_params({"forces.spring.stiffness": stiffness})
    motion = changed.simulate(t_end, formulation="embedding", tol=1e-8, output_step=t_end / 600)
    equilibrium = changed.statics()
    return stiffness, motion, equilibrium


def degrees_wrapped(angle):
    """An angle [rad] as the one way this example reports angles: degrees in (-180, 180]."""
    degrees = np.degrees(np.angle(np.exp(1j * np.asarray(angle, dtype=float))))
    return np.where(degrees == -180.0, 180.0, degrees)


def sweep(stiffnesses, t_end):
    model = mbd.load(SCENE)
    with concurrent.futures.ThreadPoolExecutor(os.cpu_count()) as pool:  # the engine runs without the GIL
        return list(pool.map(lambda k: study(model, k, t_end), stiffnesses))


def plot(results, output):
    import matplotlib
    matplotlib.use("Agg")  # a file, no display needed
    import matplotlib.pyplot as plt

    figure, (motion_axes, equilibrium_axes) = plt.subplots(1, 2, figsize=(11, 4.2))
    colours = plt.cm.viridis(np.linspace(0, 1, len(results)))
    for (k, motion, _), colour in zip(results, colours):
        motion_axes.plot(motion.t, degrees_wrapped(motion["crank.angle"]), ".", markersize=1, color=colour,
                         label=f"k = {k:.0f} N/m")
    motion_axes.set(xlabel="t [s]", ylabel="crank angle [deg], in (-180, 180]", title="Free motion from 90 deg at 5 rad/s")
    motion_axes.legend(fontsize=7)
    motion_axes.grid(True, alpha=0.3)
    k = [r[0] for r in results]
    equilibrium = [degrees_wrapped(r[2].bodies["crank"]["angle"]) for r in results]
    equilibrium_axes.semilogx(k, equilibrium, "o-", label="stable equilibrium nearest the start (mbd statics)")
    equilibrium_axes.set(xlabel="spring stiffness k [N/m]", ylabel="crank angle [deg], in (-180, 180]",
                         title="Static equilibrium from the crank at 90 deg")
    equilibrium_axes.legend(fontsize=8)
    equilibrium_axes.grid(True, which="both", alpha=0.3)
    figure.tight_layout()
    figure.savefig(output, dpi=110)
    plt.close(figure)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--output", default="four-bar-stiffness-sweep.png", help="the plot (PNG, SVG, PDF)")
    parser.add_argument("--points", type=int, default=8, help="stiffnesses from 50 to 5000 N/m")
    parser.add_argument("--t-end", type=float, default=4.0, help="length of each motion [s]")
    args = parser.parse_args(argv)
    results = sweep(np.geomspace(50.0, 5000.0, args.points), args.t_end)
    plot(results, args.output)
    for k, motion, equilibrium in results:
        print(f"k = {k:8.1f} N/m: equilibrium crank angle {degrees_wrapped(equilibrium.bodies['crank']['angle']):7.2f} deg "
              f"({equilibrium.stability}), at t = {motion.t[-1]:g} s {degrees_wrapped(motion['crank.angle'][-1]):7.2f} deg, "
              f"{motion.stats.steps} steps")
    print(f"wrote {args.output}")
    return results


if __name__ == "__main__":
    main(sys.argv[1:])
