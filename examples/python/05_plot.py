"""05: plot the hybrid test of 04 against the simulation, if matplotlib is installed."""
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

sim = ht.simulate(ROOT / "examples/rotor/numerical.yaml")
path = ROOT / "results/python-bench.csv"
run = ht.read_run(path) if path.exists() else None
fig, axes = plt.subplots(2, 1, sharex=True, figsize=(8, 6))
for k in range(1, 4):
    axes[0].plot(sim["t"], sim[f"q{k}"], label=f"q{k} simulation")
if run is not None:
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
