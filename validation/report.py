#!/usr/bin/python3
"""Writes validation/REPORT.md from the studies' results.json files.

    validation/report.py RESULTS_DIR VALIDATION_DIR

RESULTS_DIR holds one folder per study (build-ci/validation/<study>/ with
results.json and convergence.png, as `ctest -L validation` leaves them); the
figures are copied to VALIDATION_DIR/figures/. Run through
scripts/validation-report.sh.
"""
import datetime
import glob
import json
import os
import shutil
import subprocess
import sys

LEVELS = (1e-2, 1e-3, 1e-4)
# The cases of the validation plan and the study that covers each.
CASES = [
    ("1", "Cantilever rolled up by an end moment (M = pi EI/L)", "cantilever"),
    ("2", "Cantilever under a dead end load, PL^2/EI in {1, 2, 5, 10}", "cantilever"),
    ("3", "Euler buckling and post-buckling, pinned-pinned", "buckling"),
    ("4", "Elastoplastic bending cycles through the executable (both models; the discrete chain loaded slowly)",
     "plastic_cycles"),
    ("5", "Friction: capstan law along the cavity wall, and the stick/slip threshold (both models)", "capstan"),
    ("6", "Spiral packing: injection force against the tight-spiral estimate (both models)", "spiral_force"),
    ("7", "Mesh convergence: FEM p = 1, 2, 3 and discrete lambda_0 (on cases 1-3)", "cantilever"),
    ("8", "Continuum cross-check on the injection scene (injection work against L, both models)", "continuum"),
    ("-", "Work-precision of the injection statistics (measured: validation/README.md, "
          "figures/injection_statistics.png)", None),
]
TITLES = {"cantilever": "Cantilever (cases 1, 2; convergence of case 7)",
          "plastic_cycles": "Elastoplastic bending cycles (case 4)",
          "capstan": "Capstan friction along the wall (case 5)",
          "continuum": "Continuum cross-check on the injection scene (case 8)",
          "spiral_force": "Spiral packing against the tight-spiral estimate (case 6)",
          "buckling": "Euler buckling and post-buckling (case 3; convergence of case 7)"}
