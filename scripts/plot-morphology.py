#!/usr/bin/python3
"""The classic/plastic criterion along runs: A/B and its two factors against phi.

    scripts/plot-morphology.py OUT.png RUN_DIR[=label] [RUN_DIR[=label] ...]

Each RUN_DIR holds a series.csv with the curvature_ratio and
inner_wire_fraction columns. Three panels share the phi axis: the paper's
curvature ratio A/B (classic below 0.5), the share f of the wire inside the
inner disc of equal area (0.5 for wire spread evenly), and the ratio of
squared curvature per length inside to outside, A/B (1 - f)/f. Prints, per
run, the three at the end.
"""
import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    fig, axes = plt.subplots(3, 1, figsize=(8, 9), sharex=True)
    ends = []
    for arg in sys.argv[2:]:
        path, _, label = arg.partition("=")
        rows = list(csv.DictReader(open(f"{path}/series.csv")))
        if not rows or "inner_wire_fraction" not in rows[0]:
            sys.exit(f"{path}/series.csv: no inner_wire_fraction column (written by an older version?)")
        phi, ab, f, dens = [], [], [], []
        for r in rows:
            a, fi = float(r["curvature_ratio"]), float(r["inner_wire_fraction"])
            if not (math.isfinite(a) and 0.0 < fi < 1.0):
                continue
            phi.append(float(r["phi"]))
            ab.append(a)
            f.append(fi)
            dens.append(a * (1.0 - fi) / fi)
        name = label or path
        for ax, y in zip(axes, (ab, f, dens)):
            ax.plot(phi, y, lw=1, label=name)
        if phi:
            ends.append(f"{name}: phi {phi[-1]:.3f}  A/B {ab[-1]:.2f}  inside {f[-1]:.2f}  density ratio {dens[-1]:.2f}")
    axes[0].axhline(0.5, color="k", lw=0.8, ls="--")
    axes[0].set_yscale("log")
    axes[0].set_ylabel("A/B (classic below 0.5)")
    axes[1].axhline(0.5, color="k", lw=0.8, ls="--")
    axes[1].set_ylabel("wire inside the inner disc, f")
    axes[2].set_yscale("log")
    axes[2].set_ylabel("curvature density ratio\nA/B (1 - f)/f")
    axes[2].set_xlabel("phi")
    axes[0].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(sys.argv[1], dpi=100)
    print("\n".join(ends))  # after the figure is written: a test reads these lines


if __name__ == "__main__":
    main()
