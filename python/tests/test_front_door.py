"""The front door (runner/open_run.h) from Python: the command line's checks and messages, and
nothing activated or written before they pass."""
import json
import shutil
import subprocess
import sys

import pytest

import hybridtest as ht
from conftest import ROOT, pythonpath_env

BLADE = str(ROOT / "examples/06_blade_two_actuators/emulated.yaml")
NUMERICAL = str(ROOT / "examples/rotor/numerical.yaml")


class Recording:
    """A bench driver that records every call (an ideal spring in SI)."""

    def __init__(self):
        self.calls = []

    def activate(self):
        self.calls.append("activate")

    def execute(self, command):
        self.calls.append("execute")
        return command, 7200.0 * (command - 0.02)

    def hold(self):
        self.calls.append("hold")

    def deactivate(self):
        self.calls.append("deactivate")


def test_a_one_actuator_driver_on_a_specimen_of_two_is_refused_before_the_bench_is_enabled():
    bench = Recording()
    bench.actuators = 1  # says so: refused before activate(), not at the first reply
    with pytest.raises(ht.ConfigError, match=r"blade1 is set up on 2 actuators"):
        ht.run(BLADE, transfers={"blade1": bench})
    assert bench.calls == []


@pytest.fixture
def lab(tmp_path):
    shutil.copytree(ROOT / "examples/05_turbine_lab", tmp_path / "lab")
    return tmp_path / "lab"


def test_an_output_onto_a_file_the_run_read_is_refused_with_the_command_lines_message(lab, cli):
    config = lab / "simulation.yaml"
    for name in ["simulation.yaml", "turbine.model.yaml", "cp.csv"]:
        target = lab / name
        before = target.read_bytes()
        with pytest.raises(ht.ConfigError) as raised:
            ht.simulate(str(config), out=str(target), overwrite=True)
        message = str(raised.value)
        assert "a file it reads" in message and name in message
        done = subprocess.run([cli, "simulate", str(config), "--out", str(target), "--overwrite"],
                              capture_output=True, text=True, check=False)
        assert done.returncode == 2
        assert message in done.stderr, done.stderr
        assert target.read_bytes() == before
        assert not (lab / (target.stem + ".lock")).exists()


def test_the_record_names_the_model_files_table(lab, tmp_path):
    config = {"model": {"file": str(lab / "turbine.model.yaml")},
              "initial_state": {"q": [0] * 6, "u": [0, 0, 11.2, 0, 0, 0]},
              "integrator": {"tableau": "rk4", "dt": 0.002}, "duration": 0.02}
    out = tmp_path / "t.csv"
    ht.simulate(config, out=str(out))
    meta = json.loads((tmp_path / "t.meta.json").read_text())
    roles = [(i["role"], i["path"]) for i in meta["extra"]["inputs"]]
    assert roles == [("model", "lab/turbine.model.yaml"), ("table", "lab/cp.csv")]
    assert meta["extra"]["provenance"]["command_line"] == "python: hybridtest.simulate(...)"


SMALL_DISK = """
import hybridtest as ht
class Recording:
    def __init__(self):
        self.calls = []
    def activate(self):
        self.calls.append("activate")
    def execute(self, command):
        self.calls.append("execute")
        return command, 0.0
    def hold(self):
        self.calls.append("hold")
    def deactivate(self):
        self.calls.append("deactivate")
bench = Recording()
config = {{"model": {{"name": "rotor", "blades": 3}},
          "integrator": {{"tableau": "heun", "dt": 0.001}}, "duration": 1.0,
          "substructures": {{"r1": {{"type": "physical",
              "transfer": {{"type": "remote", "address": "127.0.0.1:1"}},
              "setup": {{"p0": 0.02}}, "safety": "defaults"}}}}}}
try:
    ht.run(config, transfers={{"r1": bench}}, out={out!r})
    print("ran")
except ht.ConfigError as e:
    print(e)
print("calls:", bench.calls)
try:
    ht.simulate({numerical!r}, out={sim_out!r})
except ht.ConfigError as e:
    print("python:", e)
"""


def test_an_output_that_cannot_fit_is_refused_before_anything_moves(tmp_path, cli):
    """On an 8 MB tmpfs (less than the 64 MB a run keeps free), in a private mount namespace."""
    if shutil.which("unshare") is None or subprocess.run(
            ["unshare", "-rm", "true"], capture_output=True, check=False).returncode != 0:
        pytest.skip("no private mount namespace here (unshare -rm)")
    disk = tmp_path / "disk"
    disk.mkdir()
    script = tmp_path / "small_disk.py"
    script.write_text(SMALL_DISK.format(out=str(disk / "k.csv"), numerical=NUMERICAL,
                                        sim_out=str(disk / "s.csv")))
    shell = (f"mount -t tmpfs -o size=8m tmpfs '{disk}' && '{sys.executable}' '{script}' && "
             f"'{cli}' simulate '{NUMERICAL}' --out '{disk}/s.csv'; echo \"cli exit $?\"; "
             f"ls -A '{disk}'")
    done = subprocess.run(["unshare", "-rm", "/bin/sh", "-c", shell], capture_output=True,
                          text=True, check=False, env=pythonpath_env())
    output = done.stdout + done.stderr
    assert "k.csv: this run would write about" in output, output
    assert "calls: []" in output, output
    assert "cli exit 2" in output, output
    python_message = next(line for line in done.stdout.splitlines()
                          if line.startswith("python: "))[len("python: "):]
    assert "s.csv: this run would write about" in python_message
    assert python_message in done.stderr, output  # the command line's own words
    assert done.stdout.rstrip().endswith("cli exit 2"), output  # nothing left on the disk
