#!/usr/bin/python3
"""Validation case 3: Euler buckling and post-buckling of a pinned-pinned rod
(buckling.prm: its half, a cantilever clamped at mid-span). For
P/P_cr = 0.95, 1.05, 1.5, 3 runs the discrete model and FEM degrees 1-3 over
their discretisations, compares end shortening, mid-span deflection and end
slope with the elastica of each model's compliance and the same imperfection
(validation/elastica.py: backward shooting on the end slope; checked against
the elliptic-integral solution of the inextensible rod first), measures the
orders, writes results.json and convergence.png.

    validation/buckling/run.py WIREFEM OUTDIR
"""
import math
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))
import elastica  # noqa: E402
import study  # noqa: E402

L, EA, EI = 20.0, 1000.0, 60.0  # half rod
GA_REISSNER = 0.9 * EA / 2.6
P_CR = math.pi**2 * EI / (2.0 * L) ** 2
IMPERFECTION = 1e-3  # transverse end force / P
RATIOS = (0.95, 1.05, 1.5, 3.0)
KEYS = ("error_shortening", "error_deflection", "error_slope")
# At the finest discretisation: end shortening and mid-span deflection within
# 1e-3 of the rod length 2L, the end slope within 1e-3 rad.
TOLERANCE = {k: 1e-3 for k in KEYS}


def check_reference():
    """The shooting reference against the closed form (inextensible, perfect)."""
    for alpha in (0.3, 1.5, 2.6):
        ratio, shortening, deflection = elastica.elliptic_buckling(alpha)
        x, y, a = elastica.buckled_cantilever(L, math.inf, EI, ratio * P_CR)
        err = max(abs(a - alpha), abs(2 * (L - x) / (2 * L) - shortening), abs(y / (2 * L) - deflection))
        if err > 1e-10:
            raise SystemExit(f"reference disagrees with the elliptic integrals by {err:.2e} at alpha = {alpha}")


def observables(x, y, slope):
    """End shortening / 2L, mid-span deflection / 2L, end slope of the pinned rod."""
    return (L - x) / L, y / (2 * L), slope


def main():
    wirefem, outdir = sys.argv[1], sys.argv[2]
    os.makedirs(outdir, exist_ok=True)
    check_reference()
    results, failures = [], []
    for model, model_sets, key_length, lengths, order, how in study.DISCRETISATIONS:
        GA = math.inf if model == "discrete" else GA_REISSNER
        for ratio in RATIOS:
            P = ratio * P_CR
            ref = observables(*elastica.buckled_cantilever(L, EA, EI, P, IMPERFECTION * P, GA=GA))
            name = f"P/Pcr={ratio:g}"
            sets = [f"Cantilever/End force x={-P!r}", f"Cantilever/End force y={IMPERFECTION * P!r}"]
            if model == "discrete" and ratio < 1.0:
                # Below the Euler load the deflection is small (1e-2 of the
                # rod) and the rod soft: the relaxation has to go further to
                # stay below the discretisation error at lambda_0 = L/80.
                sets.append("Cantilever/Tolerance=1e-9")
            rows = []
            tag = model.replace(" ", "_").replace("=", "")
            for h in lengths:
                s = study.run(wirefem, os.path.join(HERE, "buckling.prm"), model_sets + sets + [f"{key_length}={h!r}"],
                              os.path.join(outdir, f"{tag}_{ratio:g}_{h}"))
                if not s["converged"]:
                    failures.append(f"{model} {name}, h = {h}: no equilibrium (residual {s['residual']:.2e})")
                got = observables(s["tip_x"], s["tip_y"], s["tip_rotation"])
                row = {"h": h, "shortening": got[0], "deflection": got[1], "slope": got[2],
                       "wall_time_s": s["wall_time_s"]}
                for k, g, r in zip(KEYS, got, ref):
                    row[k] = abs(g - r)
                rows.append(row)
            study.add_orders(rows, KEYS)
            study.check(f"{model} {name}", rows, TOLERANCE, order, how, failures)
            results.append({"model": model, "case": name, "load_ratio": ratio, "discretisation": key_length,
                            "expected_order": order, "order_check": how,
                            "reference": dict(zip(("shortening", "deflection", "slope"), ref)), "rows": rows})
            study.print_rows(f"{model} {name}: reference shortening {ref[0]:.8f}, deflection {ref[1]:.8f}, "
                             f"slope {ref[2]:.8f}", rows, KEYS)
    study.write(outdir, {"validation": "buckling", "length": 2 * L, "EA": EA, "EI": EI, "GA_fem": GA_REISSNER,
                         "P_cr": P_CR, "imperfection": IMPERFECTION, "tolerance": TOLERANCE,
                         "order_slack": study.ORDER_SLACK, "floor": study.FLOOR, "cases": results,
                         "failures": failures})
    study.plot(results, ["P/Pcr=1.05", "P/Pcr=3"], "error_deflection", 2 * L, "buckling",
               os.path.join(outdir, "convergence.png"))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
