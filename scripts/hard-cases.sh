#!/usr/bin/env bash
# Runs the hard cases of the discrete model on a scene and prints one table
# row per case: how it stopped, phi, energy balance, largest overlap, time.
#   scripts/hard-cases.sh [SCENE.prm] [extra --set arguments...]
# Example: scripts/hard-cases.sh prm/quick.prm --set Cavity/Radius=25
set -u
exe=${WIREFEM:-./build/wirefem}
scene=${1:-prm/quick.prm}; shift || true
out=${OUT:-output/hard-cases}
mkdir -p "$out"
# Ten times the scene's own injection speed (1 when the scene does not set it).
speed=$(awk -F= '/^[[:space:]]*set[[:space:]]+Speed[[:space:]]*=/ {gsub(/^[[:space:]]+/, "", $2); gsub(/[[:space:]#].*/, "", $2); v=$2} END {print (v == "" ? 1 : v)}' "$scene")
speed10=$(awk -v v="$speed" 'BEGIN {print 10 * v}')
cases=(
  "default|"
  "mu_st=5|Contact/Friction/Static coefficient=5"
  "kappa=0|Wire/Plasticity/Yield curvature=0"
  "s=0|Wire/Plasticity/Hardening slope=0"
  "s=1|Wire/Plasticity/Hardening slope=1"
  "k_n x10|Contact/Normal stiffness=20000"
  "speed x10|Injection/Speed=$speed10"
)
printf "| case | exit | stop | phi | balance error | max overlap (d) | steps | wall (s) |\n|---|---|---|---|---|---|---|---|\n"
for c in "${cases[@]}"; do
  name=${c%%|*}; setting=${c#*|}
  dir="$out/$(printf %s "$name" | tr -c 'a-zA-Z0-9_' '_')"
  extra=(); [ -n "$setting" ] && extra=(--set "$setting")
  "$exe" "$scene" "$@" "${extra[@]}" --replace --set Output/Directory="$dir" --set Output/Progress=off \
    --set "Output/VTU interval=0" > "$dir.log" 2>&1
  rc=$?
  python3 - "$dir/summary.json" "$name" "$rc" <<'PY'
import json, sys
try:
    s = json.load(open(sys.argv[1]))
except (OSError, ValueError):
    print(f"| {sys.argv[2]} | {sys.argv[3]} | no summary | | | | | |"); sys.exit()
print(f"| {sys.argv[2]} | {sys.argv[3]} | {s['stop_reason']} | {s['phi_final']:.4f} | "
      f"{s['energy']['balance_error']:.2e} | {s['max_penetration']:.4f} | {s['steps']} | {s['wall_time_s']:.1f} |")
PY
done
