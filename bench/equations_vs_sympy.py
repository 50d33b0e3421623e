#!/usr/bin/python3
"""Times `hybridtest equations --format sympy` against SymPy's KanesMethod (issue 47).

    bench/equations_vs_sympy.py --binary build/release/apps/hybridtest/hybridtest
                                [--timeout 300] [--links 3,6,12] [--only NAME] [--repeat 3]

Run by hand (not part of the test suite). For every model file in examples/models/ and for
planar n-link pendulums (generated here: n point masses on massless links, each link with its
own mass m<i> and length l<i>; "on a base": the pivot rides a cart of mass m_c along n̂_y, one
more coordinate), it runs, each in a process of its own:

  * `hybridtest equations MODEL --format sympy` (printing the SymPy module), and
  * check-model's independent SymPy reader (apps/hybridtest/check_model_sympy.py: read the
    file, KanesMethod, lambdify, one state): SymPy's time to the same equations.

and prints one Markdown table: wall time and peak resident memory of each (os.wait4), and the
ratio. Each side runs --repeat times (default 3), the two alternating so that both see the same
machine, and the median wall time is shown (one run is at the mercy of a shared machine's
moment). A run over --timeout seconds is stopped and shown as "> T s". A constrained model's
`equations` prints its reduced equations too (issue 47 item 2); SymPy's side there is the
reader's tree (KanesMethod without the constraints).
"""
import argparse
import json
import os
import pathlib
import signal
import subprocess
import sys
import tempfile
import threading
import time

ROOT = pathlib.Path(__file__).resolve().parent.parent
READER = ROOT / 'apps' / 'hybridtest' / 'check_model_sympy.py'


def pendulum(n, base):
    """A planar n-link pendulum model file (text); `base`: its pivot on a cart."""
    lines = [f'name: pendulum{n}{"_base" if base else ""}',
             f'description: planar {n}-link pendulum{" on a cart" if base else ""} '
             '(bench/equations_vs_sympy.py)', 'parameters:',
             '  g: {value: 9.81, unit: m/s², description: gravity along n̂_x}']
    for i in range(1, n + 1):
        lines.append(f'  m{i}: {{value: {1 + 0.1 * i:.1f}, unit: kg, description: bob {i}}}')
        lines.append(f'  l{i}: {{value: {0.5 + 0.05 * i:.2f}, unit: m, description: link {i}}}')
    if base:
        lines.append('  m_c: {value: 2.5, unit: kg, description: cart}')
    lines.append('coordinates:')
    if base:
        lines.append('  - {name: s, unit: m, description: cart position along n̂_y}')
    for i in range(1, n + 1):
        lines.append(f'  - {{name: q{i}, unit: rad, description: angle of link {i}}}')
    lines.append('frames:')
    for i in range(1, n + 1):
        parent = 'N' if i == 1 else f'A{i - 1}'
        lines.append(f'  - {{name: A{i}, parent: {parent}, axis: z, angle: q{i}}}')
    lines.append('points:')
    pivot = 'O'
    if base:
        lines.append('  - {name: C, from: O, frame: N, position: [0, s, 0]}')
        pivot = 'C'
    for i in range(1, n + 1):
        lines.append(f'  - {{name: P{i}, from: {pivot}, frame: A{i}, position: [l{i}, 0, 0]}}')
        pivot = f'P{i}'
    lines.append('particles:')
    for i in range(1, n + 1):
        lines.append(f'  - {{name: bob{i}, point: P{i}, mass: m{i}}}')
    if base:
        lines.append('  - {name: cart, point: C, mass: m_c}')
    lines.append('forces:')
    for i in range(1, n + 1):
        lines.append(f'  - {{name: gravity {i}, point: P{i}, value: [m{i} * g, 0, 0]}}')
    if base:
        lines.append('  - {name: cart gravity, point: C, value: [m_c * g, 0, 0]}')
    return '\n'.join(lines) + '\n'


