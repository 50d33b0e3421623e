import numpy as np, hybridtest as ht
m = ht.Model.from_file("examples/models/rotor.yaml")
x = np.zeros(8); x[4:] = [0.1, -0.2, 0.3, 1.5]
M, g = m.mass_matrix(0.7, x), m.forcing(0.7, x, r=np.array([10.0, 20.0, 30.0]))
assert M.shape == (4, 4) and g.shape == (4,)
sim = ht.simulate("examples/rotor/numerical.yaml")
assert sim["q1"].shape == (10001,)

class Spring:                         # a bench driver written in Python (speaks SI: m, N)
    def __init__(self, k): self.k = k
    def activate(self): pass
    def execute(self, command): return command, self.k * (command - 0.02)
    def hold(self): pass
    def deactivate(self): pass
run = ht.run("examples/rotor/remote.yaml", transfers={"r1": Spring(7200.0)}, out="py.csv")
assert np.max(np.abs(run["q1"] - sim["q1"])) < 1e-9
