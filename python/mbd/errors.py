"""The exceptions of mbd. Each carries the message the ``mbd`` command prints after
``mbd: error:`` for the same failure, and the parts of it a program needs (file, line, key,
time, joints)."""

import re


class Error(Exception):
    """Every error of mbd."""


class InputError(Error, ValueError):
    """Input to fix: a scene, an option of a run, an output path.

    ``where`` is what the message starts with (``file:line``, or the option), or None."""

    def __init__(self, message, where=None):
        super().__init__(message)
        self.where = where


class PlacedError(InputError):
    """An input error at a place of a scene: ``file`` (for Model.from_dict its label),
    ``line`` (None when there is none: a dict has no lines) and ``key``, the path of the key
    at fault in the syntax of Model.with_params (``bodies.crank.mass``), or None."""

    def __init__(self, message, file=None, line=None, key=None):
        super().__init__(message, where=file if line is None else f"{file}:{line}")
        self.file = file
        self.line = line
        self.key = key


class SceneError(PlacedError):
    """A scene that cannot be read or built, or a key path that does not resolve."""


class PluginError(PlacedError):
    """A plugin that cannot serve: an unknown type, one built for another plugin ABI, a
    library that does not load, a plugin folder that does not exist. ``file``, ``line`` and
    ``key`` say where a scene asked for it (None when no scene did)."""


class OutputError(InputError):
    """A result file that cannot be written (a missing folder, a full disk)."""


class KinematicsError(Error):
    """A configuration that cannot be assembled; the message names the worst-violated joint
    or driver."""


def _named(kind, message):
    names = []
    for name in re.findall(kind + r" '([^']+)'", message):
        if name not in names:
            names.append(name)
    return names


class LinearisationError(Error):
    """The equations of motion cannot be linearised about the reference state (Model.modes):
    the scene has no freedom (its drivers or joints fix every coordinate), or the reference is
    not at rest or in steady motion; the message says which and what to do."""


class DynamicsError(Error):
    """A run that cannot go on. ``time`` is when it stopped (None when the failure has no
    time); ``joints`` and ``drivers`` are the elements the message names (the constraint
    rows involved in a singular configuration, say), in the order named."""

    def __init__(self, message, time=None):
        super().__init__(message)
        self.time = time
        self.joints = _named("joint", message)
        self.drivers = _named("driver", message)


class StaticsError(Error):
    """No static equilibrium found. ``result`` is the solver's report (a StaticsResult with
    converged False)."""

    def __init__(self, message, result=None):
        super().__init__(message)
        self.result = result
