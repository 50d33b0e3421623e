#!/usr/bin/env bash
# Builds the libFuzzer targets (the `fuzz` preset: clang, ASan, UBSan, build/fuzz) and runs each
# one in turn, starting from the seed corpus in fuzz/corpus/<target>/.
#
#   scripts/fuzz.sh [SECONDS_PER_TARGET] [TARGET...]
#
# SECONDS_PER_TARGET defaults to $HYBRIDTEST_FUZZ_SECONDS or 600. TARGETs default to all:
# frame_decoder run_config bench_config run_state openfresco_wire. New inputs that reach new code are written to
# build/fuzz/corpus/<target>/ (the seed corpus in the repo is only read); crashes go to
# build/fuzz/findings/<target>/ and make the script fail. Targets run one at a time, at low
# priority (nice), with one worker each.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"
seconds=${1:-${HYBRIDTEST_FUZZ_SECONDS:-600}}
shift || true
targets=("$@")
((${#targets[@]})) || targets=(frame_decoder run_config bench_config run_state openfresco_wire)

if ! command -v clang++ >/dev/null; then
  echo "hybridtest fuzz: clang++ is not installed (scripts/install-deps.sh installs it)" >&2
  exit 1
fi
if [[ ! -f build/fuzz/build.ninja ]]; then
  cmake --preset fuzz >/dev/null
fi
cmake --build --preset fuzz -j "${HYBRIDTEST_JOBS:-$(nproc)}" \
  --target "${targets[@]/#/fuzz_}"

status=0
# A third-party library's one-time allocation at start-up is not a finding (fuzz/lsan.supp).
export LSAN_OPTIONS="suppressions=$root/fuzz/lsan.supp${LSAN_OPTIONS:+:$LSAN_OPTIONS}"
for t in "${targets[@]}"; do
  mkdir -p "build/fuzz/corpus/$t" "build/fuzz/findings/$t"
  echo "hybridtest fuzz: $t for ${seconds} s"
  # -rss_limit_mb bounds memory; -timeout flags an input that takes more than 10 s.
  if ! nice -n 19 "build/fuzz/fuzz/fuzz_$t" "build/fuzz/corpus/$t" "fuzz/corpus/$t" \
      -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -max_len=65536 \
      -artifact_prefix="build/fuzz/findings/$t/" -print_final_stats=1; then
    echo "hybridtest fuzz: $t FOUND A PROBLEM; the input is in build/fuzz/findings/$t/" >&2
    status=1
  fi
done
exit $status
