#!/usr/bin/env bash
# The README's main job: builds the hybridtest binary if needed (only it: not the test suite nor
# the benchmarks, whose packages it does not install either; scripts/test.sh builds those), then
# runs the paper's scenario end to end and writes
# everything under results/:
#   1. the pure numerical simulation (Fig. 7)            results/numerical.csv
#   2. the hybrid test on the emulated bench (Fig. 6):
#      blade 1 is the steel cantilever on the actuator   results/emulated.csv (+ .stages.csv)
#   3. the same hybrid test with the lab-time scheme (MR-OS, ~200 specimen evaluations instead
#      of 20,000)                                        results/emulated-fast.csv
#   4. figures, comparisons, and self-contained HTML reports
#                                                        results/*-figures/, results/report.html,
#                                                        results/report-fast.html
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"
scripts/build.sh --app
bin=build/release/apps/hybridtest/hybridtest
mkdir -p results
# --overwrite: each run of this script replaces the previous one's results/ (without it, `run`
# and `simulate` refuse to write over an earlier run: exit 2).

echo "== 1/4 numerical simulation (examples/rotor/numerical.yaml)"
"$bin" simulate examples/rotor/numerical.yaml --out results/numerical.csv --overwrite
echo "== 2/4 hybrid test on the emulated bench (examples/rotor/emulated.yaml)"
"$bin" run examples/rotor/emulated.yaml --out results/emulated.csv --overwrite
echo "== 3/4 the same hybrid test with few specimen evaluations (examples/rotor/emulated-fast.yaml)"
"$bin" run examples/rotor/emulated-fast.yaml --out results/emulated-fast.csv --overwrite
echo "== 4/4 figures, comparisons and reports"
"$bin" plot results/numerical.csv --out results/numerical-figures
"$bin" plot results/emulated.csv --out results/emulated-figures
"$bin" plot results/emulated-fast.csv --out results/emulated-fast-figures
"$bin" compare results/emulated.csv results/numerical.csv --out results/emulated-vs-numerical
"$bin" compare results/emulated-fast.csv results/emulated.csv --out results/fast-vs-emulated
"$bin" report results/emulated.csv --against results/numerical.csv --out results/report.html
"$bin" report results/emulated-fast.csv --against results/emulated.csv --out results/report-fast.html
echo "hybridtest: results written to $root/results/ (open results/report.html)"
