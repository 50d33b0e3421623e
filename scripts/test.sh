#!/usr/bin/env bash
# The README's test command: builds if needed, then runs the whole test suite with CTest
# (unit, integration and SymPy oracle tests, and every fuzz target's seed corpus replayed,
# fuzz_replay.*), then, when clang is installed, a short libFuzzer run under ASan and UBSan of
# the decoders of bytes from the wire (HYBRIDTEST_FUZZ_TARGETS, default frame_decoder
# bench_config openfresco_wire: they need only the transfer layer, so the sanitized build stays
# small; HYBRIDTEST_FUZZ_SECONDS per target, default 30; 0 skips them). scripts/fuzz.sh runs
# every target, run_config and run_state included, for longer.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"
scripts/build.sh
# The tests' scratch files in memory when there is a tmpfs (tests/support/temp_dir.h says why):
# every test that honours TMPDIR (pytest, the oracles, std::filesystem::temp_directory_path).
if [[ -z "${HYBRIDTEST_KEEP_TMPDIR:-}" && -d /dev/shm && -w /dev/shm ]]; then
  scratch=$(mktemp -d /dev/shm/hybridtest-tests.XXXXXX)
  trap 'rm -rf "$scratch"' EXIT
  export TMPDIR="$scratch"
fi
ctest --preset release -j "${HYBRIDTEST_JOBS:-$(nproc)}" --timeout 900 "$@"
fuzz_seconds=${HYBRIDTEST_FUZZ_SECONDS:-30}
if [[ "$fuzz_seconds" != 0 ]]; then
  if command -v clang++ >/dev/null; then
    # shellcheck disable=SC2086  # a list of target names
    scripts/fuzz.sh "$fuzz_seconds" ${HYBRIDTEST_FUZZ_TARGETS:-frame_decoder bench_config openfresco_wire}
  else
    echo "hybridtest: clang++ not found, fuzz smoke tests skipped"
  fi
fi
