"""Models for studies: a changed model equals the scene file edited by hand, a scene given as
dicts equals the same scene as a file, bit for bit; one Model runs in many threads at once
with the results of one run after another; Ctrl-C stops a run."""

import _thread
import concurrent.futures
import json
import re
import threading
import time

import numpy as np
import pytest

import mbd
from conftest import bit_identical, run_cli, scene

FOUR_BAR = scene("dynamics/four-bar-spring-damper.yaml")


def final_q(model):
    return model.simulate(0.3, integrator="rk4", step=1e-3).q[-1]


def test_with_params_equals_the_scene_edited_by_hand(tmp_path):
    model = mbd.load(FOUR_BAR)
    text = open(FOUR_BAR).read()
    edited = tmp_path / "edited.yaml"
    edited.write_text(text.replace("stiffness: 250", "stiffness: 10000").replace(
        "  - name: crank                      # O -> A\n    mass: 1", "  - name: crank\n    mass: 2.0"))
    changed = model.with_params({"forces.spring.stiffness": 1e4, "bodies.crank.mass": 2.0})
    assert bit_identical(final_q(changed), final_q(mbd.load(edited)))
    assert not bit_identical(final_q(changed), final_q(model)), "the change must matter"
    assert changed.param("forces.spring.stiffness") == 1e4 and model.param("forces.spring.stiffness") == 250
    assert model.param("joints.B.point[1]") == 0.485440745751236
    # pairs as well as a dict; the original model is untouched
    assert bit_identical(final_q(model.with_params([("forces.spring.stiffness", 1e4), ("bodies.crank.mass", 2)])),
                         final_q(changed))


SCENE = {
    "name": "pendulum-pair",
    "dimension": "planar",
    "gravity": [0, -9.81],
    "bodies": [
        {"name": "upper", "mass": 1.0, "inertia": 0.1 / 12, "position": np.array([0.5, 0.0]), "angle": 0},
        {"name": "lower", "mass": np.float64(0.7), "inertia": 0.7 * 0.36 / 12, "position": (1.3, 0.0),
         "angular_velocity": np.int64(2)},
    ],
    "joints": [
        {"name": "top", "type": "revolute", "bodies": ["ground", "upper"], "point": [0, 0]},
        {"name": "knee", "type": "revolute", "bodies": ["upper", "lower"], "point": [1.0, 0.0]},
    ],
    "forces": [{"name": "spring", "type": "rotational_spring_damper", "bodies": ["upper", "lower"],
                "stiffness": 12.5, "damping": 0.1}],
    "formulation": {"type": "embedding", "pivot_threshold": 0.5},
}


def as_json(value):
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, (np.floating, np.integer)):
        return value.item()
    if isinstance(value, dict):
        return {k: as_json(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [as_json(v) for v in value]
    return value


def test_a_dict_scene_equals_the_same_scene_as_a_file(tmp_path):
    path = tmp_path / "pair.yaml"  # JSON is YAML
    path.write_text(json.dumps(as_json(SCENE), indent=1))
    from_dict, from_file = mbd.Model.from_dict(SCENE), mbd.load(path)
    assert from_dict.name == "pendulum-pair" and from_dict.bodies == ["upper", "lower"]
    assert from_dict.source == "<dict>"
    a = from_dict.simulate(0.5, reactions=True, diagnostics=True)
    b = from_file.simulate(0.5, reactions=True, diagnostics=True)
    assert a.stats.formulation == "embedding" and a.columns == b.columns
    assert bit_identical(a.data, b.data)
    changed = from_dict.with_params({"forces.spring.stiffness": 50})
    assert bit_identical(changed.simulate(0.5).data, from_file.with_params({"forces.spring.stiffness": 50}).simulate(0.5).data)
    with pytest.raises(mbd.SceneError) as error:
        from_dict.with_params({"bodies.lower.mass": 0.0, "bodies.lower.inertia": -1})
    assert error.value.key == "bodies.lower.inertia" and "<dict>: key 'bodies.lower.inertia'" in str(error.value)


def test_check_reports_what_mbd_check_prints():
    path = scene("four-bar.yaml")
    printed = run_cli("check", path).out
    report = mbd.load(path).check()

    def number(pattern):
        return int(re.search(pattern, printed).group(1))

    assert report.gruebler_dof == number(r"Gruebler count\): (\d+)")
    assert report.rank_dof == number(r"rank of C_q\): (\d+)")
    assert report.rank == number(r"\(rank (\d+)\)")
    assert report.velocities == 9 and report.joint_equations == 8 and report.driver_equations == 1
    assert report.kinematically_driven and "kinematically driven: yes" in printed
    assert f"embedding: {report.embedding} path ({report.embedding_reason})" in printed
    assert report.redundant == [] and report.q.shape == (9,)


def run_from(model, speed):
    v0 = model.initial_state()[1] * speed  # the scene's velocities times `speed`, as tests/test_threads.cpp
    return model.simulate(0.3, formulation=["augmented", "embedding", "amalgamated", "hamiltonian"][int(speed * 10) % 4],
                          tol=1e-8, output_step=0.01, v0=v0, reactions=True)


def test_threads_over_one_model_give_the_serial_results():
    model = mbd.load(FOUR_BAR)
    speeds = [1.0 + 0.1 * k for k in range(8)]
    serial = [run_from(model, s) for s in speeds]
    with concurrent.futures.ThreadPoolExecutor(4) as pool:
        parallel = list(pool.map(lambda s: run_from(model, s), speeds))
    for a, b in zip(serial, parallel):
        assert a.stats.formulation == b.stats.formulation and bit_identical(a.data, b.data)
    assert not bit_identical(serial[0].data[-1], serial[4].data[-1]), "different starts, different runs"
    assert {r.stats.formulation for r in serial} == {"augmented", "embedding", "amalgamated", "hamiltonian"}


def test_ctrl_c_stops_a_run_and_the_model_runs_again():
    model = mbd.load(scene("dynamics/pendulum-a01.yaml"))  # about 40 s to t = 1e5 s
    timer = threading.Timer(0.3, _thread.interrupt_main)
    timer.start()
    began = time.monotonic()
    with pytest.raises(KeyboardInterrupt):
        model.simulate(1e5, output_step=1.0)
    assert time.monotonic() - began < 5.0
    timer.join()
    assert len(model.simulate(1.0)) == 1001


def test_the_engine_runs_without_the_gil():
    # The main thread sleeps while another thread starts a run, then runs Python until the run
    # ends. With the GIL held through the run, the main thread could not wake before the run
    # returned: its loop would cover only the last moments of the call. Released, the loop
    # covers the run. Measured in wall time on both sides, so a loaded machine changes nothing.
    model = mbd.load(scene("bench/chain-50.yaml"))
    span = []

    def run():
        began = time.perf_counter()
        model.simulate(10.0, formulation="embedding", output_step=0.05)  # about 0.6 s of CPU, quiet
        span.extend([began, time.perf_counter()])

    worker = threading.Thread(target=run)
    worker.start()
    time.sleep(0.1)
    stamps = []
    while worker.is_alive():
        stamps.append(time.perf_counter())
    worker.join()
    began, ended = span
    assert ended - began > 0.2, "test bug: the run is too short to tell"
    covered = (stamps[-1] - stamps[0]) if stamps else 0.0
    assert covered > 0.5 * (ended - began - 0.1), (
        f"the main thread ran for {covered:.3f} s of a {ended - began:.3f} s run")
