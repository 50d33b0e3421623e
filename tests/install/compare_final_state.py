#!/usr/bin/env python3
"""Runs a C++ example and `hybridtest run` on the same run config. The example must exit 0,
print every 1,000th commit (steps 0, 1000, ... up to the last), and print as its final state
`q1 = ...` .. `qn = ...` exactly (as doubles) the q columns of the last row of the CLI's journal.

Usage: compare_final_state.py EXAMPLE HYBRIDTEST CONFIG WORKDIR
"""
import csv
import pathlib
import re
import subprocess
import sys


def fail(message, output=''):
    print(f'compare_final_state.py: {message}', file=sys.stderr)
    if output:
        print(output, file=sys.stderr)
    sys.exit(1)


def main():
    if len(sys.argv) != 5:
        fail('usage: compare_final_state.py EXAMPLE HYBRIDTEST CONFIG WORKDIR')
    example, hybridtest, config, workdir = sys.argv[1:]
    work = pathlib.Path(workdir)
    work.mkdir(parents=True, exist_ok=True)

    # The example runs in memory: it writes no file.
    ran = subprocess.run([example, config], capture_output=True, text=True, check=False)
    if ran.returncode != 0:
        fail(f'{example} {config} exited {ran.returncode}', ran.stdout + ran.stderr)
    printed = {int(m[1]): float(m[2])
               for m in re.finditer(r'^\s*q(\d+) = (\S+)\s*$', ran.stdout, re.M)}
    commits = [int(m[1]) for m in re.finditer(r'^commit (\d+):', ran.stdout, re.M)]

    # The oracle: the CLI's journal of the same config.
    journal = work / 'run.csv'
    cli = subprocess.run([hybridtest, 'run', config, '--out', str(journal), '--overwrite'],
                         capture_output=True, text=True, check=False)
    if cli.returncode != 0:
        fail(f'hybridtest run {config} exited {cli.returncode}', cli.stdout + cli.stderr)
    with open(journal, newline='') as f:
        rows = list(csv.reader(f))
    header, last = rows[0], rows[-1]
    expected = {int(name[1:]): float(last[i])
                for i, name in enumerate(header) if re.fullmatch(r'q\d+', name)}

    if not expected:
        fail(f'{journal} has no q columns: {header}')
    if printed != expected:
        fail(f'final state differs: the example printed {printed}, the journal\'s last row '
             f'holds {expected}', ran.stdout)
    last_step = len(rows) - 2  # rows 0..N after the header
    if commits != list(range(0, last_step + 1, 1000)):
        fail(f'expected the commits 0, 1000, ... {last_step // 1000 * 1000}, got {commits}',
             ran.stdout)
    print(f'final q1..q{len(expected)} equal to the last row of {journal} '
          f'({len(commits)} commits printed)')


if __name__ == '__main__':
    main()
