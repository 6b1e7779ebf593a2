"""Bad input raises the right exception, carrying the message the mbd command prints and the
parts a program needs: file, line and key of a scene, the time and the joints of a failed run."""

import numpy as np
import pytest

import mbd
from conftest import Cli, scene

SLIDER_CRANK = scene("dynamics/slider-crank.yaml")


def edited(tmp_path, name, old, new):
    text = open(SLIDER_CRANK).read()
    assert old in text, "test bug"
    path = tmp_path / name
    path.write_text(text.replace(old, new, 1))
    return path


def test_a_bad_number_in_a_scene_file_is_a_scene_error_with_file_line_and_key(tmp_path):
    path = edited(tmp_path, "bad.yaml", "    mass: 1.0\n", "    mass: heavy\n")
    with pytest.raises(mbd.SceneError) as error:
        mbd.load(path)
    e = error.value
    assert (e.file, e.line, e.key) == (str(path), 24, "bodies.rod.mass")
    assert str(e) == Cli("check", path).error == f"{path}:24: body 'rod': 'mass' must be a number, got 'heavy'"
    assert isinstance(e, mbd.InputError) and isinstance(e, ValueError)


def test_a_misspelt_key_of_a_dict_scene_names_the_key():
    bodies = [{"name": "b", "mass": 1, "inertia": 1, "masss": 2}]
    joints = [{"name": "j", "type": "revolute", "bodies": ["ground", "b"], "point": [0, 0]}]
    with pytest.raises(mbd.SceneError) as error:
        mbd.Model.from_dict({"dimension": "planar", "bodies": bodies, "joints": joints}, label="arm")
    e = error.value
    assert (e.file, e.line, e.key) == ("arm", None, "bodies.b.masss")
    assert str(e) == "arm: key 'bodies.b.masss': unknown key 'masss' in body 'b'; did you mean 'mass'?"
    with pytest.raises(mbd.SceneError) as error:  # a value no scene file can hold
        mbd.Model.from_dict({"dimension": "planar", "bodies": [{"name": "b", "mass": {1, 2}}]})
    assert error.value.key == "bodies[0].mass" and "got set" in str(error.value)
    looped = {"dimension": "planar"}
    looped["bodies"] = [looped]  # a dict that contains itself
    with pytest.raises(mbd.SceneError, match="nested more than 64 levels"):
        mbd.Model.from_dict(looped)


def test_a_parameter_that_does_not_resolve_names_the_path_and_near_names():
    model = mbd.load(SLIDER_CRANK)
    with pytest.raises(mbd.SceneError) as error:
        model.with_params({"bodies.crnak.mass": 2.0})
    e = error.value
    assert e.key == "bodies.crnak.mass" and e.file == SLIDER_CRANK and e.line == 17
    assert "no element named 'crnak' in 'bodies'; did you mean 'crank'?" in str(e)
    with pytest.raises(mbd.SceneError) as error:  # resolves, but the scene refuses the value
        model.with_params({"bodies.crank.mass": -1})
    assert error.value.key == "bodies.crank.mass" and "(with bodies.crank.mass = -1)" in str(error.value)


def test_an_unknown_joint_type_is_a_plugin_error(tmp_path):
    path = edited(tmp_path, "plug.yaml", "type: prismatic", "type: prismatik")
    with pytest.raises(mbd.PluginError) as error:
        mbd.load(path)
    e = error.value
    assert (e.file, e.line, e.key) == (str(path), 37, "joints.guide")
    assert str(e) == Cli("check", path).error
    assert "did you mean 'prismatic'?" in str(e)


def test_one_plugin_folder_may_be_given_alone(tmp_path):
    # a str (or a path) is one folder, not a sequence of one-letter folders
    mbd.set_plugin_path(str(tmp_path))
    assert mbd.plugin_path() == [str(tmp_path)]
    mbd.set_plugin_path(tmp_path)
    assert mbd.plugin_path() == [str(tmp_path)]
    with pytest.raises(mbd.PluginError, match="no such plugin folder"):
        mbd.set_plugin_path(str(tmp_path / "missing"))


def test_a_plugin_path_without_the_plugins_is_a_plugin_error(tmp_path):
    mbd.set_plugin_path([tmp_path])
    assert mbd.plugin_path() == [str(tmp_path)] and mbd.plugins() == []
    with pytest.raises(mbd.PluginError, match="unknown joint type 'revolute'"):
        mbd.load(SLIDER_CRANK)
    with pytest.raises(mbd.PluginError, match="no such plugin folder"):
        mbd.set_plugin_path([tmp_path / "missing"])
    mbd.set_plugin_path(None)
    assert mbd.plugin_path() == mbd.default_plugin_path()
    kinds = {p.kind for p in mbd.plugins()}
    assert {"joint", "force", "formulation", "statics", "inverse"} <= kinds


