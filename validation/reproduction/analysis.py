"""The reproduction study's analysis (run.py): phi_c, beta and gamma over
realizations, and the report."""
import csv
import json
import math
import os
import statistics
import sys
import textwrap

import numpy as np
from scipy.optimize import curve_fit

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import phase  # noqa: E402
from study import finished, mean_sem as mean_error  # noqa: E402

# The scenes, their overrides of prm/classic.prm and the paper's values.
SCENES = {
    "fig5": {
        "title": "elastoplastic classic (Fig. 5: kappa_theta 0.08, s 0.05, mu_st 5)",
        "sets": ["Wire/Plasticity/Yield curvature=0.08", "Wire/Plasticity/Hardening slope=0.05"],
        "phi_c": (0.46, 0.01),
        "beta": (-1.43, 0.02),
    },
    "elastic": {
        "title": "elastic classic (mu_st 5)",
        "sets": ["Wire/Plasticity/Enabled=false"],
        "phi_c": (0.54, 0.02),
        "beta": (-2.05, 0.02),
        "gamma": (1.75, 0.03),
    },
    "classic_paper": {
        "title": "classic at the paper's Fig. 1 values (kappa_theta 0.04, s 0.08, mu_st 5)",
        "sets": [],
        "gamma": (1.75, 0.03),
    },
    "plastic": {
        "title": "plastic (Fig. 1: kappa_theta 0.02, s 0.04, mu_st 5)",
        "prm": "plastic.prm",
        "sets": [],
        "gamma": (1.85, 0.04),
    },
    "spiral": {
        "title": "spiral (Fig. 1: elastic, mu_st 0)",
        "prm": "spiral.prm",
        "sets": ["Injection/Maximum packing density=1"],
        "phi_max": 1,
        "spiral": True,
    },
}
GRID = 0.001  # phi spacing of the averaged force
# The studies: a scene with a model, cavity radius and seeds, and keys of
# the model ("sets", named in the report by "label"); run directories
# OUTDIR/<study>_s<seed>.
# The FEM studies made before FEM/Self friction law = auto, FEM/Step
# error = 0.01 and FEM/Linear solver = auto became the defaults name the
# keys they were made with: the regularised law between wires, fixed steps
# and an LU of every tangent.
LU = ["FEM/Linear solver=refactorise"]
FIXED = ["FEM/Step error=0"] + LU
REGULARISED = {"sets": ["FEM/Friction law=regularised", "FEM/Self friction law=regularised"] + FIXED,
               "label": "fem, FEM/Friction law = regularised, fixed steps"}
SPRING = {"sets": ["FEM/Friction law=spring", "FEM/Self friction law=regularised"] + FIXED,
          "label": "fem, FEM/Friction law = spring, fixed steps"}
SLOW = {"sets": ["Injection/Speed=0.01"], "label": "discrete, Injection/Speed = 0.01"}
# (Quasi-static runs ignore FEM/Step error: their snaps keep fixed steps.
# The creep and energy error are their defaults, named so that runs kept
# from before those keys are not taken for runs with them.)
QUASI_STATIC = {"sets": ["FEM/Integrator=quasi-static", "FEM/Self friction law=regularised",
                         "FEM/Quasi-static creep=0.03", "FEM/Quasi-static energy error=0.1"],
                "label": "fem, FEM/Integrator = quasi-static"}
SELF_SPRING = {"sets": ["FEM/Friction law=spring", "FEM/Self friction law=spring"] + FIXED,
               "label": "fem, the chain's friction law at the wall and between wires, fixed steps"}
# ... and the step set by its error estimates (FEM/Step error, with the
# energy estimate at its default): the FEM's defaults, but for the LU.
FAST = {"sets": ["FEM/Friction law=spring", "FEM/Self friction law=spring", "FEM/Step error=1e-2"] + LU,
        "label": "fem, the chain's friction law at the wall and between wires, FEM/Step error = 1e-2, "
                 "FEM/Linear solver = refactorise"}
