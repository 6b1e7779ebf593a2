"""A result shown in Jupyter (_repr_html_) is the offline viewer page `mbd animate` writes for
the same result, holding the result's numbers (issue 38)."""

import base64
import html
import json
import re

import numpy as np
import pytest

import mbd
from conftest import run_cli, scene


def inline_page(result):
    shown = result._repr_html_()
    match = re.fullmatch(r'<iframe class="mbd-viewer" srcdoc="([^"]*)"[^>]*></iframe>', shown, re.S)
    assert match, shown[:200]
    return html.unescape(match.group(1))


def test_the_inline_viewer_is_the_page_of_mbd_animate(tmp_path):
    path = scene("dynamics/pendulum-a01.yaml")
    result = mbd.load(path).simulate(1.0, integrator="dopri5", tol=1e-9, output_step=0.01)
    page = inline_page(result)
    csv, written = tmp_path / "result.csv", tmp_path / "page.html"
    result.to_csv(csv)
    run_cli("animate", path, csv, "-o", written)
    assert page == written.read_text(encoding="utf-8")  # the same page, byte for byte
    assert page.startswith("<!DOCTYPE html>") and "three" in page.lower()


def test_the_page_holds_the_results_numbers():
    model = mbd.load(scene("dynamics/pendulum-a01.yaml"))
    result = model.simulate(1.0, integrator="dopri5", tol=1e-9, output_step=0.01)
    page = inline_page(result)
    scene_json = json.loads(re.search(r'<script id="mbd-scene" type="application/json">(.*?)</script>', page, re.S)
                            .group(1).replace("<\\/", "</"))
    assert scene_json["name"] == "pendulum-a01" and scene_json["rows"] == len(result) == 101
    columns = {c["name"]: c for c in scene_json["columns"]}
    assert list(columns) == list(result.columns)
    for name in ("bob.x", "bob.y", "bob.omega"):  # each column's range (9 digits), the plot's axis
        assert columns[name]["min"] == float(f"{result[name].min():.9g}")
        assert columns[name]["max"] == float(f"{result[name].max():.9g}")
    # the motion: first the keyframe times as float64, then each pose column as float32 there
    motion = base64.b64decode(re.search(r'<script id="mbd-motion" type="text/plain">(.*?)</script>', page, re.S)
                              .group(1))
    keyframes = scene_json["keyframes"]
    times = np.frombuffer(motion[:8 * keyframes], dtype="<f8")
    rows = np.searchsorted(result.t, times)
    assert times[0] == 0.0 and times[-1] == 1.0 and np.array_equal(result.t[rows], times)
    x = columns["bob.x"]
    bob_x = np.frombuffer(motion[x["offset"]:x["offset"] + 4 * keyframes], dtype="<f4")
    assert np.array_equal(bob_x, result["bob.x"][rows].astype(np.float32))
    # released from the horizontal: the bob starts at x = 1 and swings down through x = 0
    assert bob_x[0] == np.float32(1.0) and bob_x.min() < 0.0


def test_kinematics_shows_the_same_viewer():
    model = mbd.load(scene("four-bar.yaml"))
    page = inline_page(model.kinematics(0.1, 0.01))
    assert '"name":"crank.angle"' in page and '"rows":11' in page


def test_the_plotted_column_is_chosen_by_name():
    result = mbd.load(scene("dynamics/four-bar-spring-damper.yaml")).simulate(0.2, reactions=True, diagnostics=True,
                                                                              output_step=0.01)
    assert '"plotColumn":"kinetic_energy"' in result.viewer_page(plot="kinetic_energy")
    assert '"plotColumn":"crank.x"' in result.viewer_page()
    with pytest.raises(KeyError, match="no column 'kinetic_enrgy'; did you mean 'kinetic_energy'"):
        result.viewer_page(plot="kinetic_enrgy")
