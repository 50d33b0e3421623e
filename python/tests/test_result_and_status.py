"""A Result is a mapping of channel → array whose len, iteration, `in` and indexing agree; a
run read back has its sidecar's statistics; a Session's statuses are a Status enum and a
failure raises its typed error from step() and run(); Session.resume is a classmethod and no
argument of resume() shadows a builtin (issue 38, item 4)."""
import inspect
import json

import numpy as np
import pytest

import hybridtest as ht
from test_checks_and_resume import Spring, write_config
from test_runs import SHORT, physical_short


def test_a_result_is_a_mapping_of_channels():
    result = ht.simulate(SHORT | {"duration": 0.05})
    names = list(result)
    assert names == result.channels and len(result) == len(names) == result.values.shape[1]
    assert all(name in result for name in names) and "q1" in result and 0 not in result
    assert dict(result.items()).keys() == set(names)
    for j, name in enumerate(names):
        np.testing.assert_array_equal(result[name], result.values[:, j])
    assert result.num_rows == 51 == result.values.shape[0]
    with pytest.raises(KeyError, match=r"indexed by channel name .* rows are result\.values"):
        result[0]
    with pytest.raises(KeyError, match="no channel 'nope' in this run; its channels are: t, "):
        result["nope"]


def test_a_run_read_back_has_its_sidecars_statistics(tmp_path):
    out = tmp_path / "run.csv"
    written = ht.run(write_config(tmp_path / "run.yaml", duration=0.05),
                     transfers={"r1": Spring()}, out=out)
    read = ht.read_run(out)
    sidecar = json.loads((tmp_path / "run.meta.json").read_text())
    assert read.statistics == sidecar["statistics"]
    assert read.statistics["rows"] == read.num_rows == written.num_rows == 51
    assert read.statistics["physical_evaluations"] == written.statistics["physical_evaluations"]


def test_statuses_are_an_enum_and_a_failure_raises_from_step_and_run():
    assert ht.Status.FINISHED == "finished" and str(ht.Status.HELD) == "held"
    s = ht.Session(SHORT | {"duration": 0.02}, command="simulate")
    assert s.initialize() is ht.Status.WORKING
    assert s.step() is ht.Status.WORKING
    assert s.run() is ht.Status.FINISHED and s.status is ht.Status.FINISHED
    # A force limit the loopback's spring passes at once: a safety stop, raised by step().
    s = ht.Session(physical_short(force_soft=100.0, force_hard=200.0))
    with pytest.raises(ht.SafetyStop, match="force_soft violated"):
        for _ in range(1000):
            s.step()  # the first call initializes
    assert s.status is ht.Status.STOPPED
    s.close()
    with pytest.raises(ht.SafetyStop):
        ht.Session(physical_short(force_soft=100.0, force_hard=200.0)).run()


def test_session_resume_is_a_classmethod_and_no_argument_shadows_a_builtin(tmp_path):
    config = write_config(tmp_path / "run.yaml", duration=0.2)
    csv = tmp_path / "run.csv"
    with pytest.raises(ht.TransferError) as failed:
        ht.run(config, transfers={"r1": Spring(fail_at=100)}, out=csv)
    assert failed.value.result.num_rows > 1
    with ht.Session.resume(csv, transfers={"r1": Spring()}) as s:
        assert s.run() is ht.Status.FINISHED
    assert ht.read_run(csv).num_rows == 201
    builtins = set(dir(__import__("builtins")))
    for function in (ht.run, ht.simulate, ht.resume, ht.read_run, ht.Session.resume):
        shadowing = set(inspect.signature(function).parameters) & builtins
        assert not shadowing, f"{function.__name__} has {shadowing}"