# The FEM as a scene gets it, with no keys named.
# (Runs are reused by their keys: when a default changes, delete these
# runs, in OUTDIR and in the archive runs/, so that they are made again.)
DEFAULTS = {"sets": [], "label": "fem, the defaults (FEM/Linear solver = auto, Newton tolerance 1e-6 of EA)"}
STUDIES = {
    "fig5": {"scene": "fig5", "model": "discrete", "radius": 25, "seeds": range(1, 10)},
    "elastic": {"scene": "elastic", "model": "discrete", "radius": 25, "seeds": range(1, 10)},
    "fig5_fem": {"scene": "fig5", "model": "fem", "radius": 25, "seeds": range(1, 4), **REGULARISED},
    "elastic_fem": {"scene": "elastic", "model": "fem", "radius": 25, "seeds": range(1, 4), **REGULARISED},
    "fig5_fem_spring": {"scene": "fig5", "model": "fem", "radius": 25, "seeds": range(1, 4), **SPRING},
    "elastic_fem_spring": {"scene": "elastic", "model": "fem", "radius": 25, "seeds": range(1, 4), **SPRING},
    "elastic_f50": {"scene": "elastic", "model": "discrete", "radius": 50, "seeds": range(1, 4)},
    "classic_f50": {"scene": "classic_paper", "model": "discrete", "radius": 50, "seeds": range(1, 4)},
    "plastic_f100": {"scene": "plastic", "model": "discrete", "radius": 100, "seeds": range(1, 2)},
    # The spiral to phi = 1, where its wire fills the cavity (largest overlap
    # 0.06 d, seed 1).
    "spiral": {"scene": "spiral", "model": "discrete", "radius": 25, "seeds": range(1, 4)},
    # The quasi-static limit: 30 times slower than the shipped 0.3 (at f 25
    # prm/classic.prm jams at 0.416 +- 0.007 at 0.01, 0.409 +- 0.011 at
    # 0.003, 0.506 +- 0.025 at 0.3).
    "fig5_slow": {"scene": "fig5", "model": "discrete", "radius": 25, "seeds": range(1, 10), **SLOW},
    "elastic_slow": {"scene": "elastic", "model": "discrete", "radius": 25, "seeds": range(1, 10), **SLOW},
    # The FEM with the chain's friction law between wires too.
    "fig5_fem_self_spring": {"scene": "fig5", "model": "fem", "radius": 25, "seeds": range(1, 4), **SELF_SPRING},
    "elastic_fem_self_spring": {"scene": "elastic", "model": "fem", "radius": 25, "seeds": range(1, 4),
                                **SELF_SPRING},
    "fig5_fem_fast": {"scene": "fig5", "model": "fem", "radius": 25, "seeds": range(1, 4), **FAST},
    "elastic_fem_fast": {"scene": "elastic", "model": "fem", "radius": 25, "seeds": range(1, 4), **FAST},
    "fig5_fem_auto": {"scene": "fig5", "model": "fem", "radius": 25, "seeds": range(1, 4), **DEFAULTS},
    "elastic_fem_auto": {"scene": "elastic", "model": "fem", "radius": 25, "seeds": range(1, 4), **DEFAULTS},
    # The FEM without inertia: steps by injected length, snaps taken by
    # dynamics with the injection paused; at the scenes' speed, which its
    # dashpots read (its friction creeps per length injected).
    "fig5_fem_qs": {"scene": "fig5", "model": "fem", "radius": 25, "seeds": range(1, 4), **QUASI_STATIC},
    "elastic_fem_qs": {"scene": "elastic", "model": "fem", "radius": 25, "seeds": range(1, 4), **QUASI_STATIC},
}


def read_run(out):
    """(summary, phi, force, loops) of a run directory."""
    with open(os.path.join(out, "summary.json")) as f:
        summary = json.load(f)
    phi, force, loops = [], [], []
    with open(os.path.join(out, "series.csv")) as f:
        for row in csv.DictReader(f):
            phi.append(float(row["phi"]))
            force.append(float(row["force"]))
            loops.append(int(row["loops"]))
    return summary, np.array(phi), np.array(force), np.array(loops)


