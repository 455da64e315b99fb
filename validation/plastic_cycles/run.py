#!/usr/bin/python3
"""Validation case 4: elastoplastic bending cycles through the executable
(cycles.prm: a cantilever under an end moment cycling between +-1.2 M_y,
uniform moment along the rod). For kinematic and isotropic hardening and both
models, compares the end rotation kappa L at every recorded equilibrium with
the bilinear law driven by the moment (implemented here, independently of
wirefem's), and the plastic work at the end of the history with the law's
exact integral (kinematic: one closed cycle dissipates 4 M_y (M_1 - M_y)/H L;
isotropic: the yield range grows to M_1 in the first loading and the cycles
that follow are elastic, so all the work is done then).

    validation/plastic_cycles/run.py WIREFEM OUTDIR

Asserted for both models. FEM: exact statics. Discrete model: loaded slowly
(Load time 10000 per leg instead of 100, about 100 periods of the first
bending mode per recorded point), so that its dynamic relaxation does not
overshoot the moment at load reversals (at Load time 100 bending waves added
plastic flow worth 1e-2 rad of end rotation). Its chain has no rotational
spring on the half segment at the free end, so its springs stand for
L - lambda_0/2 of the rod: its plastic work must be the law's times
(L - lambda_0/2)/L (asserted, chain_work_error), which is first order
against the continuum (error_work, reported).
"""
import csv
import math
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))
import study  # noqa: E402

L, EI, KAPPA_Y, S = 20.0, 60.0, 0.04, 0.05
M_Y = EI * KAPPA_Y
M_1 = 1.2 * M_Y
HISTORY = (1.0, -1.0, 1.0, -1.0)
POINTS = 6
# FEM: end rotation (rad) and relative plastic work exact to round-off.
TOL_FEM = {"rotation": 1e-6, "work": 1e-6}
# Discrete model, quasi-statically loaded: end rotation (rad), and plastic
# work relative to the law over the length its springs represent.
TOL_DISCRETE = {"rotation": 1e-3, "chain_work": 1e-3}
DISCRETE_LOAD_TIME = 10000.0


def law_path(hardening):
    """(moment, kappa, plastic work per length) at each recorded point."""
    H = S * EI / (1.0 - S)
    kp = alpha = work = 0.0
    out, previous = [], 0.0
    for f in HISTORY:
        for j in range(1, POINTS + 1):
            M = M_1 * (previous + (f - previous) * j / POINTS)
            if hardening == "kinematic":
                xi = M - H * kp
                if abs(xi) > M_Y:
                    sign = 1.0 if xi > 0 else -1.0
                    new = (M - sign * M_Y) / H
                    work += sign * M_Y * (new - kp) + 0.5 * H * (new * new - kp * kp)
                    kp = new
            else:
                R = M_Y + H * alpha
                if abs(M) > R:
                    d = (abs(M) - R) / H
                    work += (M_Y + H * alpha) * d + 0.5 * H * d * d
                    kp += math.copysign(d, M)
                    alpha += d
            out.append((M, M / EI + kp, work))
        previous = f
    return out


def read_history(path):
    with open(path) as f:
        return [{k: float(v) for k, v in row.items()} for row in csv.DictReader(f)]


