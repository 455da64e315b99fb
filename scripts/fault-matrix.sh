#!/usr/bin/env bash
# The fault matrix: wirefem tried as an adversarial user would (damaged
# checkpoints, resumes onto other files, runs into earlier results, sizes
# and places it cannot have, duplicate keys, extreme stiffness, binary
# scene files, errors on MPI ranks, large shapes for analyze). One row per
# case: the exit status expected and got, whether the message is one line
# naming what it should, and whether earlier results were left intact.
#   scripts/fault-matrix.sh [WIREFEM] [OUT]
# Exit status 0 when every row passes. About 2 minutes. The analyze rows
# report their wall time (the target: 10^6 points in under 10 s).
set -u
exe=$(realpath "${1:-./build/wirefem}")
out=${2:-output/fault-matrix}
root=$(cd "$(dirname "$0")/.." && pwd)
quick=$root/prm/quick.prm
classic=$root/prm/classic.prm
rm -rf "$out"
mkdir -p "$out"
out=$(realpath "$out")
cd "$out" || exit 2
failures=0
echo "| case | expected | exit | message (first 110 characters) | one line | names | earlier results | result |"
echo "|---|---|---|---|---|---|---|---|"

snapshot() { # DIR: checksums of every file below it (empty if none)
  [ -d "$1" ] && (cd "$1" && find . -type f | sort | xargs -r md5sum) || true
}

# row CASE EXPECTED_EXIT WORD DIR_TO_KEEP COMMAND...: runs the command,
# prints the row. WORD must appear in stderr; DIR_TO_KEEP ("-" for none)
# must hold the same files before and after.
row() {
  local name=$1 expected=$2 word=$3 keep=$4
  shift 4
  local before after rc msg lines intact="-" named ok=PASS
  [ "$keep" != "-" ] && before=$(snapshot "$keep")
  "$@" > stdout.txt 2> stderr.txt
  rc=$?
  # mpirun adds its own report after a rank's error: count wirefem's lines.
  if [ "$1" = mpirun ]; then lines=$(grep -c '^wirefem' stderr.txt); else lines=$(grep -c '' stderr.txt); fi
  msg=$(head -c 110 stderr.txt | head -1 | tr '|' '/')
  if [ "$keep" != "-" ]; then
    after=$(snapshot "$keep")
    [ "$before" = "$after" ] && intact=yes || intact=CHANGED
  fi
  if [ -z "$word" ]; then named=-; elif cat stderr.txt stdout.txt | grep -qF -- "$word"; then named=yes; else named=NO; fi
  [ "$rc" = "$expected" ] || ok=FAIL
  [ "$named" = NO ] && ok=FAIL
  [ "$intact" = CHANGED ] && ok=FAIL
  if [ "$expected" = 2 ] && [ "$lines" != 1 ]; then ok=FAIL; fi
  [ $ok = PASS ] || failures=$((failures + 1))
  echo "| $name | $expected | $rc | \`$msg\` | $([ "$lines" = 1 ] && echo yes || echo "$lines lines") | $named | $intact | $ok |"
}

