"""A Python bench driver that misbehaves: it re-enters its own Session, takes longer than
safety.timeout, is interrupted by Ctrl-C, or reports a position it did not reach. Each case ends
with a clear exception, hold() called, every committed row on disk and no duplicate row."""
import os
import signal
import threading
import time

import numpy as np
import pytest

import hybridtest as ht
from test_runs import NUMERICAL, Spring, physical_short


def check_journal(out, session_rows=None):
    """The journal on disk: strictly increasing time (no duplicate row); its committed rows
    equal the session's record."""
    saved = ht.read_run(out)
    t = saved["t"]
    assert len(t) > 1 and np.all(np.diff(t) > 0), "a duplicate or reordered row"
    assert saved.metadata["status"] != "completed"
    if session_rows is not None:
        np.testing.assert_array_equal(saved.values, session_rows)
    return saved


class Reentering(Spring):
    """Calls `call(session)` from inside execute() at move `at`."""

    def __init__(self, call, at=41, swallow=False):
        super().__init__()
        self.call, self.at, self.swallow = call, at, swallow
        self.moves = 0
        self.session = None
        self.refused = None

    def execute(self, command):
        self.moves += 1
        if self.moves == self.at:
            try:
                self.call(self.session)
            except ht.Error as e:
                self.refused = e
                if not self.swallow:
                    raise
        return super().execute(command)


@pytest.mark.parametrize("name,call", [("close", lambda s: s.close()),
                                       ("step", lambda s: s.step()),
                                       ("run", lambda s: s.run())])
def test_a_session_call_from_inside_execute_is_refused_and_holds(tmp_path, name, call):
    bench = Reentering(call)
    out = tmp_path / f"{name}.csv"
    s = ht.Session(physical_short(), transfers={"r1": bench}, out=str(out))
    bench.session = s
    with pytest.raises(ht.Error, match=rf"Session\.{name}\(\) called from inside the bench "
                                       r"driver's execute\(.* m\) of slot r1") as caught:
        s.run()
    assert not isinstance(caught.value, ht.TransferError)
    assert "every committed row is kept" in str(caught.value)
    assert bench.calls == ["activate", "hold"]
    assert isinstance(bench.refused, ht.Error)
    assert s.status == "stopped"
    rows = s.values.copy()
    s.close()
    saved = check_journal(out, rows)
    # Heun: 41 moves are row 0 and steps 1..20; step 20's trial failed: 20 committed rows and
    # step 20 without forces.
    assert saved.num_rows == 21 and np.isnan(saved["r1"][-1]) and not np.isnan(saved["r1"][-2])


def test_a_refused_reentry_that_the_driver_swallows_still_stops_the_run(tmp_path):
    bench = Reentering(lambda s: s.step(), swallow=True)
    out = tmp_path / "swallowed.csv"
    with ht.Session(physical_short(), transfers={"r1": bench}, out=str(out)) as s:
        bench.session = s
        with pytest.raises(ht.Error, match=r"Session\.step\(\) called from inside"):
            s.run()
        assert s.status == "held"  # the step in progress committed, then the run held
        assert bench.calls == ["activate", "hold"]
        rows = s.values.copy()
    saved = check_journal(out, rows)
    assert saved.num_rows == 21 and not np.isnan(saved["r1"][-1])


def test_an_execute_beyond_safety_timeout_stops_the_run(tmp_path):
    class Slow(Spring):
        moves = 0

        def execute(self, command):
            self.moves += 1
            if self.moves == 11:
                time.sleep(1.0)
            return super().execute(command)

    bench = Slow()
    out = tmp_path / "slow.csv"
    with pytest.raises(ht.TransferError, match=r"execute\(.* m\) did not return within the "
                                               r"slot's safety\.timeout 0\.4 s") as caught:
        ht.run(physical_short(timeout=0.4), transfers={"r1": bench}, out=out)
    assert "substructures.r1.safety.timeout" in str(caught.value)
    assert bench.calls == ["activate", "hold"]
    saved = check_journal(out, caught.value.result.values)
    assert saved.num_rows == 6  # moves 1..10: row 0 and steps 1..5 committed, step 5 without forces


