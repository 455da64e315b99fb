#!/usr/bin/env bash
# Runs one scene with the discrete model and then with the rod FEM, back to
# back on the same machine, REPEAT times each (alternating), and prints one
# row per model: median wall time, phi at the end, loops, how it stopped,
# energy balance, largest overlap; the FEM's cost as a multiple of the
# chain's (ratio of the medians); and the FEM's wall time per Newton
# iteration and iterations per step.
#   scripts/models-back-to-back.sh SCENE.prm [extra --set arguments...]
# Example: scripts/models-back-to-back.sh prm/quick.prm --set Cavity/Radius=20 \
#            --set "Injection/Maximum packing density=0.35"
# Environment: WIREFEM (default ./build/wirefem), OUT (default
# output/back-to-back), REPEAT (default 3); SEEDS (e.g. "1 2 3": run r
# uses the r-th seed, REPEAT = their number); DISCRETE_SET and FEM_SET,
# --set arguments for one model only, e.g.
#   DISCRETE_SET="Injection/Speed=0.03" FEM_SET="FEM/Integrator=quasi-static"
# (split at semicolons if there is one, else at spaces:
#   FEM_SET="FEM/Step error=1e-2;FEM/Newton tolerance=1e-6").
set -u
exe=${WIREFEM:-./build/wirefem}
[ $# -ge 1 ] || { echo "usage: $0 SCENE.prm [--set Key=value ...]" >&2; exit 2; }
scene=$1; shift
out=${OUT:-output/back-to-back}
seeds=(${SEEDS:-})
repeat=${REPEAT:-3}
[ ${#seeds[@]} -eq 0 ] || repeat=${#seeds[@]}
mkdir -p "$out"
for r in $(seq 1 "$repeat"); do
  for model in discrete fem; do
    dir="$out/${model}_$r"
    extra=()
    [ ${#seeds[@]} -eq 0 ] || extra+=(--set "Injection/Seed=${seeds[$((r - 1))]}")
    if [ $model = discrete ]; then given=${DISCRETE_SET:-}; else given=${FEM_SET:-}; fi
    if [[ $given == *";"* ]]; then IFS=';' read -ra sets <<< "$given"; else sets=($given); fi
    for kv in "${sets[@]}"; do extra+=(--set "$kv"); done
    "$exe" "$scene" "$@" "${extra[@]}" --set Model=$model --replace --set Output/Directory="$dir" \
      --set Output/Progress=off --set "Output/VTU interval=0" > "$dir.log" 2>&1
    echo "$?" > "$dir.rc"
  done
done
python3 - "$out" "$repeat" <<'PY'
import json, statistics, sys
out, repeat = sys.argv[1], int(sys.argv[2])
print("| model | run | exit | stop | phi | loops | balance error | max overlap (d) | steps | wall (s) |")
print("|---|---|---|---|---|---|---|---|---|---|")
median, phis = {}, {}
for model in ("discrete", "fem"):
    walls = []
    for r in range(1, repeat + 1):
        code = open(f"{out}/{model}_{r}.rc").read().strip()
        try:
            s = json.load(open(f"{out}/{model}_{r}/summary.json"))
        except (OSError, ValueError):
            print(f"| {model} | {r} | {code} | no summary | | | | | | |")
            continue
        walls.append(s["wall_time_s"])
        phis.setdefault(model, []).append(s["phi_final"])
        print(f"| {model} | {r} | {code} | {s['stop_reason']} | {s['phi_final']:.4f} | "
              f"{s['loops']} | {s['energy']['balance_error']:.2e} | {s['max_penetration']:.4f} | "
              f"{s['steps']} | {s['wall_time_s']:.2f} |")
    if walls:
        median[model] = statistics.median(walls)
print()
for model, p in phis.items():
    spread = f" +- {statistics.stdev(p):.3f} (sd of {len(p)})" if len(p) > 1 else ""
    print(f"{model}: phi {statistics.mean(p):.3f}{spread}, median wall {median[model]:.2f} s")
if len(median) == 2 and median["discrete"] > 0:
    print(f"FEM / chain wall time: {median['fem'] / median['discrete']:.2f} (medians of {repeat})")
# The FEM's cost per Newton iteration (one linear solve and its assembly)
# and its iterations per step: runs are chaotic, so two builds of the FEM
# follow different trajectories and their wall times differ by more than
# their cost per iteration does.
per_iteration, per_step = [], []
for r in range(1, repeat + 1):
    try:
        s = json.load(open(f"{out}/fem_{r}/summary.json"))
    except (OSError, ValueError):
        continue
    iterations = s.get("solver_statistics", {}).get("newton_iterations", 0)
    if iterations > 0 and s["steps"] > 0:
        per_iteration.append(1e6 * s["wall_time_s"] / iterations)
        per_step.append(iterations / s["steps"])
if per_iteration:
    print(f"FEM: {statistics.median(per_iteration):.0f} us of wall time per Newton iteration, "
          f"{statistics.median(per_step):.2f} iterations per step (medians of {len(per_iteration)})")
PY