INTRO = {
    "plastic_cycles": "Cantilever L = {length:g} under an end moment cycling between +-{M_1:g} (M_y = {M_y:g}, "
                      "hardening slope {hardening_slope:g}; history 1, -1, 1, -1), so the moment is uniform and "
                      "the end rotation is kappa L. Errors: largest end-rotation error over the recorded "
                      "equilibria (rad) and the relative error of the plastic work at the end, against the "
                      "bilinear law driven by the moment (validation/plastic_cycles/run.py). The discrete model "
                      "is loaded slowly (Load time {discrete_load_time:g} per leg), so its dynamic relaxation "
                      "does not overshoot the moment at load reversals; its chain has no spring on the half "
                      "segment at its free end, so its work is (L - lambda_0/2)/L of the continuum's (first "
                      "order, the order shown; against that fraction of the law it is asserted to "
                      "{tolerance_discrete[chain_work]:g}, and the end rotation to "
                      "{tolerance_discrete[rotation]:g} rad).",
    "capstan": "A wire on the wall of a cavity of radius {radius:g} (centreline at r - d/2), over a wrap angle "
               "Theta, pushed along it against a compressive end force T0 = {end_force:g}; both ends carry "
               "the moment that holds the wall's curvature, so the compression N presses the wire on the wall "
               "with N kappa per length and dN/ds = mu N kappa. Sliding cases: velocity control (0.05 d per "
               "time), mu_d = 0.8 mu_st, the push force averaged over the second half of the sliding against "
               "T0 exp(mu_d Theta) (h is lambda_0); the pushed end slides as a roller (radius free), and the "
               "cases marked clamped (radius held; reported, not asserted) show the friction the support takes "
               "off the wall in a boundary layer of length (EI/k_n)^(1/4). Slip onset: force control, the push "
               "force rising at 1e-4 "
               "T0 per time until the leading end has moved 0.01 d; with mu_d = mu_st the error is against "
               "T0 exp(mu Theta); with mu_d < mu_st the onset must lie between T0 exp(mu_d Theta) and "
               "T0 exp(mu_st Theta), and the error shown is the distance below the static value. "
               "FEM (sliding only, quasi-static; its trailing end slides with its radius free): errors against "
               "T0 exp(mu_d Theta) as for the chain, and asserted within 1e-3 of the law of the extensible rod "
               "(EA = 1000) at the regularised friction's coefficient at the push speed at the finest p = 1 "
               "mesh; its orders are self-convergence orders (successive differences of the push force). "
               "validation/capstan/run.py.",
    "cantilever": "Rod L = {length:g} d, EA = {EA:g}, EI = {EI:g}, clamped at the origin, loaded at its free "
                  "end. Errors at the free end: position error / L and rotation error (rad). The case "
                  "slender_1e4 has slenderness L sqrt(EA/EI) = 1e4 (FEM only): the locking check.",
    "buckling": "Pinned-pinned rod of length {length:g} d (EA = {EA:g}, EI = {EI:g}; P_cr = {P_cr:.5g}), "
                "computed as its half: a cantilever clamped at mid-span pushed axially at the pinned end, "
                "with a transverse imperfection of {imperfection:g} P in the models and in the reference. "
                "Errors: end shortening / rod length, mid-span deflection / rod length, end slope (rad). "
                "The reference is checked against the elliptic-integral solution of the inextensible "
                "rod (P/P_cr = (2K/pi)^2, shortening 2 - 2E/K, deflection k/K) to 1e-10 before use.",
}
COMMON = ("Each model is compared with the elastica of its own axial (and for the FEM, Reissner, "
          "GA = {GA_fem:.4g}, shear) compliance: validation/elastica.py, scipy DOP853 shooting. Acceptance: "
          "at the finest discretisation every error below its tolerance ({tolerances}); the order between "
          "the two finest discretisations within {order_slack} of 2 (discrete model, p = 1) or at least "
          "p + 1 - {order_slack} (p = 2, 3). Errors below {floor:g} are round-off and give no order.")


def cheapest(rows, key, level):
    """The row of least wall time whose key is at most level, or None."""
    ok = [r for r in rows if r.get(key, float("inf")) <= level]
    return min(ok, key=lambda r: r["wall_time_s"]) if ok else None


def orders(rows, key):
    vals = [f"{r['order_' + key[6:]]:.2f}" if "order_" + key[6:] in r else "-" for r in rows[1:]]
    return ", ".join(vals) if any(v != "-" for v in vals) else "-"


def level_cells(rows, uncertainty, prefix):
    """Per level: the cheapest row below it (its h or knob value after
    prefix, its error and wall time), 'n/r' below the reference's
    uncertainty, '-' where no row reaches it."""
    cells = []
    for lv in LEVELS:
        best = cheapest(rows, "error_work", lv)
        cells.append("n/r" if lv < uncertainty else
                     f"{prefix}{best['h']:g}: {best['error_work']:.1e}, {best['wall_time_s']:.1f} s" if best else "-")
    return cells


