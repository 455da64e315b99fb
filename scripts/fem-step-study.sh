#!/usr/bin/env bash
# Work against precision of the rod FEM's largest time step (FEM/Time step)
# on one scene to its end, over seeds, beside the discrete model: one row
# per run and one per step size with the means (phi at the end, loops,
# steps, wall time, energy balance error). Runs already finished in OUT are
# reused, so the study can be run in pieces.
#   scripts/fem-step-study.sh SCENE.prm "STEPS" "SEEDS" [extra --set arguments...]
# Example: scripts/fem-step-study.sh prm/classic.prm "0.025 0.05 0.1 0.2" "1 2 3" \
#            --set Cavity/Radius=15
# Environment: WIREFEM (default ./build/wirefem), OUT (default
# output/fem-step-study).
set -u
exe=${WIREFEM:-./build/wirefem}
[ $# -ge 3 ] || { echo "usage: $0 SCENE.prm \"STEPS\" \"SEEDS\" [--set Key=value ...]" >&2; exit 2; }
scene=$1 steps=$2 seeds=$3
shift 3
out=${OUT:-output/fem-step-study}
mkdir -p "$out"
run() { # DIR ARGS...
  local dir=$1
  shift
  [ -f "$dir/summary.json" ] && return
  "$exe" "$scene" "$@" --replace --set Output/Directory="$dir" --set Output/Progress=off \
    --set "Output/VTU interval=0" > "$dir.log" 2>&1
}
for seed in $seeds; do
  run "$out/chain_$seed" "$@" --set Model=discrete --set Injection/Seed="$seed"
  for dt in $steps; do
    run "$out/fem_${dt}_$seed" "$@" --set Model=fem --set Injection/Seed="$seed" --set "FEM/Time step=$dt"
  done
done
python3 - "$out" "$steps" "$seeds" <<'PY'
import json, statistics, sys
out, steps, seeds = sys.argv[1], sys.argv[2].split(), sys.argv[3].split()
def row(name, dirs):
    runs = []
    for d in dirs:
        try:
            runs.append(json.load(open(f"{out}/{d}/summary.json")))
        except (OSError, ValueError):
            print(f"| {name} | {d}: no summary (see {out}/{d}.log) |")
    if not runs:
        return
    mean = lambda key: statistics.mean(r[key] for r in runs)
    spread = lambda key: statistics.stdev(r[key] for r in runs) if len(runs) > 1 else 0.0
    balance = max(abs(r["energy"]["balance_error"]) for r in runs if r["energy"].get("balance_error") is not None)
    print(f"| {name} | {len(runs)} | {mean('phi_final'):.4f} +- {spread('phi_final'):.4f} "
          f"| {mean('loops'):.1f} +- {spread('loops'):.1f} | {sum(r['failed'] for r in runs)} "
          f"| {mean('steps'):.0f} | {mean('wall_time_s'):.1f} | {balance:.2e} |")
print("| model | runs | phi at the end | loops | failed | steps | wall (s) | worst balance error |")
print("|---|---|---|---|---|---|---|---|")
row("discrete", [f"chain_{s}" for s in seeds])
for dt in steps:
    row(f"fem, step <= {dt}", [f"fem_{dt}_{s}" for s in seeds])
PY
