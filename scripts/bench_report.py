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

from work_precision import engine_cost_at

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

BEGIN = "<!-- work-precision:begin -->"
END = "<!-- work-precision:end -->"
TARGETS = (1e-6, 1e-9)


def fmt(x, digits=3):
    if x is None or (isinstance(x, float) and not math.isfinite(x)):
        return "—"
    return f"{x:.{digits}g}"


def series_key(row):
    if row["engine"] == "mbd":
        return f"mbd {row['formulation']} + {row['integrator']}"
    return f"{row['engine']} {row['integrator']}"


def cost_cell(found, target):
    """The text of an engine's cost at `target` (work_precision.engine_cost_at), its CPU time and
    whether that time is exact (False: an upper bound)."""
    if found is None:
        return f"not reached ({target:g} not bracketed by any series)", None, True
    cpu, exact, name = found
    text = f"{fmt(cpu)} s ({name})"
    if not exact:
        text = f"<= {text}, every point more accurate"
    return text, cpu, exact


def ratio_cell(peer, mbd):
    """peer / mbd at the target (> 1: mbd is faster) from two cost_cell() results; a dash when
    either did not reach it, <= or >= when one side's time is an upper bound."""
    (_, peer_cpu, peer_exact), (_, mbd_cpu, mbd_exact) = peer, mbd
    if not peer_cpu or not mbd_cpu or (not peer_exact and not mbd_exact):
        return "—"
    bound = "" if peer_exact and mbd_exact else ("<= " if not peer_exact else ">= ")
    return bound + fmt(peer_cpu / mbd_cpu, 3)


def cost_table(data, rows_by_scene, target):
    """One row per scene: each engine's cost at `target` and the peers' ratios."""
    md = [f"### CPU time at error {target:g}", "",
          "| scene | reference | mbd | Simbody | ratio | MuJoCo | ratio |", "|---|---|---|---|---|---|---|"]
    for scene in data["scenes"]:
        rows = rows_by_scene.get(scene["scene"], [])
        mbd = cost_cell(engine_cost_at([r for r in rows if r["engine"] == "mbd"], target, series_name), target)
        cells = [f"`{scene['scene']}`", scene["reference_kind"], mbd[0]]
        for engine in ("simbody", "mujoco"):
            er = [r for r in rows if r["engine"] == engine]
            if not er:
                note = next((n for n in scene["notes"] if n.startswith(f"peer {engine}")), None)
                cells += ["not run" + (" (not installed)" if note else " (no model)"), "—"]
                continue
            peer = cost_cell(engine_cost_at(er, target, series_name), target)
            cells += [peer[0], ratio_cell(peer, mbd)]
        md.append("| " + " | ".join(cells) + " |")
    return md + [""]


def automatic_table(data, rows_by_scene):
    """The automatic choice of `mbd simulate` (no --formulation / --integrator) for each scene, its
    cost at each target read off its own series, and that cost over mbd's best of grid."""
    md = ["### The automatic choice against the best of grid", "",
          "What `mbd simulate` runs when neither the command line nor the scene names a formulation or an "
          "integrator (docs/user-guide.md, \"The automatic choice\"), its CPU time at each target error read "
          "off its own series as above, and that time over mbd's best of grid (1: the automatic choice is the "
          "best pair; the target of issue 13 is at most 1.5).", "",
          "| scene | automatic choice | " + " | ".join(f"at {t:g} | / best" for t in TARGETS) + " |",
          "|---|---|" + "---|---|" * len(TARGETS)]
    for scene in data["scenes"]:
        auto = scene.get("automatic")
        if not auto:
            continue
        pair = f"{auto['formulation']} + {auto['integrator']}"
        rows = [r for r in rows_by_scene.get(scene["scene"], []) if r["engine"] == "mbd"]
        own = [r for r in rows if series_name(r) == pair]
        cells = [f"`{scene['scene']}`", pair]
        for target in TARGETS:
            mine = cost_cell(engine_cost_at(own, target, series_name), target)
            best = cost_cell(engine_cost_at(rows, target, series_name), target)
            cells += [fmt(mine[1]) + ("" if mine[2] else " (<=)") if mine[1] else "not reached",
                      ratio_cell(mine, best) if own else "not in the grid"]
        md.append("| " + " | ".join(cells) + " |")
    return md + [""]


