"""hybridtest from Python: Kane-method models, simulations and hybrid tests as numpy arrays.

    import numpy as np, hybridtest as ht
    m = ht.Model.from_file("examples/models/rotor.yaml")
    M = m.mass_matrix(0.0, np.zeros(m.num_states))
    sim = ht.simulate("examples/rotor/numerical.yaml")        # in memory; out= writes files
    run = ht.run("examples/rotor/remote.yaml", transfers={"r1": MyBench()}, out="run.csv")

Every quantity is SI. Errors are hybridtest.Error and its subclasses ConfigError, ModelError,
TransferError, IoError and SafetyStop, with the C++ library's messages. docs/python.md has the
whole API.
"""
import os

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
from ._core import read_run as _read_run

__all__ = [
    "ConfigError", "Error", "IoError", "Model", "ModelError", "Result", "SafetyStop", "Session",
    "TransferError", "read_run", "resume", "run", "simulate",
]


class Result:
    """A run's channels as numpy arrays: result["q1"] is one column (rows,), SI.

    values: (rows × channels); channels: names in column order; units and descriptions: by
    name; metadata: the sidecar (a run read from files) or None.
    """

    def __init__(self, values, channels, metadata=None, warnings=()):
        self.values = values
        self.channels = [c[0] for c in channels]
        self.units = {c[0]: c[1] for c in channels}
        self.descriptions = {c[0]: c[2] for c in channels}
        self.metadata = metadata
        self.warnings = list(warnings)
        self._column = {name: j for j, name in enumerate(self.channels)}

    def __getitem__(self, name):
        try:
            return self.values[:, self._column[name]]
        except KeyError:
            raise KeyError(f"no channel {name!r} in this run; its channels are: "
                           f"{', '.join(self.channels)}") from None

    def __contains__(self, name):
        return name in self._column

    def __len__(self):
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
        return f"<hybridtest.Result {len(self)} rows × {len(self.channels)} channels>"


class Session(_CoreSession):
    """A run stepped from Python: initialize(), step(), run(), add_observer(), result()."""

    def result(self):
        """The rows recorded so far as a Result (a view once the run has ended)."""
        return Result(self.values, self.channels)


def _execute(config, command, transfers, laws, out, overwrite, observers):
    out = None if out is None else os.fspath(out)
    with Session(config, transfers=dict(transfers or {}), laws=dict(laws or {}), out=out,
                 overwrite=overwrite, command=command) as session:
        for observer in observers:
            session.add_observer(observer)
        status = session.run()
        result = session.result()
        result.values = result.values.copy()  # outlives the session
        result.statistics = session.statistics
        if status != "finished":
            try:
                session.raise_error()
            except Error as e:
                e.result = result  # every committed row, as the journal keeps them
                raise
            raise Error(f"the run ended {status}: {session.reason}")
        return result


def simulate(config, *, laws=None, out=None, overwrite=False, observers=()):
    """A numerical simulation of `config` (a run-config path or a dict with the same keys).

    laws: {slot: callable r = law(d)} replaces slots' numerical laws. out: also write the
    journal and its sidecar there (never replacing a run unless overwrite). Returns a Result.
    """
    return _execute(config, "simulate", None, laws, out, overwrite, observers)


def run(config, *, transfers=None, laws=None, out=None, overwrite=False, observers=()):
    """A hybrid test of `config`; transfers: {slot: bench driver} serves physical slots.

    A bench driver has activate(), execute(command) -> (position, force[, lab_time]), hold()
    and deactivate(), in SI unless it has units = ("mm", "kN"). Raises the error that stopped
    the run (its .result holds every committed row). Returns a Result.
    """
    return _execute(config, "run", transfers, laws, out, overwrite, observers)


def _settings(changes):
    """{key: value} or ["KEY=VALUE", ...] as the command line's --set strings."""
    if changes is None:
        return []
    if isinstance(changes, dict):
        return [f"{key}={float(value)!r}" for key, value in changes.items()]
    return [str(c) for c in changes]


def resume(csv_path, *, transfers=None, laws=None, set=None, after_safety_stop=False,
           force_tolerance=None, position_tolerance=None, observers=()):
    """Continues the run written at csv_path from its last committed step, as
    `hybridtest resume` does: the run's own config (its sidecar's copy), its run state, the
    bench brought back to the last committed command and checked.

    transfers/laws: Python drivers and laws in place of configured slots (a Python driver
    the run used is not recorded: give it again). set: {key: value} changes of a safety
    limit, a timeout or a resume tolerance (SI), recorded in the sidecar's resume record as
    --set is. after_safety_stop: the operator found and fixed the cause of a safety stop.
    force_tolerance [N], position_tolerance [m]: the re-imposition check's tolerances.
    Returns the whole run (its journal, read back) as a Result; raises the error that stopped
    it again (its .result holds the rows of this resume).
    """
    csv_path = os.fspath(csv_path)
    with Session(transfers=dict(transfers or {}), laws=dict(laws or {}), resume=csv_path,
                 after_safety_stop=after_safety_stop, force_tolerance=force_tolerance,
                 position_tolerance=position_tolerance, set=_settings(set)) as session:
        for observer in observers:
            session.add_observer(observer)
        status = session.run()
        if status != "finished":
            result = session.result()
            result.values = result.values.copy()
            try:
                session.raise_error()
            except Error as e:
                e.result = result
                raise
            raise Error(f"the run ended {status}: {session.reason}")
        notes = list(session.notes)
        statistics = session.statistics
    result = read_run(csv_path)
    result.warnings = notes + result.warnings
    result.statistics = statistics
    return result


def read_run(csv_path):
    """A run written to files (journal or stage record) with its sidecar, as a Result."""
    data = _read_run(str(csv_path))
    return Result(data["values"], data["channels"], data["metadata"], data["warnings"])
