#!/usr/bin/env python3
"""dop853 against dopri5 at equal error (docs/integrators.md, "dop853"): run it on a quiet machine with

    /usr/bin/python3 bench/pairs_at_equal_error.py [--build BUILD_DIR] [--repeat N] [--target 1e-9]

For A01 (scenes/bench/a01-pendulum.yaml, closed-form reference) and chain-5
(scenes/bench/chain-5.yaml), a copy of the bench scene whose `runs:` are augmented and
embedding, each with dopri5 and dop853 over tolerances 1e-4 .. 1e-13 (4 per decade); chain-5's
reference is made tighter than its committed one (embedding + dopri5 at 1e-12, which the
augmented cross-check puts ~1e-8 off, too coarse for a 1e-9 target): embedding + dop853 at
1e-13, cross-checked by augmented + dop853 at 1e-13. `mbd bench` measures the error and
the median CPU time of each point; `mbd simulate --json` at the same settings counts its
right-hand-side evaluations. At the target error, log(CPU time) and log(rhs evaluations) are
interpolated in log(error) along each series (scripts/work_precision.py) and printed as a table.
"""

import argparse
import csv
import json
import pathlib
import re
import subprocess
import sys
import tempfile

ROOT = pathlib.Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "scripts"))
from work_precision import series_cost_at  # noqa: E402

SCENES = {
    "a01-pendulum": None,
    "chain-5": "{kind: tight_run, formulation: embedding, integrator: dop853, tolerance: 1.0e-13, "
               "cross_check: augmented}",
}
GRID = "{from: 0.0001, to: 1e-13, per_decade: 4}"


def scene_copy(name, folder):
    text = (ROOT / "scenes" / "bench" / f"{name}.yaml").read_text()
    head, rest = text.split("  runs:\n")
    if SCENES[name]:
        head = "\n".join(("  reference: " + SCENES[name]) if line.startswith("  reference:") else line
                         for line in head.split("\n"))
    runs = "".join(f"    - {{formulation: {f}, integrator: {i}, tolerances: {GRID}}}\n"
                   for f in ("augmented", "embedding") for i in ("dopri5", "dop853"))
    path = folder / f"{name}.yaml"
    path.write_text(head + "  runs:\n" + runs)
    return path


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--build", default=str(ROOT / "build"))
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--target", type=float, default=1e-9)
    args = parser.parse_args()
    mbd = pathlib.Path(args.build) / "bin" / "mbd"
    with tempfile.TemporaryDirectory() as tmp:
        folder = pathlib.Path(tmp)
        paths = [scene_copy(name, folder) for name in SCENES]
        subprocess.run([str(mbd), "bench", *map(str, paths), "--repeat", str(args.repeat), "-q",
                        "--csv", str(folder / "bench.csv"), "--json", str(folder / "bench.json")],
                       check=True, stderr=subprocess.DEVNULL)
        report = json.loads((folder / "bench.json").read_text())
        rows = list(csv.DictReader(open(folder / "bench.csv")))
        t_ends = {s["scene"]: s["t_end"] for s in report["scenes"]}
        series = {}
        for r in rows:
            if r["engine"] != "mbd" or r["status"] != "ok":
                continue
            scene = r["scene"]
            t_end = t_ends[scene]
            output_step = re.search(r"^  output_step: *([0-9.e+-]+)", (folder / f"{scene}.yaml").read_text(),
                                    re.M).group(1)
            run = subprocess.run([str(mbd), "simulate", str(folder / f"{scene}.yaml"), "--t-end", str(t_end),
                                  "--output-step", str(output_step), "--formulation", r["formulation"],
                                  "--integrator", r["integrator"], "--tol", r["tolerance"], "-o",
                                  str(folder / "run.csv"), "-q", "--json"],
                                 check=True, capture_output=True, text=True)
            rhs = json.loads(run.stdout)["rhs_evaluations"]
            key = (scene, r["formulation"], r["integrator"])
            series.setdefault(key, []).append((float(r["tolerance"]), float(r["error"]), float(r["cpu_s"]), rhs))
        for s in report["scenes"]:
            print(f"{s['scene']}: reference {s['reference']}" +
                  (f", cross-check {s['cross_check']}" if s.get("cross_check") else ""))
    print(f"| scene | formulation | integrator | rhs evaluations at error {args.target:g} | CPU time [s] |")
    print("|---|---|---|---|---|")
    for (scene, formulation, integrator), points in sorted(series.items()):
        cpu = series_cost_at([(t, e, c) for t, e, c, _ in points], args.target)
        rhs = series_cost_at([(t, e, n) for t, e, _, n in points], args.target)
        text = lambda got, fmt: "not reached" if got is None else ("" if got[1] else "<= ") + fmt % got[0]
        print(f"| {scene} | {formulation} | {integrator} | {text(rhs, '%.0f')} | {text(cpu, '%.4f')} |")


if __name__ == "__main__":
    main()
