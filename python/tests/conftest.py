"""Shared fixtures: the repository root, the command line beside the package, SymPy's rotor."""
import os
import pathlib
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "examples/python"))


@pytest.fixture
def root():
    return ROOT


@pytest.fixture
def cli():
    """The hybridtest binary of the build tree the package comes from (skips without it)."""
    import hybridtest
    build = pathlib.Path(hybridtest.__file__).resolve().parents[2]
    path = build / "apps/hybridtest/hybridtest"
    if not path.exists():
        pytest.skip(f"no command line at {path}: build the target hybridtest")
    return str(path)


@pytest.fixture
def in_tmp(tmp_path, monkeypatch):
    """A temporary working directory whose examples/ is the repository's."""
    (tmp_path / "examples").symlink_to(ROOT / "examples")
    monkeypatch.chdir(tmp_path)
    return tmp_path


def pythonpath_env():
    env = dict(os.environ)
    import hybridtest
    env["PYTHONPATH"] = str(pathlib.Path(hybridtest.__file__).resolve().parents[1])
    return env