class StuckUntilHold(Spring):
    """At move `at`, execute() does not return until hold() is called (bounded: `seconds`),
    after calling `before()`; `released_by_hold` says whether hold() released it."""

    def __init__(self, at, seconds, before=lambda: None):
        super().__init__()
        self.at, self.seconds, self.before = at, seconds, before
        self.moves = 0
        self.held = threading.Event()
        self.released_by_hold = None

    def execute(self, command):
        self.moves += 1
        if self.moves == self.at:
            self.before()
            self.released_by_hold = self.held.wait(self.seconds)
        return super().execute(command)

    def hold(self):
        super().hold()
        self.held.set()


def test_an_execute_that_does_not_return_is_abandoned_at_safety_timeout_and_the_bench_holds(
        tmp_path):
    """Issue 45: the run does not wait for an execute() past safety.timeout. The call is left
    running (a Python thread cannot be killed), the run raises, and hold() is called while
    execute() is still inside: this driver's execute() returns only once hold() was called."""
    bench = StuckUntilHold(at=11, seconds=20)
    out = tmp_path / "stuck.csv"
    with pytest.raises(ht.TransferError, match=r"execute\(.* m\) did not return within the "
                                               r"slot's safety\.timeout 0\.5 s") as caught:
        ht.run(physical_short(timeout=0.5), transfers={"r1": bench}, out=out)
    message = str(caught.value)
    assert "substructures.r1.safety.timeout" in message and "hold() is called" in message
    for _ in range(2000):  # bounded: the abandoned call returns once hold() was called
        if bench.released_by_hold is not None:
            break
        time.sleep(0.01)
    assert bench.released_by_hold is True  # the bench was told to hold while execute() ran
    assert bench.calls[:2] == ["activate", "hold"]
    saved = check_journal(out, caught.value.result.values)
    assert saved.num_rows == 6  # moves 1..10: row 0 and steps 1..5 committed


def test_ctrl_c_inside_a_driver_that_never_returns_is_a_keyboard_interrupt(tmp_path):
    # bounded: the test fails, not hangs, if Ctrl-C is lost; the call, left running by the
    # interrupted run, returns once hold() was called
    bench = StuckUntilHold(at=31, seconds=30, before=lambda: threading.Timer(
        0.3, os.kill, (os.getpid(), signal.SIGINT)).start())
    out = tmp_path / "stuck.csv"
    s = ht.Session(physical_short(), transfers={"r1": bench}, out=str(out))
    started = time.monotonic()
    with pytest.raises(KeyboardInterrupt):
        s.run()
    assert time.monotonic() - started < 25
    assert bench.calls == ["activate", "hold"]
    assert s.status == "held"
    assert "KeyboardInterrupt inside the Python transfer system's execute(" in s.reason
    rows = s.values.copy()
    s.close()
    saved = check_journal(out, rows)
    assert saved.num_rows == 16 and np.isnan(saved["r1"][-1])


@pytest.mark.parametrize("lie", [0.050, 0.0015])  # [m]: +50 mm, +1.5 mm
def test_a_position_lie_is_a_following_error(tmp_path, lie):
    class Liar(Spring):
        moves = 0

        def execute(self, command):
            self.moves += 1
            position = command + (lie if self.moves >= 21 else 0.0)
            return position, self.k * (command - self.p0)

    bench = Liar()
    out = tmp_path / "liar.csv"
    with pytest.raises(ht.SafetyStop) as caught:
        ht.run(physical_short(), transfers={"r1": bench}, out=out)
    e = caught.value
    assert e.limit == "following_error"
    assert e.value == pytest.approx(lie)
    assert e.limit_value == pytest.approx(0.0002)  # four settling windows of 0.05 mm
    assert "The Python transfer system of slot r1 answered execute(" in str(e)
    assert bench.calls == ["activate", "hold"]
    check_journal(out, e.result.values)


