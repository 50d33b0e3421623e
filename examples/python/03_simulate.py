"""03: simulate the paper's rotor (every blade numerical), from a config file or a dict.

ht.simulate keeps the run in memory; out="results/x.csv" also writes the journal and its
sidecar as `hybridtest simulate` does. The result's columns are numpy arrays, SI.
"""
import pathlib

import numpy as np

import hybridtest as ht

ROOT = pathlib.Path(__file__).resolve().parents[2]

sim = ht.simulate(ROOT / "examples/rotor/numerical.yaml")
print(sim, "channels:", sim.channels)
print(f"t = {sim['t'][-1]} s: q1 = {sim['q1'][-1]:.6f} {sim.units['q1']}, "
      f"hub speed u4 = {sim['u4'][-1]:.4f} {sim.units['u4']}")
print("statistics:", sim.statistics)

# The same run as a dict with the config's keys, one parameter changed and 2 s only.
config = {
    "model": {"name": "rotor", "blades": 3, "parameters": {"k_b": 9000.0}},
    "integrator": {"tableau": "heun", "dt": 0.001},
    "duration": 2.0,
}
stiff = ht.simulate(config)
print(f"k_b = 9000 N/m: q1 at 2 s = {stiff['q1'][-1]:.6f} m "
      f"(7200 N/m: {sim['q1'][2000]:.6f} m)")

# A numerical blade whose law is a Python function r = law(d) [m] -> [N]: a stiffening spring.
soft = ht.simulate(config | {"model": {"name": "rotor", "blades": 3}},
                   laws={"r1": lambda d: 7200.0 * d * (1.0 + 50.0 * d * d)})
print(f"stiffening blade 1: q1 at 2 s = {soft['q1'][-1]:.6f} m")

# A pandas DataFrame when pandas is installed.
try:
    df = sim.to_dataframe()
    print(df[["t", "q1", "q4"]].describe())
except ImportError as e:
    print(f"(no pandas: {e})")
assert np.all(np.isfinite(sim.values))