# An interrupted run of the classic scene at f = 20 (its checkpoint and
# series), copied for each case that damages it.
args=(--set Cavity/Radius=20 --set Output/Progress=off --set "Output/VTU interval=50")
"$exe" "$classic" "${args[@]}" --set Output/Directory=base > base.log 2>&1 &
pid=$!
for _ in $(seq 1 600); do [ -s base/series.csv ] && break; sleep 0.1; done
sleep 1.5
kill -INT $pid
wait $pid
[ -f base/checkpoint.bin ] || { echo "no checkpoint from the interrupted run (see $out/base.log)"; exit 1; }
fresh() { rm -rf run; cp -r base run; }
damage() { # FILE KIND
  python3 - "$1" "$2" <<'PY'
import sys
path, kind = sys.argv[1], sys.argv[2]
data = bytearray(open(path, "rb").read())
mid = len(data) // 2
if kind == "ff16":
    data[mid:mid + 16] = b"\xff" * 16
elif kind == "flip":
    data[mid] ^= 0x01
elif kind == "zero2000":
    data[mid - 1000:mid + 1000] = bytes(2000)
elif kind == "cut":
    data = data[:mid]
elif kind == "half":  # series.csv: the first half of its lines
    lines = data.split(b"\n")
    data = b"\n".join(lines[: len(lines) // 2]) + b"\n"
open(path, "wb").write(bytes(data))
PY
}
resume=("$exe" "$classic" "${args[@]}" --set Output/Directory=run --resume)

for kind in ff16 flip zero2000 cut; do
  fresh
  damage run/checkpoint.bin $kind
  row "checkpoint: $kind" 2 "checkpoint.bin: cannot resume: damaged" run "${resume[@]}"
done
fresh
row "interrupted run started again without --resume" 2 "holds an interrupted run" run \
  "$exe" "$classic" "${args[@]}" --set Output/Directory=run
fresh
damage run/series.csv half
row "series.csv shorter than the checkpoint's" 2 "series.csv: cannot resume" run "${resume[@]}"
fresh
printf '1,2,3\n' >> run/series.csv
sed -i '3s/.*/1,x/' run/series.csv
row "series.csv with a damaged row" 2 "is damaged" run "${resume[@]}"
fresh
rm run/series.csv
row "series.csv missing" 2 "series.csv: cannot resume" run "${resume[@]}"
fresh
row "resume with another Output/Interval" 2 "Output/Interval" run "${resume[@]}" --set Output/Interval=2
fresh
row "--resume and --replace together" 2 "exclude each other" run "${resume[@]}" --replace

# A finished run (quick scene) and what may happen to it.
"$exe" "$quick" --set Output/Directory=done --set Output/Progress=off > done.log 2>&1
row "run into a finished run's directory" 2 "holds an earlier run" done \
  "$exe" "$quick" --set Output/Directory=done --set Output/Progress=off
row "--resume a finished run" 2 "no checkpoint to resume from" done \
  "$exe" "$quick" --set Output/Directory=done --set Output/Progress=off --resume
cp -r done replaced
touch replaced/notes.txt replaced/wire_00999.vtu
row "--replace a finished run (exit 0)" 0 "" - \
  "$exe" "$quick" --set Output/Directory=replaced --set Output/Progress=off --set "Output/VTU interval=20" --replace
stale=$( [ -f replaced/wire_00999.vtu ] && echo "stale VTU left" ; [ -f replaced/notes.txt ] || echo "notes.txt deleted")
vtus=$(ls replaced/wire_*.vtu | wc -l)
entries=$(grep -c 'file=' replaced/wire.pvd)
if [ -n "$stale" ] || [ "$vtus" != "$entries" ]; then
  echo "| --replace: the old run's files gone, others kept | | | $stale; $vtus VTU files, $entries in wire.pvd | | | | FAIL |"
  failures=$((failures + 1))
else
  echo "| --replace: the old run's files gone, others kept | | | $vtus VTU files, all in wire.pvd; notes.txt kept | | | | PASS |"
fi

# Sizes and places.
for model in discrete fem; do
  row "radius 1e9 ($model)" 2 "Cavity/Radius" - "$exe" "$classic" --set Model=$model --set Cavity/Radius=1e9 \
    --set Output/Directory=big
done
row "radius 1e5" 2 "Cavity/Radius" - "$exe" "$classic" --set Cavity/Radius=1e5 --set Output/Directory=big
for r in 1.0001 2 3.5; do
  row "radius $r" 2 "Cavity/Radius" - "$exe" "$classic" --set Cavity/Radius=$r --set Output/Directory=small
done
touch a_file
row "Output/Directory is a file" 2 "Output/Directory" - "$exe" "$quick" --set Output/Directory=a_file
row "Output/Directory under a file" 2 "Output/Directory" - "$exe" "$quick" --set Output/Directory=a_file/run
row "Output/Directory cannot be created" 2 "Output/Directory" - "$exe" "$quick" --set Output/Directory=/proc/wirefem
row "a directory as the scene" 2 "is a directory" - "$exe" "$root/prm"
printf 'subsection Cavity\n  set Radius = 12\nend\nsubsection Cavity\n  set Radius = 14\nend\n' > twice.prm
row "a key set twice in one file" 2 "set again (first set on line 2)" - "$exe" twice.prm --set Output/Directory=twice
python3 -c "import random, sys; random.seed(5); sys.stdout.buffer.write(bytes(random.randrange(256) for _ in range(300)))" > binary.prm
printf '\033[31mred\033]0;title\007\n' >> binary.prm
row "binary scene file" 2 "binary.prm" - "$exe" binary.prm --set Output/Directory=binary
if grep -q $'\033' stderr.txt; then
  echo "| binary scene file: no escape character reaches the terminal | | | raw ESC in the message | | | | FAIL |"
  failures=$((failures + 1))
fi

# Quality alarms: a stiff contact (a tiny step, interrupted after 2 s) and
# the FEM with 100x the contact stiffness (its energy ledger does not close).
"$exe" "$quick" --set "Contact/Normal stiffness=1e12" --set Output/Directory=stiff --set Output/Progress=off \
  > /dev/null 2> stiff.err &
pid=$!
sleep 2
kill -INT $pid
wait $pid
rc=$?
if grep -q "warning: time step .* is below" stiff.err; then r=PASS; else r=FAIL; failures=$((failures + 1)); fi
echo "| contact stiffness 1e12: a warning at the start | 130 | $rc | \`$(head -c 110 stiff.err | head -1)\` | | | | $r |"
row "FEM, 100x the contact stiffness, automatic step (a fifth of the contact period)" 0 "" - \
  "$exe" "$quick" --set Model=fem --set "Contact/Normal stiffness=200000" --set Output/Directory=fem_stiff_auto \
  --set Output/Progress=off
python3 -c "import json,sys; s=json.load(open('fem_stiff_auto/summary.json')); e=s['energy']['balance_error']; print(f'| ... its energy balance error | | | {e:.2e} | | | | {\"PASS\" if abs(e) < 0.01 else \"FAIL\"} |'); sys.exit(abs(e) >= 0.01)" \
  || failures=$((failures + 1))
row "FEM, 100x the contact stiffness, step held at 0.025: balance alarm, failed" 3 "energy balance error" - \
  "$exe" "$quick" --set Model=fem --set "Contact/Normal stiffness=200000" --set "FEM/Time step=0.025" \
  --set Output/Directory=fem_stiff --set Output/Progress=off
python3 -c "import json,sys; s=json.load(open('fem_stiff/summary.json')); sys.exit(0 if s['failed'] and s['warnings'] else 1)" \
  && echo "| ... its summary.json: failed true, the warning recorded | | | | | | | PASS |" \
  || { echo "| ... its summary.json: failed true, the warning recorded | | | | | | | FAIL |"; failures=$((failures + 1)); }
row "overlap stop with a stiff contact names the step" 3 "time step is too coarse" - \
  "$exe" "$quick" --set "Contact/Normal stiffness=20000" --set "Discrete/Time step=0.02" \
  --set Output/Directory=coarse --set Output/Progress=off

# MPI: a bad sweep file on two ranks gives one message.
if command -v mpirun > /dev/null; then
  printf 'subsection Sweep\n  set No such key = 1\nend\n' > bad_sweep.prm
  row "bad sweep file on 2 MPI ranks" 2 "bad_sweep.prm" - \
    mpirun --allow-run-as-root --oversubscribe -np 2 "$exe" sweep bad_sweep.prm
fi

# wirefem analyze on a tight spiral of N points (every point in contact).
for n in 10000 100000 1000000; do
  python3 - $n <<'PY'
import math, sys
n = int(sys.argv[1])
with open(f"spiral_{n}.csv", "w") as f:
    f.write("x,y\n")
    th = 0.0
    for _ in range(n):
        r = 3.0 + th / (2 * math.pi) * 0.95
        f.write(f"{r * math.cos(th):.6f},{r * math.sin(th):.6f}\n")
        th += 0.5 / r
PY
  start=$(date +%s.%N)
  "$exe" analyze spiral_$n.csv > analyze_$n.json 2> analyze_$n.err
  rc=$?
  t=$(echo "$(date +%s.%N) - $start" | bc)
  loops=$(python3 -c "import json; print(json.load(open('analyze_$n.json'))['loops'])" 2>/dev/null)
  r=PASS
  # The time is reported, not asserted (shared machines are noisy).
  if [ $rc != 0 ] || [ "$loops" != 1 ]; then
    r=FAIL; failures=$((failures + 1))
  fi
  printf '| analyze, spiral of %s points | 0 | %s | %.1f s, %s loop(s) | | | | %s |\n' $n $rc "$t" "$loops" $r
done
echo
echo "$failures failing rows (outputs in $out)"
[ $failures = 0 ]
