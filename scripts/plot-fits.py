#!/usr/bin/python3
"""The scaling fits of a run, as written to its summary.json.

    scripts/plot-fits.py RUN_DIR [OUT.png]

Left: loops against phi (log-log) with N_l = c phi^gamma over the fitted
range. Right: inlet force against phi_c - phi (log-log) with
F = A (phi_c - phi)^beta. Writes RUN_DIR/fits.png (or OUT.png) and .svg.
"""
import csv
import json
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    run = sys.argv[1]
    out = sys.argv[2] if len(sys.argv) > 2 else f"{run}/fits.png"
    rows = list(csv.DictReader(open(f"{run}/series.csv")))
    summary = json.load(open(f"{run}/summary.json"))
    fits = summary.get("fits", {})
    phi = [float(r["phi"]) for r in rows]
    loops = [float(r["loops"]) for r in rows]
    force = [float(r["force"]) for r in rows]

    fig, (a, b) = plt.subplots(1, 2, figsize=(10, 4.2))
    a.loglog([p for p, n in zip(phi, loops) if n > 0], [n for n in loops if n > 0], ".", ms=3, label="run")
    lf = fits.get("loops", {})
    if "gamma" in lf:
        xs = [lf["phi_min"] * (lf["phi_max"] / lf["phi_min"]) ** (i / 50) for i in range(51)]
        a.loglog(xs, [math.exp(lf["log_prefactor"]) * x ** lf["gamma"] for x in xs], "-",
                 label=f"$\\gamma$ = {lf['gamma']:.2f} $\\pm$ {lf['gamma_error']:.2f}")
    else:
        a.set_title(f"no fit: {lf.get('reason', '')}", fontsize=8)
    a.set_xlabel("$\\phi$")
    a.set_ylabel("loops $N_l$")
    a.legend()

    ff = fits.get("force", {})
    if "beta" in ff:
        sel = [(ff["phi_c"] - p, f) for p, f in zip(phi, force) if p >= ff["phi_min"] and f > 0]
        b.loglog([s[0] for s in sel], [s[1] for s in sel], ".", ms=3, label="run")
        gaps = sorted(s[0] for s in sel)
        b.loglog(gaps, [math.exp(ff["log_prefactor"]) * g ** ff["beta"] for g in gaps], "-",
                 label=f"$\\beta$ = {ff['beta']:.2f} $\\pm$ {ff['beta_error']:.2f}, "
                       f"$\\phi_c$ = {ff['phi_c']:.4f} $\\pm$ {ff['phi_c_error']:.4f}")
        b.set_xlabel("$\\phi_c - \\phi$")
        b.legend(fontsize=8)
    else:
        b.plot(phi, force, ".", ms=3)
        b.set_xlabel("$\\phi$")
        b.set_title(f"no fit: {ff.get('reason', '')}", fontsize=8)
    b.set_ylabel("inlet force F")
    fig.suptitle(f"{summary.get('scene', '')} ({summary.get('model', '')}), "
                 f"f = {summary.get('cavity_radius', '?')}")
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    fig.savefig(out.rsplit(".", 1)[0] + ".svg")
    print(out)


if __name__ == "__main__":
    main()
