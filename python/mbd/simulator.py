"""mbd.Simulator: a simulation your program steps (docs/python.md, docs/embedding.md).

    sim = mbd.Simulator(model, integrator="dopri5", tol=1e-8)
    sim.set_input("force", 1.5)      # held until changed
    sim.advance_to(0.01)             # continues: the integrator keeps its step size and history
    x = sim.q[0]                     # read-only view of the current coordinates

The engine steps with the GIL released; a user force or event callback takes it back while
it runs.
"""

import numpy as np

from . import _mbd
from .errors import DynamicsError
from .model import Model


class Simulator:
    """One model stepped by your program: its own state, inputs and user force. Settings as for
    Model.simulate (formulation, integrator, tol, step, stabilization, linear_algebra, q0, v0,
    with the same automatic choices); ``t_end`` is the expected end of the run, which the
    automatic choices and the largest adaptive step follow, not a limit.

    After a failed step (mbd.DynamicsError, including a user force that raised or returned
    the wrong shape) the state stays that of the last good step, and step() / advance_to()
    raise until reset().
    """

    __slots__ = ("_model", "_sim", "_user_force", "_on_event")

    def __init__(self, model, *, t_end=1.0, formulation=None, integrator=None, tol=None, step=None,
                 stabilization=None, linear_algebra=None, q0=None, v0=None):
        if not isinstance(model, Model):
            raise TypeError(f"a Simulator runs an mbd.Model, not {type(model).__name__}")
        arguments = model._arguments(t_end, formulation, integrator, tol, step, None, False, False,
                                     stabilization, linear_algebra, q0, v0)
        self._model = model
        self._sim = _mbd.Simulator(model._handle, arguments)
        self._user_force = None
        self._on_event = None

    model = property(lambda self: self._model, doc="The Model stepped.")
    formulation = property(lambda self: self._sim.info()["formulation"], doc="The formulation in use.")
    integrator = property(lambda self: self._sim.info()["integrator"], doc="The integrator in use.")
    tolerance = property(lambda self: self._sim.info()["tolerance"],
                         doc="The adaptive integrator's tolerance; 0 for a fixed step.")
    messages = property(lambda self: list(self._sim.info()["messages"]),
                        doc="The messages of the set-up (the automatic choices), as simulate() gives them.")

    # --- stepping
    def step(self):
        """One accepted integrator step (it may end on an event)."""
        self._stepping(self._sim.step)

    def advance_to(self, t):
        """Continue to time t (not before time): the integrator keeps its step size and history;
        dopri5 and dop853 read t from the continuous extension of the step that passes it when
        nothing changed since the last call (docs/embedding.md)."""
        self._stepping(lambda: self._sim.advance_to(float(t)))

    def reset(self, q=None, v=None, *, t=None):
        """Restart. With no arguments: the scene's (or q0, v0's) initial state at t = 0. Otherwise
        from the current state with the given coordinates q, velocities v and time t changed:
        positions assembled onto the constraints, then velocities made consistent (drivers
        included), as a run's start is. The integrator starts afresh."""
        self._stepping(lambda: self._sim.reset(None if t is None else float(t), _vector(q), _vector(v)))

    # --- the state
    time = property(lambda self: self._sim.time(), doc="The current time.")
    q = property(lambda self: self._sim.q(),
                 doc="The current coordinates: a read-only numpy view (no copy) of the Simulator's state "
                     "buffer, which every step and reset overwrites; .copy() to keep values.")
    v = property(lambda self: self._sim.v(),
                 doc="The current velocities: a read-only view, as q.")

    def state(self):
        """(t, q, v) now, as copies."""
        return self.time, self.q.copy(), self.v.copy()

    def body_state(self, body):
        """A body's coordinates and velocities (copies): planar x, y, theta / vx, vy, omega;
        spatial R (3), Euler parameters (4) / velocity (3), body-frame angular velocity (3)."""
        return self._sim.body_state(str(body))

    def set_body_state(self, body, q, v):
        """reset() with one body's coordinates and velocities changed (then assembled and made
        consistent as reset() does)."""
        self._stepping(lambda: self._sim.set_body_state(str(body), _vector(q), _vector(v)))

    def joint_state(self, joint):
        """A joint's coordinate and rate (a joint with one: a revolute's angle, a prismatic's
        displacement, as a driver of it prescribes)."""
        return self._sim.joint_state(str(joint))

    def set_joint_state(self, joint, coordinate, rate=0.0):
        """Change the state as little as can be (the minimum-norm change of the positions, then
        of the velocities) so that the joint has this coordinate and rate and every constraint
        holds, then reset() from it. KinematicsError for a coordinate the mechanism cannot reach."""
        self._stepping(lambda: self._sim.set_joint_state(str(joint), float(coordinate), float(rate)))

    # --- inputs
    input_names = property(lambda self: list(self._sim.input_names()),
                           doc="The names of the scene's {type: input, name: NAME} time functions.")

    def set_input(self, name, value):
        """Hold input `name` at `value` from now on (zero-order hold). An unknown name raises
        InputError listing the scene's inputs."""
        self._sim.set_input(str(name), float(value))

    def input(self, name):
        """The value input `name` holds (0 until set)."""
        return self._sim.input(str(name))

    # --- callbacks
    def set_user_force(self, force, *, kind="generalized"):
        """Add forces your code computes to every right-hand side: ``force(t, q, v)`` (q, v new
        arrays each call) returns, with kind="generalized", a vector of model.nv generalized
        forces in the order of v; with kind="bodies", one row per body (model.bodies order):
        planar (fx, fy, torque), spatial (fx, fy, fz, mx, my, mz), forces and moments in world
        axes at the mass centre. None removes the force. An exception it raises fails the
        step: mbd.DynamicsError, whose __cause__ is your exception with its traceback."""
        self._sim.set_user_force(force, str(kind))
        self._user_force = force

    def on_event(self, callback):
        """Call ``callback(event)`` as each located event (a dict: time, force, event, kind,
        rate_before, rate_after) is passed during stepping. None: no callback."""
        self._sim.on_event(callback)
        self._on_event = callback

    @property
    def events(self):
        """The events located since the last reset, in time order (dicts as on_event gives)."""
        return self._sim.events()

    @property
    def stats(self):
        """Steps, rejected steps, right-hand sides, Jacobians, Newton iterations since the last reset."""
        return self._sim.stats()

    def __repr__(self):
        return (f"<mbd.Simulator {self._model.name!r} t={self.time:.6g} {self.formulation}/"
                f"{self.integrator}>")

    def _stepping(self, work):
        try:
            work()
        except DynamicsError as error:
            cause = self._sim.take_callback_error()
            if cause is None:
                raise
            raise error from cause


def _vector(values):
    return None if values is None else np.ascontiguousarray(values, dtype=float).ravel()
