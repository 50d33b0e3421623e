#!/usr/bin/env bash
# The README's test command: builds if needed, then runs the whole test suite with CTest
# (unit, integration and SymPy oracle tests, and every fuzz target's seed corpus replayed,
# fuzz_replay.*), then, when clang is installed, a short libFuzzer run under ASan and UBSan of
# the decoders of bytes from the wire (HYBRIDTEST_FUZZ_TARGETS, default frame_decoder
# bench_config openfresco_wire: they need only the transfer layer, so the sanitized build stays
# small; HYBRIDTEST_FUZZ_SECONDS per target, default 30; 0 skips them). scripts/fuzz.sh runs
# every target, run_config and run_state included, for longer.
#
# At its end (also when a stage fails) it prints the wall time of each stage (dependencies,
# configure, build, ctest, fuzz) and the ten slowest tests. CTest's wall time is checked against
# the budget in tests/time-budget.txt (the one place it is written): over it, the command fails.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"
budget_file=tests/time-budget.txt
junit=build/release/ctest-results.xml
export HYBRIDTEST_STAGE_LOG
HYBRIDTEST_STAGE_LOG=$(mktemp)
started=$(date +%s)

summary() {
  local status=$?
  trap - EXIT
  echo
  echo "hybridtest: stage times (wall clock, $(nproc) cores)"
  awk '{ printf "  %-13s %7.0f s\n", $1, $2 }' "$HYBRIDTEST_STAGE_LOG"
  printf "  %-13s %7d s\n" total $(($(date +%s) - started))
  if [[ -f "$junit" ]]; then
    echo "hybridtest: the ten slowest tests"
    # One <testcase name="..." ... time="..."> element per test. awk reads the whole list (no
    # `head`: sort, cut off with a full pipe, would die of SIGPIPE, and under pipefail and
    # errexit the command would exit 141 after the suite had passed).
    sed -n 's/.*<testcase name="\([^"]*\)".* time="\([0-9.]*\)".*/\2 \1/p' "$junit" |
      sort -g -r | awk 'NR <= 10 { printf "  %7.1f s  %s\n", $1, $2 }'
  fi
  rm -f "$HYBRIDTEST_STAGE_LOG"
  [[ -n "${scratch:-}" ]] && rm -rf "$scratch"
  exit "$status"
}
trap summary EXIT
rm -f "$junit"  # the slowest tests are this run's

# shellcheck source=scripts/lib/stage.sh
source scripts/lib/stage.sh

# Dependencies, configure and build (scripts/build.sh records its own stages in the log).
scripts/build.sh

# The tests' scratch files in memory when there is a tmpfs (tests/support/temp_dir.h says why):
# every test that honours TMPDIR (pytest, the oracles, std::filesystem::temp_directory_path).
if [[ -z "${HYBRIDTEST_KEEP_TMPDIR:-}" && -d /dev/shm && -w /dev/shm ]]; then
  scratch=$(mktemp -d /dev/shm/hybridtest-tests.XXXXXX)
  export TMPDIR="$scratch"
fi
ctest_status=0
stage ctest ctest --preset release -j "${HYBRIDTEST_JOBS:-$(nproc)}" --timeout 900 \
  --output-junit "$root/$junit" "$@" || ctest_status=$?

fuzz_seconds=${HYBRIDTEST_FUZZ_SECONDS:-30}
if ((ctest_status == 0)) && [[ "$fuzz_seconds" != 0 ]]; then
  if command -v clang++ >/dev/null; then
    # shellcheck disable=SC2086  # a list of target names
    stage fuzz scripts/fuzz.sh "$fuzz_seconds" ${HYBRIDTEST_FUZZ_TARGETS:-frame_decoder bench_config openfresco_wire}
  else
    echo "hybridtest: clang++ not found, fuzz smoke tests skipped"
  fi
fi
((ctest_status == 0)) || exit "$ctest_status"

# The budget: CTest's wall time on a machine of CI's size (2 cores). A machine with fewer cores
# gets proportionally more; a filtered run (arguments given) is not checked.
if (($# == 0)); then
  budget=$(awk '$1 == "ctest_seconds_on_2_cores" { print $2 }' "$budget_file")
  cores=$(nproc)
  ((cores >= 2)) || budget=$((budget * 2 / cores))
  took=$(awk '$1 == "ctest" { printf "%d", $2 }' "$HYBRIDTEST_STAGE_LOG")
  if ((took > budget)); then
    echo "hybridtest: CTest took ${took} s, over its budget of ${budget} s" \
      "($budget_file, ctest_seconds_on_2_cores): the slowest tests are listed below;" \
      "shorten them (a shorter run that checks the same property) or raise the budget" \
      "with a reason in that file" >&2
    exit 1
  fi
  echo "hybridtest: CTest took ${took} s of its ${budget} s budget ($budget_file)"
fi
