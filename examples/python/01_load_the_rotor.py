"""01: load the paper's rotor from its model file and evaluate its equations of motion.

Run from anywhere once the package is importable (README):
    PYTHONPATH=build/release/python python3 examples/python/01_load_the_rotor.py
"""
import pathlib

import numpy as np

import hybridtest as ht

ROOT = pathlib.Path(__file__).resolve().parents[2]

# The model file; any parameter can be overridden by name, in SI.
m = ht.Model.from_file(ROOT / "examples/models/rotor.yaml")
print(m)
for name, (value, unit, description) in m.parameters.items():
    print(f"  {name:<7} {value:>8g} {unit:<7} {description}")
print("coordinates:", [c[0] for c in m.coordinates], " slots:", [s[0] for s in m.slots])

# A state x = [q; u] (q1..q3 tip deflections [m], q4 hub angle [rad]; u their rates).
x = np.zeros(m.num_states)
x[4:] = [0.1, -0.2, 0.3, 1.5]
r = np.array([10.0, 20.0, 30.0])  # restoring forces of the three blades [N]
t = 0.7                           # [s]

M = m.mass_matrix(t, x)           # (4 × 4) [kg, kg·m, kg·m²]
g = m.forcing(t, x, r=r)          # (4)
print("M =\n", M)
print("g =", g)
print("ẋ =", m.state_derivative(t, x, r=r))
print("B = ∂g/∂r =\n", m.coupling_matrix(t, x))
print("d (slot displacements) =", m.slot_displacements(t, x))
# Without r, each slot's default numerical spring gives r = k_b d.
print("g with r = k_b q:", m.forcing(t, x))
print("check:", m.check())

# A stiffer blade, by name:
stiff = ht.Model.from_file(ROOT / "examples/models/rotor.yaml", parameters={"k_b": 9000.0})
print("k_b:", stiff.parameters["k_b"][0], "N/m; default slot stiffness:", stiff.slot_stiffness)
