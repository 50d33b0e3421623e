#!/usr/bin/python3
"""The cost of a Python transfer system, measured against C++ in the same run (not a test).

1. One evaluation: Execute of a Python spring driver against the C++ NumericalLoopback (a
   linear spring), both called from C++ through transfer::TransferSystem without the GIL held,
   as the run loop calls them (hybridtest.time_transfer).
2. A whole run: the paper's 10 s rotor test (Heun, 1 ms, 20,001 evaluations of blade 1) with
   the Python driver behind remote.yaml's physical slot, against the same config with the C++
   loopback transfer system (transfer type loopback, the same spring) in that slot: both
   through the physical substructure, its setup transform and safety gate. In memory; best of
   `repeats` wall times each.

Usage: PYTHONPATH=build/release/python python3 bench/python_transfer.py [EVALUATIONS] [REPEATS]
"""
import pathlib
import sys
import time

import yaml

import hybridtest as ht

ROOT = pathlib.Path(__file__).resolve().parents[1]


class Spring:
    def __init__(self, k=7200.0, p0=0.02):
        self.k, self.p0 = k, p0

    def activate(self):
        pass

    def execute(self, command):
        return command, self.k * (command - self.p0)

    def hold(self):
        pass

    def deactivate(self):
        pass


def best(f, repeats):
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        f()
        times.append(time.perf_counter() - start)
    return min(times)


def main():
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 200000
    repeats = int(sys.argv[2]) if len(sys.argv) > 2 else 5
    runs = [ht.time_transfer(Spring(), n=n) for _ in range(repeats)]
    one = min(runs, key=lambda r: r["python_seconds"])
    cpp = min(r["cpp_seconds"] for r in runs)
    print(f"one evaluation (best of {repeats} × {n}): Python {one['python_seconds'] * 1e9:.0f} ns, "
          f"C++ {cpp * 1e9:.1f} ns, ratio {one['python_seconds'] / cpp:.0f}")
    python_run = best(lambda: ht.run(str(ROOT / "examples/rotor/remote.yaml"),
                                     transfers={"r1": Spring()}), repeats)
    config = yaml.safe_load((ROOT / "examples/rotor/remote.yaml").read_text())
    config["substructures"]["r1"]["transfer"] = {
        "type": "loopback", "law": {"type": "linear", "stiffness": 7200.0}}
    cpp_run = best(lambda: ht.run(config), repeats)
    evaluations = 20001
    print(f"whole 10 s test ({evaluations} evaluations of blade 1, best of {repeats}): "
          f"Python driver {python_run * 1e3:.1f} ms, C++ loopback {cpp_run * 1e3:.1f} ms, "
          f"ratio {python_run / cpp_run:.2f}; extra per evaluation "
          f"{(python_run - cpp_run) / evaluations * 1e9:.0f} ns")


if __name__ == "__main__":
    main()
