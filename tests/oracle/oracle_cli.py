"""Talking to `hybridtest eom` for the Kane oracle: configs out, JSON answers in.

Every failure of the binary (non-zero exit, timeout, output that is not the expected JSON
object, wrong shapes, non-finite numbers) raises CliFailure with a message that quotes what the
binary printed, so that a failing oracle run says why.
"""

import json
import os
import re
import subprocess

import numpy as np

TIMEOUT_S = 60


class CliFailure(Exception):
    """The binary did not give a well-formed answer."""


def write_config(workdir, filename, model, overrides):
    """Writes a YAML run config for the model with the given parameter overrides."""
    lines = ['model:', f'  name: {model.name}']
    if model.num_blades:
        lines.append(f'  blades: {model.num_blades}')
    if overrides:
        lines.append('  parameters:')
        lines += [f'    {key}: {float(value)!r}' for key, value in sorted(overrides.items())]
    lines += ['integrator: {tableau: heun, dt: 0.001}', 'duration: 1.0', '']
    path = os.path.join(workdir, re.sub(r'[^\w.-]', '_', filename))
    with open(path, 'w', encoding='utf-8') as out:
        out.write('\n'.join(lines))
    return path


def _numbers(values):
    return ','.join(repr(float(v)) for v in values)


def eom_command(binary, config, t, x, r, with_restoring):
    # The '--opt=value' form keeps a leading minus sign from being read as an option.
    cmd = [binary, 'eom', config, f'--time={float(t)!r}', f'--state={_numbers(x)}']
    if with_restoring:
        cmd.append(f'--restoring={_numbers(r)}')
    cmd.append('--json')
    return cmd


def _run(cmd):
    try:
        return subprocess.run(cmd, capture_output=True, text=True, timeout=TIMEOUT_S,
                              check=False)
    except subprocess.TimeoutExpired as err:
        raise CliFailure(f'timed out after {TIMEOUT_S} s: {" ".join(cmd)}') from err
    except OSError as err:
        raise CliFailure(f'could not start {cmd[0]!r}: {err}') from err


def _array(answer, key, shape, cmd):
    if key not in answer:
        raise CliFailure(f'JSON answer has no key {key!r} (keys: {sorted(answer)}); '
                         f'command: {" ".join(cmd)}')
    try:
        value = np.array(answer[key], dtype=float)
    except (TypeError, ValueError) as err:
        raise CliFailure(f'{key!r} is not an array of numbers: {answer[key]!r}') from err
    if value.shape != shape:
        raise CliFailure(f'{key!r} has shape {value.shape}, expected {shape}: {answer[key]!r}')
    if not np.all(np.isfinite(value)):
        raise CliFailure(f'{key!r} has non-finite entries: {answer[key]!r}')
    return value


def run_eom(binary, config, t, x, r, n):
    """Runs `eom`; returns (mass_matrix (n x n), forcing (n,), xdot (2n,))."""
    cmd = eom_command(binary, config, t, x, r, with_restoring=len(r) > 0)
    proc = _run(cmd)
    if proc.returncode != 0:
        raise CliFailure(f'exit status {proc.returncode}; stderr: {proc.stderr.strip()!r}; '
                         f'command: {" ".join(cmd)}')
    try:
        answer = json.loads(proc.stdout)
    except json.JSONDecodeError as err:
        raise CliFailure(f'stdout is not JSON ({err}): {proc.stdout[:500]!r}; '
                         f'command: {" ".join(cmd)}') from err
    if not isinstance(answer, dict):
        raise CliFailure(f'stdout is JSON but not an object: {proc.stdout[:500]!r}')
    return (_array(answer, 'mass_matrix', (n, n), cmd), _array(answer, 'forcing', (n,), cmd),
            _array(answer, 'xdot', (2 * n,), cmd))


def expect_length_rejection(binary, config, length, expected, num_restoring):
    """Runs `eom` with a state of `length` entries and `num_restoring` restoring forces (none
    given if 0). Returns '' if the binary exits non-zero with a message naming `expected`, else
    a description of what went wrong."""
    x = [0.1] * length
    cmd = eom_command(binary, config, 0.0, x, [0.0] * num_restoring,
                      with_restoring=num_restoring > 0)
    try:
        proc = _run(cmd)
    except CliFailure as err:
        return str(err)
    text = proc.stdout + proc.stderr
    if proc.returncode == 0:
        return f'exit status 0 (expected non-zero); output: {text.strip()[:300]!r}'
    if not re.search(rf'(?<![\w.]){expected}(?![\w.])', text):
        return (f'exit status {proc.returncode}, but the message does not name the expected '
                f'length {expected}: {text.strip()[:300]!r}')
    return ''