def continuum_section(res, figures):
    out = [f"## {TITLES['continuum']}", "",
           "Elastic, frictionless wire injected into a cavity of radius 10 at speed 0.1 (ramp 20), from the "
           "straight start through buckling to just past the first wall contact (phi = 0.1). The discrete "
           "chain refined in lambda_0 with EA, EI and the viscosities fixed, the FEM in h for p = 1, 2. "
           "Injection work W (the force integrated over the injected length L); asserted: the finest discrete "
           f"chain and the finest FEM agree within {res['tolerance']:g} at every L "
           "(validation/continuum/run.py).", "",
           "| model | h | " + " | ".join(f"W(L = {x:g})" for x in res["lengths"]) + " | wall time |",
           "|---|---|" + "---|" * (len(res["lengths"]) + 1)]
    for c in res["cases"]:
        for r in c["rows"]:
            out.append(f"| {c['model']} | {r['h']:g} | " + " | ".join(f"{w:.4f}" for w in r["work"]) +
                       f" | {r['wall_time_s']:.1f} s |")
    out += ["", "Finest discrete against finest FEM (p = 2), relative difference of W: " +
            ", ".join(f"{g:.2e}" for g in res["gaps"]) + ".", ""]
    if "reference_uncertainty" in res:
        u = res["reference_uncertainty"]
        out += ["### What accuracy costs in time (injection work)", "",
                "Error of a run: the largest relative difference of its W(L) from the finest FEM's (p = 2, "
                f"h = 1/8) over the five L. That reference differs from the FEM at h = 1/4 by {u:.2e}, so "
                "levels below that are not resolved ('n/r'). Cheapest run of each model below each level:", "",
                "| model | " + " | ".join(f"{lv:g}" for lv in LEVELS) + " |", "|---|" + "---|" * len(LEVELS)]
        for c in res["cases"]:
            out.append(f"| {c['model']} | " + " | ".join(level_cells(c["rows"], u, "h = ")) + " |")
        chain = next(c["rows"] for c in res["cases"] if c["model"] == "discrete")
        ratios = ", ".join(f"{b['wall_time_s'] / a['wall_time_s']:.0f}" for a, b in zip(chain, chain[1:]))
        out += ["", "Where the FEM reaches a level, it is the cheaper way to the continuum answer in this short "
                "dynamic scene: the explicit chain's time step falls with lambda_0 (the rotational dashpot "
                "eta_b/lambda_0 and k2 = EI/lambda_0 set it), so its successive halvings of lambda_0 cost "
                f"{ratios} times more. The figure shows the crossing: coarse chains are the cheaper at errors of a "
                "few percent, the FEM below. The chain "
                "at lambda_0 = 1, the paper's model, is the cheap one when the discrete wire itself is the "
                "object of study (README, Cost).", ""]
    if "knobs" in res:
        out += ["The FEM's time step and Newton tolerance, one at a time on the reference's discretisation "
                "(p = 2, h = 1/8; the reference has time step 0.025 and tolerance 1e-8 of EA, "
                f"{res['reference_wall_time_s']:.1f} s). Error: the largest relative difference of W(L) from the "
                "reference's, the knob's own (floor 1e-9). Levels below the reference's uncertainty are not "
                "resolved here either: a tighter Newton tolerance than the reference's moves W as much as a "
                "looser one, so W is resolved to about 1e-3 under any small perturbation of the run "
                "(validation/README.md):", "",
                "| knob | value | error | wall time |", "|---|---|---|---|"]
        for k in res["knobs"]:
            for r in k["rows"]:
                out.append(f"| {k['knob']} | {r['h']:g} | {r['error_work']:.1e} | {r['wall_time_s']:.1f} s |")
        out += ["", "| knob | " + " | ".join(f"{lv:g}" for lv in LEVELS) + " |", "|---|" + "---|" * len(LEVELS)]
        for k in res["knobs"]:
            out.append(f"| {k['knob']} | " + " | ".join(level_cells(k["rows"], u, "")) + " |")
        out.append("")
    out += [f"![{f}](figures/{f})" for f in figures]
    if res["failures"]:
        out += ["", "**Failures:**", ""] + [f"- {m}" for m in res["failures"]]
    return out + [""]


