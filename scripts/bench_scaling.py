#!/usr/bin/env python3
"""Per-step cost against body count for every formulation plugin (scripts/bench.sh).

    bench_scaling.py MBD OUT.csv [--sizes 10,30,...] [--budget SECONDS] [--repeats 3]

For each formulation that `MBD plugins` lists, each kind of chain and each size N, writes a chain
of N links to a temporary scene: planar (0.1 m, 1 kg, revolute joints, gravity; the model of
bench/bench_augmented.cpp) or spatial (0.1 m, 1 kg rods on spherical joints, gravity along -z,
the last link given a sideways velocity so that the motion is spatial) and runs `MBD simulate
--integrator rk4 --step 1e-4` with --json twice, over k and 3k steps, with output rows only at the
start and the end (--output-step = the run's length). The CPU time per step is the difference of
the two runs' cpu_s over 2k steps, the median of --repeats such pairs (5): the cost of one more step (4 right-hand sides and the
projection), without what a run pays once (the assembly, a formulation's first factorization with
its ordering) and without writing output rows (each row converts the state, evaluates the
constraints and formats every coordinate: on a 10,000-link chain as much as a third of a step). A
formulation that fails on a size, or whose last point took longer than the budget, stops there.
"""
import argparse
import csv
import json
import os
import statistics
import subprocess
import sys
import tempfile


def chain(n):
    lines = ["name: chain", "dimension: planar", "gravity: [0, -9.81]", "bodies:"]
    lines += [f"  - {{name: l{k}, mass: 1.0, inertia: 0.000833333333333333, position: [{0.1 * k + 0.05:.6f}, 0]}}"
              for k in range(n)]
    lines.append("joints:")
    lines += [f"  - {{name: j{k}, type: revolute, bodies: [{'ground' if k == 0 else f'l{k - 1}'}, l{k}], "
              f"point: [{0.1 * k:.6f}, 0]}}" for k in range(n)]
    return "\n".join(lines) + "\n"


def spatial_chain(n):
    lines = ["name: spatial-chain", "dimension: spatial", "gravity: [0, 0, -9.81]", "bodies:"]
    lines += [f"  - {{name: l{k}, mass: 1.0, inertia: [1e-4, 0.000833333333333333, 0.000833333333333333], "
              f"position: [{0.1 * k + 0.05:.6f}, 0, 0]"
              + (", velocity: [0, 0.1, 0], angular_velocity: [0, 0, 2]" if k == n - 1 else "") + "}"
              for k in range(n)]
    lines.append("joints:")
    lines += [f"  - {{name: j{k}, type: spherical, bodies: [{'ground' if k == 0 else f'l{k - 1}'}, l{k}], "
              f"point: [{0.1 * k:.6f}, 0, 0]}}" for k in range(n)]
    return "\n".join(lines) + "\n"


CHAINS = {"planar": chain, "spatial": spatial_chain}


def formulations(mbd):
    out = subprocess.run([mbd, "plugins"], capture_output=True, text=True).stdout
    names = []
    for line in out.splitlines():
        words = line.replace(",", " ").split()
        if "formulation" in words:
            i = words.index("formulation")
            if i + 1 < len(words) and words[i + 1] not in names and words[i + 1].isidentifier():
                names.append(words[i + 1])
    return names or ["augmented", "embedding"]


def main():
    p = argparse.ArgumentParser()
    p.add_argument("mbd")
    p.add_argument("out")
    p.add_argument("--sizes", default="10,30,100,300,1000,3000,10000")
    p.add_argument("--budget", type=float, default=10.0)
    p.add_argument("--repeats", type=int, default=5, help="pairs of runs per point; the median estimate is kept")
    p.add_argument("--chains", default="planar,spatial")
    p.add_argument("--formulations", default="", help="comma-separated (default: every installed plugin)")
    a = p.parse_args()
    sizes = [int(s) for s in a.sizes.split(",")]
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        scenes = {}
        kinds = a.chains.split(",")
        for kind in kinds:
            for n in sizes:
                scenes[kind, n] = os.path.join(tmp, f"{kind}-chain-{n}.yaml")
                with open(scenes[kind, n], "w") as f:
                    f.write(CHAINS[kind](n))
        names = a.formulations.split(",") if a.formulations else formulations(a.mbd)
        for kind, name in [(k, f) for k in kinds for f in names]:
            last = None  # (N, cpu per step) of the previous size
            for n in sizes:
                steps = max(4, min(400, int(40000 / n)))
                if last:
                    # predicted cost per step (cubic growth as the worst case): ~2 s per point (both runs) at
                    # most, and stop before a point whose first run would exceed the budget even with 4 steps
                    predicted = last[1] * (n / last[0]) ** 3
                    if 4 * predicted > a.budget:
                        print(f"scaling: {kind} {name} N = {n}: skipped (predicted {predicted:.2g} s per step)",
                              file=sys.stderr)
                        break
                    steps = max(4, min(steps, int(0.5 / predicted)))
                def run(count):
                    t_end = f"{count * 1e-4:.6g}"
                    cmd = [a.mbd, "simulate", scenes[kind, n], "--formulation", name, "--integrator", "rk4",
                           "--step", "1e-4", "--t-end", t_end, "--output-step", t_end, "--json", "-q", "-o",
                           os.path.join(tmp, "out.csv")]
                    try:
                        r = subprocess.run(cmd, capture_output=True, text=True, timeout=6 * a.budget)
                    except subprocess.TimeoutExpired:
                        return None, "timeout"
                    try:
                        j = json.loads(r.stdout) if r.returncode == 0 else None
                    except json.JSONDecodeError:
                        j = None
                    if not j or not j.get("steps"):
                        return None, (r.stderr.strip().splitlines() or ["?"])[-1]
                    return j, ""
                estimates, failure = [], ""
                for _ in range(a.repeats):
                    j, msg = run(steps)
                    j3, msg3 = run(3 * steps) if j else (None, "")
                    if not j or not j3:
                        failure = msg or msg3
                        break
                    # the cost of one more step; a difference below the clock's resolution falls back to the average
                    extra = j3["cpu_s"] - j["cpu_s"]
                    estimates.append(extra / (j3["steps"] - j["steps"]) if extra > 0 else j3["cpu_s"] / j3["steps"])
                if failure:
                    print(f"scaling: {kind} {name} N = {n}: failed ({failure[:120]})", file=sys.stderr)
                    rows.append({"chain": kind, "formulation": name, "bodies": n, "steps": "", "cpu_s": "",
                                 "cpu_per_step_s": ""})
                    break
                per = statistics.median(estimates)
                last = (n, per)
                rows.append({"chain": kind, "formulation": name, "bodies": n, "steps": j3["steps"], "cpu_s": j3["cpu_s"],
                             "cpu_per_step_s": per})
                print(f"scaling: {kind:7s} {name:12s} N = {n:6d}: {per:.3e} s per step", file=sys.stderr)
                if j3["cpu_s"] > a.budget:
                    break
    with open(a.out, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=["chain", "formulation", "bodies", "steps", "cpu_s", "cpu_per_step_s"])
        w.writeheader()
        w.writerows(rows)


if __name__ == "__main__":
    main()