def main():
    wirefem, outdir = sys.argv[1], sys.argv[2]
    os.makedirs(outdir, exist_ok=True)
    failures, results = [], []
    first, last = POINTS - 1, 3 * POINTS - 1  # the first +M and the second
    for hardening in ("kinematic", "isotropic"):
        ref = law_path(hardening)
        ref_cycle = (ref[last][2] - ref[first][2]) * L
        ref_total = ref[-1][2] * L
        for model, sets, lengths in (("discrete", [f"Cantilever/Load time={DISCRETE_LOAD_TIME!r}"], [2.0, 1.0, 0.5]),
                                     ("fem p=1", ["Model=fem", "Cantilever/Tolerance=1e-10"], [1.0])):
            rows = []
            for h in lengths:
                key = "Discrete/Segment length" if model == "discrete" else "FEM/Element length"
                out = os.path.join(outdir, f"{hardening}_{model.replace(' ', '_').replace('=', '')}_{h}")
                s = study.run(wirefem, os.path.join(HERE, "cycles.prm"),
                              sets + [f"Wire/Plasticity/Hardening={hardening}", f"{key}={h!r}"], out)
                if not s["converged"]:
                    failures.append(f"{hardening} {model} h = {h}: no equilibrium")
                    continue
                hist = read_history(os.path.join(out, "history.csv"))
                rot = max(abs(r["tip_rotation"] - p[1] * L) for r, p in zip(hist, ref))
                cycle = hist[last]["plastic_work"] - hist[first]["plastic_work"]
                total = hist[-1]["plastic_work"]
                represented = (L - 0.5 * h) / L if model == "discrete" else 1.0
                rows.append({"h": h, "error_rotation": rot, "cycle_work": cycle, "work": total,
                             "error_work": abs(total - ref_total) / ref_total,
                             "chain_work_error": abs(total / (represented * ref_total) - 1.0),
                             "wall_time_s": s["wall_time_s"],
                             "loop": [[r["load_factor"] * M_1, r["tip_rotation"] / L] for r in hist]})
                if model == "discrete" and (rot > TOL_DISCRETE["rotation"] or
                                            rows[-1]["chain_work_error"] > TOL_DISCRETE["chain_work"]):
                    failures.append(f"{hardening} discrete lambda_0 = {h}: end rotation error {rot:.2e} (limit "
                                    f"{TOL_DISCRETE['rotation']:g}), plastic work against (L - lambda_0/2)/L of "
                                    f"the law's {rows[-1]['chain_work_error']:.2e} (limit "
                                    f"{TOL_DISCRETE['chain_work']:g})")
            study.add_orders(rows, ("error_work",))
            label = f"{hardening} {model}"
            if model != "discrete":
                study.check(label, rows, {"error_rotation": TOL_FEM["rotation"], "error_work": TOL_FEM["work"]},
                            0.0, "at least", failures)
            else:
                # Against the continuum the missing half segment is first order.
                study.check(label, rows, {}, 1.0, "equal", failures)
            results.append({"model": model, "case": hardening, "reference_cycle_work": ref_cycle,
                            "reference_work": ref_total, "asserted": True, "rows": rows})
            print(f"{label}: reference plastic work {ref_total:.10g}, of one closed cycle {ref_cycle:.10g}")
            for r in rows:
                print(f"  h = {r['h']:<5} end rotation error {r['error_rotation']:.2e}, plastic work {r['work']:.10g}"
                      f" (relative error {r['error_work']:.2e}, order {r.get('order_work', float('nan')):.2f};"
                      f" against the springs' length {r['chain_work_error']:.2e}),"
                      f" cycle {r['cycle_work']:.10g}, {r['wall_time_s']:.2f} s")
    study.write(outdir, {"validation": "plastic_cycles", "length": L, "EA": 1000.0, "EI": EI, "GA_fem": 0.9 * 1000 / 2.6,
                         "M_y": M_Y, "M_1": M_1, "hardening_slope": S,
                         "tolerance": {"error_rotation": TOL_FEM["rotation"], "error_work": TOL_FEM["work"]},
                         "tolerance_discrete": TOL_DISCRETE, "discrete_load_time": DISCRETE_LOAD_TIME,
                         "order_slack": study.ORDER_SLACK, "floor": study.FLOOR, "cases": results,
                         "failures": failures})
    plot(results, os.path.join(outdir, "convergence.png"))
    return 1 if failures else 0


def plot(results, filename):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.5))
    for ax, hardening in zip(axes, ("kinematic", "isotropic")):
        ref = law_path(hardening)
        ax.plot([p[1] for p in ref], [p[0] for p in ref], "k-", lw=3, alpha=0.3, label="bilinear law")
        for c in results:
            if c["case"] == hardening and c["rows"]:
                loop = c["rows"][-1]["loop"]
                ax.plot([p[1] for p in loop], [p[0] for p in loop], "o--", ms=3,
                        label=f"{c['model']} (h = {c['rows'][-1]['h']:g})")
        ax.set_xlabel("curvature (end rotation / L)")
        ax.set_ylabel("moment")
        ax.set_title(f"{hardening} hardening, +-1.2 M_y")
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(filename, dpi=100)


if __name__ == "__main__":
    sys.exit(main())
