#!/usr/bin/python3
"""The elastic wire at mu_st = 5 under the FEM's two wall-friction laws,
beside the chain: a table of the state at the end and a figure of the
inlet force.

    scripts/fem-friction-law.py WIREFEM OUTDIR [--radius F] [--seeds 1 2 3]
                                [--trace-only]

Scene: prm/classic.prm with Wire/Plasticity/Enabled = false at cavity
radius F (15). Runs (reused when finished): the chain, the FEM with
FEM/Friction law = regularised and = spring, each seed to its end; and the
same three for the first seed to phi 0.14 with a row every 0.03 d of
injection (the trace). Writes OUTDIR/friction-law.md and
OUTDIR/friction-law.png.
"""
import argparse
import os
import statistics
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "validation"))
import study  # noqa: E402
VARIANTS = {
    "chain": ["Model=discrete"],
    "fem_regularised": ["Model=fem", "FEM/Friction law=regularised"],
    "fem_spring": ["Model=fem", "FEM/Friction law=spring"],
}


def run(wirefem, out, sets):
    """One run of the elastic wire into OUT with the keys SETS; a finished
    one is reused, an interrupted one resumed."""
    return study.scene_run(wirefem, "classic.prm", ["Wire/Plasticity/Enabled=false"] + sets, out)



def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("wirefem")
    parser.add_argument("outdir")
    parser.add_argument("--radius", type=float, default=15)
    parser.add_argument("--seeds", type=int, nargs="+", default=[1, 2, 3])
    parser.add_argument("--trace-only", action="store_true")
    args = parser.parse_args()
    wirefem = os.path.abspath(args.wirefem)
    os.makedirs(args.outdir, exist_ok=True)
    radius = [f"Cavity/Radius={args.radius:g}"]

    fig, ax = plt.subplots(2, 1, figsize=(10, 6), sharex=True)
    for name, sets in VARIANTS.items():
        out = os.path.join(args.outdir, f"trace_{name}")
        run(wirefem, out, sets + radius + [f"Injection/Seed={args.seeds[0]}", "Output/Interval=0.03",
                                           "Injection/Maximum packing density=0.14"])
        rows = study.read_series(out)
        t = [r["time"] for r in rows]
        ax[0].plot(t, [r["force"] for r in rows], lw=0.7, label=name.replace("_", ", "))
        ax[1].plot(t, [r["energy_kinetic"] for r in rows], lw=0.7)
    ax[0].set_ylabel("inlet force (mean of the channels)")
    ax[1].set_ylabel("kinetic energy")
    ax[1].set_xlabel("time")
    ax[0].set_title(f"elastic wire, mu_st = 5, f = {args.radius:g}, seed {args.seeds[0]}, to phi 0.14")
    ax[0].legend()
    fig.tight_layout()
    fig.savefig(os.path.join(args.outdir, "friction-law.png"), dpi=90)
    if args.trace_only:
        return

    lines = [f"Elastic wire, mu_st = 5, f = {args.radius:g}: `prm/classic.prm --set Wire/Plasticity/Enabled=false "
             f"--set Cavity/Radius={args.radius:g}` and the keys of each row.", "",
             "| model | seed | phi at the end | jammed | loops | morphology | energy balance | wall time (s) |",
             "|---|---|---|---|---|---|---|---|"]
    means = {}
    for name, sets in VARIANTS.items():
        for seed in args.seeds:
            s = run(wirefem, os.path.join(args.outdir, f"{name}_s{seed}"), sets + radius + [f"Injection/Seed={seed}"])
            means.setdefault(name, []).append(s["phi_final"])
            lines.append(f"| {' '.join(sets)} | {seed} | {s['phi_final']:.3f} | {s['jammed']} | {s['loops']} | "
                         f"{s['morphology']} | {s['energy']['balance_error']:.1e} | {s['wall_time_s']:.1f} |")
    lines.append("")
    for name, phis in means.items():
        sd = statistics.stdev(phis) if len(phis) > 1 else 0.0
        lines.append(f"- {name}: phi at the end {statistics.mean(phis):.3f} +- {sd:.3f} (standard deviation)")
    with open(os.path.join(args.outdir, "friction-law.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
