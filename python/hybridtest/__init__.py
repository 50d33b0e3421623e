"""hybridtest from Python: Kane-method models, simulations and hybrid tests as numpy arrays.

    import numpy as np, hybridtest as ht
    m = ht.Model.from_file("examples/models/rotor.yaml")
    M = m.mass_matrix(0.0, np.zeros(m.num_states))
    sim = ht.simulate("examples/rotor/numerical.yaml")        # in memory; out= writes files
    lin = ht.modes("examples/models/whipple_bicycle.yaml", set={"v": 5.0})  # eigenvalues, A
    run = ht.run("examples/rotor/remote.yaml", transfers={"r1": MyBench()}, out="run.csv")

Every quantity is SI. Errors are hybridtest.Error and its subclasses ConfigError, ModelError,
TransferError, IoError and SafetyStop, with the C++ library's messages. docs/python.md has the
whole API.
"""
import enum
import os
import sys
import sysconfig
from collections.abc import Mapping

from . import _build_info


def _import_error(problem):
    """An ImportError that names the interpreter the module was built for and this one."""
    return ImportError(
        f"{problem}: hybridtest's module was built for {_build_info.INTERPRETER} (Python "
        f"{_build_info.VERSION}, {_build_info.SOABI}); this is {sys.executable} (Python "
        f"{sys.version.split()[0]}, {sysconfig.get_config_var('SOABI')}). Run it with that "
        "interpreter, or rebuild for this one: cmake -S . -B build/release "
        "-DPython3_EXECUTABLE=$(command -v python3) (docs/python.md, \"Which interpreter\")")


# numpy: the interpreter's own, else the one found at build time for the same ABI tag (Debian's
# python3-numpy for a pyenv python3 of Debian's minor version), searched after every other path.
try:
    import numpy  # noqa: F401
except ImportError:
    if not _build_info.NUMPY_PATH or sysconfig.get_config_var("SOABI") != _build_info.SOABI:
        raise _import_error("hybridtest needs numpy, and this interpreter has none") from None
    sys.path.append(_build_info.NUMPY_PATH)
    try:
        import numpy  # noqa: F401
    except ImportError as e:
        raise _import_error(f"numpy from {_build_info.NUMPY_PATH} did not load ({e})") from None

try:
    from . import _core  # noqa: F401
except ImportError as e:
    raise _import_error(f"the module hybridtest._core did not load ({e})") from None

from ._core import (  # noqa: F401
    ConfigError,
    Error,
    IoError,
    Model,
    ModelError,
    SafetyStop,
    TransferError,
    __version__,
    time_transfer,
)
from ._core import Session as _CoreSession
from ._modes import Mode, ModeAnalysis, SteadyState, modes  # noqa: F401
from ._core import read_run as _read_run

__all__ = [
    "ConfigError", "Error", "IoError", "Mode", "ModeAnalysis", "Model", "ModelError", "Result",
    "SafetyStop", "Session", "Status", "SteadyState", "TransferError", "modes", "read_run",
    "resume", "run", "simulate",
]


class Status(str, enum.Enum):
    """A session's status: WORKING (a step was committed, more to go), FINISHED, HELD (stopped
    on request: resumable) or STOPPED (a failure: step() and run() raise it instead). Equal to
    its name in lower case ("finished"), as the command line prints it."""

    WORKING = "working"
    FINISHED = "finished"
    HELD = "held"
    STOPPED = "stopped"

    def __str__(self):
        return self.value


class Result(Mapping):
    """A run's channels as a mapping of channel name → numpy array (rows,), SI.

    len(result), iteration, `in` and indexing all speak of channels: len(result) is the number
    of channels, `for name in result` gives their names in column order, result["q1"] one
    column. num_rows is the number of rows; values: (rows × channels); units and descriptions:
    by name; metadata: the sidecar (a run read from files) or None; statistics: the run's
    statistics (its sidecar's, for a run read from files) or None.
    """

    def __init__(self, values, channels, metadata=None, warnings=(), statistics=None):
        self.values = values
        self.channels = [c[0] for c in channels]
        self.units = {c[0]: c[1] for c in channels}
        self.descriptions = {c[0]: c[2] for c in channels}
        self.metadata = metadata
        self.warnings = list(warnings)
        self.statistics = statistics
        self._column = {name: j for j, name in enumerate(self.channels)}

    def __getitem__(self, name):
        if not isinstance(name, str):
            raise KeyError(f"{name!r}: a Result is indexed by channel name (result['q1']); "
                           "rows are result.values[i]")
        try:
            return self.values[:, self._column[name]]
        except KeyError:
            raise KeyError(f"no channel {name!r} in this run; its channels are: "
                           f"{', '.join(self.channels)}") from None

    def __contains__(self, name):
        return name in self._column

    def __iter__(self):
        return iter(self.channels)

    def __len__(self):
        return len(self.channels)

    @property
    def num_rows(self):
        """The number of rows (committed points) of the run."""
        return self.values.shape[0]

    def keys(self):
        return list(self.channels)

    def to_dataframe(self):
        """A pandas DataFrame (one column per channel; units in df.attrs["units"])."""
        try:
            import pandas
        except ImportError as e:
            raise ImportError("to_dataframe() needs pandas (Debian: python3-pandas)") from e
        df = pandas.DataFrame(self.values, columns=self.channels)
        df.attrs["units"] = dict(self.units)
        return df

    def __repr__(self):
        return f"<hybridtest.Result {self.num_rows} rows × {len(self.channels)} channels>"


