#!/bin/bash
# The runs of the injection-statistics study (validation/README.md): the
# classic scene at (cavity radius f, injection speed, time step factor,
# seed) as listed below: f = 25 and f = 15 for the speed down to the
# quasi-static limit, f = 25 for the time step. Finished runs (with a
# summary.json) are skipped.
#   WIREFEM=build-ci/wirefem RUNS=build-ci/injection_statistics validation/injection_statistics/run.sh
set -e
cd "$(dirname "$0")/../.."
WIREFEM=${WIREFEM:-build-ci/wirefem}
RUNS=${RUNS:-build-ci/injection_statistics}
mkdir -p "$RUNS"
while read -r radius speed factor seed; do
  out=$RUNS/v${speed}_f${factor}_s$seed
  [ "$radius" = 25 ] || out=$RUNS/r${radius}_v${speed}_f${factor}_s$seed
  [ -f "$out/summary.json" ] && continue
  "$WIREFEM" prm/classic.prm --set Cavity/Radius="$radius" --set Injection/Speed="$speed" \
    --set "Discrete/Time step factor=$factor" --set Injection/Seed="$seed" \
    --set Output/Directory="$out" --set Output/Progress=off --replace < /dev/null > "$out.log" 2>&1
done <<'LIST'
25 0.3 0.25 1
25 0.3 0.125 1
25 0.1 0.25 1
25 0.3 0.25 2
25 0.3 0.125 2
25 0.1 0.25 2
25 0.3 0.25 3
25 0.3 0.125 3
25 0.1 0.25 3
25 0.3 0.25 4
25 0.3 0.125 4
25 0.1 0.25 4
25 0.3 0.0625 1
25 0.3 0.0625 2
25 0.03 0.25 1
25 0.03 0.25 2
25 0.03 0.25 3
25 0.01 0.25 1
25 0.01 0.25 2
25 0.01 0.25 3
25 0.003 0.25 1
25 0.003 0.25 2
25 0.003 0.25 3
15 0.3 0.25 1
15 0.3 0.25 2
15 0.3 0.25 3
15 0.1 0.25 1
15 0.1 0.25 2
15 0.1 0.25 3
15 0.03 0.25 1
15 0.03 0.25 2
15 0.03 0.25 3
15 0.01 0.25 1
15 0.01 0.25 2
15 0.01 0.25 3
15 0.003 0.25 1
15 0.003 0.25 2
15 0.003 0.25 3
LIST
