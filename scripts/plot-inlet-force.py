#!/usr/bin/python3
"""Inlet force against injected length before the first wire-wire contact.

    scripts/plot-inlet-force.py OUT.png RUN_DIR[=label] [RUN_DIR[=label] ...]

Each RUN_DIR holds a series.csv (run with a small Output/Interval, e.g. 0.05,
to resolve what happens while a node or element passes the inlet). Prints, per
run, the mean and standard deviation of the force over that stretch and the
largest jump between neighbouring rows.
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    fig, ax = plt.subplots(figsize=(8, 4.5))
    for arg in sys.argv[2:]:
        path, _, label = arg.partition("=")
        rows = list(csv.DictReader(open(f"{path}/series.csv")))
        L, F = [], []
        for r in rows:
            if float(r["contacts"]) > 0:
                break
            L.append(float(r["injected_length"]))
            F.append(float(r["force_left"]))
        if len(F) < 3:
            print(f"{path}: fewer than 3 rows before the first contact")
            continue
        # Statistics over the second half of the stretch: after the first
        # buckling transient, where only the inlet's own artefacts would show.
        k0 = len(F) // 2
        tail = F[k0:]
        mean = sum(tail) / len(tail)
        std = (sum((f - mean) ** 2 for f in tail) / len(tail)) ** 0.5
        jump = max(abs(b - a) for a, b in zip(tail, tail[1:]))
        print(f"{label or path}: L {L[0]:.1f}..{L[-1]:.1f}, rows {len(F)}; second half: mean force {mean:.3f}, "
              f"std {std:.3f}, largest jump between rows {jump:.3f}")
        ax.plot(L, F, lw=1, label=label or path)
    ax.set_xlabel("injected length L (d)")
    ax.set_ylabel("left inlet force")
    ax.set_title("Inlet force before the first wire-wire contact")
    ax.legend()
    fig.tight_layout()
    fig.savefig(sys.argv[1], dpi=120)


if __name__ == "__main__":
    main()
