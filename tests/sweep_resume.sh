#!/bin/bash
# The phase-diagram sweep on 2 MPI ranks, stopped midway (SIGTERM) and
# rerun: cases finished before the stop are not run again, the rest are,
# and the phase diagram is drawn. Usage: sweep_resume.sh WIREFEM SWEEP.prm WORKDIR
set -u
exe=$1 sweep=$2 work=$3
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
rm -rf "$work" && mkdir -p "$work" && cd "$work" || exit 1
out=sweep-small
# Finished cases: a summary.json not written by an interrupted run.
finished() { grep -l '"interrupted": false' $(find "$out" -name summary.json 2>/dev/null) /dev/null 2>/dev/null | sort; }
count() { finished | wc -l; }

mpirun -np 2 "$exe" sweep "$sweep" > first.log 2>&1 &
pid=$!
for _ in $(seq 1 3000); do # up to a minute on a loaded machine
  [ "$(count)" -ge 6 ] && break
  sleep 0.02
done
kill -TERM $pid
wait $pid
before=$(count)
total=27
echo "stopped with $before of $total cases finished"
if [ "$before" -lt 6 ] || [ "$before" -ge $total ]; then
  echo "FAIL: the sweep was not stopped midway ($before finished)"; exit 1
fi
finished > finished-before.txt
touch marker
sleep 1.1 # file times are compared at one-second resolution at worst

mpirun -np 2 "$exe" sweep "$sweep" > second.log 2>&1 || { echo "FAIL: rerun exit $?"; cat second.log; exit 1; }
cat second.log
after=$(count)
[ "$after" -eq $total ] || { echo "FAIL: $after of $total cases finished after the rerun"; exit 1; }
rerun=$(find "$out" -name summary.json -newer marker | sort)
again=$(comm -12 finished-before.txt <(echo "$rerun"))
[ -z "$again" ] || { echo "FAIL: finished cases were run again: $again"; exit 1; }
skipped=$(grep -o '[0-9]* already finished' second.log | awk '{s += $1} END {print s}')
[ "$skipped" -eq "$before" ] || { echo "FAIL: skipped $skipped, expected $before"; exit 1; }
for f in sweep.csv cells.csv phase_diagram.png phase_diagram.svg; do
  [ -s "$out/$f" ] || { echo "FAIL: no $out/$f"; exit 1; }
done
[ "$(grep -c ',finished,' "$out/sweep.csv")" -eq $total ] || { echo "FAIL: sweep.csv lacks finished rows"; exit 1; }
echo "PASS: $before finished before the stop were skipped, $((total - before)) run after it"
