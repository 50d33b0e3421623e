#!/usr/bin/env bash
# The README's main job: builds if needed, then runs the paper's rotor scenario and writes the
# results under results/.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"
scripts/build.sh
bin=build/release/apps/hybridtest/hybridtest
mkdir -p results
"$bin" simulate examples/rotor/numerical.yaml --out results/numerical.csv
echo "hybridtest: results written to $root/results/"
