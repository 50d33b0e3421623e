#!/usr/bin/env bash
# Installs the dependencies if needed, then configures and builds the optimised tree
# (build/release). Incremental: a second call only rebuilds what changed.
#   scripts/build.sh          everything: the hybridtest binary, the test suite, the benchmarks
#   scripts/build.sh --app    only the hybridtest binary and what it links (the main job), and
#                             the example FMUs (examples/fmi/); a fresh tree is configured
#                             without tests and benchmarks, so their packages are not needed
#   scripts/build.sh --python only the Python package (build/release/python/hybridtest)
#   --print                   print the commands instead of running them
# HYBRIDTEST_WERROR=ON (.ci/run sets it) configures the tree with warnings as errors in the
# project's own files.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"
app_only=0
python_only=0
print_only=0
for arg in "$@"; do
  case "$arg" in
    --app) app_only=1 ;;
    --python) python_only=1 ;;
    --print) print_only=1 ;;
    *) echo "build.sh: unknown option '$arg'; expected --app, --python and/or --print" >&2; exit 2 ;;
  esac
done
# shellcheck source=scripts/lib/stage.sh
source scripts/lib/stage.sh
# run STAGE COMMAND...: runs (or, with --print, prints) COMMAND, timed as STAGE.
run() {
  local name=$1
  shift
  if ((print_only)); then echo "$*"; else stage "$name" "$@"; fi
}
cache=build/release/CMakeCache.txt
if ((app_only)); then
  run dependencies scripts/install-deps.sh --app
  if [[ ! -f build/release/build.ninja ]]; then
    run configure cmake --preset release -DHYBRIDTEST_BUILD_TESTS=OFF -DHYBRIDTEST_BUILD_BENCH=OFF
  fi
  run build cmake --build --preset release -j "${HYBRIDTEST_JOBS:-$(nproc)}" --target hybridtest hybridtest_example_fmus
  exit 0
fi
if ((python_only)); then
  run dependencies scripts/install-deps.sh
  [[ -f build/release/build.ninja ]] || run configure cmake --preset release
  run build cmake --build --preset release -j "${HYBRIDTEST_JOBS:-$(nproc)}" --target hybridtest_python
  exit 0
fi
run dependencies scripts/install-deps.sh
# A tree first configured by --app has the tests and benchmarks off: turn them on.
if [[ ! -f build/release/build.ninja ]] || grep -q "^HYBRIDTEST_BUILD_TESTS:BOOL=OFF" "$cache" ||
   grep -q "^HYBRIDTEST_BUILD_BENCH:BOOL=OFF" "$cache"; then
  run configure cmake --preset release -DHYBRIDTEST_BUILD_TESTS=ON -DHYBRIDTEST_BUILD_BENCH=ON \
    -DHYBRIDTEST_WERROR="${HYBRIDTEST_WERROR:-OFF}"
fi
run build cmake --build --preset release -j "${HYBRIDTEST_JOBS:-$(nproc)}"
