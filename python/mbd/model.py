"""mbd.Model: a multibody system read from a scene, and the analyses of the ``mbd`` command
on it. A Model is immutable; any number of threads may run it at once (each run has its own
workspace), and the engine works with the GIL released."""

import collections.abc
import logging
import os
import warnings

import numpy as np

from . import _mbd
from .errors import StaticsError
from .modes import ModesResult
from .results import CheckReport, InverseResult, KinematicsResult, SimulationResult, StaticsResult


_log = logging.getLogger("mbd")


def load(path):
    """The Model of a scene file (YAML, docs/scene-format.md) or of a model file (MJCF, URDF or
    SDF, known from its content), imported as `mbd import` imports it (docs/import.md); what the
    import leaves out is one UserWarning. Raises SceneError (file, line, key) for a scene or model
    to fix and PluginError for a type no plugin provides."""
    handle, left_out = _mbd.load(os.fspath(path))
    if left_out:
        warnings.warn("not imported: " + left_out.split(": not imported: ", 1)[-1], stacklevel=2)
    return Model(handle)


def _plain(value, depth=0):
    """Mappings as dicts, all the way down (from_dict reads dicts, lists and scalars). Deeper
    than any scene nests, values are left as they are: the reader refuses them by name (a dict
    that contains itself, say)."""
    if depth > 80:
        return value
    if isinstance(value, collections.abc.Mapping):
        return {key: _plain(item, depth + 1) for key, item in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(item, depth + 1) for item in value]
    return value


