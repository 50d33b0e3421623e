"""The package's contract script and the numbered examples, run as a user runs them."""
import pathlib
import subprocess
import sys

import pytest

from conftest import ROOT, pythonpath_env


def run_script(path, cwd):
    return subprocess.run([sys.executable, str(path)], cwd=cwd, env=pythonpath_env(),
                          capture_output=True, text=True, timeout=600)


def test_contract_script_passes(in_tmp):
    done = run_script(ROOT / "python/tests/contract.py", in_tmp)
    assert done.returncode == 0, done.stderr
    # It wrote the run as `hybridtest run` does: journal, sidecar, stage record, run state.
    for name in ["py.csv", "py.meta.json", "py.stages.csv", "py.state.json"]:
        assert (in_tmp / name).exists(), name


def test_contract_script_refuses_to_replace_a_run(in_tmp):
    (in_tmp / "py.csv").write_text("t\n0\n")
    again = run_script(ROOT / "python/tests/contract.py", in_tmp)
    assert again.returncode != 0
    assert "hybridtest.ConfigError" in again.stderr and "py.csv" in again.stderr


EXAMPLES = sorted((ROOT / "examples/python").glob("[0-9][0-9]_*.py"))


@pytest.mark.parametrize("example", EXAMPLES, ids=[p.name for p in EXAMPLES])
def test_example_runs_top_to_bottom(example, tmp_path):
    done = run_script(example, tmp_path)
    assert done.returncode == 0, done.stdout + done.stderr


def test_examples_are_numbered_from_one():
    assert [p.name[:2] for p in EXAMPLES] == [f"{i:02}" for i in range(1, len(EXAMPLES) + 1)]
