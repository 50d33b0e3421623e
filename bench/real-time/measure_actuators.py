#!/usr/bin/env python3
"""The paced loop of the two-actuator benchmark against the one-actuator storey, at 1 kHz on the
wall clock, in the same invocation (issue 46, measures).

    python3 bench/real-time/measure_actuators.py [--binary B] [--rounds N] [--duration S]
                                                 [--as-is] [--no-lock]

Runs examples/real-time/coupler-ats.yaml (two servo-hydraulic actuators on one coupled
specimen, ATS on each) and examples/real-time/storey-ats.yaml (one actuator, ATS) with
`integrator.dt: 0.001` (1 kHz) and `--clock wall`, alternately (coupler, storey, coupler, …) so
that a change of the machine's load falls on both. From each run's sidecar
(statistics.real_time) it prints the ticks, the misses, the misses per minute of wall time
(misses · 60 / (ticks · dt)), the compute time of a tick (Session::Step) and its wake-up
lateness, p50 and p99 [µs]; then, pooled over the rounds (the median of the rounds' p50 and p99,
the misses summed), the coupler's figures as a ratio to the storey's.

  --as-is    keep the examples' miss policy (hold_after_misses: 10): a loaded machine then
             holds a run early. Without it the policy is off (0), so every tick is measured.
  --no-lock  set lock_memory to false (where mlockall is refused).

Not a test: nothing is asserted. The storey of the same invocation is the reference: compare
with it, not with figures from another machine or another time.
"""
import argparse
import json
import pathlib
import statistics
import subprocess
import sys
import tempfile

ROOT = pathlib.Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples/real-time"
TICK = 0.001  # [s] 1 kHz
RUNS = {"coupler": ("coupler-ats.yaml", "coupler.model.yaml"),
        "storey": ("storey-ats.yaml", "storey.model.yaml")}


def config(work: pathlib.Path, name: str, duration: float, as_is: bool, lock: bool) -> pathlib.Path:
    file, model = RUNS[name]
    text = (EXAMPLES / file).read_text()
    edits = [(f"file: {model}", f"file: {EXAMPLES / model}"),
             ("dt: 0.0009765625", f"dt: {TICK}"),
             ("duration: 10.0", f"duration: {duration}")]
    if not as_is:
        edits.append(("hold_after_misses: 10", "hold_after_misses: 0"))
    if not lock:
        edits.append(("lock_memory: true", "lock_memory: false"))
    for old, new in edits:
        if old not in text:
            sys.exit(f"measure_actuators: {old!r} not found in {file}; update this script")
        text = text.replace(old, new, 1)
    path = work / f"{name}.yaml"
    path.write_text(text)
    return path


def measure(binary: str, name: str, cfg: pathlib.Path, work: pathlib.Path, tag: str) -> dict:
    csv = work / f"{name}-{tag}.csv"
    log = work / f"{name}-{tag}.log"
    with open(log, "w") as out:
        status = subprocess.run([binary, "run", str(cfg), "--clock", "wall", "--out", str(csv),
                                 "--quiet", "--overwrite"], stdout=out, stderr=out,
                                timeout=600).returncode
    meta = csv.with_suffix(".meta.json")
    if not meta.exists():
        sys.exit(f"measure_actuators: {name} exited {status} without a sidecar:\n"
                 f"{log.read_text()}")
    sidecar = json.loads(meta.read_text())
    rt = sidecar["statistics"]["real_time"]
    minutes = rt["ticks"] * TICK / 60.0
    return {"run": name, "exit": status, "status": sidecar.get("status", "?"),
            "held": rt["held_on_misses"] or rt["held_on_queue"],
            "ticks": rt["ticks"], "misses": rt["misses"],
            "misses_per_min": rt["misses"] / minutes if minutes > 0 else float("nan"),
            "compute_p50_us": rt["compute_s"]["p50"] * 1e6,
            "compute_p99_us": rt["compute_s"]["p99"] * 1e6,
            "late_p50_us": rt["late_s"]["p50"] * 1e6, "late_p99_us": rt["late_s"]["p99"] * 1e6}


def pooled(rows: list) -> dict:
    ticks = sum(r["ticks"] for r in rows)
    misses = sum(r["misses"] for r in rows)
    out = {"ticks": ticks, "misses": misses, "misses_per_min": misses / (ticks * TICK / 60.0)}
    for key in ("compute_p50_us", "compute_p99_us", "late_p50_us", "late_p99_us"):
        out[key] = statistics.median(r[key] for r in rows)
    return out


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--binary", default=str(ROOT / "build/release/apps/hybridtest/hybridtest"))
    p.add_argument("--rounds", type=int, default=2)
    p.add_argument("--duration", type=float, default=10.0, help="[s] of each run")
    p.add_argument("--as-is", action="store_true")
    p.add_argument("--no-lock", action="store_true")
    a = p.parse_args()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        work = pathlib.Path(tmp)
        cfgs = {n: config(work, n, a.duration, a.as_is, not a.no_lock) for n in RUNS}
        for r in range(a.rounds):
            for name in RUNS:
                row = measure(a.binary, name, cfgs[name], work, str(r))
                row["round"] = r + 1
                rows.append(row)
                print(json.dumps(row), flush=True)
    load = pathlib.Path("/proc/loadavg").read_text().split()[0]
    print(f"\n{'round':>5} {'run':>8} {'exit':>4} {'status':>9} {'held':>4} {'ticks':>6} {'misses':>6} "
          f"{'miss/min':>8} {'comp p50':>8} {'comp p99':>8} {'late p50':>8} {'late p99':>8}  [µs]")
    for r in rows:
        print(f"{r['round']:>5} {r['run']:>8} {r['exit']:>4} {r['status']:>9} {'yes' if r['held'] else 'no':>4} "
              f"{r['ticks']:>6} {r['misses']:>6} {r['misses_per_min']:>8.1f} "
              f"{r['compute_p50_us']:>8.1f} {r['compute_p99_us']:>8.1f} "
              f"{r['late_p50_us']:>8.1f} {r['late_p99_us']:>8.1f}")
    pool = {n: pooled([r for r in rows if r["run"] == n]) for n in RUNS}
    print(f"\npooled over {a.rounds} round(s) of {a.duration:g} s at 1 kHz "
          f"(load average at the end {load}):")
    for n, v in pool.items():
        print(f"  {n:>8}: {v['ticks']} ticks, {v['misses']} misses ({v['misses_per_min']:.1f} "
              f"per minute); compute p50 {v['compute_p50_us']:.1f} µs, p99 "
              f"{v['compute_p99_us']:.1f} µs; late p50 {v['late_p50_us']:.1f} µs, p99 "
              f"{v['late_p99_us']:.1f} µs")
    c, s = pool["coupler"], pool["storey"]

    def ratio(key: str) -> str:
        return f"{c[key] / s[key]:.2f}" if s[key] > 0 else "— (storey 0)"
    print(f"  coupler / storey: compute p50 {ratio('compute_p50_us')}, p99 "
          f"{ratio('compute_p99_us')}; late p50 {ratio('late_p50_us')}, p99 "
          f"{ratio('late_p99_us')}; misses per minute {ratio('misses_per_min')}")


if __name__ == "__main__":
    main()