def average_force(runs, phi_end):
    """The force of every realization at equal phi (linear interpolation on
    a grid of GRID), averaged, up to phi_end."""
    grid = np.arange(0.05, phi_end, GRID)
    curves = [np.interp(grid, phi, force) for _, phi, force, _ in runs]
    return grid, np.mean(curves, axis=0)


def fit_power(phi, force, phi_c=None):
    """log F = log A + beta log(phi_c - phi): (beta, beta error, phi_c,
    phi_c error, log A), phi_c free above the window unless given."""
    keep = force > 0
    phi, y = phi[keep], np.log(force[keep])
    if phi_c is not None:
        x = np.log(phi_c - phi)
        (beta, log_a), cov = np.polyfit(x, y, 1, cov=True)
        return beta, math.sqrt(cov[0][0]), phi_c, 0.0, log_a

    def model(p, log_a, beta, gap):
        return log_a + beta * np.log(phi[-1] + math.exp(gap) - p)

    best = None
    for guess in (0.005, 0.02, 0.05, 0.1):
        try:
            params, cov = curve_fit(model, phi, y, p0=(y[0], -1.0, math.log(guess)), maxfev=20000)
        except RuntimeError:
            continue
        residual = float(np.sum((model(phi, *params) - y) ** 2))
        if best is None or residual < best[0]:
            best = (residual, params, cov)
    if best is None:
        return [float("nan")] * 5
    _, (log_a, beta, gap), cov = best
    phi_c = phi[-1] + math.exp(gap)
    return beta, math.sqrt(cov[1][1]), phi_c, math.exp(gap) * math.sqrt(cov[2][2]), log_a


def study_results(outdir, study):
    st = STUDIES[study]
    runs = []
    for seed in st["seeds"]:
        out = os.path.join(outdir, f"{study}_s{seed}")
        if finished(out):
            runs.append(read_run(out))
    r = {"runs": len(runs), "scene": st["scene"], "study": study, "model": st.get("label", st["model"]),
         "radius": st["radius"],
         "seeds": st["seeds"]}
    if not runs:
        return r
    summaries = [run[0] for run in runs]
    scene = SCENES[st["scene"]]
    # phi at jamming and the force's fits from the runs that jammed (not
    # those that failed or stopped at the maximum density).
    jammed = [run for run in runs if run[0]["jammed"] and not run[0]["failed"]]
    r["jammed"] = sum(summary["jammed"] for summary in summaries)
    r["failed"] = sum(summary["failed"] for summary in summaries)
    r["phi_final"] = mean_error([run[0]["phi_final"] for run in (jammed if "phi_c" in scene else runs)])
    r["loops_each"] = [summary["loops"] for summary in summaries]
    r["phi_each"] = [summary["phi_final"] for summary in summaries]
    r["gamma"] = mean_error([summary.get("gamma") for summary in summaries])
    if r["gamma"][2] == 1:
        # One run: its fit's own standard error stands in for the spread.
        fit = next(summary.get("gamma_error") for summary in summaries if summary.get("gamma") is not None)
        r["gamma"] = (r["gamma"][0], fit if fit is not None else float("nan"), 1)
    r["single_beta"] = sorted(summary.get("beta") for summary in summaries if summary.get("beta") is not None)
    r["loops"] = mean_error([summary["loops"] for summary in summaries])
    r["morphology"] = sorted({summary["morphology"] for summary in summaries})
    r["versions"] = sorted({summary["version"] for summary in summaries})
    r["force_final"] = [float(force[-1]) for _, _, force, _ in runs]
    # From which phi on the loop count no longer changes, and its largest value.
    r["loops_settled"] = [float(phi[np.flatnonzero(loops != loops[-1])[-1] + 1]) if np.any(loops != loops[-1])
                          else float(phi[0]) for _, phi, _, loops in runs]
    r["loops_max"] = max(int(loops.max()) for _, _, _, loops in runs)
    if "phi_c" in scene and jammed:
        force_fits(r, jammed, scene["phi_c"][0])
    return r


