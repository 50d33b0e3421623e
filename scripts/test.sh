#!/usr/bin/env bash
# The README's test command: builds if needed, then runs the whole test suite with CTest
# (unit, integration and SymPy oracle tests).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"
scripts/build.sh
ctest --preset release -j "${HYBRIDTEST_JOBS:-$(nproc)}" --timeout 900 "$@"
