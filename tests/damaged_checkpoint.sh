#!/usr/bin/env bash
# A damaged checkpoint is refused: interrupt a run, then resume it with
# checkpoint.bin damaged in three ways (16 bytes overwritten in the middle,
# one byte flipped, the last 100 bytes cut). Each resume must exit 2 with
# one line saying the checkpoint is damaged, and leave every file of the
# run directory as it was. The undamaged checkpoint then resumes (exit 0).
set -u
exe=$1; prm=$2; out=$3
rm -rf "$out"; mkdir -p "$out"
args=(--set Cavity/Radius=25 --set Output/Progress=off --set "Output/VTU interval=0" --set Output/Directory="$out/run")
"$exe" "$prm" "${args[@]}" > "$out/part1.log" 2>&1 &
pid=$!
for _ in $(seq 1 600); do [ -s "$out/run/series.csv" ] && break; sleep 0.1; done
sleep 1
kill -INT $pid
wait $pid
[ -f "$out/run/checkpoint.bin" ] || { echo "FAIL: no checkpoint written"; exit 1; }
cp "$out/run/checkpoint.bin" "$out/good.bin"
for damage in overwrite flip cut; do
  cp "$out/good.bin" "$out/run/checkpoint.bin"
  python3 - "$out/run/checkpoint.bin" "$damage" <<'PY'
import sys
path, damage = sys.argv[1], sys.argv[2]
data = bytearray(open(path, "rb").read())
mid = len(data) // 2
if damage == "overwrite":
    data[mid:mid + 16] = b"\xff" * 16
elif damage == "flip":
    data[mid] ^= 0x01
else:
    data = data[:-100]
open(path, "wb").write(bytes(data))
PY
  before=$(cd "$out/run" && find . -type f | sort | xargs md5sum)
  "$exe" "$prm" "${args[@]}" --resume > "$out/$damage.log" 2>&1
  rc=$?
  after=$(cd "$out/run" && find . -type f | sort | xargs md5sum)
  [ $rc -eq 2 ] || { echo "FAIL: $damage: exit $rc, expected 2"; cat "$out/$damage.log"; exit 1; }
  grep -q "checkpoint.bin: cannot resume: damaged" "$out/$damage.log" || { echo "FAIL: $damage: message"; cat "$out/$damage.log"; exit 1; }
  [ "$(wc -l < "$out/$damage.log")" -eq 1 ] || { echo "FAIL: $damage: more than one line"; cat "$out/$damage.log"; exit 1; }
  [ "$before" = "$after" ] || { echo "FAIL: $damage: the run directory changed"; exit 1; }
done
cp "$out/good.bin" "$out/run/checkpoint.bin"
"$exe" "$prm" "${args[@]}" --resume > "$out/good.log" 2>&1 || { echo "FAIL: the undamaged checkpoint did not resume"; exit 1; }
echo "PASS: damaged checkpoints refused (exit 2, one line, nothing changed); the undamaged one resumes"
