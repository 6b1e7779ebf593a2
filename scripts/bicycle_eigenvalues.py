#!/usr/bin/env python3
"""Eigenvalues of the Whipple bicycle benchmark against forward speed, from `mbd modes`.

For each speed v in 0..10 m/s this writes the benchmark scene (scenes/reference/whipple-bicycle.yaml)
with every body moving at [v, 0, 0] and the wheels turning at v / r, runs
`mbd modes SCENE --about initial --json`, and plots the real and imaginary parts of the
eigenvalues of the modes (the ignorable directions and the free forward speed's zero left out), as the
benchmark paper's Fig. 3 does. The weave and capsize speeds are marked where the weave's real
part and the capsize eigenvalue cross zero (linear interpolation between the speeds).

Usage: scripts/bicycle_eigenvalues.py [--mbd build/bin/mbd] [--output docs/images/whipple-bicycle-eigenvalues.png]
Needs numpy and matplotlib (Debian: python3-matplotlib).
"""
import argparse
import json
import os
import re
import subprocess
import tempfile

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCENE = os.path.join(ROOT, "scenes", "reference", "whipple-bicycle.yaml")
RADII = {"rear_wheel": 0.3, "front_wheel": 0.35}


def scene_at(text, v):
    """The scene text with its speed 5 m/s replaced by v."""
    text = re.sub(r"velocity: \[5, 0, 0\]", f"velocity: [{v!r}, 0, 0]", text)
    for body, r in RADII.items():
        text = re.sub(rf"(- name: {body}\n(?:    .*\n)*?    angular_velocity: )\[0, [0-9.e+-]+, 0\]",
                      lambda m: f"{m.group(1)}[0, {v / r!r}, 0]", text)
    return text


def eigenvalues(mbd, text, v):
    with tempfile.NamedTemporaryFile("w", suffix=".yaml", delete=False) as f:
        f.write(scene_at(text, v))
        path = f.name
    try:
        out = subprocess.run([mbd, "modes", path, "--about", "initial", "--json"], check=True,
                             capture_output=True, text=True).stdout
    finally:
        os.remove(path)
    values = []
    for m in json.loads(out)["modes"]:
        re_, im = m["eigenvalue"]
        values.append(complex(re_, im))
        if m["kind"] == "oscillatory":
            values.append(complex(re_, -im))
    # the free forward speed: the eigenvalue nearest zero (a neighbouring steady motion)
    values.remove(min(values, key=abs))
    return values


def crossing(speeds, values):
    for k in range(1, len(values)):
        a, b = values[k - 1], values[k]
        if a is not None and b is not None and (a < 0) != (b < 0):
            return speeds[k - 1] + (speeds[k] - speeds[k - 1]) * a / (a - b)
    return None


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--mbd", default=os.path.join(ROOT, "build", "bin", "mbd"))
    parser.add_argument("--output", default=os.path.join(ROOT, "docs", "images", "whipple-bicycle-eigenvalues.png"))
    args = parser.parse_args()
    text = open(SCENE).read()
    speeds = [k / 10 for k in range(0, 101)]
    rows = [eigenvalues(args.mbd, text, v) for v in speeds]
    weave = [next((z.real for z in row if z.imag > 1e-6), None) for row in rows]
    capsize = [min((z.real for z in row if z.imag == 0 and abs(z.real) < 2), key=abs, default=None) for row in rows]
    v_w, v_c = crossing(speeds, weave), crossing(speeds, capsize)

    fig, ax = plt.subplots(figsize=(7, 4.5))
    for v, row in zip(speeds, rows):
        ax.plot([v] * len(row), [z.real for z in row], "k.", markersize=3)
        ax.plot([v] * sum(1 for z in row if z.imag > 0), [z.imag for z in row if z.imag > 0], ".",
                color="tab:blue", markersize=3)
    ax.plot([], [], "k.", label="Re(λ)")
    ax.plot([], [], ".", color="tab:blue", label="Im(λ) of the weave pair")
    for speed, name in ((v_w, "weave"), (v_c, "capsize")):
        if speed is not None:
            ax.axvline(speed, color="tab:gray", linestyle="--", linewidth=0.8)
            ax.text(speed, 9.3, f" v_{name[0]} = {speed:.3f}", fontsize=8)
    ax.axhline(0.0, color="black", linewidth=0.5)
    ax.set_xlim(0, 10)
    ax.set_ylim(-10, 10)
    ax.set_xlabel("forward speed v (m/s)")
    ax.set_ylabel("eigenvalue (1/s)")
    ax.set_title("Whipple bicycle benchmark: mbd modes --about initial")
    ax.legend(loc="lower left", fontsize=8)
    fig.tight_layout()
    fig.savefig(args.output, dpi=120)
    print(f"weave speed {v_w:.4f} m/s, capsize speed {v_c:.4f} m/s (interpolated); wrote {args.output}")


if __name__ == "__main__":
    main()
