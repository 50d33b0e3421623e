#!/usr/bin/env bash
# Random kill-and-resume trials beyond the test suite's (docs/safety.md, "Resuming a run").
#   scripts/kill-test.sh [TRIALS] [CONFIG]
# Runs CONFIG (default examples/rotor/dummy.yaml) once to the end as the reference, then
# TRIALS times (default 20): starts it, kills it with SIGKILL after a random delay, resumes it
# (repeatedly, if a resume is killed too — every third trial kills the resume once as well),
# and compares the final journal with the reference, bit for bit except the *_lab_time
# columns. Prints one line per trial and a summary; exits 1 if any trial differs.
# Needs a release build (./scripts/build.sh). In-process configs only: a bench server holds
# where the previous run left it, so a new run's first command would be refused (the test
# suite covers remote runs with a fresh server per run). TMPDIR=/dev/shm makes fsync free.
set -euo pipefail
cd "$(dirname "$0")/.."
trials=${1:-20}
config=${2:-examples/rotor/dummy.yaml}
bin=build/release/apps/hybridtest/hybridtest
bench_args=()
dir=$(mktemp -d "${TMPDIR:-/tmp}/hybridtest-kill-test.XXXXXX")
trap 'rm -rf "$dir"' EXIT

"$bin" run "$config" --out "$dir/reference.csv" --quiet "${bench_args[@]}"
start=$(date +%s.%N)
"$bin" run "$config" --out "$dir/timing.csv" --quiet "${bench_args[@]}"
duration=$(awk -v a="$start" -v b="$(date +%s.%N)" 'BEGIN { print b - a }')

# The columns to compare: all but *_lab_time.
keep=$(head -1 "$dir/reference.csv" | tr ',' '\n' | grep -vn '_lab_time$' | cut -d: -f1 | paste -sd,)
failed=0
for ((i = 1; i <= trials; i++)); do
  csv="$dir/trial$i.csv"
  delay=$(awk -v d="$duration" -v r="$RANDOM" 'BEGIN { printf "%.3f", d * (r % 90 + 5) / 100 }')
  "$bin" run "$config" --out "$csv" --quiet "${bench_args[@]}" & pid=$!
  sleep "$delay"; kill -9 "$pid" 2>/dev/null || true; wait "$pid" 2>/dev/null || true
  resumes=0
  if [[ ! -e "${csv%.csv}.state.json" ]]; then
    # Killed before row 0 was committed: nothing to resume, the operator starts again.
    "$bin" run "$config" --out "$csv" --quiet --overwrite "${bench_args[@]}"
  fi
  if ((i % 3 == 0)) && ! grep -q '"status": "completed"' "${csv%.csv}.meta.json"; then
    "$bin" resume "$csv" --quiet "${bench_args[@]}" & pid=$!
    sleep "$(awk -v d="$delay" 'BEGIN { printf "%.3f", d / 2 }')"; kill -9 "$pid" 2>/dev/null || true
    wait "$pid" 2>/dev/null || true
    resumes=1
  fi
  status=0
  if ! grep -q '"status": "completed"' "${csv%.csv}.meta.json"; then
    "$bin" resume "$csv" --quiet "${bench_args[@]}" || status=$?
    resumes=$((resumes + 1))
  fi
  if [[ $status -eq 0 ]] && cmp -s <(cut -d, -f"$keep" "$dir/reference.csv") <(cut -d, -f"$keep" "$csv"); then
    echo "trial $i: killed after ${delay} s, $resumes resume(s): identical"
  else
    echo "trial $i: killed after ${delay} s, $resumes resume(s): DIFFERS (resume status $status)"
    failed=$((failed + 1))
  fi
done
echo "kill test: $trials trials of $config, $failed differing"
[[ $failed -eq 0 ]]
