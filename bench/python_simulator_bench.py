"""The cost of a Python user force in mbd.Simulator (docs/benchmarks.md, "Stepping", issue 38).

    /usr/bin/python3 bench/python_simulator_bench.py [--build BUILD] [--rounds N]

On scenes/bench/chain-5.yaml to t = 2 s (dopri5 at 1e-6, rk4 at h = 1 ms): one advance_to
without a user force, then with a Python user force that returns a preallocated zero vector
(the least a callback can do, so the difference is the overhead of calling Python from every
right-hand side: taking the GIL, two numpy arrays for q and v, the call, reading the result).
Wall time of the calling thread in CPU seconds, median over interleaved rounds; per call =
(with - without) / calls, per step = (with - without) / steps.
"""

import argparse
import pathlib
import statistics
import sys
import time

ROOT = pathlib.Path(__file__).resolve().parents[1]


def run(mbd, model, integrator, settings, force):
    sim = mbd.Simulator(model, integrator=integrator, t_end=2.0, **settings)
    calls = [0]
    if force:
        zeros = __import__("numpy").zeros(model.nv)

        def user_force(t, q, v):
            calls[0] += 1
            return zeros

        sim.set_user_force(user_force)
    start = time.thread_time()
    sim.advance_to(2.0)
    return time.thread_time() - start, sim.stats["steps"], calls[0], sim.q.copy()


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--build", default=str(ROOT / "build"))
    parser.add_argument("--rounds", type=int, default=7)
    args = parser.parse_args()
    sys.path.insert(0, str(pathlib.Path(args.build) / "python"))
    import mbd

    model = mbd.load(ROOT / "scenes" / "bench" / "chain-5.yaml")
    print("| chain-5, 2 s | without | with a Python force | steps | force calls | per call | per step |")
    print("|---|---|---|---|---|---|---|")
    for integrator, settings in (("dopri5", {"tol": 1e-6}), ("rk4", {"step": 1e-3})):
        without, with_force = [], []
        for _ in range(args.rounds):
            t0, steps, _, q0 = run(mbd, model, integrator, settings, False)
            t1, steps1, calls, q1 = run(mbd, model, integrator, settings, True)
            assert steps == steps1 and (q0 == q1).all(), "a zero force changed the run"
            without.append(t0)
            with_force.append(t1)
        a, b = statistics.median(without), statistics.median(with_force)
        print(f"| {integrator} | {a * 1e3:.2f} ms | {b * 1e3:.2f} ms | {steps} | {calls} | "
              f"{(b - a) / calls * 1e6:.2f} us | {(b - a) / steps * 1e6:.2f} us |")


if __name__ == "__main__":
    main()
