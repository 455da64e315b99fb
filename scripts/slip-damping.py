#!/usr/bin/python3
"""The slow chain with its slips damped, beside the quasi-static FEM: a
table of each run's end and of its state at one packing density, and a
figure of loops, inlet force and bending energy against phi.

    scripts/slip-damping.py WIREFEM OUTDIR [--radius F] [--seed S]
                            [--speed V] [--gammas 0 0.1 1 3 10] [--plastic]
                            [--at PHI] [--fem-gammas G ...]

Scene: prm/classic.prm at cavity radius F (15), the elastic wire unless
--plastic. Runs (reused when finished, resumed when interrupted): the
chain injected at speed V (0.003) with Discrete/Translational damping
gamma for each of --gammas, and the FEM with FEM/Integrator =
quasi-static; with --fem-gammas, also the dynamic FEM at speed V with
FEM/Translational damping gamma (the same drag). The drag also pulls on
wire sliding along itself with gamma rho A V per length: keep gamma V
small. Writes OUTDIR/slip-damping.md
and OUTDIR/slip-damping.png.
"""
import argparse
import bisect
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "validation"))
import study  # noqa: E402

COLUMNS = ["loops", "force", "energy_bending"]


def at(rows, phi, key):
    """KEY in the first row at or past PHI (the last row if none)."""
    i = bisect.bisect_left([r["phi"] for r in rows], phi)
    return rows[min(i, len(rows) - 1)][key]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("wirefem")
    parser.add_argument("outdir")
    parser.add_argument("--radius", type=float, default=15)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--speed", type=float, default=0.003)
    parser.add_argument("--gammas", type=float, nargs="+", default=[0, 0.1, 1, 3, 10])
    parser.add_argument("--plastic", action="store_true", help="the plastic wire of prm/classic.prm")
    parser.add_argument("--at", type=float, default=0.48, help="the packing density of the table's state")
    parser.add_argument("--fem-gammas", type=float, nargs="*", default=[],
                        help="the dynamic FEM at speed V with FEM/Translational damping gamma, for each")
    args = parser.parse_args()
    wirefem = os.path.abspath(args.wirefem)
    os.makedirs(args.outdir, exist_ok=True)
    scene = [f"Cavity/Radius={args.radius:g}", f"Injection/Seed={args.seed}"]
    if not args.plastic:
        scene.append("Wire/Plasticity/Enabled=false")
    variants = {f"chain, gamma {g:g}": (f"chain_gamma{g:g}", ["Model=discrete", f"Injection/Speed={args.speed:g}",
                                                               f"Discrete/Translational damping={g:g}"])
                for g in args.gammas}
    for g in args.fem_gammas:
        variants[f"FEM, gamma {g:g}"] = (f"fem_gamma{g:g}", ["Model=fem", f"Injection/Speed={args.speed:g}",
                                                           f"FEM/Translational damping={g:g}"])
    variants["quasi-static FEM"] = ("fem_quasi_static", ["Model=fem", "FEM/Integrator=quasi-static"])

    rows = [f"| run | phi at the end | stop | loops | symmetry | loops at {args.at:g} | inlet force | "
            "bending | friction + damping |", "|---|---|---|---|---|---|---|---|---|"]
    fig, ax = plt.subplots(3, 1, figsize=(8, 9), sharex=True)
    for label, (name, sets) in variants.items():
        out = os.path.join(args.outdir, name)
        study.scene_run(wirefem, "classic.prm", ["Output/Interval=3"] + sets + scene, out)
        with open(os.path.join(out, "summary.json")) as f:
            s = json.load(f)
        r = study.read_series(out)
        stop = "jammed" if s.get("jammed") else "phi_max" if "Maximum packing" in s["stop_reason"] else s["stop_reason"]
        dissipated = at(r, args.at, "friction_dissipation") + at(r, args.at, "damping_dissipation")
        rows.append(f"| {label} | {s['phi_final']:.3f} | {stop} | {s['loops']} | "
                    f"{s['symmetry']:.2f} | {at(r, args.at, 'loops'):.0f} | {at(r, args.at, 'force'):.1f} | "
                    f"{at(r, args.at, 'energy_bending'):.0f} | {dissipated:.0f} |")
        phi = [x["phi"] for x in r]
        for a, key in zip(ax, COLUMNS):
            a.plot(phi, [x[key] for x in r], lw=1.6 if "quasi-static" in label else 0.9, label=label,
                   color="black" if "quasi-static" in label else None,
                   ls="--" if label.startswith("FEM") else "-")
    wire = "plastic (prm/classic.prm)" if args.plastic else "elastic"
    ax[0].set_title(f"{wire} wire, mu_st 5, f = {args.radius:g}, seed {args.seed}; "
                    f"chain at speed {args.speed:g}")
    for a, key in zip(ax, ["loops", "inlet force", "bending energy"]):
        a.set_ylabel(key)
    ax[1].set_ylim(bottom=0)
    ax[2].set_xlabel("phi")
    ax[0].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(args.outdir, "slip-damping.png"), dpi=90)
    with open(os.path.join(args.outdir, "slip-damping.md"), "w") as f:
        f.write("\n".join(rows) + "\n")
    print("\n".join(rows))


if __name__ == "__main__":
    main()
