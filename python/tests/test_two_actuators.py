"""A Python bench driver for a specimen on several actuators (issue 38, item 4): numpy arrays of
commands, positions and forces in the driver's units, its own p0 per actuator, named exchanges,
and a driver's exception as the cause of the error that ends the run."""
import numpy as np
import pytest

import hybridtest as ht
from conftest import ROOT

BLADE = str(ROOT / "examples/06_blade_two_actuators/emulated.yaml")
STIFFNESS = np.array([[5000.0, 1200.0], [1200.0, 3000.0]])  # bench-2act.yaml, actuator axes [N/m]
P0_MM = np.array([20.0, 30.0])  # bench-2act.yaml p0_mm


class IdealTwoActuatorBench:
    """bench-2act.yaml's ideal bench, spoken in mm and kN: each actuator reaches its command, the
    specimen pushes back with F = K (a − p0)."""

    units = ("mm", "kN")
    p0 = [20.0, 30.0]  # [mm]
    actuators = 2

    def __init__(self, fail_at=None):
        self.calls = []
        self.commands = []
        self.fail_at = fail_at

    def activate(self):
        self.calls.append("activate")

    def execute(self, commands):
        assert isinstance(commands, np.ndarray) and commands.shape == (2,)
        self.commands.append(commands.copy())
        if self.fail_at is not None and len(self.commands) == self.fail_at:
            raise OSError("load cell 2: no signal")
        forces_n = STIFFNESS @ ((commands - P0_MM) / 1000.0)
        return commands, forces_n / 1000.0

    def hold(self):
        self.calls.append("hold")

    def deactivate(self):
        self.calls.append("deactivate")


def test_a_python_driver_of_two_actuators_equals_the_emulated_bench():
    # In memory (no out=): 20,001 synced journal rows each would only cost time here.
    emulated = ht.run(BLADE)
    bench = IdealTwoActuatorBench()
    driven = ht.run(BLADE, transfers={"blade1": bench})
    assert driven.num_rows == emulated.num_rows == 10001
    assert bench.calls[0] == "activate" and bench.calls[-1] == "deactivate"
    # The driver received millimetres: the first command is p0.
    np.testing.assert_allclose(bench.commands[0], P0_MM, rtol=0, atol=1e-9)
    compared = 0
    for name in emulated:
        if name.startswith(("q", "u", "r_", "blade1_")) and not name.endswith("lab_time"):
            np.testing.assert_allclose(driven[name], emulated[name], rtol=0, atol=1e-12,
                                       err_msg=name)
            compared += 1
    # q, u, both slots' forces and each actuator's command, position and force.
    assert compared >= 4 + 2 + 6, list(emulated)
    assert float(np.max(np.abs(emulated["blade1_a2_force"]))) > 1.0  # the blade moved


def test_a_driver_that_raises_ends_the_run_with_its_exception_as_the_cause(tmp_path):
    bench = IdealTwoActuatorBench(fail_at=301)
    out = tmp_path / "failed.csv"
    with pytest.raises(ht.TransferError, match=r"OSError: load cell 2: no signal") as raised:
        ht.run(BLADE, transfers={"blade1": bench}, out=out)
    cause = raised.value.__cause__
    assert isinstance(cause, OSError) and "no signal" in str(cause)
    assert cause.__traceback__ is not None  # where in the driver it was raised
    message = str(raised.value)
    # The command in the driver's unit (mm), and where every actuator holds in both units.
    assert "execute([" in message and "] mm)" in message and " mm)" in message.split("holds")[-1]
    assert "hold" in bench.calls  # the bench held
    # Every committed row is on disk: 150 Heun steps (two trials each) before the failure.
    journal = ht.read_run(out)
    committed = journal["t"][np.isfinite(journal["blade1_a1_force"])]
    assert committed.size >= 150 and abs(committed[-1] - 0.149) < 1e-12
    np.testing.assert_array_equal(raised.value.result["q_flap"][:150], journal["q_flap"][:150])


def test_each_trial_names_its_actuators_exchanges():
    trials = []
    session = ht.Session(BLADE, transfers={"blade1": IdealTwoActuatorBench()})
    session.add_observer(type("T", (), {"on_trial": lambda self, e: trials.append(
        (e.actuators, e.exchanges.copy()))})())
    for _ in range(3):
        session.step()
    session.close()
    names, exchanges = trials[-1]
    assert names == ("blade1_a1", "blade1_a2")
    assert exchanges.dtype.names == ("command", "position", "force", "lab_time")
    # SI: the commands are p0 + T d, about 0.02 m and 0.03 m.
    np.testing.assert_allclose(exchanges["command"], [0.02, 0.03], atol=1e-3)
    np.testing.assert_array_equal(exchanges["position"], exchanges["command"])


@pytest.mark.parametrize("attribute, value, expected", [
    ("actuators", 1, r"actuators = 1, but substructure blade1 is set up on 2 actuators"),
    ("p0", [20.0], r"p0 = \[20.0\]: expected a finite number \(or a list of 2, one per "
                   r"actuator\)"),
    ("p0", [20.0, 35.0], r"setup.p0\[2\] = 0.03 m, but the Python transfer system of blade1 "
                         r"announces p0 = 0.035 m .* for actuator 2"),
    ("following_error", [0.05, -1.0], r"following_error = \[0.05, -1.0\]: expected a positive"),
])
def test_a_driver_that_disagrees_with_the_setup_is_refused_before_it_is_activated(
        attribute, value, expected):
    bench = IdealTwoActuatorBench()
    setattr(bench, attribute, value)
    with pytest.raises(ht.ConfigError, match=expected):
        ht.run(BLADE, transfers={"blade1": bench})
    assert bench.calls == []


def test_a_reply_of_the_wrong_width_is_a_transfer_error_and_holds():
    class OneForceShort(IdealTwoActuatorBench):
        def execute(self, commands):
            positions, forces = super().execute(commands)
            return positions, forces[:1]

    bench = OneForceShort()
    with pytest.raises(ht.TransferError, match=r"returned 1 forces; expected 2, one per actuator"):
        ht.run(BLADE, transfers={"blade1": bench})
    assert "hold" in bench.calls
