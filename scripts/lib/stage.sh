# Sourced by scripts/build.sh and scripts/test.sh.
# stage NAME COMMAND...: runs COMMAND; when HYBRIDTEST_STAGE_LOG names a file, appends
# "NAME SECONDS" (wall clock) to it, so that scripts/test.sh can print where the time went.
stage() {
  local name=$1 t0 t1
  shift
  t0=$(date +%s.%N)
  "$@"
  t1=$(date +%s.%N)
  if [[ -n "${HYBRIDTEST_STAGE_LOG:-}" ]]; then
    awk -v n="$name" -v a="$t0" -v b="$t1" 'BEGIN { printf "%s %.1f\n", n, b - a }' \
      >>"$HYBRIDTEST_STAGE_LOG"
  fi
}