def test_a_singular_configuration_is_a_dynamics_error_with_time_and_joints():
    dead_centre = scene("extreme/slider-crank-dead-centre.yaml")
    model = mbd.load(dead_centre)
    with pytest.raises(mbd.DynamicsError) as error:
        model.simulate(1.0, tol=1e-8)
    e = error.value
    assert e.time == pytest.approx(0.5, abs=1e-3)  # the dead centre (the scene's header)
    assert e.drivers == ["push"] and e.joints == []
    assert str(e) == Cli("simulate", dead_centre, "--t-end", 1, "--tol", 1e-8, "-o", "/dev/null", "-q").error
    with pytest.raises(mbd.DynamicsError) as error:  # another pair: the same dead centre, by name
        model.simulate(1.0, formulation="amalgamated", integrator="cvode", tol=1e-8)
    assert error.value.time == pytest.approx(0.5, abs=1e-3)
    assert error.value.drivers == ["push"] or error.value.joints == ["O"]
    assert "singular configuration" in str(error.value)


def test_a_massless_body_is_a_dynamics_error_at_t_zero():
    with pytest.raises(mbd.DynamicsError) as error:
        mbd.load(scene("extreme/zero-mass-body.yaml")).simulate(0.1)
    assert error.value.time == 0.0 and "zero mass" in str(error.value)


@pytest.mark.parametrize("keywords, where, text", [
    (dict(integrator="rk4"), "step", "give their size with step (e.g. step=1e-3)"),
    (dict(integrator="rk4", step=1e-3, tol=1e-6), "tol", "rk4 takes fixed steps: set them with step"),
    (dict(step=1e-3), "step", "the automatic integrator (dop853 or cvode) chooses its own steps: set its accuracy with tol"),
    (dict(integrator="dopri5", step=1e-3), "step", "dopri5 chooses its own steps: set its accuracy with tol"),
    (dict(tol=0.0), "tol", "expected a number from 1e-14 to 1"),
    (dict(integrator="rk5"), "integrator", "unknown integrator 'rk5'"),
    (dict(output_step=-1.0), "output_step", "must be a positive finite number"),
    (dict(stabilization="strong"), "stabilization", "expected one of 'projection', 'baumgarte', 'none'"),
    (dict(linear_algebra="fast"), "linear_algebra", "use auto, dense or sparse"),
    (dict(q0=[0.0, 1.0]), "q0", "expected 9 coordinates, got 2"),
])
def test_options_that_do_not_apply_are_refused_by_name(keywords, where, text):
    with pytest.raises(mbd.InputError) as error:
        mbd.load(SLIDER_CRANK).simulate(0.1, **keywords)
    assert error.value.where == where and text in str(error.value)
    assert not isinstance(error.value, mbd.SceneError)


def test_every_integrator_of_the_table_takes_the_option_its_description_says():
    # mbd.integrators() reads the engine's table: a fixed-step one is refused without a step,
    # an adaptive one with a step (the message lists the fixed-step ones from the same table)
    described = mbd.integrators()
    assert {"euler", "rk4", "dopri5", "dop853", "generalized_alpha", "cvode"} <= {d.name for d in described}
    fixed = [d.name for d in described if not d.adaptive]
    for d in described:
        with pytest.raises(mbd.InputError) as error:
            mbd.load(SLIDER_CRANK).simulate(0.1, integrator=d.name, **({} if not d.adaptive else dict(step=1e-3)))
        assert error.value.where == "step", d.name
        if d.adaptive:
            assert all(name in str(error.value) for name in fixed), str(error.value)


def test_an_unknown_formulation_is_a_plugin_error():
    with pytest.raises(mbd.PluginError, match="did you mean 'augmented'"):
        mbd.load(SLIDER_CRANK).simulate(0.1, formulation="augmentd")


def test_a_result_file_never_overwrites_the_scene_and_needs_its_folder(tmp_path):
    path = edited(tmp_path, "scene.yaml", "stiffness: 100", "stiffness: 100")
    result = mbd.load(path).simulate(0.01)
    before = path.read_bytes()
    with pytest.raises(mbd.InputError, match="input"):
        result.to_csv(path)
    assert path.read_bytes() == before
    with pytest.raises(mbd.InputError):
        result.to_csv(tmp_path / "missing" / "out.csv")
    assert not (tmp_path / "missing").exists()


def test_statics_that_find_no_equilibrium_raise_with_the_report():
    # a free body under gravity has no equilibrium
    free = {"dimension": "planar", "gravity": [0, -9.81],
            "bodies": [{"name": "ball", "mass": 1, "inertia": 0.1}]}
    with pytest.raises(mbd.StaticsError) as error:
        mbd.Model.from_dict(free).statics(objective="virtual-work", max_iterations=10)
    assert error.value.result is not None and not error.value.result.converged
    assert str(error.value).startswith("statics of <dict> failed: ")


def test_a_configuration_that_cannot_be_assembled_is_a_kinematics_error():
    with pytest.raises(mbd.KinematicsError):
        mbd.load(scene("extreme/unreachable-driver.yaml")).check()


def test_results_are_read_only():
    result = mbd.load(SLIDER_CRANK).simulate(0.01)
    with pytest.raises(ValueError):
        result.q[0, 0] = 1.0
    assert isinstance(result.q, np.ndarray)


def test_inverse_dynamics_without_actuators_is_a_scene_error():
    with pytest.raises(mbd.SceneError, match="needs actuators") as error:
        mbd.load(SLIDER_CRANK).inverse(0.1, 0.01)
    assert error.value.file == SLIDER_CRANK