def spiral_section(res, figures):
    lo, hi = res["phi_range"]
    out = [f"## {TITLES['spiral_force']}", "",
           "prm/spiral.prm (elastic, frictionless, EI = 60) at cavity radius f, injected to phi = "
           f"{hi:g}. The tight spiral (turns d apart against the wall, inner radius R sqrt(1 - phi)) stores "
           "E_ts = (pi EI / 2d) ln(1/(1 - phi)), so a quasi-static injection pushes with F_ts = EI / (2 R^2 "
           "(1 - phi)). Its geometry is a wire that joins the spiral along the wall: the asserted runs use "
           "tangential channels (`Injection/Channels = tangential`), where what the estimate leaves out (the "
           "S joining the two arms in the hole) stores O(EI/R) against the spiral's O(EI/d), so the estimate "
           "is the large-f limit. Rates: least-squares slopes "
           f"of the stored energy (the stored-energy rate) and of the injection work less the kinetic energy "
           f"(the force) against E_ts(phi) over phi in [{lo:g}, {hi:g}], i.e. their means over F_ts. Asserted "
           f"(tangential channels): the fit a + b/f of the stored-energy rate has |a - 1| <= "
           f"{res['tolerance_limit']:g}; the quasi-static "
           "force (linear in the speed through 0.01 and 0.1, taken at 0) exceeds the stored-energy rate by "
           f"-0.02 to {res['tolerance_quasi_static']:g} of it; the "
           f"stored-energy rate changes by at most {res['tolerance_speed']:g} of it from speed 0.01 to 0.1. "
           "The rod FEM (p = 1, h = d) runs the tangential scene at f = 12, 16, 20, as does the chain at the "
           "same speed: asserted, the FEM's own fit has |a - 1| <= "
           f"{res['tolerance_limit']:g}, and its stored-energy rate is within "
           f"{res.get('tolerance_models', 0):g} of the chain's at each f. "
           "Measured only: the paper's radial channels, where the arms bend over at the inlets and hold the "
           "band off the wall there. Band: nodes in the cavity farther than 0.75 rho from its centre, at phi = "
           f"{hi:g}; as centred circles: EI/(2 r^2) per node (validation/README.md, "
           "validation/spiral_force/run.py).", "",
           "| model | channels | f | speed | stored-energy rate / F_ts (phi 0.2-0.35, 0.35-0.5) | force / F_ts | "
           "band / E_ts (as centred circles) | S / E_ts | band's inner edge / rho, towards the inlets; across | "
           "wall time | energy balance |",
           "|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in sorted(res["runs"], key=lambda r: (r.get("model", "discrete") != "discrete",
                                                r.get("channels", "radial") != "tangential", r["f"], r["speed"])):
        e, h = r["final_energy"], r["stored_rate_halves"]
        out.append(f"| {r.get('model', 'discrete')} | {r.get('channels', 'radial')} | {r['f']} | {r['speed']:g} | "
                   f"{r['stored_rate']:.3f} "
                   f"({h[0]:.2f}, {h[1]:.2f}) | "
                   f"{r['work_rate']:.3f} | {e['band']:.2f} ({e['band_as_centred_circles']:.2f}) | {e['rest']:.3f} | "
                   f"{', '.join(f'{x:.2f}' for x in e['inner_edge_inlets'])}; "
                   f"{', '.join(f'{x:.2f}' for x in e['inner_edge_across'])} | "
                   f"{r['wall_time_s']:.0f} s | {r['energy_balance_error']:.1e} |")
    out += ["", f"Limit f -> infinity of the stored-energy rate / F_ts, tangential channels: **{res['limit']:.3f} +- "
            f"{res['limit_sigma']:.3f}** (fit {res['limit']:.3f} + {res['slope']:.2f} / f over the ladder)."]
    if "fem_limit" in res:
        out.append(f"The rod FEM's fit: **{res['fem_limit']:.3f} +- {res['fem_limit_sigma']:.3f}** + "
                   f"{res['fem_slope']:.2f} / f; its stored-energy rate over the chain's, minus 1: " +
                   ", ".join(f"f = {c['f']}: {c['relative_difference']:+.4f}" for c in res["model_checks"]) + ".")
    if "radial_limit" in res:
        out.append(f"The same fit with radial channels (not asserted): {res['radial_limit']:.3f} + "
                   f"{res['radial_slope']:.2f} / f.")
    out += ["Quasi-static force (linear in the speed through 0.01 and 0.1, at speed 0) over the "
            "stored-energy rate, minus 1: " + ", ".join(f"f = {q['f']}: {q['dissipated_share']:+.3f}"
                                                        for q in res["quasi_static"]) + ".",
            "Speed checks (relative change of the stored-energy rate): " +
            ", ".join(f"f = {c['f']}, {c['speeds'][0]:g} -> {c['speeds'][1]:g}: {c['relative_difference']:+.3f}"
                      for c in res["speed_checks"]) + ".", ""]
    out += [f"![{f}](figures/{f})" for f in figures]
    if res["failures"]:
        out += ["", "**Failures:**", ""] + [f"- {m}" for m in res["failures"]]
    return out + [""]