def series_name(row):
    return row["formulation"] + " + " + row["integrator"] if row["engine"] == "mbd" else row["integrator"]


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
    for target in TARGETS:
        ax.axhline(target, color="grey", lw=0.8, ls=":")
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
                name = f"{row.get('chain', 'planar')} {row['formulation']}"
                data.setdefault(name, []).append((int(row["bodies"]), float(row["cpu_per_step_s"])))
    fig, ax = plt.subplots(figsize=(6.4, 4.6))
    lines = ["| chain, formulation | " + " | ".join(f"N = {n}" for n in sorted({n for v in data.values() for n, _ in v}))
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
    ax.set_xlabel("bodies (chain links)")
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
              "of its series are skipped. Without `--peers`, the peer programs are looked for beside the running `mbd` "
              "(`bin/peers` in the build tree, `libexec/mbd/peers` when installed). A peer program that is missing "
              "(library not installed, peers not built) is reported on stderr and in the JSON notes, its runs are "
              "counted as skipped in the summary, and the bench goes on. For a single run, `mbd simulate SCENE "
              "--error-estimate` repeats it at a ten times tighter tolerance (fixed step: half the step, with the "
              "Richardson factor 2^p / (2^p - 1)) and ends with `error estimate: CPU time ... s, estimated global "
              "position error ... m` (with `--json`: the field `error_estimate`); on the pendulum the estimate is "
              "within a factor of 10 of the closed-form error (tests/test_bench.cpp).")
    md.append("")
    md.append("### CPU time at equal error")
    md.append("")
    md.append("Each engine's CPU time at error 1e-6 and 1e-9, read off its own work-precision curves "
              "(scripts/work_precision.py): along each series (one formulation x integrator, or one peer integrator, "
              "its settings loosest first) log(CPU time) is interpolated linearly in log(error) between the two "
              "consecutive points whose errors bracket the target, and the engine's time is the least over its "
              "series (named in the cell). A series whose every point is already more accurate gives its cheapest "
              "point, an upper bound (marked <=); an engine none of whose series reaches the target reads "
              "'not reached'. Ratio = peer / mbd (> 1: mbd is faster; <= or >= where one side is an upper bound).")
    md.append("")
    for target in TARGETS:
        md += cost_table(data, rows_by_scene, target)
    md += automatic_table(data, rows_by_scene)
    details = []
    for scene in data["scenes"]:
        rows = rows_by_scene.get(scene["scene"], [])
        plot_scene(scene, rows, a.out_dir)
        failed = [r for r in rows if r["status"] != "ok"]
        details.append(f"- `{scene['scene']}`: {scene['error_measure']}; reference: {scene['reference']}."
                       + (f" {len(failed)} of {len(rows)} runs failed or were skipped"
                          f" (first: {failed[0]['engine']} {failed[0]['formulation']} + {failed[0]['integrator']}:"
                          f" {failed[0]['status'][:160]})." if failed else "")
                       + (" Notes: " + "; ".join(scene["notes"]) + "." if scene["notes"] else ""))
    md += ["", "### Scenes, error measures and references", ""] + details
    md += ["", "### Per-step cost against body count", "",
           "CPU time of one fixed rk4 step (4 right-hand sides and the formulation's projection) of `mbd simulate` on "
           "planar chains (0.1 m, 1 kg links, revolute joints, gravity) and spatial chains (0.1 m, 1 kg rods on "
           "spherical joints, gravity, the last link swinging sideways), for every formulation plugin installed: "
           "the cost of one more step, i.e. the difference of a run of k and a run of 3k steps over 2k, the median "
           "of 5 such pairs, with output rows only at the ends (scripts/bench_scaling.py: without the assembly, "
           "a formulation's first factorization and the writing of output rows, which the runs before 2026-12-06 "
           "included), "
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
    print("\n".join(md[md.index("### CPU time at equal error"):md.index("### Scenes, error measures and references")]))


if __name__ == "__main__":
    sys.exit(main())
