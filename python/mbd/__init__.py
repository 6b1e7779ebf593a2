"""mbd: multibody dynamics with honest numbers, from Python (docs/python.md).

    import mbd
    model = mbd.load("scenes/dynamics/four-bar-spring-damper.yaml")
    result = model.simulate(2.0, formulation="embedding", tol=1e-8)
    angle = result["crank.angle"]

Scenes come from files (mbd.load) or dicts (mbd.Model.from_dict); studies change keys
without reading files again (Model.with_params); every analysis of the ``mbd`` command
(check, simulate, statics, inverse, modes, kinematics) is a method of Model and runs with the
GIL released, so threads run models in parallel. mbd.Simulator steps a model inside your
own loop (inputs, a user force in Python, the state as numpy arrays).
"""

import collections
import os

from . import _mbd
from .errors import (DynamicsError, Error, InputError, KinematicsError, LinearisationError, OutputError,
                     PlacedError, PluginError, SceneError, StaticsError)
from .model import Model, load
from .modes import Mode, ModesResult
from .results import (CheckReport, InverseResult, KinematicsResult, RunStats, SimulationResult, StaticsResult,
                      Table)
from .simulator import Simulator

__version__ = _mbd.version
abi_version = _mbd.abi_version  # element plugins (joint, force, body)
kit_abi_version = _mbd.kit_abi_version  # formulation, statics and inverse plugins

PluginType = collections.namedtuple("PluginType", "kind type abi library version usable")
PluginType.__doc__ = ("A plugin type found in the plugin path; usable is False when it was built for another ABI "
                      "(abi_version for element plugins, kit_abi_version for formulation, statics and inverse plugins).")


def plugins():
    """Every joint, force, formulation, statics and inverse type of the plugin path, as
    ``mbd plugins`` lists them (no library is loaded to list them)."""
    return [PluginType(**t) for t in _mbd.plugin_types()]


Integrator = collections.namedtuple("Integrator", "name order adaptive locates_events needs_index3 stiff summary")
Integrator.__doc__ = ("An integrator as the engine describes it: its order, whether it chooses its own steps (tol) "
                      "or takes fixed ones (step), locates events, needs the index-3 form (the augmented "
                      "formulation), is implicit (stiff problems).")


def integrators():
    """Every integrator Model.simulate accepts, as ``mbd simulate --help`` lists them."""
    return [Integrator(**d) for d in _mbd.integrators()]


def plugin_path():
    """The plugin folders searched, in order (earlier folders win)."""
    return _mbd.plugin_path()


def default_plugin_path():
    """The folder installed beside libmbd_core, then the folders of MBD_PLUGIN_PATH."""
    return _mbd.default_plugin_path()


def set_plugin_path(folders):
    """Search these folders for the plugins of models loaded from now on (None: the default
    path); models loaded before keep theirs. To add a folder of your own plugins:
    ``mbd.set_plugin_path(mbd.default_plugin_path() + ["/my/plugins"])``. A folder that does
    not exist raises PluginError. One folder may be given alone, as a str or a path."""
    if isinstance(folders, (str, os.PathLike)):
        folders = [folders]  # one folder, not a sequence of one-letter folders
    _mbd.set_plugin_path(None if folders is None else [os.fspath(f) for f in folders])


def plugin_problems():
    """Files of the plugin path that look like plugins but were skipped, with the reason."""
    return _mbd.plugin_problems()


__all__ = ["load", "Model", "Simulator", "plugins", "integrators", "Integrator", "plugin_path", "default_plugin_path", "set_plugin_path", "plugin_problems",
           "PluginType", "Table", "SimulationResult", "KinematicsResult", "ModesResult", "Mode", "InverseResult",
           "StaticsResult", "CheckReport", "RunStats",
           "Error", "InputError", "PlacedError", "SceneError", "PluginError", "OutputError", "KinematicsError",
           "LinearisationError", "DynamicsError", "StaticsError"]
