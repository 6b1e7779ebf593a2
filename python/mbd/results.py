"""Results of mbd's analyses as Python objects: tables of named columns over numpy arrays
(simulation, inverse dynamics) and reports (statics, check)."""

import dataclasses
import difflib
import os

import numpy as np

from . import _mbd
from .viewer import ViewerPage


def _read_only(array):
    array.flags.writeable = False
    return array


class Table:
    """Rows of named columns, as ``mbd`` writes them to CSV. ``table["crank.angle"]`` is a
    column (a numpy view); ``table.data`` all of them (rows x columns, read-only)."""

    def __init__(self, columns, data, inputs=()):
        self.columns = tuple(columns)
        self.data = _read_only(data)
        self._index = {name: k for k, name in enumerate(self.columns)}
        self._inputs = list(inputs)

    def __getitem__(self, name):
        try:
            return self.data[:, self._index[name]]
        except (KeyError, TypeError):
            raise KeyError(self._unknown(name)) from None

    def _unknown(self, name):
        near = difflib.get_close_matches(str(name), self.columns, n=3, cutoff=0.75)
        if near:
            return f"no column {name!r}; did you mean {', '.join(repr(n) for n in near)}?"
        shown = ", ".join(self.columns[:12]) + (", ..." if len(self.columns) > 12 else "")
        return f"no column {name!r}; the columns are {shown}"

    def __contains__(self, name):
        return name in self._index

    def keys(self):
        return list(self.columns)

    def __len__(self):
        return self.data.shape[0]

    @property
    def t(self):
        """The times of the rows."""
        return self["t"]

    def _block(self, names, what, how):
        if not names:
            raise AttributeError(f"this result has no {what}: {how}")
        return self.data[:, [self._index[n] for n in names]]

    _reactions_how = "ask for reactions=True"

    @property
    def reactions(self):
        """rows x joints x 3 (planar fx, fy, tz) or 6 (spatial fx, fy, fz, tx, ty, tz): the
        reaction on each joint's second body at the joint point, world axes."""
        return _reactions(self, self._reactions_how)[0]

    @property
    def reaction_joints(self):
        """The joints of ``reactions``, in its order."""
        return _reactions(self, self._reactions_how)[1]

    def to_csv(self, path):
        """Write the table as ``mbd`` writes its CSV files: the same columns and numbers (17
        significant digits), to PATH.partial and renamed to PATH once complete. A path that is
        one of the scene's files is refused."""
        _mbd.write_csv(os.fspath(path), list(self.columns), self.data, self._inputs)

    def __repr__(self):
        return f"<{type(self).__name__}: {len(self)} rows x {len(self.columns)} columns>"


def _reaction_names(columns):
    return [c for c in columns if c.rsplit(".", 1)[-1] in ("fx", "fy", "fz", "tx", "ty", "tz")]


