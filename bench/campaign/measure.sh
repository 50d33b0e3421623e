#!/bin/bash
# Campaign throughput and overhead (docs/campaigns.md, "Measured"): N short simulations of the
# paper's rotor (examples/rotor/numerical.yaml, `duration` seconds each, wind load f_w varied)
# as one campaign with 1, 2 and 4 MPI ranks and with 1, 2 and 4 local worker threads, against
# the same cases run as separate `hybridtest simulate` processes, one after the other.
#   bench/campaign/measure.sh [BINARY] [N] [DURATION]
# Wall times [s] go to stdout; beyond the machine's cores the MPI runs are oversubscribed
# (`--oversubscribe`) and say so.
set -euo pipefail
HT=$(realpath "${1:-build/release/apps/hybridtest/hybridtest}")
N=${2:-200}
DURATION=${3:-2.0}
SRC=$(cd "$(dirname "$0")/../.." && pwd)
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
CORES=$(nproc)
values=$(seq -s, 1 "$N")
cat > "$WORK/campaign.yaml" <<YAML
base: $SRC/examples/rotor/numerical.yaml
set: {duration: $DURATION}
grid: {model.parameters.f_w: [$values]}
metrics: [max_abs(q1)]
figures: false
YAML
# label, command...: wall time and CPU time (user + system, children included) [s].
run() {
  local label=$1; shift
  /usr/bin/time -f "%e %U %S" -o "$WORK/time" "$@" > "$WORK/last.log" 2>&1 ||
    { cat "$WORK/last.log"; exit 1; }
  read -r wall user sys < "$WORK/time"
  printf '%-46s wall %7.2f s (%6.1f ms/case)  cpu %6.2f s (%5.1f ms/case)\n' "$label" "$wall" \
    "$(echo "$wall * 1000 / $N" | bc -l)" "$(echo "$user + $sys" | bc -l)" \
    "$(echo "($user + $sys) * 1000 / $N" | bc -l)"
}
echo "$N cases of the paper's rotor, ${DURATION} s each, on $CORES cores ($(uname -n))"
run "campaign, local, 1 worker" "$HT" campaign "$WORK/campaign.yaml" --out "$WORK/l1" --workers 1 --quiet
# The cases' configs of the first campaign, run as separate processes.
cat > "$WORK/separate.sh" <<'SH'
set -e
mkdir -p "$2/sep"
for dir in "$2"/l1/cases/*/; do
  "$1" simulate "$dir/config.yaml" --out "$2/sep/$(basename "$dir").csv" --quiet
done
SH
run "separate simulate processes, one at a time" bash "$WORK/separate.sh" "$HT" "$WORK"
cat > "$WORK/separate2.sh" <<'SH'
set -e
mkdir -p "$2/sep2"
ls -d "$2"/l1/cases/*/ | xargs -P 2 -I{} sh -c '"$0" simulate "$1/config.yaml" --out "$2/sep2/$(basename "$1").csv" --quiet' "$1" {} "$2"
SH
run "separate simulate processes, 2 at a time" bash "$WORK/separate2.sh" "$HT" "$WORK"
run "campaign, local, 2 workers" "$HT" campaign "$WORK/campaign.yaml" --out "$WORK/l2" --workers 2 --quiet
run "campaign, local, 4 workers" "$HT" campaign "$WORK/campaign.yaml" --out "$WORK/l4" --workers 4 --quiet
if command -v mpirun > /dev/null && "$HT" campaign --help | grep -q "MPI: built with"; then
  for n in 1 2 4; do
    note=""
    [ "$n" -gt "$CORES" ] && note=" (oversubscribed)"
    run "campaign, mpirun -n $n$note" mpirun --allow-run-as-root -n "$n" --oversubscribe \
      "$HT" campaign "$WORK/campaign.yaml" --out "$WORK/m$n" --quiet
  done
else
  echo "MPI runs skipped: mpirun or an MPI-built hybridtest is missing"
fi