def force_fits(r, runs, paper_c):
    """The realization-averaged force and its fits, into r."""
    end = min(r_[0]["phi_final"] for r_ in runs)
    grid, force = average_force(runs, end)
    r["curve"] = (grid, force)
    r["window_end"] = end
    r["fits"] = {}
    for start in (0.4, 0.5, 0.6):
        w = grid >= start * end
        r["fits"][start] = fit_power(grid[w], force[w])
    w = (grid >= 0.5 * end) & (grid <= paper_c - 0.005)
    r["fixed"] = fit_power(grid[w], force[w], phi_c=paper_c)
    r["fixed_window"] = (0.5 * end, min(end, paper_c - 0.005))


def plot(results, filename):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    if not results:
        return
    cols = min(len(results), 2)
    rows = (len(results) + cols - 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(6 * cols, 4.5 * rows), squeeze=False)
    for ax in axes.flat[len(results):]:
        ax.set_visible(False)
    for ax, r in zip(axes.flat, results):
        if r["runs"] == 0:
            continue
        grid, force = r["curve"]
        # Against phi (each fit has its own phi_c): the mean force, the
        # fit with phi_c free, the fit with the paper's phi_c.
        w = grid >= 0.4 * r["window_end"]
        ax.semilogy(grid[w], force[w], ".", ms=3, label=f"mean of {r['runs']} realizations")
        for (beta, _, phi_c, _, log_a), style, label in (
                (r["fits"][0.5], "-", "phi_c free"), (r["fixed"], "--", "paper's phi_c")):
            x = grid[(grid >= 0.5 * r["window_end"]) & (grid < phi_c)]
            ax.semilogy(x, np.exp(log_a) * (phi_c - x) ** beta, style,
                        label=f"fit, {label}: beta {beta:.2f}, phi_c {phi_c:.3f}")
        ax.set_xlabel("phi")
        ax.set_ylabel("inlet force (mean over realizations)")
        title = SCENES[r["scene"]]["title"] + ("" if r["model"] == "discrete" else f", {r['model']}")
        ax.set_title(textwrap.fill(title, 70), fontsize=9)
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(filename, dpi=120)
    plt.close(fig)


def where(r):
    w = f"{r['model']}, f {r['radius']}, seeds {min(r['seeds'])}-{max(r['seeds'])}"
    if len(r["seeds"]) == 1:
        w = f"{r['model']}, f {r['radius']}, seed {r['seeds'][0]}"
    if 0 < r["runs"] < len(r["seeds"]):
        w += f" ({r['runs']} finished)"
    return w


def force_rows(r, s):
    """phi at jamming and beta: the realization-averaged force's fits."""
    w = where(r)
    if "fits" not in r:
        return [f"| phi at jamming, {s['title']} | {s['phi_c'][0]} +- {s['phi_c'][1]} | none of {r['runs']} runs "
                f"jammed ({r['failed']} failed) | {w} | |"]
    m, e, _ = r["phi_final"]
    rows = [f"| phi at jamming, {s['title']} | {s['phi_c'][0]} +- {s['phi_c'][1]} | {m:.3f} +- {e:.3f} "
            f"({r['jammed']} of {r['runs']} jammed, {r['failed']} failed; {', '.join(r['morphology'])}; "
            f"{r['loops'][0]:.1f} loops) | {w} | mean over realizations |"]
    b, be, c, ce, _ = r["fits"][0.5]
    rows.append(f"| beta, same | {s['beta'][0]} +- {s['beta'][1]} | {b:.2f} +- {be:.2f} (phi_c {c:.3f} +- {ce:.3f}) "
                f"| {w} | force averaged at equal phi, fitted on phi {0.5 * r['window_end']:.3f}-"
                f"{r['window_end']:.3f} (half of the earliest jamming to it) |")
    fb, fbe, _, _, _ = r["fixed"]
    lo, hi = r["fixed_window"]
    rows.append(f"| beta, phi_c fixed at the paper's {s['phi_c'][0]} | {s['beta'][0]} | {fb:.2f} +- {fbe:.2f} "
                f"| {w} | same average, phi {lo:.3f}-{hi:.3f} |")
    others = ", ".join(f"{r['fits'][k][0]:.2f} from {k} x" for k in (0.4, 0.6))
    rows.append(f"| beta, the window's start moved | | {others} the earliest jamming | {w} | same average |")
    single = r["single_beta"]
    if single:
        rows.append(f"| beta of single runs | | median {statistics.median(single):.2f}, "
                    f"{single[0]:.2f} to {single[-1]:.2f} | {w} | each run's own fit (summary.json) |")
    return rows