def _settings(changes):
    """{key: value} or ["KEY=VALUE", ...] as the command line's --set strings."""
    if changes is None:
        return []
    if isinstance(changes, dict):
        return [f"{key}={float(value)!r}" for key, value in changes.items()]
    return [str(c) for c in changes]


class Session(_CoreSession):
    """A run stepped from Python: initialize(), step(), run() return a Status and raise the
    typed error (SafetyStop, TransferError, ...) of a run that stopped on a failure;
    add_observer(), result(), Session.resume(csv, ...)."""

    @classmethod
    def resume(cls, csv_path, *, transfers=None, laws=None, changes=None,
               after_safety_stop=False, force_tolerance=None, position_tolerance=None):
        """The session that continues the run written at csv_path (see hybridtest.resume)."""
        return cls(transfers=dict(transfers or {}), laws=dict(laws or {}),
                   resume=os.fspath(csv_path), after_safety_stop=after_safety_stop,
                   force_tolerance=force_tolerance, position_tolerance=position_tolerance,
                   set=_settings(changes))

    def _checked(self, status):
        status = Status(status)
        if status is Status.STOPPED:
            self.raise_error()
            raise Error(f"the run stopped: {self.reason}")
        return status

    def initialize(self):
        """Starts the run (r_0 tried at x_0); returns its Status, raises a failure."""
        return self._checked(super().initialize())

    def step(self):
        """One committed step; returns the Status, raises a failure."""
        return self._checked(super().step())

    def run(self):
        """Steps until the run is no longer working; returns the Status, raises a failure."""
        return self._checked(super().run())

    @property
    def status(self):
        return Status(super().status)

    def result(self):
        """The rows recorded so far as a Result (a view once the run has ended)."""
        return Result(self.values, self.channels)


def _finish(session):
    """session.run(); a failure's exception carries every committed row (.result)."""
    try:
        status = session.run()
    except Error as e:
        result = session.result()
        result.values = result.values.copy()  # outlives the session
        e.result = result  # every committed row, as the journal keeps them
        raise
    if status is not Status.FINISHED:
        result = session.result()
        result.values = result.values.copy()
        try:
            session.raise_error()
        except Error as e:
            e.result = result
            raise
        raise Error(f"the run ended {status}: {session.reason}")
    return status


def _execute(config, command, transfers, laws, out, overwrite, observers, clock=None):
    out = None if out is None else os.fspath(out)
    with Session(config, transfers=dict(transfers or {}), laws=dict(laws or {}), out=out,
                 overwrite=overwrite, command=command, clock=clock) as session:
        for observer in observers:
            session.add_observer(observer)
        _finish(session)
        result = session.result()
        result.values = result.values.copy()  # outlives the session
        result.statistics = session.statistics
        return result


def simulate(config, *, laws=None, out=None, overwrite=False, observers=()):
    """A numerical simulation of `config` (a run-config path or a dict with the same keys).

    laws: {slot: callable r = law(d)} replaces slots' numerical laws. out: also write the
    journal and its sidecar there (never replacing a run unless overwrite). Returns a Result.
    """
    return _execute(config, "simulate", None, laws, out, overwrite, observers)


def run(config, *, transfers=None, laws=None, out=None, overwrite=False, observers=(),
        clock=None):
    """A hybrid test of `config`; transfers: {slot: bench driver} serves physical slots.

    A bench driver has activate(), execute(command) -> (position, force[, lab_time]), hold()
    and deactivate(), in SI unless it has units = ("mm", "kN"). Raises the error that stopped
    the run (its .result holds every committed row). Returns a Result.

    A config with `real_time:` is paced as on the command line, on its real_time.clock or
    clock ("virtual" or "wall", as `hybridtest run --clock`).
    """
    return _execute(config, "run", transfers, laws, out, overwrite, observers, clock)


def resume(csv_path, *, transfers=None, laws=None, changes=None, after_safety_stop=False,
           force_tolerance=None, position_tolerance=None, observers=()):
    """Continues the run written at csv_path from its last committed step, as
    `hybridtest resume` does: the run's own config (its sidecar's copy), its run state, the
    bench brought back to the last committed command and checked.

    transfers/laws: Python drivers and laws in place of configured slots (a Python driver
    the run used is not recorded: give it again). changes: {key: value} changes of a safety
    limit, a timeout or a resume tolerance (SI), recorded in the sidecar's resume record as
    --set is. after_safety_stop: the operator found and fixed the cause of a safety stop.
    force_tolerance [N], position_tolerance [m]: the re-imposition check's tolerances.
    Returns the whole run (its journal, read back) as a Result; raises the error that stopped
    it again (its .result holds the rows of this resume).
    """
    csv_path = os.fspath(csv_path)
    with Session.resume(csv_path, transfers=transfers, laws=laws, changes=changes,
                        after_safety_stop=after_safety_stop, force_tolerance=force_tolerance,
                        position_tolerance=position_tolerance) as session:
        for observer in observers:
            session.add_observer(observer)
        _finish(session)
        notes = list(session.notes)
        statistics = session.statistics
    result = read_run(csv_path)
    result.warnings = notes + result.warnings
    result.statistics = statistics
    return result


def read_run(csv_path):
    """A run written to files (journal or stage record) with its sidecar, as a Result."""
    data = _read_run(os.fspath(csv_path))
    metadata = data["metadata"]
    statistics = metadata.get("statistics") if isinstance(metadata, dict) else None
    return Result(data["values"], data["channels"], metadata, data["warnings"], statistics)
