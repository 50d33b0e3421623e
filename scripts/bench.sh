#!/usr/bin/env bash
# Builds and runs the benchmarks (about a minute), then prints the figures with their
# references measured in the same run:
#   - one rotor RHS: the Kane engine against the hand-written closed form (target ≤ 1.5×);
#   - the runner's own overhead per stage, and the journal's cost per row;
#   - a whole `hybridtest simulate examples/rotor/numerical.yaml`, median of 5, against the
#     simulated time (real time) and against the RHS evaluations it contains.
# Usage: scripts/bench.sh [extra --benchmark_* flags]
set -euo pipefail
cd "$(dirname "$0")/.."

cmake --preset release >/dev/null
cmake --build build/release --target hybridtest_bench hybridtest -j1 >/dev/null

out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
build/release/bench/hybridtest_bench --benchmark_min_time=0.3 \
  --benchmark_filter='RotorRhs|Runner' \
  --benchmark_out="$out/bench.json" --benchmark_out_format=json "$@"

# Whole process: median of 5 wall times of the paper's numerical simulation.
times=()
for _ in 1 2 3 4 5; do
  start=$(date +%s.%N)
  build/release/apps/hybridtest/hybridtest simulate examples/rotor/numerical.yaml \
    --out "$out/numerical.csv" --quiet --overwrite >/dev/null
  end=$(date +%s.%N)
  times+=("$(awk -v a="$start" -v b="$end" 'BEGIN { print b - a }')")
done
printf '%s\n' "${times[@]}" > "$out/simulate.txt"

/usr/bin/python3 - "$out/bench.json" "$out/simulate.txt" <<'PY'
import json, statistics, sys
runs = {b["name"]: b for b in json.load(open(sys.argv[1]))["benchmarks"]}
def ns(name):
    b = runs[name]
    scale = {"ns": 1.0, "us": 1e3, "ms": 1e6, "s": 1e9}[b["time_unit"]]
    return b["real_time"] * scale
print()
print("== rotor RHS (3 blades, Table 1) ==")
e, c = ns("RotorRhs/KaneEngine"), ns("RotorRhs/ClosedForm")
print(f"engine {e/1e3:.3f} µs vs closed form {c/1e3:.3f} µs: {e/c:.2f}× (separate benchmarks; target ≤ 1.5×)")
r = runs["RotorRhs/EngineOverClosedForm"]
print(f"engine {r['engine_ns']/1e3:.3f} µs vs closed form {r['closed_form_ns']/1e3:.3f} µs: "
      f"{r['ratio']:.2f}× (alternating blocks in one loop)")
a = ns("RotorRhs/ClosedFormArrow")
print(f"closed form, arrow solve {a/1e3:.3f} µs vs Cholesky {c/1e3:.3f} µs: {a/c:.2f}×")
d = ns("RotorRhs/KaneEngineAutoDiff")
print(f"engine AutoDiff (8 directions) {d/1e3:.3f} µs vs double {e/1e3:.3f} µs: {d/e:.1f}×")
print()
print("== runner, per Runge–Kutta stage, numerical rotor, no bench ==")
w = runs["Runner/WholeRun"]
print(f"whole run: {w['per_stage_ns']:.0f} ns per stage, of which RHS {w['rhs_ns']:.0f} ns: "
      f"overhead {w['overhead_ns']:.0f} ns (mean)")
s = runs["Runner/StageSeam"]
print(f"stage seam, all stages: overhead p50 {s['overhead_p50_ns']:.0f} ns, p99 "
      f"{s['overhead_p99_ns']:.0f} ns vs RHS {s['rhs_ns']:.0f} ns")
print(f"  stage 0 (commit + journal row): p50 {s['stage0_overhead_p50_ns']:.0f} ns, p99 "
      f"{s['stage0_overhead_p99_ns']:.0f} ns")
print(f"  stage 1:                        p50 {s['stage1_overhead_p50_ns']:.0f} ns, p99 "
      f"{s['stage1_overhead_p99_ns']:.0f} ns")
jb, je = ns("Runner/JournalAppend/batched"), ns("Runner/JournalAppend/every_row")
print(f"journal row: batched {jb/1e3:.2f} µs vs every-row fsync {je/1e3:.1f} µs: {je/jb:.0f}×")
print()
print("== hybridtest simulate examples/rotor/numerical.yaml (10 s, h = 1 ms, Heun) ==")
t = statistics.median(float(x) for x in open(sys.argv[2]))
rhs_total = 20000 * e * 1e-9
print(f"wall time {t:.3f} s (median of 5) vs simulated 10 s: {t/10:.4f}× real time; "
      f"its 20 000 RHS evaluations take {rhs_total*1e3:.1f} ms ({100*rhs_total/t:.1f} %)")
PY
