#!/usr/bin/env python3
"""Work-precision report of `mbd bench` (scripts/bench.sh runs it).

    bench_report.py OUT_DIR DOC [--scaling scaling.csv] [--rhs rhs.txt] [--wall SECONDS]

Reads OUT_DIR/work-precision.json (written by `mbd bench`), draws one work-precision diagram per
scene (error against CPU time, log-log; mbd's series and the peers', measured in the same run) as
OUT_DIR/<scene>.png and .svg, the per-step scaling plot from the scaling CSV, and rewrites the part
of DOC (docs/benchmarks.md) between the markers
    <!-- work-precision:begin --> ... <!-- work-precision:end -->
(appended at the end when the markers are missing), leaving the other sections as they are.
"""
import argparse
import csv
import json
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

BEGIN = "<!-- work-precision:begin -->"
END = "<!-- work-precision:end -->"
TARGET = 1e-6


def fmt(x, digits=3):
    if x is None or (isinstance(x, float) and not math.isfinite(x)):
        return "—"
    return f"{x:.{digits}g}"


def series_key(row):
    if row["engine"] == "mbd":
        return f"mbd {row['formulation']} + {row['integrator']}"
    return f"{row['engine']} {row['integrator']}"


def best_at(rows, target=TARGET):
    """Best CPU time among runs with error <= target; else the most accurate run (marked)."""
    ok = [r for r in rows if r["status"] == "ok" and r["error"] is not None and math.isfinite(r["error"])]
    if not ok:
        return None
    reached = [r for r in ok if r["error"] <= target]
    if reached:
        r = min(reached, key=lambda r: r["cpu_s"])
        return r, True
    r = min(ok, key=lambda r: (r["error"], r["cpu_s"]))
    return r, False


def describe(best):
    if best is None:
        return "no successful run", None, False
    r, reached = best
    setting = f"tol {fmt(r['tolerance'])}" if r["tolerance"] else f"h {fmt(r['step'])}"
    name = r["formulation"] + " + " + r["integrator"] if r["engine"] == "mbd" else r["integrator"]
    text = f"{fmt(r['cpu_s'])} s ({name}, {setting}, error {fmt(r['error'], 2)})"
    if not reached:
        text += " — 1e-6 not reached, most accurate point"
    return text, r["cpu_s"], reached


def ratio_cell(peer_cpu, peer_reached, mbd_cpu, mbd_reached):
    """peer / mbd at 1e-6; when one side never reaches 1e-6 the ratio of the two shown points, marked."""
    if not peer_cpu or not mbd_cpu:
        return "—"
    ratio = fmt(peer_cpu / mbd_cpu, 3)
    if peer_reached and mbd_reached:
        return ratio
    who = "peer" if not peer_reached else "mbd"
    if not peer_reached and not mbd_reached:
        who = "neither"
    return f"{ratio} ({who} never reached 1e-6: ratio of the points shown)"


def plot_scene(scene, rows, out_dir):
    fig, ax = plt.subplots(figsize=(6.4, 4.6))
    groups = {}
    for r in rows:
        if r["status"] != "ok" or r["error"] is None or not math.isfinite(r["error"]) or r["error"] <= 0:
            continue
        groups.setdefault(series_key(r), []).append(r)
    markers = "os^vD<>ph*"
    for k, (name, rs) in enumerate(sorted(groups.items())):
        rs = sorted(rs, key=lambda r: r["cpu_s"])
        style = "-" if name.startswith("mbd") else "--"
        ax.loglog([max(r["cpu_s"], 1e-6) for r in rs], [r["error"] for r in rs], style,
                  marker=markers[k % len(markers)], label=name)
    ax.axhline(TARGET, color="grey", lw=0.8, ls=":")
    ax.set_xlabel("CPU time [s] (median of the repeats)")
    ax.set_ylabel("error (" + (rows[0]["reference_kind"] if rows else "") + ")")
    ax.set_title(f"work-precision: {scene['scene']}")
    ax.grid(True, which="both", lw=0.3)
    if groups:
        ax.legend(fontsize=7)
    fig.tight_layout()
    for ext in ("png", "svg"):
        fig.savefig(os.path.join(out_dir, f"{scene['scene']}.{ext}"), dpi=110)
    plt.close(fig)


