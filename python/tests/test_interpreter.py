"""The README's Python line with every interpreter that can run the module: the one it was built
for (the python3 first on PATH at configure time: pyenv's on a pyenv machine), Debian's
/usr/bin/python3 and the python3 first on PATH now, when they share its ABI tag; and the error
that another interpreter gets."""
import os
import pathlib
import shutil
import subprocess
import sys
import sysconfig

import pytest

import hybridtest
from hybridtest import _build_info

README_LINE = ("import hybridtest as ht; "
               "print(repr(float(ht.simulate('examples/rotor/numerical.yaml')['q1'][-1])))")
PACKAGE_PARENT = pathlib.Path(hybridtest.__file__).resolve().parents[1]


def soabi(python):
    out = subprocess.run([python, "-c", "import sysconfig; print(sysconfig.get_config_var('SOABI'))"],
                         capture_output=True, text=True, timeout=60)
    return out.stdout.strip() if out.returncode == 0 else None


def interpreters():
    """Every distinct interpreter (by real path) that shares the module's ABI tag."""
    found = {}
    for python in [_build_info.INTERPRETER, "/usr/bin/python3", shutil.which("python3"),
                   sys.executable]:
        if python and os.path.exists(python):
            real = os.path.realpath(python)
            if real not in found and soabi(python) == _build_info.SOABI:
                found[real] = python
    return list(found.values())


def readme_line(python, root, package_parent=PACKAGE_PARENT):
    env = dict(os.environ, PYTHONPATH=str(package_parent), PYTHONDONTWRITEBYTECODE="1")
    return subprocess.run([python, "-c", README_LINE], cwd=root, env=env, capture_output=True,
                          text=True, timeout=300)


def test_the_build_records_the_interpreter_it_was_built_for():
    assert os.path.isabs(_build_info.INTERPRETER) and os.path.exists(_build_info.INTERPRETER)
    assert _build_info.SOABI == soabi(_build_info.INTERPRETER)
    # This interpreter runs the module, so it shares the ABI tag.
    assert sysconfig.get_config_var("SOABI") == _build_info.SOABI


def test_the_readme_line_gives_one_answer_with_every_interpreter_of_the_modules_abi(root):
    pythons = interpreters()
    assert _build_info.INTERPRETER in pythons or os.path.realpath(_build_info.INTERPRETER) in [
        os.path.realpath(p) for p in pythons]
    answers = {}
    for python in pythons:
        out = readme_line(python, root)
        assert out.returncode == 0, f"{python}: {out.stderr}"
        answers[python] = float(out.stdout.strip())
    # The same build, the same numbers, whichever interpreter drives it.
    assert len(set(answers.values())) == 1, answers
    assert abs(next(iter(answers.values()))) > 0


def test_an_interpreter_of_another_abi_is_told_which_one_the_module_is_for(root, tmp_path):
    # A copy of the package whose record names another ABI tag and interpreter: what a Python of
    # another minor version sees (its import of _core finds no module of its own tag).
    copy = tmp_path / "hybridtest"
    shutil.copytree(PACKAGE_PARENT / "hybridtest", copy,
                    ignore=shutil.ignore_patterns("_core*", "__pycache__"))
    info = copy / "_build_info.py"
    text = info.read_text()
    text = text.replace(f'SOABI = "{_build_info.SOABI}"', 'SOABI = "cpython-399-x86_64-linux-gnu"')
    text = text.replace(f'INTERPRETER = "{_build_info.INTERPRETER}"',
                        'INTERPRETER = "/opt/python3.99/bin/python3"')
    info.write_text(text)
    out = readme_line(sys.executable, root, tmp_path)
    assert out.returncode != 0
    assert "built for /opt/python3.99/bin/python3" in out.stderr
    assert sys.executable in out.stderr
    assert "-DPython3_EXECUTABLE" in out.stderr


def test_an_interpreter_without_numpy_uses_the_numpy_found_at_build_time(root, tmp_path):
    # Debian's interpreter without its site directories (-S) has no numpy, as a fresh pyenv
    # python3 has none: with NUMPY_PATH the README line still runs; without, the error says why.
    if subprocess.run([sys.executable, "-S", "-c", "import numpy"],
                      capture_output=True).returncode == 0:
        pytest.skip("numpy is importable without site directories here")
    copy = tmp_path / "hybridtest"
    shutil.copytree(PACKAGE_PARENT / "hybridtest", copy,
                    ignore=shutil.ignore_patterns("__pycache__"))
    numpy_dir = str(pathlib.Path(__import__("numpy").__file__).resolve().parents[1])
    info = copy / "_build_info.py"
    lines = [ln for ln in info.read_text().splitlines() if not ln.startswith("NUMPY_PATH")]
    env = dict(os.environ, PYTHONPATH=str(tmp_path), PYTHONDONTWRITEBYTECODE="1")
    for numpy_path, works in [(numpy_dir, True), ("", False)]:
        info.write_text("\n".join(lines + [f'NUMPY_PATH = "{numpy_path}"']) + "\n")
        out = subprocess.run([sys.executable, "-S", "-c", README_LINE], cwd=root, env=env,
                             capture_output=True, text=True, timeout=300)
        if works:
            assert out.returncode == 0, out.stderr
            assert float(out.stdout) == float(readme_line(sys.executable, root).stdout)
        else:
            assert out.returncode != 0
            assert "hybridtest needs numpy, and this interpreter has none" in out.stderr
