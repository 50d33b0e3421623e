#!/usr/bin/env bash
# The README's main job: builds if needed, then runs the paper's scenario end to end and writes
# everything under results/:
#   1. the pure numerical simulation (Fig. 7)            results/numerical.csv
#   2. the hybrid test on the emulated bench (Fig. 6):
#      blade 1 is the steel cantilever on the actuator   results/emulated.csv (+ .stages.csv)
#   3. figures of both, their comparison, and one self-contained HTML report
#                                                        results/*-figures/, results/report.html
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"
scripts/build.sh
bin=build/release/apps/hybridtest/hybridtest
mkdir -p results
# --overwrite: each run of this script replaces the previous one's results/ (without it, `run`
# and `simulate` refuse to write over an earlier run: exit 2).

echo "== 1/3 numerical simulation (examples/rotor/numerical.yaml)"
"$bin" simulate examples/rotor/numerical.yaml --out results/numerical.csv --overwrite
echo "== 2/3 hybrid test on the emulated bench (examples/rotor/emulated.yaml)"
"$bin" run examples/rotor/emulated.yaml --out results/emulated.csv --overwrite
echo "== 3/3 figures, comparison and report"
"$bin" plot results/numerical.csv --out results/numerical-figures
"$bin" plot results/emulated.csv --out results/emulated-figures
"$bin" compare results/emulated.csv results/numerical.csv --out results/emulated-vs-numerical
"$bin" report results/emulated.csv --against results/numerical.csv --out results/report.html
echo "hybridtest: results written to $root/results/ (open results/report.html)"