def gamma_row(r, s):
    gm, ge, gn = r["gamma"]
    m, e, _ = r["phi_final"]
    ref = "f 50" if s["gamma"][0] == 1.75 else "f 100"
    name = "gamma, same" if "phi_c" in s else f"gamma, {s['title']}"
    spread = f"+- {e:.3f}" if gn > 1 else "(one run)"
    end = "" if "phi_c" in s else (f" (ended at phi {m:.3f} {spread}, {r['jammed']} of {r['runs']} jammed, "
                                   f"{r['failed']} failed; {', '.join(r['morphology'])}; {r['loops'][0]:.0f} loops)")
    how = f"mean of single-run fits ({gn} runs)" if gn > 1 else "one run: the fit's standard error"
    return [f"| {name} | {s['gamma'][0]} +- {s['gamma'][1]} ({ref}) | {gm:.2f} +- {ge:.2f}{end} | {where(r)} "
            f"| {how} |"]


def spiral_rows(r, s):
    phis = ", ".join(f"{x:.3f}" for x in r["phi_each"])
    forces = ", ".join(f"{x:.1f}" for x in r["force_final"])
    settled = max(r["loops_settled"])
    return [f"| loops, {s['title']} | 2 (gamma 0 up to phi 1) | {', '.join(map(str, r['loops_each']))} at the end; "
            "the count stays "
            f"fixed from phi {settled:.2f} on, at most {r['loops_max']} along the runs; "
            f"{', '.join(r['morphology'])} | {where(r)} | series.csv of each run |",
            f"| phi_c, same | about 1 | {r['jammed']} of {r['runs']} jammed; the runs end at phi {phis} "
            f"(Injection/Maximum packing density {s['phi_max']}) with inlet forces {forces} (jamming: 50) | {where(r)} "
            "| summary.json |"]


def differ_lines(r, s):
    """How far each row with a paper value lies from it."""
    lines = []
    head = f"- {s['title']}, {r['model']} at f {r['radius']}:"
    if "phi_c" in s and "fits" in r:
        m, e, _ = r["phi_final"]
        pc, pe = s["phi_c"]
        b, be = r["fits"][0.5][:2]
        pb, pbe = s["beta"]
        err = math.hypot(e, pe) if math.isfinite(e) else pe
        lines.append(f"{head} phi at jamming {m - pc:+.3f} from the paper's ({abs(m - pc) / err:.1f} "
                     f"combined standard errors); beta {b - pb:+.2f} from it ({abs(b - pb) / math.hypot(be, pbe):.0f} "
                     "errors of the fit, which do not hold the window's choice).")
    elif "gamma" in s and r["gamma"][2] > 0:
        gm, ge, gn = r["gamma"]
        pg, pge = s["gamma"]
        err = math.hypot(ge, pge) if math.isfinite(ge) else pge
        lines.append(f"{head} gamma {gm - pg:+.2f} from the paper's ({abs(gm - pg) / err:.1f} combined standard "
                     f"errors{'' if gn > 1 else ', with one run its fit error'}); ended "
                     f"{', '.join(r['morphology'])}.")
    return lines


