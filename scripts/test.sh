#!/usr/bin/env bash
# The README's test command: builds if needed, then runs the whole test suite with CTest
# (unit, integration and SymPy oracle tests), then, when clang is installed, a short fuzz run
# of each libFuzzer target (HYBRIDTEST_FUZZ_SECONDS per target, default 30, a smoke run that
# keeps CI's 2-core budget; 0 skips them; scripts/fuzz.sh runs them longer).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"
scripts/build.sh
ctest --preset release -j "${HYBRIDTEST_JOBS:-$(nproc)}" --timeout 900 "$@"
fuzz_seconds=${HYBRIDTEST_FUZZ_SECONDS:-30}
if [[ "$fuzz_seconds" != 0 ]]; then
  if command -v clang++ >/dev/null; then
    scripts/fuzz.sh "$fuzz_seconds"
  else
    echo "hybridtest: clang++ not found, fuzz smoke tests skipped"
  fi
fi
