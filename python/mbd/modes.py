"""The modes of a model (Model.modes): the report of ``mbd modes --json`` as a Python object."""

import collections

import numpy as np

Mode = collections.namedtuple("Mode", "kind eigenvalue natural_frequency damped_frequency damping_ratio shape joint_shape")
Mode.__doc__ = ("One mode: kind ('oscillatory', 'real' or 'free_velocity'), the eigenvalue (complex; of a pair the "
                "one with Im > 0), natural and damped frequency (rad/s), damping ratio, and the shape in the "
                "independent and in the joint coordinates (complex arrays, max |.| = 1).")


def _read_only(array):
    array.flags.writeable = False
    return array


def _complex(pairs):
    return _read_only(np.array([complex(re, im) for re, im in pairs], dtype=complex))


def _matrix(rows, columns):
    values = [[np.nan if x is None else x for x in row] for row in rows]
    return _read_only(np.array(values, dtype=float).reshape(len(rows), columns))


class ModesResult:
    """The equations of motion linearised about the reference state, as ``mbd modes --json``
    reports them (docs/user-guide.md, "Modes"): ``about``, ``residual``, ``coordinates``,
    ``velocity_coordinates``, ``joint_coordinates``, ``states``, ``inputs``, ``modes`` (a
    list of Mode, ascending natural frequency), ``ignorable`` (the cyclic coordinates, named),
    ``A`` (states x states) and ``B`` (states x inputs) as arrays; ``eigenvalues``,
    ``natural_frequencies`` and ``damping_ratios`` of the modes as arrays. ``to_dict()`` gives
    the JSON object itself."""

    def __init__(self, report):
        self._report = report
        for key in ("about", "residual", "coordinates", "velocity_coordinates", "joint_coordinates", "states",
                    "inputs", "ignorable"):
            setattr(self, key, report[key])
        self.modes = [Mode(m["kind"], complex(*m["eigenvalue"]), m["natural_frequency"], m["damped_frequency"],
                           m["damping_ratio"], _complex(m["shape"]), _complex(m["joint_shape"]))
                      for m in report["modes"]]
        states = len(report["states"])
        self.A = _matrix(report["A"], states)
        self.B = _matrix(report["B"], len(report["inputs"]))
        self.eigenvalues = _read_only(np.array([m.eigenvalue for m in self.modes], dtype=complex))
        self.natural_frequencies = _read_only(np.array([m.natural_frequency for m in self.modes], dtype=float))
        self.damping_ratios = _read_only(np.array([m.damping_ratio for m in self.modes], dtype=float))

    def to_dict(self):
        return self._report

    def __repr__(self):
        shown = ", ".join(f"{w:.6g}" for w in self.natural_frequencies[:6])
        more = ", ..." if len(self.modes) > 6 else ""
        return f"<ModesResult about {self.about}: {len(self.modes)} modes, omega_n = [{shown}{more}] rad/s>"