def report(outdir):
    results = [study_results(outdir, study) for study in STUDIES]
    plotted = ("fig5", "elastic", "fig5_slow", "elastic_slow", "fig5_fem_qs", "elastic_fem_qs")
    plot([r for r in results if r["study"] in plotted and "curve" in r],
         os.path.join(outdir, "force_average.png"))
    lines = ["# The paper's numbers beside this code's", "",
             "Generated by `validation/reproduction/run.py WIREFEM OUTDIR`: the scene file of each row "
             "(`prm/classic.prm` unless named) at the cavity radius f of the row with the scene's keys; the "
             "model and the seeds are in each row. Errors are standard errors over the realizations (phi at "
             "jamming, gamma) or of the fit (beta).", "",
             "| quantity | paper | this code | model, f, realizations | how |", "|---|---|---|---|---|"]
    for r in results:
        s = SCENES[r["scene"]]
        if r["runs"] == 0:
            lines.append(f"| {s['title']} | | no runs yet | {where(r)} | |")
            continue
        if "phi_c" in s:
            lines += force_rows(r, s)
        if "gamma" in s:
            lines += gamma_row(r, s)
        if s.get("spiral"):
            lines += spiral_rows(r, s)
    lines += phase.section(outdir)
    lines += ["", "## Where this code and the paper differ", ""]
    for r in results:
        if r["runs"]:
            lines += differ_lines(r, SCENES[r["scene"]])
    lines += phase.differences(outdir)
    by_study = {r["study"]: r for r in results}

    def gap(scene):
        """phi at jamming, the slow chain's less the quasi-static FEM's."""
        slow, qs = by_study[scene + "_slow"], by_study[scene + "_fem_qs"]
        if not (slow["runs"] and qs["runs"]):
            return "(not yet run)"
        return f"{slow['phi_final'][0] - qs['phi_final'][0]:.3f}"

    lines += ["",
              "What this code's inlet force does near jamming: the jamming criterion (the inlet force, averaged "
              "over 1 d of injection, above 50) ends each run when the force reaches 50, so the averaged force "
              "covers about one decade, and over it the force of the elastic scene grows about exponentially in "
              "phi rather than as a power of (phi_c - phi); beta then depends on the window and on whether phi_c "
              "is free. The yield axis of the phase diagram (classic from kappa_theta 0.3 here, 0.027 in the "
              "paper) is a finding of this code; what was tried is in `docs/notes/2026-12-04-readme-record.md`.",
              "",
              "The FEM's rows come in two wall-friction laws: `FEM/Friction law = spring` (the chain's law, the "
              "FEM's default) and `regularised` (mu(v) tanh(v/v_th), its law before). With the elastic wire at "
              "mu_st 5 only the first agrees with the chain; why is in "
              "`docs/notes/2026-12-05-fem-friction-law.md`. Between wires the FEM uses the regularised law "
              "unless `FEM/Self friction law = spring`, the rows that name the chain's law between wires "
              "(`docs/notes/2026-12-06-fem-self-friction.md`).",
              "",
              "The rows `fem, FEM/Integrator = quasi-static` are the FEM without inertia, stepping by injected "
              "length (`docs/notes/2026-12-05-quasi-static-injection.md`), at the scenes' speed 0.3. Its friction "
              "creeps by `FEM/Quasi-static creep` (0.03) per length injected, whatever the speed; a smaller "
              "creep lowers phi at jamming by up to 0.01 at f = 15 "
              "(`docs/notes/2026-12-07-quasi-static-creep.md`). Its dashpots still read the speed "
              "(`docs/notes/2026-12-07-quasi-static-dashpots.md`). On the "
              f"Fig. 5 scene it jams {gap('fig5')} below the chain injected at 0.01; on the elastic scene "
              f"{gap('elastic')} below it, "
              "with regular cascades and wide gaps between them. There the chain's slips are inertial: damped "
              "by a drag they take it half-way to the quasi-static FEM "
              "(`docs/notes/2026-12-07-elastic-quasi-static-limit.md`). Without dashpots in its steps the FEM "
              "jams near the slow chain at f = 15 (0.57 against 0.600) but lower at f = 8; f = 25 was not run "
              "so."]
    versions = sorted({v for r in results for v in r.get("versions", [])})
    lines += ["", f"Runs made by wirefem {', '.join(versions)}.", "",
              "The inlet force averaged over the realizations at f = 25 (the chain, and the quasi-static "
              "FEM), and its fits:", "",
              "![force](force_average.png)", ""]
    with open(os.path.join(outdir, "report.md"), "w") as f:
        f.write("\n".join(lines))
    return results
