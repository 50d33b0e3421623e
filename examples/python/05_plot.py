"""05: plot a hybrid test through a Python bench against the simulation (with matplotlib)."""
import pathlib

import hybridtest as ht

ROOT = pathlib.Path(__file__).resolve().parents[2]
try:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:
    print("matplotlib is not installed (Debian: python3-matplotlib): no figure")
    raise SystemExit(0)



class Spring:
    """An ideal bench in SI: force = k (command − p0)."""
    def activate(self): pass
    def execute(self, command): return command, 7200.0 * (command - 0.02)
    def hold(self): pass
    def deactivate(self): pass


sim = ht.simulate(ROOT / "examples/rotor/numerical.yaml")
run = ht.run(ROOT / "examples/rotor/remote.yaml", transfers={"r1": Spring()})
fig, axes = plt.subplots(2, 1, sharex=True, figsize=(8, 6))
for k in range(1, 4):
    axes[0].plot(sim["t"], sim[f"q{k}"], label=f"q{k} simulation")
axes[0].plot(run["t"], run["q1"], "k--", label="q1 hybrid (Python bench)")
axes[0].set_ylabel("tip deflection [m]")
axes[0].legend()
axes[1].plot(sim["t"], sim["u4"])
axes[1].set_ylabel("hub speed [rad/s]")
axes[1].set_xlabel("t [s]")
out = ROOT / "results/python-rotor.png"
out.parent.mkdir(exist_ok=True)
fig.savefig(out, dpi=120)
print("wrote", out)
