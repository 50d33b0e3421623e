#!/usr/bin/env python3
"""Runs a C++ example that writes a journal through the front door and `hybridtest run` on the
run config it mirrors. The example must exit 0 and write, as its journal, the CLI's journal:
the same channels, the same number of rows and the same values, bit for bit (as written);
its sidecar must say `completed`, name no input (a spec written in code reads no file) and
carry the example's command line in its provenance.

Usage: compare_journals.py EXAMPLE HYBRIDTEST CONFIG WORKDIR
"""
import csv
import json
import pathlib
import subprocess
import sys


def fail(message, output=''):
    print(f'compare_journals.py: {message}', file=sys.stderr)
    if output:
        print(output, file=sys.stderr)
    sys.exit(1)


def rows_of(path):
    with open(path, newline='') as f:
        return list(csv.reader(f))


def main():
    if len(sys.argv) != 5:
        fail('usage: compare_journals.py EXAMPLE HYBRIDTEST CONFIG WORKDIR')
    example, hybridtest, config, workdir = sys.argv[1:]
    work = pathlib.Path(workdir)
    work.mkdir(parents=True, exist_ok=True)
    for old in work.glob('example*'):
        old.unlink()  # the front door never replaces an earlier run

    journal = work / 'example.csv'
    ran = subprocess.run([example, str(journal)], capture_output=True, text=True, check=False)
    if ran.returncode != 0:
        fail(f'{example} {journal} exited {ran.returncode}', ran.stdout + ran.stderr)
    again = subprocess.run([example, str(journal)], capture_output=True, text=True, check=False)
    if again.returncode != 2 or 'exists already' not in again.stderr:
        fail(f'a second run onto {journal} was not refused by the front door (exit '
             f'{again.returncode})', again.stdout + again.stderr)

    oracle = work / 'cli.csv'
    cli = subprocess.run([hybridtest, 'run', config, '--out', str(oracle), '--overwrite',
                          '--quiet'], capture_output=True, text=True, check=False)
    if cli.returncode != 0:
        fail(f'hybridtest run {config} exited {cli.returncode}', cli.stdout + cli.stderr)

    mine, theirs = rows_of(journal), rows_of(oracle)
    if mine[0] != theirs[0]:
        fail(f'channels differ: the example wrote {mine[0]}, the CLI {theirs[0]}')
    if len(mine) != len(theirs):
        fail(f'the example wrote {len(mine) - 1} rows, the CLI {len(theirs) - 1}')
    for i, (a, b) in enumerate(zip(mine, theirs)):
        if a != b:
            diffs = [(mine[0][j], x, y) for j, (x, y) in enumerate(zip(a, b)) if x != y]
            fail(f'row {i} differs (channel, example, CLI): {diffs[:4]}')

    sidecar = json.loads((work / 'example.meta.json').read_text())
    extra = sidecar.get('extra', {})
    if sidecar.get('status') != 'completed':
        fail(f'the example\'s sidecar says {sidecar.get("status")!r}')
    if extra.get('inputs') != []:
        fail(f'a spec written in code read no file, but its record names {extra.get("inputs")}')
    if extra.get('provenance', {}).get('command_line') != 'run_spec_in_code':
        fail(f'provenance: {extra.get("provenance")}')
    print(f'{journal}: {len(mine) - 1} rows, equal to {oracle} value for value')


if __name__ == '__main__':
    main()