def test_a_settled_driver_passes_and_its_own_limits_are_read():
    class Settled(Spring):
        """Settles within 0.03 mm of every command (SI)."""
        moves = 0

        def execute(self, command):
            self.moves += 1
            return command + (0.00003 if self.moves % 2 else -0.00003), \
                self.k * (command - self.p0)

    assert ht.run(physical_short(), transfers={"r1": Settled()}).num_rows == 1001

    class Loose(Spring):
        units = ("mm", "N")
        settle_tolerance = 0.5  # mm: following error 2 mm (4 windows), capped at 5 mm

        def __init__(self):
            super().__init__(p0=20.0)

        def execute(self, command):
            return command + 1.0, self.k * 1e-3 * (command - self.p0)

    assert ht.run(physical_short(), transfers={"r1": Loose()}).num_rows == 1001

    class Wrong(Settled):
        following_error = -1.0

    with pytest.raises(ht.ConfigError, match="following_error = -1.0: expected a positive"):
        ht.run(physical_short(), transfers={"r1": Wrong()})


def test_a_driver_whose_reading_freezes_is_stopped():
    class Frozen(Spring):
        moves = 0
        frozen = None

        def execute(self, command):
            self.moves += 1
            if self.moves == 20:
                self.frozen = super().execute(command)
            return self.frozen if self.moves >= 20 else super().execute(command)

    # The command walks away from the frozen reading: a stale reply as soon as one command
    # moves by more than two settling windows, else a following error once it is 0.2 mm off.
    bench = Frozen()
    with pytest.raises(ht.SafetyStop) as caught:
        ht.run(physical_short(), transfers={"r1": bench})
    assert caught.value.limit in ("stale_acknowledgement", "following_error")
    assert bench.calls == ["activate", "hold"]


def test_ctrl_c_inside_a_python_law_is_a_keyboard_interrupt(tmp_path):
    calls = []

    def law(d):
        calls.append(d)
        if len(calls) == 21:
            raise KeyboardInterrupt
        return 7200.0 * d

    out = tmp_path / "law.csv"
    s = ht.Session(NUMERICAL, laws={"r2": law}, command="simulate", out=str(out))
    with pytest.raises(KeyboardInterrupt):
        s.run()
    assert s.status == "held"
    assert "KeyboardInterrupt inside the Python law of slot r2" in s.reason
    rows = s.values.copy()
    s.close()
    saved = check_journal(out, rows)
    assert 1 < saved.num_rows <= 21


def test_ctrl_c_inside_a_python_observer_is_a_keyboard_interrupt(tmp_path):
    def watcher(c):
        if c.step == 10:
            raise KeyboardInterrupt

    out = tmp_path / "observer.csv"
    s = ht.Session(physical_short(), transfers={"r1": Spring()}, out=str(out))
    s.add_observer(watcher)
    with pytest.raises(KeyboardInterrupt):
        s.run()
    assert s.status == "held"
    assert "KeyboardInterrupt inside a Python observer's" in s.reason
    rows = s.values.copy()
    s.close()
    saved = check_journal(out, rows)
    assert saved.num_rows >= 11 and saved["t"][10] == pytest.approx(0.010)


class LeftAt(Spring):
    """A driver that can read where its actuator is (read()), left at `at` [m] by a run."""

    def __init__(self, at):
        super().__init__()
        self.at, self.moves = at, []

    def read(self):
        return self.at, self.k * (self.at - self.p0)

    def execute(self, command):
        self.moves.append(command)
        self.at = command
        return super().execute(command)


def test_a_driver_left_off_p0_is_refused_before_it_moves_or_ramped_with_start_ramp():
    # The start check (docs/safety.md): the driver's read() is compared with the first command.
    bench = LeftAt(0.031)
    with pytest.raises(ht.SafetyStop, match=r"the actuator is at 0\.031 m.*p0 = 0\.02 m.*start: "
                                            r"ramp"):
        ht.run(physical_short(), transfers={"r1": bench})
    assert bench.moves == []
    ramped = LeftAt(0.031)
    ht.run(physical_short() | {"start": "ramp"}, transfers={"r1": ramped})
    steps = np.abs(np.diff([0.031] + ramped.moves))
    assert ramped.moves[2] == pytest.approx(0.02) and np.all(steps < 0.005)