def section(study, res, figures):
    if study == "continuum":
        return continuum_section(res, figures)
    if study == "spiral_force":
        return spiral_section(res, figures)
    keys = [k for k in res["cases"][0]["rows"][0] if k.startswith("error_")]
    tolerances = ", ".join(f"{k[6:]} {v:g}" for k, v in res["tolerance"].items())
    if study == "plastic_cycles":
        common = f"Tolerances (FEM): {tolerances}; discrete order of the work error: 1 +- {res['order_slack']}."
    elif study == "capstan":
        common = (f"Tolerance: {tolerances} (relative). No order in lambda_0 is asserted for the chain: its own "
                  "statics is within 1e-4 of the continuum at lambda_0 = 1, below what the sliding dynamics "
                  "resolve; finer chains lose up to 0.23% of the friction (a vibration while sliding, and the "
                  "wire's extensibility). FEM p = 1: self-convergence order 2 +- 0.3 asserted up to pi/2.")
    else:
        common = COMMON.format(tolerances=tolerances, **res)
    out = [f"## {TITLES.get(study, study)}", "", INTRO.get(study, "").format(**res) + " " + common, ""]
    out += ["| model | case | finest h | " + " | ".join(k[6:] + " error" for k in keys) + " | " +
            " | ".join("orders (" + k[6:] + ")" for k in keys) + " |",
            "|---|---|---|" + "---|" * (2 * len(keys))]
    for c in res["cases"]:
        f = c["rows"][-1]
        out.append(f"| {c['model']} | {c['case']} | {f['h']:g} | " + " | ".join(f"{f[k]:.2e}" for k in keys) +
                   " | " + " | ".join(orders(c["rows"], k) for k in keys) + " |")
    models = list(dict.fromkeys(c["model"] for c in res["cases"]))
    if any("order_" + keys[0][6:] in r for c in res["cases"] for r in c["rows"]):
        out += ["", "Order between the two finest discretisations, median over the cases (" + keys[0][6:] + "):", ""]
    for model in models:
        last = sorted(c["rows"][-1]["order_" + keys[0][6:]] for c in res["cases"]
                      if c["model"] == model and "order_" + keys[0][6:] in c["rows"][-1])
        if last:
            out.append(f"- {model}: {last[len(last) // 2]:.2f}")
    key = keys[0]
    out += ["", f"### What accuracy costs in time ({key[6:]})", "",
            "Cheapest discretisation (measured wall time of the solve) whose error is below each level; "
            "'-' where no run reached it.", "",
            "| case | model | " + " | ".join(f"{lv:g}" for lv in LEVELS) + " |", "|---|---|" + "---|" * len(LEVELS)]
    for c in res["cases"]:
        cells = []
        for lv in LEVELS:
            best = cheapest(c["rows"], key, lv)
            cells.append(f"h = {best['h']:g}, {best['wall_time_s'] * 1000:.0f} ms" if best else "-")
        out.append(f"| {c['case']} | {c['model']} | " + " | ".join(cells) + " |")
    if len(models) > 1:
        out += ["", "Cheapest model per level over all cases (the largest of its cheapest times across the "
                "cases):", ""]
    for lv in LEVELS if len(models) > 1 else ():
        cost = {}
        for c in res["cases"]:
            best = cheapest(c["rows"], key, lv)
            cost[c["model"]] = max(cost.get(c["model"], 0.0), best["wall_time_s"] if best else float("inf"))
        best = min(cost, key=cost.get)
        others = ", ".join(f"{m} {'-' if v == float('inf') else f'{v * 1000:.0f} ms'}" for m, v in cost.items())
        out.append(f"- {lv:g}: **{best}** ({others})")
    if len(models) > 1:
        out += ["", "The discrete model reaches a static equilibrium by dynamic relaxation, many explicit "
                "steps; in the injection scenes, which are dynamic, it is the far cheaper model (README, Cost)."]
    out += [""]
    out += [f"![{f}](figures/{f})" for f in figures]
    if res["failures"]:
        out += ["", "**Failures:**", ""] + [f"- {m}" for m in res["failures"]]
    return out + [""]


