"""Simulations and runs from Python against the command line's own output, and the parts of
a run that Python supplies: transfer systems, laws, observers."""
import json
import subprocess

import numpy as np
import pytest

import hybridtest as ht
from conftest import ROOT

NUMERICAL = str(ROOT / "examples/rotor/numerical.yaml")
REMOTE = str(ROOT / "examples/rotor/remote.yaml")
SHORT = {"model": {"name": "rotor", "blades": 3},
         "integrator": {"tableau": "heun", "dt": 0.001}, "duration": 1.0}


class Spring:
    """An ideal bench in SI: force = k (command − p0)."""

    def __init__(self, k=7200.0, p0=0.02):
        self.k, self.p0 = k, p0
        self.calls = []

    def activate(self):
        self.calls.append("activate")

    def execute(self, command):
        return command, self.k * (command - self.p0)

    def hold(self):
        self.calls.append("hold")

    def deactivate(self):
        self.calls.append("deactivate")


def physical_short(**safety):
    limits = {"stroke_min": -0.15, "stroke_max": 0.15, "max_increment": 0.005,
              "force_soft": 8000, "force_hard": 10000, "timeout": 5} | safety
    return SHORT | {"substructures": {"r1": {
        "type": "physical", "transfer": {"type": "loopback", "law": {"type": "linear",
                                                                     "stiffness": 7200}},
        "setup": {"p0": 0.02}, "safety": limits}}}


@pytest.fixture(scope="module")
def sim():
    return ht.simulate(NUMERICAL)


def test_simulate_equals_the_command_line(sim, cli, tmp_path):
    csv = tmp_path / "cli.csv"
    subprocess.run([cli, "simulate", NUMERICAL, "--out", str(csv)], check=True,
                   capture_output=True)
    ref = ht.read_run(csv)
    assert ref.channels == sim.channels and ref.values.shape == sim.values.shape
    # The journal prints 17 significant digits: the same doubles.
    np.testing.assert_array_equal(ref.values, sim.values)
    assert ref.units["q4"] == "rad" and sim.units["q4"] == "rad"


def test_a_dict_config_is_the_same_run_as_its_file(sim):
    with open(NUMERICAL) as f:
        import yaml
        config = yaml.safe_load(f)
    np.testing.assert_array_equal(ht.simulate(config).values, sim.values)


def test_python_transfer_reproduces_the_simulation_in_bench_units(sim):
    class MillimetreBench(Spring):
        units = ("mm", "kN")

        def execute(self, command):
            return command, self.k * 1e-6 * (command - self.p0)

    bench = MillimetreBench(7200.0, 20.0)
    run = ht.run(REMOTE, transfers={"r1": bench})
    assert np.max(np.abs(run["q1"] - sim["q1"])) < 1e-9
    np.testing.assert_allclose(run["r1_command"], 0.02 + run["q1"], atol=1e-12)
    assert bench.calls == ["activate", "deactivate"]


def test_a_python_law_is_a_numerical_substructure(sim):
    run = ht.simulate(NUMERICAL, laws={"r2": lambda d: 7200.0 * d})
    np.testing.assert_array_equal(run.values, sim.values)
    stiff = ht.simulate(NUMERICAL, laws={"r2": lambda d: 9000.0 * d})
    assert np.max(np.abs(stiff["q2"] - sim["q2"])) > 1e-4


def test_an_exception_in_execute_is_a_transfer_error_and_holds(tmp_path):
    class Failing(Spring):
        def __init__(self):
            super().__init__()
            self.moves = 0

        def execute(self, command):
            self.moves += 1
            if self.moves == 101:
                raise ConnectionError("lost the ADS route")
            return super().execute(command)

    bench = Failing()
    out = tmp_path / "failing.csv"
    with pytest.raises(ht.TransferError, match="lost the ADS route") as caught:
        ht.run(REMOTE, transfers={"r1": bench}, out=out)
    assert "ConnectionError" in str(caught.value) and str(caught.value).startswith("r1: ")
    assert bench.calls == ["activate", "hold"]
    # Heun: trial 1 is row 0, then two a step; the 101st is the one at the end of step 50. Rows
    # 0..49 are committed, then the state of step 50 without its forces; the file says the same.
    result = caught.value.result
    assert result.num_rows == 51 and np.isnan(result["r1"][-1]) and not np.isnan(result["r1"][-2])
    assert result["t"][-1] == pytest.approx(0.050)
    saved = ht.read_run(out)
    np.testing.assert_array_equal(saved.values[:50], result.values[:50])
    assert saved.metadata["status"].startswith("stopped")
    assert (tmp_path / "failing.state.json").exists()


def test_a_force_beyond_force_hard_is_a_safety_stop():
    class Overloaded(Spring):
        def execute(self, command):
            return command, 20000.0

    with pytest.raises(ht.SafetyStop) as caught:
        ht.run(REMOTE, transfers={"r1": Overloaded()})
    assert caught.value.limit == "force_hard" and caught.value.value == 20000.0


