#!/usr/bin/env bash
# Runs a scene once per case of a list of overrides, JOBS at a time, and prints
# one Markdown table row per case: phi at the end, jammed, the paper's
# curvature ratio A/B at the end and its smallest value from phi = 0.1 on
# (with that phi), the share of the wire inside the inner disc and the ratio of
# squared curvature per length inside to outside at the end (A/B = f/(1-f)
# times that ratio), the mirror-symmetry score, loops, energy balance, wall time.
#   scripts/morphology-scan.sh SCENE.prm CASES [extra --set arguments...]
# CASES has one case a line, "name|Key=value;Key=value" ('#' starts a comment;
# an empty override list runs the scene as it is). Example:
#   JOBS=2 scripts/morphology-scan.sh prm/classic.prm scripts/classic-cases.txt \
#     --set Cavity/Radius=50
# Environment: WIREFEM (default ./build/wirefem), OUT (default
# output/morphology-scan), JOBS (default 2).
set -u
exe=${WIREFEM:-./build/wirefem}
scene=${1:?scene file}; cases=${2:?cases file}; shift 2
out=${OUT:-output/morphology-scan}
jobs=${JOBS:-2}
mkdir -p "$out"

case_dir() { printf '%s/%s' "$out" "$(printf %s "$1" | tr -c 'a-zA-Z0-9_.' '_')"; }
case_lines() { grep -v '^[[:space:]]*\(#\|$\)' "$cases"; }

run_case() { # name, overrides; the scene's extra arguments are in extra_q
  local name=$1 settings=$2
  local dir extra=() s
  dir=$(case_dir "$name")
  eval "extra=($extra_q)"
  IFS=';' read -ra list <<< "$settings"
  for s in "${list[@]}"; do
    s=$(printf %s "$s" | sed 's/^[[:space:]]*//; s/[[:space:]]*$//')
    [ -n "$s" ] && extra+=(--set "$s")
  done
  "$exe" "$scene" "${extra[@]}" --replace --set Output/Directory="$dir" --set Output/Progress=off \
    --set "Output/VTU interval=0" > "$dir.log" 2>&1
  echo $? > "$dir.rc" # the table trusts only the output of this run
}
extra_q=""
[ $# -gt 0 ] && extra_q=$(printf '%q ' "$@")
export -f run_case case_dir
export exe scene out extra_q

case_lines | while IFS='|' read -r name settings; do
  printf '%s\0%s\0' "$name" "$settings"
done | xargs -0 -n 2 -P "$jobs" bash -c 'run_case "$@"' _

printf "| case | phi | jammed | A/B | min A/B (phi >= 0.1) | wire inside | curvature density ratio | symmetry | loops | balance | wall (s) |\n"
printf "|---|---|---|---|---|---|---|---|---|---|---|\n"
case_lines | while IFS='|' read -r name _; do
  dir=$(case_dir "$name")
  python3 - "$dir" "$name" <<'PY'
import csv, json, sys
d, name = sys.argv[1], sys.argv[2]
try:
    if open(d + ".rc").read().strip() != "0":
        raise ValueError("the run failed")
    s = json.load(open(d + "/summary.json"))
    rows = list(csv.DictReader(open(d + "/series.csv")))
except (OSError, ValueError):
    print(f"| {name} | no summary: see {d}.log | | | | | | | | | |"); sys.exit()
num = lambda x: "inf" if x is None else f"{x:.2f}"  # JSON has no infinity: null
late = [(float(r["curvature_ratio"]), float(r["phi"])) for r in rows if float(r["phi"]) >= 0.1]
low = f"{min(late)[0]:.2f} at {min(late)[1]:.2f}" if late else "-"
print(f"| {name} | {s['phi_final']:.3f} | {'yes' if s['jammed'] else 'no'} | {num(s['curvature_ratio'])} | {low} | "
      f"{s['inner_wire_fraction']:.2f} | {num(s['curvature_density_ratio'])} | {s['symmetry']:.2f} | {s['loops']} | {s['energy']['balance_error']:.1e} | {s['wall_time_s']:.0f} |")
PY
done
