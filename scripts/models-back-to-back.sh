#!/usr/bin/env bash
# Runs one scene with the discrete model and then with the rod FEM, back to
# back on the same machine, REPEAT times each (alternating), and prints one
# row per model: median wall time, phi at the end, loops, how it stopped,
# energy balance, largest overlap; and the FEM's cost as a multiple of the
# chain's (ratio of the medians).
#   scripts/models-back-to-back.sh SCENE.prm [extra --set arguments...]
# Example: scripts/models-back-to-back.sh prm/quick.prm --set Cavity/Radius=20 \
#            --set "Injection/Maximum packing density=0.35"
# Environment: WIREFEM (default ./build/wirefem), OUT (default
# output/back-to-back), REPEAT (default 3).
set -u
exe=${WIREFEM:-./build/wirefem}
[ $# -ge 1 ] || { echo "usage: $0 SCENE.prm [--set Key=value ...]" >&2; exit 2; }
scene=$1; shift
out=${OUT:-output/back-to-back}
repeat=${REPEAT:-3}
mkdir -p "$out"
for r in $(seq 1 "$repeat"); do
  for model in discrete fem; do
    dir="$out/${model}_$r"
    "$exe" "$scene" "$@" --set Model=$model --replace --set Output/Directory="$dir" --set Output/Progress=off \
      --set "Output/VTU interval=0" > "$dir.log" 2>&1
    echo "$?" > "$dir.rc"
  done
done
python3 - "$out" "$repeat" <<'PY'
import json, statistics, sys
out, repeat = sys.argv[1], int(sys.argv[2])
print("| model | exit | stop | phi | loops | balance error | max overlap (d) | steps | median wall (s) |")
print("|---|---|---|---|---|---|---|---|---|")
median = {}
for model in ("discrete", "fem"):
    walls, last = [], None
    codes = []
    for r in range(1, repeat + 1):
        codes.append(open(f"{out}/{model}_{r}.rc").read().strip())
        try:
            s = json.load(open(f"{out}/{model}_{r}/summary.json"))
        except (OSError, ValueError):
            continue
        walls.append(s["wall_time_s"])
        last = s
    if last is None:
        print(f"| {model} | {','.join(codes)} | no summary | | | | | | |")
        continue
    median[model] = statistics.median(walls)
    print(f"| {model} | {','.join(sorted(set(codes)))} | {last['stop_reason']} | {last['phi_final']:.4f} | "
          f"{last['loops']} | {last['energy']['balance_error']:.2e} | {last['max_penetration']:.4f} | "
          f"{last['steps']} | {median[model]:.2f} |")
if len(median) == 2 and median["discrete"] > 0:
    print(f"\nFEM / chain wall time: {median['fem'] / median['discrete']:.1f} (medians of {repeat})")
PY
