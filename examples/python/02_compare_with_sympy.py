"""02: check hybridtest's M and g against the rotor derived by hand with SymPy's KanesMethod.

rotor_sympy.py (beside this file) writes the rotor with sympy.physics.mechanics, sharing
nothing with hybridtest but the parameter values. This compares M(q) and g(t, q, u, r) at
random states; the worst relative difference is round-off.
"""
import pathlib
import sys

import numpy as np

import hybridtest as ht

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
import rotor_sympy  # noqa: E402

m = ht.Model.from_file(HERE.parents[1] / "examples/models/rotor.yaml")
parameters = {name: value for name, (value, _, _) in m.parameters.items()}
M_sympy, g_sympy = rotor_sympy.mass_and_forcing(parameters)

rng = np.random.default_rng(7)
worst_M = worst_g = 0.0
for _ in range(20):
    t = rng.uniform(0.0, 2.0)
    q = np.r_[rng.uniform(-0.1, 0.1, 3), rng.uniform(-3.0, 3.0)]
    u = rng.uniform(-1.0, 1.0, 4)
    r = rng.uniform(-100.0, 100.0, 3)
    x = np.r_[q, u]
    M_ht, g_ht = m.mass_matrix(t, x), m.forcing(t, x, r=r)
    M_ref, g_ref = M_sympy(q), g_sympy(t, q, u, r)
    worst_M = max(worst_M, np.max(np.abs(M_ht - M_ref)) / np.max(np.abs(M_ref)))
    worst_g = max(worst_g, np.max(np.abs(g_ht - g_ref)) / np.max(np.abs(g_ref)))

print(f"worst relative difference at 20 random states: M {worst_M:.2e}, g {worst_g:.2e}")
assert worst_M < 1e-12 and worst_g < 1e-12, "hybridtest and SymPy disagree"