def test_a_bad_reply_is_a_transfer_error():
    class Mute(Spring):
        def execute(self, command):
            return None

    with pytest.raises(ht.TransferError, match=r"not \(position, force"):
        ht.run(REMOTE, transfers={"r1": Mute()})


def test_bad_transfers_and_units_are_config_errors():
    with pytest.raises(ht.ConfigError, match="slot r2 is numerical"):
        ht.run(REMOTE, transfers={"r2": Spring()})
    with pytest.raises(ht.ConfigError, match="no such slot; its slots are: r1, r2, r3"):
        ht.run(REMOTE, transfers={"r7": Spring()})

    class Inches(Spring):
        units = ("in", "N")

    with pytest.raises(ht.ConfigError, match='units length "in"'):
        ht.run(REMOTE, transfers={"r1": Inches()})
    with pytest.raises(ht.ConfigError, match="hold"):
        ht.run(REMOTE, transfers={"r1": object()})
    with pytest.raises(ht.ConfigError, match="dt"):
        ht.simulate(SHORT | {"integrator": {"tableau": "heun", "dt": -1.0}})


def test_observers_see_every_committed_row_as_views():
    rows, stops = [], []

    class Watcher:
        def on_commit(self, c):
            assert not c.x.flags.writeable
            rows.append((c.step, c.t, c.x.copy(), c.r.copy(), c.row.copy()))

        def on_stop(self, status, reason):
            stops.append(status)

    trials = []
    result = ht.run(physical_short(), observers=[Watcher(), lambda c: None],
                    transfers={"r1": Spring()})
    s = ht.Session(physical_short())
    s.add_observer(type("T", (), {"on_trial": lambda self, e: trials.append(e.exchanges.copy())})())
    assert s.run() == "finished"
    assert len(rows) == result.num_rows == 1001 and stops == ["finished"]
    np.testing.assert_array_equal(np.array([r[4] for r in rows]), result.values)
    np.testing.assert_array_equal(rows[-1][2], result.values[-1, 1:9])
    assert len(trials) == 2 * 1000 + 1 and trials[0].shape == (1,)
    assert trials[0]["command"][0] == 0.02 and trials[0]["force"][0] == 144.0


def test_an_observer_exception_stops_the_run():
    def broken(c):
        if c.step == 10:
            raise ValueError("disk full")

    with pytest.raises(ht.Error, match="ValueError: disk full"):
        ht.simulate(SHORT, observers=[broken])


def test_stepping_and_stopping_a_session():
    s = ht.Session(SHORT, command="simulate")
    assert s.initialize() == "working" and s.t == 0.0
    for _ in range(10):
        assert s.step() == "working"
    assert s.t == pytest.approx(0.010)
    s.request_stop()
    assert s.step() == "held"
    assert s.result().num_rows == 12
    np.testing.assert_array_equal(s.x, s.result().values[-1, 1:9])


def test_out_writes_the_command_lines_files_and_never_replaces_them(tmp_path):
    out = tmp_path / "sim.csv"
    first = ht.simulate(NUMERICAL, out=out)
    np.testing.assert_array_equal(ht.read_run(out).values, first.values)
    meta = json.loads((tmp_path / "sim.meta.json").read_text())
    assert meta["status"] == "completed"
    with pytest.raises(ht.ConfigError, match="sim.csv"):
        ht.simulate(NUMERICAL, out=out)
    ht.simulate(NUMERICAL, out=out, overwrite=True)


def test_result_channels_units_and_dataframe(sim):
    assert sim.channels[:5] == ["t", "q1", "q2", "q3", "q4"] and sim.units["r1"] == "N"
    with pytest.raises(KeyError, match="its channels are"):
        sim["nope"]
    try:
        import pandas  # noqa: F401
    except ImportError:
        with pytest.raises(ImportError, match="pandas"):
            sim.to_dataframe()
    else:
        assert list(sim.to_dataframe().columns) == sim.channels


def test_cost_of_a_python_transfer_evaluation_is_measured():
    timing = ht.time_transfer(Spring(), n=2000)
    assert timing["python_seconds"] > 0 and timing["cpp_seconds"] > 0


def test_ctrl_c_holds_the_run_after_the_step_in_progress():
    import os
    import signal
    import threading

    s = ht.Session(SHORT | {"duration": 500.0}, command="simulate")
    threading.Timer(0.3, os.kill, (os.getpid(), signal.SIGINT)).start()
    with pytest.raises(KeyboardInterrupt):
        s.run()
    assert s.status == "held"
    assert 1 < s.result().num_rows < 500001
    np.testing.assert_array_equal(s.x, s.result().values[-1, 1:9])