def slope(ns, ts):
    pts = [(math.log(n), math.log(t)) for n, t in zip(ns, ts) if t > 0]
    if len(pts) < 2:
        return float("nan")
    mx = sum(p[0] for p in pts) / len(pts)
    my = sum(p[1] for p in pts) / len(pts)
    sxx = sum((p[0] - mx) ** 2 for p in pts)
    return sum((p[0] - mx) * (p[1] - my) for p in pts) / sxx if sxx > 0 else float("nan")


def scaling_section(path, out_dir):
    if not path or not os.path.exists(path):
        return ["Scaling: not measured in this run."]
    data = {}
    with open(path) as f:
        for row in csv.DictReader(f):
            if row["cpu_per_step_s"]:
                data.setdefault(row["formulation"], []).append((int(row["bodies"]), float(row["cpu_per_step_s"])))
    fig, ax = plt.subplots(figsize=(6.4, 4.6))
    lines = ["| formulation | " + " | ".join(f"N = {n}" for n in sorted({n for v in data.values() for n, _ in v}))
             + " | slope (all N) | slope (N >= 100) |"]
    all_n = sorted({n for v in data.values() for n, _ in v})
    lines.append("|---" * (len(all_n) + 3) + "|")
    for name, pts in sorted(data.items()):
        pts.sort()
        ns, ts = [p[0] for p in pts], [p[1] for p in pts]
        big = [(n, t) for n, t in pts if n >= 100]
        s_all, s_big = slope(ns, ts), slope([p[0] for p in big], [p[1] for p in big])
        ax.loglog(ns, ts, marker="o", label=f"{name} (slope {s_all:.2f})")
        by_n = dict(pts)
        lines.append(f"| {name} | " + " | ".join(fmt(by_n.get(n)) for n in all_n) + f" | {s_all:.2f} | {s_big:.2f} |")
    ax.set_xlabel("bodies (planar chain)")
    ax.set_ylabel("CPU time per rk4 step [s]")
    ax.set_title("per-step cost against body count")
    ax.grid(True, which="both", lw=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    for ext in ("png", "svg"):
        fig.savefig(os.path.join(out_dir, f"scaling.{ext}"), dpi=110)
    plt.close(fig)
    return lines


def main():
    p = argparse.ArgumentParser()
    p.add_argument("out_dir")
    p.add_argument("doc")
    p.add_argument("--scaling")
    p.add_argument("--rhs")
    p.add_argument("--wall", type=float)
    a = p.parse_args()
    with open(os.path.join(a.out_dir, "work-precision.json")) as f:
        data = json.load(f)
    rows_by_scene = {}
    for r in data["rows"]:
        rows_by_scene.setdefault(r["scene"], []).append(r)

    md = [BEGIN, "## Work-precision: error against CPU time (`mbd bench`, scripts/bench.sh)", ""]
    md.append("Generated by `scripts/bench.sh` (do not edit between the markers). Each scene of "
              "`scenes/bench/` states its error measure and reference in its `bench:` key; every grid point "
              "(formulation x integrator x tolerance or step) is run 3 times and the median CPU time of the "
              "integration is kept (assembly of the initial state excluded). Peers (bench/peers/: Simbody 3.7, "
              "MuJoCo 2.2.2) build the same models with their own APIs and are run in the same `mbd bench` "
              "call, on the same machine, against the same reference and error measure.")
    if a.wall:
        md.append(f"Last run: {a.wall:.0f} s wall time for the whole script on the shared 2-core container.")
    md.append("Raw data: `docs/benchmarks/work-precision.csv` / `.json`; diagrams: `docs/benchmarks/<scene>.png` (and .svg).")
    md.append("")
    md.append("Usage: `mbd bench SCENE... [--repeat N] [--peers DIR] [--csv F] [--json F] [--formulation F] [--min-tol T]` "
              "writes one row per run (engine, scene, formulation, integrator, tolerance or step, cpu_s, steps, error, "
              "error_measure, reference_kind, status); a failed run is a row with its message, and the tighter points "
              "of its series are skipped. A peer program that is missing (library not installed, peers not built) is "
              "reported on stderr and in the JSON notes, and the bench goes on. For a single run, `mbd simulate SCENE "
              "--error-estimate` repeats it at a ten times tighter tolerance (fixed step: half the step, with the "
              "Richardson factor 2^p / (2^p - 1)) and ends with `error estimate: CPU time ... s, estimated global "
              "position error ... m` (with `--json`: the field `error_estimate`); on the pendulum the estimate is "
              "within a factor of 10 of the closed-form error (tests/test_bench.cpp).")
    md.append("")
    md.append("### Best CPU time at error 1e-6")
    md.append("")
    md.append("Best = the cheapest run whose error is <= 1e-6; when no run of an engine reaches it, its most accurate "
              "point is shown instead (marked), and the ratio of the two points shown is given with that mark (the engine "
              "marked did not get to 1e-6 at any setting measured). "
              "Ratio = peer / mbd (> 1: mbd is faster).")
    md.append("")
    md.append("| scene | reference | mbd best | Simbody best | ratio | MuJoCo best | ratio |")
    md.append("|---|---|---|---|---|---|---|")
    details = []
    for scene in data["scenes"]:
        rows = rows_by_scene.get(scene["scene"], [])
        plot_scene(scene, rows, a.out_dir)
        mbd_text, mbd_cpu, mbd_reached = describe(best_at([r for r in rows if r["engine"] == "mbd"]))
        cells = [f"`{scene['scene']}`", scene["reference_kind"], mbd_text]
        for engine in ("simbody", "mujoco"):
            er = [r for r in rows if r["engine"] == engine]
            if not er:
                note = next((n for n in scene["notes"] if n.startswith(f"peer {engine}")), None)
                cells += ["not run" + (" (not installed)" if note else " (no model)"), "—"]
                continue
            text, cpu, reached = describe(best_at(er))
            cells += [text, ratio_cell(cpu, reached, mbd_cpu, mbd_reached)]
        md.append("| " + " | ".join(cells) + " |")
        failed = [r for r in rows if r["status"] != "ok"]
        details.append(f"- `{scene['scene']}`: {scene['error_measure']}; reference: {scene['reference']}."
                       + (f" {len(failed)} of {len(rows)} runs failed or were skipped"
                          f" (first: {failed[0]['engine']} {failed[0]['formulation']} + {failed[0]['integrator']}:"
                          f" {failed[0]['status'][:160]})." if failed else "")
                       + (" Notes: " + "; ".join(scene["notes"]) + "." if scene["notes"] else ""))
    md += ["", "### Scenes, error measures and references", ""] + details
    md += ["", "### Per-step cost against body count", "",
           "CPU time of one fixed rk4 step (4 right-hand sides and the formulation's projection) of `mbd simulate` on "
           "planar chains (0.1 m, 1 kg links, revolute joints, gravity), for every formulation plugin installed, "
           "with log-log slopes fitted over all N and over N >= 100 (`docs/benchmarks/scaling.csv`, "
           "`docs/benchmarks/scaling.png`). The rhs-only breakdown (dense vs sparse, recursive vs dense) is "
           "`bench_augmented` / `bench_embedding` (sections above), rerun by the script into "
           "`docs/benchmarks/rhs-scaling.txt`.", ""]
    md += scaling_section(a.scaling, a.out_dir)
    if a.rhs and os.path.exists(a.rhs):
        slopes = [l.strip() for l in open(a.rhs) if "slope" in l]
        if slopes:
            md += ["", "Fitted slopes printed by the rhs benchmarks in this run: " + "; ".join(slopes) + "."]
    md += ["", END]

    text = open(a.doc).read() if os.path.exists(a.doc) else "# Benchmarks\n"
    if BEGIN in text and END in text:
        head, rest = text.split(BEGIN, 1)
        tail = rest.split(END, 1)[1]
        text = head + "\n".join(md) + tail
    else:
        text = text.rstrip("\n") + "\n\n" + "\n".join(md) + "\n"
    with open(a.doc, "w") as f:
        f.write(text)
    print("\n".join(md[md.index("### Best CPU time at error 1e-6"):md.index("### Scenes, error measures and references")]))


if __name__ == "__main__":
    sys.exit(main())
