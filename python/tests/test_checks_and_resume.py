"""The library's checks before moving refuse a Python run as they refuse the command line's,
before the Python bench is touched; a Python run stopped by its bench is resumed from Python
as `hybridtest resume` does, and ends as an uninterrupted run."""
import json
import subprocess

import numpy as np
import pytest

import hybridtest as ht
from conftest import ROOT

LIMITS = {"stroke_min": -0.15, "stroke_max": 0.15, "max_increment": 0.005,
          "force_soft": 8000, "force_hard": 10000, "timeout": 5}


class Spring:
    """An ideal bench in SI that records every call; raises on execute number `fail_at`."""

    def __init__(self, k=7200.0, p0=None, fail_at=None):
        self.k, self.fail_at, self.calls = k, fail_at, []
        if p0 is not None:
            self.p0 = p0  # announced: the run checks setup.p0 against it

    def activate(self):
        self.calls.append("activate")

    def execute(self, command):
        self.calls.append("execute")
        if self.fail_at is not None and self.calls.count("execute") >= self.fail_at:
            raise ConnectionError("the bench stopped answering")
        return command, self.k * (command - 0.02)

    def hold(self):
        self.calls.append("hold")

    def deactivate(self):
        self.calls.append("deactivate")


def write_config(path, dt=0.001, duration=1.0, r2=None):
    """A run config (JSON is YAML): the rotor, blade 1 behind a loopback bench (p0 = 0.02 m)."""
    subs = {"r1": {"type": "physical",
                   "transfer": {"type": "loopback",
                                "law": {"type": "linear", "stiffness": 7200}},
                   "setup": {"p0": 0.02}, "safety": LIMITS}}
    if r2 is not None:
        subs["r2"] = r2
    config = {"model": {"name": "rotor", "blades": 3},
              "integrator": {"tableau": "heun", "dt": dt}, "duration": duration,
              "substructures": subs}
    path.write_text(json.dumps(config, indent=2) + "\n")
    return str(path)


def cli_refusal(cli, config, out):
    p = subprocess.run([cli, "run", config, "--out", str(out), "--quiet"], capture_output=True,
                       text=True)
    assert p.returncode == 2, p.stderr
    prefix = "hybridtest: configuration error: "
    assert p.stderr.startswith(prefix), p.stderr
    return p.stderr[len(prefix):].strip()


def test_an_unstable_step_is_refused_as_the_command_line_refuses_it(cli, tmp_path):
    config = write_config(tmp_path / "unstable.yaml", dt=0.004, duration=0.2)
    expected = cli_refusal(cli, config, tmp_path / "cli.csv")
    assert "is beyond the stability limit of heun" in expected
    bench = Spring()
    with pytest.raises(ht.ConfigError) as e:
        ht.run(config, transfers={"r1": bench}, out=tmp_path / "py.csv")
    assert str(e.value) == expected
    assert bench.calls == []  # not activated, no command
    assert not (tmp_path / "py.csv").exists()
    with pytest.raises(ht.ConfigError) as e:  # in memory too, and through a Session
        ht.Session(config, transfers={"r1": bench})
    assert str(e.value) == expected and bench.calls == []


def test_a_p0_the_bench_disagrees_with_is_refused_as_the_command_line_refuses_it(cli, tmp_path):
    # Blade 2 on the emulated ideal bench (p0_mm: 20) with setup.p0 = 0.03 m.
    r2 = {"type": "physical",
          "transfer": {"type": "emulated", "config": str(ROOT / "examples/rotor/bench-ideal.yaml")},
          "setup": {"p0": 0.03}, "safety": LIMITS}
    config = write_config(tmp_path / "p0.yaml", r2=r2)
    expected = cli_refusal(cli, config, tmp_path / "cli.csv")
    assert expected.startswith("substructures.r2.setup.p0 = 0.03 m, but ")
    bench = Spring()
    with pytest.raises(ht.ConfigError) as e:
        ht.run(config, transfers={"r1": bench})
    assert str(e.value) == expected
    assert bench.calls == []


def test_a_python_driver_announces_its_p0(tmp_path):
    config = write_config(tmp_path / "run.yaml", duration=0.05)
    far = Spring(p0=0.03)
    with pytest.raises(ht.ConfigError, match=r"substructures\.r1\.setup\.p0 = 0\.02 m, but the "
                                             r"Python transfer system of r1 announces p0 = 0\.03"):
        ht.run(config, transfers={"r1": far})
    assert far.calls == []
    close = Spring(p0=0.0201)  # within a tenth of max_increment
    assert ht.run(config, transfers={"r1": close}).num_rows == 51
    assert close.calls.count("execute") > 0
    with pytest.raises(ht.ConfigError, match="p0 = 'x'"):
        ht.run(config, transfers={"r1": Spring(p0="x")})


