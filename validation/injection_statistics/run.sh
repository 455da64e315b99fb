#!/bin/bash
# The runs of the injection-statistics study (validation/README.md): the
# classic scene at f = 25 at (injection speed, time step factor, seed) as
# listed below. Finished runs (with a summary.json) are skipped.
#   WIREFEM=build-ci/wirefem RUNS=build-ci/injection_statistics validation/injection_statistics/run.sh
set -e
cd "$(dirname "$0")/../.."
WIREFEM=${WIREFEM:-build-ci/wirefem}
RUNS=${RUNS:-build-ci/injection_statistics}
mkdir -p "$RUNS"
while read -r speed factor seed; do
  out=$RUNS/v${speed}_f${factor}_s$seed
  [ -f "$out/summary.json" ] && continue
  "$WIREFEM" prm/classic.prm --set Cavity/Radius=25 --set Injection/Speed="$speed" \
    --set "Discrete/Time step factor=$factor" --set Injection/Seed="$seed" \
    --set Output/Directory="$out" --set Output/Progress=off < /dev/null > "$out.log" 2>&1
done <<'LIST'
0.3 0.25 1
0.3 0.125 1
0.1 0.25 1
0.3 0.25 2
0.3 0.125 2
0.1 0.25 2
0.3 0.25 3
0.3 0.125 3
0.1 0.25 3
0.3 0.25 4
0.3 0.125 4
0.1 0.25 4
0.3 0.0625 1
0.3 0.0625 2
LIST
