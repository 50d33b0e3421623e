"""04: a hybrid test whose bench is driven from Python.

examples/rotor/remote.yaml puts blade 1 on a remote bench (setup p0 = 0.020 m, safety limits).
Here a Python object replaces that bench: any object with activate(), execute(command) ->
(position, force[, lab_time]), hold() and deactivate() will do, so a lab's own driver (e.g. a
Beckhoff ADS client) plugs in as it is. This one is an ideal spring that speaks mm and kN, as
many benches do; the runner converts (units), checks every command and measurement against
the safety limits, journals every step and holds on any error, as for a C++ bench.
"""
import pathlib
import tempfile

import numpy as np

import hybridtest as ht

ROOT = pathlib.Path(__file__).resolve().parents[2]


class SpringBench:
    """An ideal steel blade on an ideal actuator: force = k (position − p0), in mm and kN."""
    units = ("mm", "kN")

    def __init__(self, k_n_per_m, p0_mm):
        self.k_kn_per_mm = k_n_per_m * 1e-6
        # Announced: the run refuses a setup.p0 that disagrees, before anything moves.
        self.p0 = p0_mm
        self.moves = 0

    def activate(self):
        print("bench: drive enabled")

    def execute(self, command_mm):
        self.moves += 1
        return command_mm, self.k_kn_per_mm * (command_mm - self.p0)

    def hold(self):
        print("bench: holding")

    def deactivate(self):
        print(f"bench: drive disabled after {self.moves} moves")


class Progress:
    """An observer: called at every committed step with numpy views of x and r."""

    def __init__(self):
        self.peak = 0.0

    def on_commit(self, c):
        self.peak = max(self.peak, abs(c.x[0]))
        if c.step % 2500 == 0:
            print(f"  t = {c.t:5.2f} s  q1 = {c.x[0]: .5f} m  r1 = {c.r[0]: 8.2f} N")


# In memory; out="results/python-bench.csv" would also write the journal, its sidecar, the
# stage record and the run state exactly as `hybridtest run` does (ht.read_run reads them back).
progress = Progress()
run = ht.run(ROOT / "examples/rotor/remote.yaml", transfers={"r1": SpringBench(7200.0, 20.0)},
             observers=[progress])
sim = ht.simulate(ROOT / "examples/rotor/numerical.yaml")
print(f"largest |q1| {progress.peak:.5f} m; largest difference from the simulation "
      f"{np.max(np.abs(run['q1'] - sim['q1'])):.2e} m")
print("bench channels:", [c for c in run.channels if c.startswith("r1_")])
print(f"lab time of the Python bench: {run['r1_lab_time'][-1]:.3f} s; statistics:",
      run.statistics)


# A driver that fails: its exception is a TransferError, the bench holds, every committed
# step is kept (the error's .result and, with out=, the journal and run state).
class FailingBench(SpringBench):
    def execute(self, command_mm):
        if self.moves == 1000:
            raise ConnectionError("lost the ADS route")
        return super().execute(command_mm)


out = pathlib.Path(tempfile.mkdtemp()) / "python-bench.csv"
try:
    ht.run(ROOT / "examples/rotor/remote.yaml", transfers={"r1": FailingBench(7200.0, 20.0)},
           out=out)
except ht.TransferError as e:
    print(f"TransferError: {e}\n  committed rows kept: {e.result.num_rows}")

# The route is back: continue from the last committed step, as `hybridtest resume` does (the
# bench is brought back to the last committed command and checked first).
resumed = ht.resume(out, transfers={"r1": SpringBench(7200.0, 20.0)})
print(f"resumed to t = {resumed['t'][-1]:.3f} s; largest difference from the uninterrupted run "
      f"{np.max(np.abs(resumed['q1'] - run['q1'])):.2e} m")
