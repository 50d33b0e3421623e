#!/usr/bin/env bash
# Installs the dependencies if needed, then configures and builds the optimised tree
# (build/release). Incremental: a second call only rebuilds what changed.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"
scripts/install-deps.sh
if [[ ! -f build/release/build.ninja ]]; then
  cmake --preset release >/dev/null
fi
cmake --build --preset release -j "${HYBRIDTEST_JOBS:-$(nproc)}"