def _reactions(table, how):
    names = _reaction_names(table.columns)
    block = table._block(names, "reactions", how)
    joints = list(dict.fromkeys(n.rsplit(".", 1)[0] for n in names))
    return block.reshape(len(table), len(joints), len(names) // len(joints)), joints


@dataclasses.dataclass(frozen=True)
class RunStats:
    """How a simulation went: the formulation and integrator used (and the tolerance of an
    adaptive one, given or automatic; 0 for a fixed step), output rows, accepted and
    rejected steps, right-hand side, Jacobian and Newton evaluations, the process CPU time of
    the integration (``cpu_s``: all threads of the process, as ``mbd simulate`` reports it),
    the wall time and the CPU time of the calling thread for the whole run (``wall_s``,
    ``thread_cpu_s``: the run's own cost also when other threads run at once), and the
    constraint violation (max |C|, max |J v + C_t|) at the last row."""

    formulation: str
    integrator: str
    tolerance: float
    rows: int
    steps: int
    rejected_steps: int
    rhs_evaluations: int
    jacobian_evaluations: int
    newton_iterations: int
    cpu_s: float
    wall_s: float
    thread_cpu_s: float
    position_violation: float
    velocity_violation: float


class SimulationResult(ViewerPage, Table):
    """A forward-dynamics run: the columns of ``mbd simulate``'s CSV, and

    - ``t``: the output times;
    - ``q``, ``v``: the engine's coordinates and velocities at each (planar: x, y, angle and
      their rates per body; spatial: position and Euler parameters, then the velocity and the
      angular velocity in body axes; the CSV's angular velocities are in world axes);
    - ``reactions`` (with reactions=True): rows x joints x 3 (planar fx, fy, tz) or 6
      (spatial fx, fy, fz, tx, ty, tz), the reaction on each joint's second body at the joint
      point in world axes; ``reaction_joints`` names the joints;
    - ``energies`` (with diagnostics=True): rows x 2, kinetic and potential energy;
    - ``stats``: a RunStats; ``messages``: the engine's messages during the run.

    In Jupyter the result shows as the viewer of ``mbd animate`` (``viewer_page()``)."""

    _reactions_how = "simulate(..., reactions=True)"

    def __init__(self, raw, inputs, model_handle=None):
        super().__init__(raw["columns"], raw["data"], inputs)
        self._model_handle = model_handle
        self.q = _read_only(raw["q"])
        self.v = _read_only(raw["v"])
        self.stats = RunStats(**raw["stats"])
        self.messages = list(raw["messages"])

    @property
    def energies(self):
        return self._block([c for c in ("kinetic_energy", "potential_energy") if c in self],
                           "energies", "simulate(..., diagnostics=True)")


class KinematicsResult(ViewerPage, Table):
    """Kinematically driven motion: the columns of ``mbd kinematics --output`` (t, then
    every body's position and velocity). In Jupyter it shows as the viewer of ``mbd animate``."""

    def __init__(self, raw, inputs, model_handle):
        super().__init__(raw["columns"], raw["data"], inputs)
        self._model_handle = model_handle


class InverseResult(Table):
    """Inverse dynamics: the columns of ``mbd inverse``'s CSV; ``efforts`` (rows x actuators,
    named by ``actuators``) and, with reactions=True, ``reactions`` as in SimulationResult."""

    _reactions_how = "inverse(..., reactions=True)"

    def __init__(self, raw, actuators, inputs):
        super().__init__(raw["columns"], raw["data"], inputs)
        self.actuators = list(actuators)

    @property
    def efforts(self):
        return self._block(self.actuators, "actuators", "add 'actuators:' to the scene")


class StaticsResult:
    """A static equilibrium: the keys of ``mbd statics --json`` (docs/statics.md) as
    attributes (``converged``, ``status``, ``iterations``, ``residual``, ``objective``,
    ``stability``, ``message``, ``bodies``, ``reactions``, ``coordinates``, ``drivers``,
    ``limits``, ``reactions_determined``, ``redundant_rows``, ``undetermined_reactions``),
    ``tangent_eigenvalues`` as an array and ``q`` the equilibrium coordinates.
    A value that is not a finite number is None, as in the JSON. ``to_dict()`` gives the JSON
    object itself."""

    def __init__(self, report, q):
        self._report = report
        self.q = _read_only(q)
        for key, value in report.items():
            setattr(self, key, value)
        self.message = report.get("message", "")
        self.tangent_eigenvalues = _read_only(np.array(
            [np.nan if x is None else x for x in report["tangent_eigenvalues"]], dtype=float))

    def to_dict(self):
        return self._report

    def __repr__(self):
        state = "equilibrium" if self.converged else "FAILED"
        return f"<StaticsResult: {state}, stability {self.stability}, residual {self.residual:.3g}>"


@dataclasses.dataclass(frozen=True)
class CheckReport:
    """What ``mbd check`` reports: the assembly at t = 0 (iterations, residual, the assembled
    ``q``), the counts of velocities and joint and driver equations, the degrees of freedom by
    the Gruebler count and by the rank of C_q, the redundant constraint rows, whether the
    drivers prescribe the motion, and the embedding formulation's path."""

    assembly_iterations: int
    assembly_residual: float
    q: np.ndarray
    velocities: int
    joint_equations: int
    driver_equations: int
    gruebler_dof: int
    rank: int
    rank_dof: int
    redundant: list
    full_rank: int
    free_dof: int
    dependent_driver_rows: int
    kinematically_driven: bool
    embedding: str
    embedding_reason: str
