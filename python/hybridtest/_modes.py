"""hybridtest.modes: `hybridtest modes` from Python (the same C++ implementation,
io::AnalyseModes), as objects with numpy arrays. Everything is SI."""
import os

import numpy as np

from ._core import modes as _core_modes


class Mode:
    """One mode: eigenvalue λ [1/s] (complex), frequency_hz = |λ|/2π, damped_frequency_hz =
    |Im λ|/2π, damping_ratio = −Re λ/|λ|, shape (complex numpy array over the independent
    states, its largest read coordinate 1), label (the model file's `modes.labels` name, or
    ""), dominant (the read coordinates with |shape| ≥ ½), unstable (Re λ > 0 beyond
    rounding)."""

    __slots__ = ("eigenvalue", "frequency_hz", "damped_frequency_hz", "damping_ratio", "shape",
                 "label", "dominant", "unstable")

    def __init__(self, d):
        self.label = d["label"]
        self.dominant = list(d["dominant"])
        self.unstable = bool(d["unstable"])
        self.eigenvalue = complex(d["eigenvalue"])
        self.frequency_hz = d["frequency_hz"]
        self.damped_frequency_hz = d["damped_frequency_hz"]
        self.damping_ratio = d["damping_ratio"]
        self.shape = np.asarray(d["shape"], dtype=complex)

    def __repr__(self):
        return (f"<hybridtest.Mode λ = {self.eigenvalue:.6g} 1/s, f_n = "
                f"{self.frequency_hz:.6g} Hz, ζ = {self.damping_ratio:.4g}>")


class SteadyState:
    """The steady state found before linearising: coordinates (names) and their values [SI],
    iterations (Gauss–Newton steps), residual = max |u̇| at it (unit residual_unit, the rate
    of speed residual_speed, the largest), converged (always True: one that is not found
    raises ModelError), driven (the speeds a drive held)."""

    def __init__(self, d):
        self.coordinates = list(d["coordinates"])
        self.values = np.asarray(d["values"], dtype=float)
        self.iterations = d["iterations"]
        self.residual = d["residual"]
        self.residual_speed = d["residual_speed"]
        self.residual_unit = d["residual_unit"]
        self.converged = d["converged"]
        self.driven = list(d["driven"])

    def __repr__(self):
        found = ", ".join(f"{n} = {v:.12g}" for n, v in zip(self.coordinates, self.values))
        return (f"<hybridtest.SteadyState {found} in {self.iterations} iterations, residual "
                f"{self.residual:.3g} {self.residual_unit}>")


class ModeAnalysis:
    """The result of hybridtest.modes: model (name), time [s], start (the operating point
    asked for, before assembly), x (the operating point used: steady, assembled; 2n + nz),
    states (names of the independent states), A (state matrix in them), modes (list of Mode,
    by ascending |λ|), eigenvalues (complex numpy array, the modes' order), steady
    (SteadyState or None), equilibrium (False when max |u̇| at x, `residual`, exceeds 1e-8:
    then the modes are of the instantaneous linearisation only; pass steady=)."""

    def __init__(self, d):
        self.model = d["model"]
        self.time = d["time"]
        self.start = np.asarray(d["start"], dtype=float)
        self.x = np.asarray(d["x"], dtype=float)
        self.states = list(d["states"])
        self.A = np.asarray(d["A"], dtype=float)
        self.modes = [Mode(m) for m in d["modes"]]
        self.steady = SteadyState(d["steady"]) if d["steady"] is not None else None
        self.equilibrium = bool(d["equilibrium"])
        self.residual = d["residual"]

    @property
    def eigenvalues(self):
        return np.array([m.eigenvalue for m in self.modes], dtype=complex)

    def __repr__(self):
        return (f"<hybridtest.ModeAnalysis {self.model}: {len(self.states)} independent "
                f"states, {len(self.modes)} modes>")


def _names(value):
    """A list of names from None, "a,b" or an iterable of names."""
    if value is None:
        return []
    if isinstance(value, str):
        return [s.strip() for s in value.split(",") if s.strip()]
    return [str(s) for s in value]


def modes(path, *, at=None, set=None, time=0.0, steady=None, driven=None, tolerance=1e-10,
          max_iterations=50):
    """Linearises a model file or run config about an operating point, through its
    constraints, as `hybridtest modes` does, and returns a ModeAnalysis.

    at: {"q": [...], "u": [...]} replaces the start's coordinates and/or speeds (n values
    each, SI; the dependent ones are solved). set: {parameter: SI value} overrides. time: t
    [s]. steady: coordinate names (a list, or "q1,q3") solved first for u̇ = 0 with the other
    coordinates and the independent speeds held; driven: speeds a drive holds at their values
    (a motor at its set speed; unconstrained models), whose rates need not vanish; tolerance
    on max |u̇| in the speed rates' units, max_iterations of Gauss–Newton. Raises ConfigError
    for bad input and ModelError for an operating point the model cannot take or a steady
    state that is not found (the message names the residual, the largest speed rate and what
    to try).
    """
    if at is not None:
        at = {key: [float(v) for v in np.ravel(values)] for key, values in dict(at).items()}
    if set is not None:
        set = {str(key): float(value) for key, value in dict(set).items()}
    return ModeAnalysis(_core_modes(os.fspath(path), at, set, float(time), _names(steady),
                                    _names(driven), float(tolerance), int(max_iterations)))