def measure_once(command, timeout):
    """(wall seconds, peak RSS in MiB, exit status, stderr tail) of one process. It is waited
    for (os.wait4, no polling interval in the time); a watchdog kills it at `timeout`."""
    err = tempfile.TemporaryFile()
    start = time.monotonic()
    p = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=err,
                         start_new_session=True)
    expired = threading.Event()

    def kill():
        expired.set()
        os.killpg(p.pid, signal.SIGKILL)

    watchdog = threading.Timer(timeout, kill)
    watchdog.start()
    _, status, usage = os.wait4(p.pid, 0)
    wall = time.monotonic() - start
    watchdog.cancel()
    if expired.is_set():
        return None, usage.ru_maxrss / 1024, -9, 'timeout'
    err.seek(0)
    tail = err.read().decode(errors='replace').strip().splitlines()[-1:] or ['']
    return wall, usage.ru_maxrss / 1024, os.waitstatus_to_exitcode(status), tail[0]


def median_of(runs):
    """The run with the median wall time (a timed-out run, if any, stands for all)."""
    for r in runs:
        if r[0] is None or r[2] != 0:
            return r
    ordered = sorted(runs, key=lambda r: r[0])
    middle = ordered[len(ordered) // 2]
    return middle[0], max(r[1] for r in runs), middle[2], middle[3]


def states_file(model, workdir):
    """One state (zeros, t = 0.3) for the reader, sized from its own parse."""
    import yaml
    doc = yaml.safe_load(pathlib.Path(model).read_text(encoding='utf-8'))
    n = len(doc['coordinates'])
    slots = len(doc.get('slots') or [])
    nz = len(doc.get('states') or {})
    path = pathlib.Path(workdir) / 'state.json'
    path.write_text(json.dumps([{'t': 0.3, 'q': [0.1] * n, 'u': [0.2] * n, 'r': [0.0] * slots,
                                 'z': [0.0] * nz}]))
    return path


def show(wall, timeout):
    return f'> {timeout:.0f} s' if wall is None else f'{wall:.2f} s'


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument('--binary', required=True)
    ap.add_argument('--timeout', type=float, default=300.0)
    ap.add_argument('--links', default='3,6,12')
    ap.add_argument('--only', default=None, help='run only the models whose name contains this')
    ap.add_argument('--repeat', type=int, default=3,
                    help='runs of each side per model, alternating; the median wall time is shown')
    args = ap.parse_args()
    work = tempfile.mkdtemp(prefix='eqbench-')
    models = sorted(str(p) for p in (ROOT / 'examples' / 'models').glob('*.yaml'))
    for n in (int(x) for x in args.links.split(',') if x):
        for base in (False, True):
            path = pathlib.Path(work) / f'pendulum{n}{"_base" if base else ""}.yaml'
            path.write_text(pendulum(n, base), encoding='utf-8')
            models.append(str(path))
    print('| model | `equations --format sympy` | peak memory | SymPy KanesMethod | peak memory '
          '| ratio |')
    print('|---|---|---|---|---|---|')
    for model in models:
        name = pathlib.Path(model).stem
        if args.only and args.only not in name:
            continue
        ours_runs, theirs_runs = [], []
        state = str(states_file(model, work))
        for _ in range(max(1, args.repeat)):  # alternating, so that both see the same machine
            ours_runs.append(measure_once([args.binary, 'equations', model, '--format', 'sympy'],
                                          args.timeout))
            theirs_runs.append(measure_once([sys.executable, str(READER), model, state],
                                            args.timeout))
            if ours_runs[-1][0] is None or theirs_runs[-1][0] is None:
                break
        ours, theirs = median_of(ours_runs), median_of(theirs_runs)
        note = ''
        if ours[2] not in (0, -9):
            note = f' (equations: {ours[3][:80]})'
        ratio = '' if ours[0] is None or theirs[0] is None else f'{ours[0] / theirs[0]:.3f}'
        print(f'| {name}{note} | {show(ours[0], args.timeout)} | {ours[1]:.0f} MiB '
              f'| {show(theirs[0], args.timeout)} | {theirs[1]:.0f} MiB | {ratio} |', flush=True)


if __name__ == '__main__':
    main()