def main():
    results_dir, validation_dir = sys.argv[1], sys.argv[2]
    figures_dir = os.path.join(validation_dir, "figures")
    os.makedirs(figures_dir, exist_ok=True)
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True,
                            cwd=validation_dir).stdout.strip()
    lines = ["# wirefem validation report", "",
             f"Generated {datetime.date.today().isoformat()} at commit {commit or 'unknown'} by "
             "`scripts/validation-report.sh` (runs `ctest -L validation`, then `validation/report.py`). "
             "Wall times are single runs on a shared 2-core machine: read ratios, not absolute values.", "",
             "## Cases", "",
             "Solvers: the class (or function) that ran the case, from each run's summary.json (`solver`).", "",
             "| # | case | status | solvers |", "|---|---|---|---|"]
    studies = {}
    for name in sorted(os.listdir(results_dir)) if os.path.isdir(results_dir) else []:
        f = os.path.join(results_dir, name, "results.json")
        if os.path.exists(f):
            with open(f) as fh:
                studies[name] = json.load(fh)
    for num, title, study in CASES:
        if study and study in studies:
            status = "passes" if not studies[study]["failures"] else "FAILS (see below)"
        else:
            status = "not run" if study else ("measured" if "measured" in title else "not implemented yet")
        solvers = sorted({json.load(open(f)).get("solver", "not recorded")
                          for f in glob.glob(os.path.join(results_dir, study, "**", "summary.json"),
                                             recursive=True)}) if study else []
        lines.append(f"| {num} | {title} | {status} | {', '.join(f'`{x}`' for x in solvers) or '-'} |")
    lines.append("")
    for study, res in studies.items():
        figs = []
        src = os.path.join(results_dir, study, "convergence.png")
        if os.path.exists(src):
            shutil.copy(src, os.path.join(figures_dir, f"{study}-convergence.png"))
            figs.append(f"{study}-convergence.png")
        src = os.path.join(results_dir, study, "spiral_force.png")
        if os.path.exists(src):
            shutil.copy(src, os.path.join(figures_dir, "spiral_force.png"))
            figs.append("spiral_force.png")
        src = os.path.join(results_dir, study, "work_precision.png")
        if os.path.exists(src):
            shutil.copy(src, os.path.join(figures_dir, f"{study}-work-precision.png"))
            figs.append(f"{study}-work-precision.png")
        lines += section(study, res, figs)
        versions = sorted({json.load(open(f)).get("version", "not recorded")
                           for f in glob.glob(os.path.join(results_dir, study, "*", "summary.json"))})
        if versions:
            lines[-1:-1] = ["", "Runs made by wirefem " + ", ".join(versions) + "."]
    with open(os.path.join(validation_dir, "REPORT.md"), "w") as f:
        f.write("\n".join(lines))
    print(f"wrote {os.path.join(validation_dir, 'REPORT.md')}")


if __name__ == "__main__":
    main()
