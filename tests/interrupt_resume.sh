#!/usr/bin/env bash
# Interrupts a run with SIGINT, resumes it with --resume, and compares the
# result with an uninterrupted run: summary and series.csv must be identical.
set -u
exe=$1; prm=$2; out=$3
rm -rf "$out"; mkdir -p "$out"
args=(--set Cavity/Radius=25 --set Output/Progress=off --set "Output/VTU interval=0")
"$exe" "$prm" "${args[@]}" --set Output/Directory="$out/straight" > "$out/straight.log" 2>&1 || exit 1
"$exe" "$prm" "${args[@]}" --set Output/Directory="$out/resumed" > "$out/part1.log" 2>&1 &
pid=$!
# Interrupt once the run is stepping (its signal handler is installed when
# it starts writing series.csv; a loaded machine may take seconds to get there).
for _ in $(seq 1 600); do [ -s "$out/resumed/series.csv" ] && break; sleep 0.1; done
sleep 1
kill -INT $pid
wait $pid; rc=$?
if [ $rc -ne 130 ]; then echo "expected exit 130 after SIGINT, got $rc (did the run end first?)"; exit 1; fi
[ -f "$out/resumed/checkpoint.bin" ] || { echo "no checkpoint written"; exit 1; }
"$exe" "$prm" "${args[@]}" --set Output/Directory="$out/resumed" --resume > "$out/part2.log" 2>&1 || exit 1
[ -f "$out/resumed/checkpoint.bin" ] && { echo "checkpoint left after a finished run"; exit 1; }
cmp "$out/straight/series.csv" "$out/resumed/series.csv" || { echo "series.csv differs"; exit 1; }
python3 - "$out" <<'PY' || exit 1
import json, sys
a = json.load(open(sys.argv[1] + "/straight/summary.json"))
b = json.load(open(sys.argv[1] + "/resumed/summary.json"))
for k in ["phi_final", "steps", "loops", "time", "force_final", "energy"]:
    assert a[k] == b[k], (k, a[k], b[k])
PY
# Resuming without a checkpoint is bad input.
"$exe" "$prm" "${args[@]}" --set Output/Directory="$out/none" --resume > /dev/null 2>&1
[ $? -eq 2 ] || { echo "resume without checkpoint should exit 2"; exit 1; }
echo "interrupted and resumed run identical to the straight run"
