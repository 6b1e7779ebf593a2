"""mbd.load of a model file (MJCF, URDF, SDF; issue 37, docs/import.md) is the command's import:
the same model as the scene `mbd import` writes, so every number of a simulation is the same bit
for bit as `mbd simulate` of that scene; what the import leaves out is one warning; a bad model
file raises SceneError naming the element."""

import pathlib
import warnings

import pytest

import mbd
from conftest import SOURCE, bit_identical, read_csv, run_cli

MODELS = [
    "/usr/share/mujoco/model/humanoid/humanoid.xml",  # MJCF through MuJoCo's compiler (libmujoco-samples)
    str(SOURCE.parent / "shared" / "models" / "erd_ur5" / "ur5_robot.urdf"),  # URDF, read in place
    str(SOURCE.parent / "shared" / "models" / "sdf_double_pendulum" / "double_pendulum.sdf"),  # SDF
]


@pytest.mark.parametrize("model_file", MODELS, ids=["mjcf", "urdf", "sdf"])
def test_load_of_a_model_file_is_the_imported_scene(tmp_path, model_file):
    assert pathlib.Path(model_file).is_file(), model_file
    written = tmp_path / "scene.yaml"
    run_cli("import", model_file, "-o", written)
    cli_csv = tmp_path / "cli.csv"
    run_cli("simulate", written, "--t-end", 0.05, "--formulation", "embedding", "--tol", "1e-8", "-o", cli_csv, "-q")
    header, rows = read_csv(cli_csv)

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        model = mbd.load(model_file)
    left_out = [str(w.message) for w in caught]
    assert len(left_out) <= 1 and all(m.startswith("not imported: ") for m in left_out), left_out
    assert model.bodies == mbd.load(written).bodies and model.joints == mbd.load(written).joints
    result = model.simulate(0.05, formulation="embedding", tol=1e-8)
    assert list(result.columns) == header
    assert bit_identical(result.data, rows)


def test_a_bad_model_file_raises_naming_the_element(tmp_path):
    bad = tmp_path / "mimic.urdf"
    bad.write_text("""<?xml version="1.0"?>
<robot name="bad">
  <link name="base"/>
  <link name="arm"><inertial><mass value="1"/><inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial></link>
  <joint name="hinge" type="continuous"><parent link="base"/><child link="arm"/><axis xyz="0 1 0"/>
    <mimic joint="nowhere"/></joint>
</robot>
""")
    with pytest.raises(mbd.SceneError, match="URDF joint 'hinge' <mimic>: its leader joint 'nowhere' is not a joint"):
        mbd.load(bad)
