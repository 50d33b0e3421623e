# Sourced by scripts/build.sh and scripts/test.sh.
# stage NAME COMMAND...: runs COMMAND and returns its exit status; when HYBRIDTEST_STAGE_LOG
# names a file, appends "NAME SECONDS" (wall clock) to it, so that scripts/test.sh can print
# where the time went. (The status is kept explicitly: called as `stage ... || x`, bash runs the
# function without errexit, and a failing COMMAND must still fail the stage.)
stage() {
  local name=$1 t0 t1 status=0
  shift
  t0=$(date +%s.%N)
  "$@" || status=$?
  t1=$(date +%s.%N)
  if [[ -n "${HYBRIDTEST_STAGE_LOG:-}" ]]; then
    awk -v n="$name" -v a="$t0" -v b="$t1" 'BEGIN { printf "%s %.1f\n", n, b - a }' \
      >>"$HYBRIDTEST_STAGE_LOG"
  fi
  return "$status"
}