class Model:
    """A multibody system: bodies, joints, forces, drivers and actuators. Make one with
    mbd.load(path) or Model.from_dict(scene); with_params() gives a changed copy."""

    __slots__ = ("_handle", "_info")

    def __init__(self, handle):
        if not isinstance(handle, _mbd.Model):
            raise TypeError("make a Model with mbd.load(path) or mbd.Model.from_dict(scene)")
        self._handle = handle
        self._info = handle.info()

    @classmethod
    def from_dict(cls, scene, *, label="<dict>"):
        """The Model of a scene given as Python values: the keys of a scene file
        (docs/scene-format.md) as dicts, lists, numbers and strings (numpy arrays too). No
        file is read, so there is no ``base:``. Errors name ``label`` and the key at fault."""
        if not isinstance(scene, collections.abc.Mapping):
            raise TypeError(f"a scene is a dict of keys, not {type(scene).__name__}")
        return cls(_mbd.from_dict(_plain(scene), str(label)))

    # --- what the model holds
    name = property(lambda self: self._info["name"], doc="The scene's name.")
    source = property(lambda self: self._info["source"], doc="The scene file (or the label of a dict).")
    dimension = property(lambda self: self._info["dimension"], doc="'planar' or 'spatial'.")
    nq = property(lambda self: self._info["nq"], doc="Number of coordinates.")
    nv = property(lambda self: self._info["nv"], doc="Number of velocities.")
    bodies = property(lambda self: [b["name"] for b in self._info["bodies"]], doc="Body names.")
    joints = property(lambda self: [j["name"] for j in self._info["joints"]], doc="Joint names.")
    forces = property(lambda self: [f["name"] for f in self._info["forces"]], doc="Force element names.")
    drivers = property(lambda self: [d["name"] for d in self._info["drivers"]], doc="Driver names.")
    actuators = property(lambda self: [a["name"] for a in self._info["actuators"]], doc="Actuator names.")

    def initial_state(self):
        """The scene's state at t = 0 as written (q, v), before assembly: the start of
        simulate() unless q0, v0 are given."""
        return self._info["q0"].copy(), self._info["v0"].copy()

    def info(self):
        """Everything above, with each element's type, bodies and file:line, as a dict."""
        return dict(self._info)

    def _inputs(self):
        """The files a result must never overwrite: the scene and its ``base:`` files."""
        return [self._info["source"]] + list(self._info["base_files"])

    def __repr__(self):
        counts = ", ".join(f"{len(getattr(self, k))} {k}" for k in ("bodies", "joints", "forces", "drivers"))
        return f"<mbd.Model {self.name!r} ({self.dimension}): {counts}>"

    # --- studies
    def param(self, path):
        """The number at a key path of the scene (``bodies.crank.mass``,
        ``joints.O.point[0]``, ``gravity[1]``; docs/python.md)."""
        return self._handle.param(path)

    def with_params(self, values):
        """A new Model with the scene's keys at these paths set to these numbers, built from
        the scene this model keeps (no file is read again)::

            stiff = model.with_params({"forces.spring.stiffness": 1e4, "bodies.crank.mass": 2.0})
        """
        if isinstance(values, collections.abc.Mapping):
            values = values.items()
        return Model(self._handle.with_params([(str(path), float(value)) for path, value in values]))

    # --- analyses
    def check(self, *, rank_tolerance=1e-9):
        """What ``mbd check`` reports: assembly, degrees of freedom, redundant rows (CheckReport).
        Raises KinematicsError when the scene cannot be assembled."""
        return CheckReport(**self._handle.check(float(rank_tolerance)))

    def simulate(self, t_end, *, formulation=None, integrator=None, tol=None, step=None, output_step=None,
                 reactions=False, diagnostics=False, stabilization=None, linear_algebra=None, q0=None, v0=None):
        """Forward dynamics from the scene's initial state (or q0, v0, assembled and made
        consistent) to t_end, as ``mbd simulate``: the formulation (default: the scene's, else
        the automatic choice: embedding for a tree, augmented otherwise), the integrator
        (default: the automatic choice, dop853, or cvode for a stiff scene; mbd.integrators()
        lists them all: an adaptive one takes tol, default: the automatic choice, 1e-6 or tighter
        as the scene's stiction velocities need, with a warning for a given tol too coarse for
        one; a fixed-step one takes step), rows every output_step (default: the step, else
        t_end / 1000).
        Returns a SimulationResult; raises DynamicsError (time, joints) when the run fails.
        The engine's messages (what ``mbd simulate`` prints on stderr: the embedding path
        taken, redundant constraints left out, ...) go to the logger "mbd" at level INFO and
        are kept in result.messages."""
        raw = _mbd.simulate(self._handle, self._arguments(
            t_end, formulation, integrator, tol, step, output_step, reactions, diagnostics, stabilization,
            linear_algebra, q0, v0))
        for message in raw["messages"]:
            _log.info("%s", message)
        return SimulationResult(raw, self._inputs(), self._handle)

    def _arguments(self, t_end, formulation, integrator, tol, step, output_step, reactions, diagnostics,
                   stabilization, linear_algebra, q0, v0):
        a = _mbd.SimulateArguments()
        a.t_end = float(t_end)
        a.formulation = formulation or ""
        a.integrator = integrator or ""
        a.tol = None if tol is None else float(tol)
        a.step = None if step is None else float(step)
        a.output_step = None if output_step is None else float(output_step)
        a.reactions = bool(reactions)
        a.diagnostics = bool(diagnostics)
        a.stabilization = stabilization
        a.linear_algebra = linear_algebra
        a.q0 = None if q0 is None else np.asarray(q0, dtype=float).ravel()
        a.v0 = None if v0 is None else np.asarray(v0, dtype=float).ravel()
        return a

    def statics(self, *, time=0.0, objective="auto", hessian="exact", tolerance=1e-10, max_iterations=500,
                solver="ipopt", verbose=False):
        """Static equilibrium, as ``mbd statics``: from the scene's configuration, with the
        drivers held at ``time``; objective auto (potential when every force is conservative at
        rest), potential or virtual-work. Returns a StaticsResult; raises StaticsError (with
        the result) when no equilibrium is found, KinematicsError when the start cannot be
        assembled."""
        report, q = _mbd.statics(self._handle, float(time), objective, hessian, float(tolerance),
                                 int(max_iterations), solver, bool(verbose))
        import json  # the report of `mbd statics --json`, parsed as any JSON reader would
        result = StaticsResult(json.loads(report), q)
        if not result.converged:
            raise StaticsError(f"statics of {self.source} failed: {result.message}", result)
        return result

    def inverse(self, t_end, step, *, reactions=False, solver="ipopt"):
        """Inverse dynamics, as ``mbd inverse``: the actuator efforts (``actuators:`` of the
        scene) for the motion the drivers prescribe, at t = 0, step, ..., t_end. Returns an
        InverseResult; raises DynamicsError naming the time it fails."""
        raw = _mbd.inverse(self._handle, float(t_end), float(step), bool(reactions), solver)
        return InverseResult(raw, self.actuators, self._inputs())

    def modes(self, *, about="statics", residual_tolerance=1e-8, solver="ipopt", statics_iterations=500):
        """The modes, as ``mbd modes --json``: the equations of motion linearised in independent
        coordinates about the static equilibrium (about="statics", found by the statics plugin
        ``solver``) or the scene's initial state taken as a steady motion (about="initial");
        eigenvalues, natural frequencies, damping ratios, mode shapes and the state-space A, B.
        Returns a ModesResult with the command's numbers to the bit; raises StaticsError when
        the statics does not converge, LinearisationError when the scene has no freedom to
        linearise or the reference accelerates more than residual_tolerance, KinematicsError
        when it cannot be assembled."""
        converged, message, report = _mbd.modes(self._handle, str(about), float(residual_tolerance), str(solver),
                                                int(statics_iterations))
        if not converged:
            raise StaticsError(f"no modes: the statics of {self.source} did not converge: {message}")
        import json  # the report of `mbd modes --json`, parsed as any JSON reader would
        return ModesResult(json.loads(report))

    def kinematics(self, t_end, step, *, tolerance=1e-10, max_iterations=50, linear_algebra="auto"):
        """Kinematically driven motion, as ``mbd kinematics --output``: every body's position
        and velocity at t = 0, step, ..., t_end, each time assembled by Newton-Raphson to
        max |C| <= tolerance. Returns a KinematicsResult (a table of the command's columns);
        raises KinematicsError naming the time it fails."""
        raw = _mbd.kinematics(self._handle, float(t_end), float(step), float(tolerance), int(max_iterations),
                              str(linear_algebra))
        return KinematicsResult(raw, self._inputs(), self._handle)