def test_a_stopped_python_run_is_resumed_from_python(tmp_path):
    config = write_config(tmp_path / "run.yaml", duration=1.0)
    reference = ht.run(config, transfers={"r1": Spring()}, out=tmp_path / "reference.csv")
    csv = tmp_path / "run.csv"
    failing = Spring(fail_at=700)
    with pytest.raises(ht.TransferError, match="the bench stopped answering") as e:
        ht.run(config, transfers={"r1": failing}, out=csv)
    assert failing.calls[-1] == "hold"
    committed = ht.read_run(csv)
    assert 100 < committed.num_rows < reference.num_rows  # committed rows kept (+ the uncommitted one)
    assert committed.metadata["status"] != "completed"

    with pytest.raises(ht.ConfigError, match="nothing to resume"):
        ht.resume(tmp_path / "reference.csv", transfers={"r1": Spring()})
    good = Spring()
    resumed = ht.resume(csv, transfers={"r1": good},
                        changes={"substructures.r1.safety.force_soft": 8500})
    assert good.calls[0] == "activate" and good.calls[-1] == "deactivate"
    assert resumed.channels == reference.channels
    assert resumed.values.shape == reference.values.shape
    # Every channel but the bench's lab time equals the uninterrupted run, bit for bit, as
    # the command line's resume tests require of an ideal bench.
    for name in reference.channels:
        if name != "r1_lab_time":
            np.testing.assert_array_equal(resumed[name], reference[name], err_msg=name)
    sidecar = resumed.metadata
    assert sidecar["status"] == "completed"
    record = sidecar["resumes"][0]
    assert record["changes"] == [{"key": "substructures.r1.safety.force_soft", "from": 8000.0,
                                  "to": 8500.0}]
    assert record["previous_stop"]["kind"] == "transfer" and record["step"] == 349
    assert record["command_line"].startswith("python: hybridtest.resume")


def test_resume_refuses_what_the_command_line_refuses(tmp_path):
    with pytest.raises(ht.ConfigError, match="no such journal"):
        ht.resume(tmp_path / "none.csv")
    config = write_config(tmp_path / "run.yaml", duration=0.2)
    csv = tmp_path / "run.csv"
    with pytest.raises(ht.TransferError):
        ht.run(config, transfers={"r1": Spring(fail_at=50)}, out=csv)
    with pytest.raises(ht.ConfigError, match="unknown key 'resume.bogus'"):
        ht.resume(csv, transfers={"r1": Spring()}, changes={"resume.bogus": 1.0})
    with pytest.raises(ht.ConfigError, match="no config"):
        ht.Session(str(csv), resume=str(csv))


@pytest.mark.parametrize("example, ticks, actuators", [
    ("examples/real-time/storey-ats.yaml", 10240, 1),
    # Issue 46: the blade on two servo-hydraulic actuators, ATS on each.
    ("examples/06_blade_two_actuators/real-time.yaml", 10240, 2),
])
def test_a_real_time_run_from_python_is_the_command_lines_bit_for_bit(cli, tmp_path, example,
                                                                       ticks, actuators):
    """The Session paces a `real_time:` config from Python as from the command line (one loop,
    Session::Run, on the virtual clock): the same journal, byte for byte."""
    config = str(ROOT / example)
    a, b = tmp_path / "cli.csv", tmp_path / "py.csv"
    p = subprocess.run([cli, "run", config, "--clock", "virtual", "--out", str(a), "--quiet"],
                       capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    result = ht.run(config, clock="virtual", out=b)
    assert len(result.values) == ticks + 1
    assert a.read_bytes() == b.read_bytes()
    for csv in (a, b):
        rt = json.loads(csv.with_suffix(".meta.json").read_text())["statistics"]["real_time"]
        assert rt["clock"] == "virtual" and rt["ticks"] == ticks and rt["misses"] == 0
        assert len(rt["actuators"]) == actuators


def test_python_real_time_refusals_name_the_way_on(tmp_path):
    """A clock without `real_time:`, and step() on a paced run, are refused with the fix."""
    with pytest.raises(ht.ConfigError, match=r"no `real_time:` block"):
        ht.run(write_config(tmp_path / "plain.yaml", duration=0.01), clock="virtual",
               transfers={"r1": Spring()})
    with ht.Session(str(ROOT / "examples/real-time/storey-ats.yaml"), clock="virtual") as s:
        s.initialize()
        with pytest.raises(ht.ConfigError, match=r"call run\(\)"):
            s.step()