#!/usr/bin/python3
"""Writes validation/REPORT.md from the studies' results.json files.

    validation/report.py RESULTS_DIR VALIDATION_DIR

RESULTS_DIR holds one folder per study (build-ci/validation/<study>/ with
results.json and its PNG figures, as `ctest -L validation` leaves them);
the figures are copied to VALIDATION_DIR/figures/. Run through
scripts/validation-report.sh.
"""
import datetime
import json
import os
import shutil
import subprocess
import sys

LEVELS = (1e-2, 1e-3, 1e-4)
# The cases of the validation issue and where each stands; a study whose
# results.json is present is reported from it.
CASES = [
    ("1", "Cantilever rolled up by an end moment (M = pi EI/L)", "cantilever"),
    ("2", "Cantilever under a dead end load, PL^2/EI in {1, 2, 5, 10}", "cantilever"),
    ("3", "Euler buckling and post-buckling, pinned-pinned", None),
    ("4", "Elastoplastic bending cycles through the executable", None),
    ("5", "Friction: capstan law along the cavity wall", None),
    ("6", "Spiral packing force against the tight-spiral estimate", None),
    ("7", "Mesh convergence: FEM p = 1, 2, 3 and discrete lambda_0 (on cases 1, 2)", "cantilever"),
    ("8", "Continuum cross-check on the injection scene", None),
]


def fmt_order(rows, key):
    vals = [r[key] for r in rows if key in r]
    return ", ".join(f"{v:.2f}" for v in vals) if vals else "(exact)"


def cantilever_section(res, figures):
    out = ["## Cantilever (cases 1, 2 and the convergence of case 7)", ""]
    out += [f"Rod L = {res['length']:g} d, EA = {res['EA']:g}, EI = {res['EI']:g}; the FEM uses the Reissner "
            f"rod with GA = {res['GA_fem']:.4g}, and each model is compared with the elastica of its own axial "
            "(and, for the FEM, shear) compliance (validation/elastica.py, scipy DOP853 shooting). Errors are "
            "at the free end: position error / L and rotation error (rad). Acceptance: at the finest "
            f"discretisation position error below {res['tolerance']['error_position']:g} and rotation error "
            f"below {res['tolerance']['error_rotation']:g}; every measured order within "
            f"{res['order_slack']} of 2 (discrete model, p = 1) or at least p + 1 - {res['order_slack']} "
            "(p = 2, 3). Errors below "
            f"{res['floor']:g} are round-off and give no order.", ""]
    out += ["| model | case | h (finest) | position error | rotation error | orders (position) | "
            "orders (rotation) |", "|---|---|---|---|---|---|---|"]
    for c in res["cases"]:
        f = c["rows"][-1]
        out.append(f"| {c['model']} | {c['case']} | {f['h']:g} | {f['error_position']:.2e} | "
                   f"{f['error_rotation']:.2e} | {fmt_order(c['rows'], 'order_position')} | "
                   f"{fmt_order(c['rows'], 'order_rotation')} |")
    out += ["", "Measured order at the free end (a node), median over the load cases of the order between the "
            "two finest discretisations:", ""]
    for model in dict.fromkeys(c["model"] for c in res["cases"]):
        last = sorted(c["rows"][-1]["order_position"] for c in res["cases"]
                      if c["model"] == model and "order_position" in c["rows"][-1])
        if last:
            out.append(f"- {model}: {last[len(last) // 2]:.2f}")
    out.append("")
    out += ["### What accuracy costs in time", "",
            "Cheapest discretisation (by measured wall time of the solve) whose tip position error is below "
            "each level; '-' where none of the runs reached it. The discrete model relaxes dynamically to "
            "equilibrium (its cost grows as lambda_0^-3); the FEM solves the statics by Newton.", "",
            "| case | model | " + " | ".join(f"{lv:g}" for lv in LEVELS) + " |",
            "|---|---|" + "---|" * len(LEVELS)]
    for c in res["cases"]:
        cells = []
        for lv in LEVELS:
            ok = [r for r in c["rows"] if r["error_position"] <= lv]
            if ok:
                best = min(ok, key=lambda r: r["wall_time_s"])
                cells.append(f"h = {best['h']:g}, {best['wall_time_s'] * 1000:.0f} ms")
            else:
                cells.append("-")
        out.append(f"| {c['case']} | {c['model']} | " + " | ".join(cells) + " |")
    out += ["", "Cheapest model per level, over all cases (the largest of its cheapest times across the "
            "cases):", ""]
    for lv in LEVELS:
        cost = {}
        for c in res["cases"]:
            ok = [r["wall_time_s"] for r in c["rows"] if r["error_position"] <= lv]
            t = min(ok) if ok else float("inf")
            cost[c["model"]] = max(cost.get(c["model"], 0.0), t)
        best = min(cost, key=cost.get)
        others = ", ".join(f"{m} {'-' if v == float('inf') else f'{v * 1000:.0f} ms'}" for m, v in cost.items())
        out.append(f"- {lv:g}: **{best}** ({others})")
    out += ["", "The discrete model relaxes the statics dynamically, so its cost is that of many explicit steps; "
            "in the injection scenes, which are dynamic, it is the far cheaper model (README, Cost).", ""]
    for fig in figures:
        out.append(f"![{fig}](figures/{fig})")
    if res["failures"]:
        out += ["", "**Failures:**", ""] + [f"- {m}" for m in res["failures"]]
    return out


def main():
    results_dir, validation_dir = sys.argv[1], sys.argv[2]
    figures_dir = os.path.join(validation_dir, "figures")
    os.makedirs(figures_dir, exist_ok=True)
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True,
                            cwd=validation_dir).stdout.strip()
    lines = ["# wirefem validation report", "",
             f"Generated {datetime.date.today().isoformat()} at commit {commit or 'unknown'} by "
             "`scripts/validation-report.sh` (runs `ctest -L validation`, then `validation/report.py`). "
             "Wall times are single runs on a shared 2-core machine: read ratios, not absolute values.", "", "## Cases", "", "| # | case | status |", "|---|---|---|"]
    studies = {}
    for name in sorted(os.listdir(results_dir)) if os.path.isdir(results_dir) else []:
        f = os.path.join(results_dir, name, "results.json")
        if os.path.exists(f):
            with open(f) as fh:
                studies[name] = json.load(fh)
    for num, title, study in CASES:
        if study and study in studies:
            status = "passes" if not studies[study]["failures"] else "FAILS (see below)"
        elif study:
            status = "not run"
        else:
            status = "not implemented yet"
        lines.append(f"| {num} | {title} | {status} |")
    lines.append("")
    if "cantilever" in studies:
        figs = []
        for png in ("convergence.png",):
            src = os.path.join(results_dir, "cantilever", png)
            if os.path.exists(src):
                shutil.copy(src, os.path.join(figures_dir, "cantilever-" + png))
                figs.append("cantilever-" + png)
        lines += cantilever_section(studies["cantilever"], figs)
    with open(os.path.join(validation_dir, "REPORT.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print(f"wrote {os.path.join(validation_dir, 'REPORT.md')}")


if __name__ == "__main__":
    main()
