#!/usr/bin/python3
"""Variants of one scene over seeds, side by side: one row per variant with
the state at the end (phi, loops, morphology, how many jammed or failed),
the median wall time, steps, the worst energy balance and the largest
overlap.

    scripts/variant-study.py WIREFEM SCENE.prm OUTDIR --seeds 1 2 3
        --common "Cavity/Radius=15" "Model=fem"
        --variant p1 "FEM/Degree=1" "FEM/Element length=1"
        --variant p2 "FEM/Degree=2" "FEM/Element length=2"

Each run goes to OUTDIR/<variant>_s<seed>; finished runs are reused and
interrupted ones resumed, so the study can be run in pieces (run one
variant at a time to keep the wall times comparable). Writes
OUTDIR/variants.md and prints it.
"""
import argparse
import os
import statistics
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "validation"))
import study  # noqa: E402


def mean_error(xs):
    m, e, n = study.mean_sem(xs)
    if n < 2:
        return f"{m:.4f}" if n else "-"
    return f"{m:.4f} +- {e:.4f}"


def row(name, sets, summaries):
    phi = [s["phi_final"] for s in summaries]
    loops = ", ".join(str(s["loops"]) for s in summaries)
    morph = ", ".join(sorted({s["morphology"] for s in summaries}))
    balance = max(abs(s["energy"]["balance_error"]) for s in summaries)
    overlap = max(s["max_penetration"] for s in summaries)
    wall = statistics.median(s["wall_time_s"] for s in summaries)
    steps = statistics.median(s["steps"] for s in summaries)
    jammed = sum(s["jammed"] for s in summaries)
    failed = sum(s["failed"] for s in summaries)
    return (f"| {name} | {'; '.join(sets)} | {len(summaries)} ({jammed} jammed, {failed} failed) | {mean_error(phi)} "
            f"| {loops} | {morph} | {steps:,.0f} | {wall:.1f} | {balance:.2e} | {overlap:.3f} |")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("wirefem")
    parser.add_argument("scene")
    parser.add_argument("outdir")
    parser.add_argument("--seeds", type=int, nargs="+", default=[1, 2, 3])
    parser.add_argument("--common", nargs="*", default=[], help="Key=value for every run")
    parser.add_argument("--variant", nargs="+", action="append", required=True, metavar=("NAME", "KEY=VALUE"),
                        help="a name and its Key=value overrides (repeatable)")
    args = parser.parse_args()
    os.makedirs(args.outdir, exist_ok=True)
    base = ["Output/Progress=off", "Output/VTU interval=0"] + args.common
    lines = ["| variant | keys | runs | phi at the end | loops | morphology | steps (median) | wall s (median) "
             "| worst balance | largest overlap (d) |", "|---|---|---|---|---|---|---|---|---|---|"]
    for name, *sets in args.variant:
        summaries = []
        for seed in args.seeds:
            out = os.path.join(args.outdir, f"{name}_s{seed}")
            summaries.append(study.run(os.path.abspath(args.wirefem), os.path.abspath(args.scene),
                                       base + sets + [f"Injection/Seed={seed}"], out, reuse=True, log=out + ".log"))
        lines.append(row(name, sets, summaries))
    text = "\n".join([f"`{os.path.basename(args.scene)}` with {'; '.join(args.common) or 'its own keys'}, seeds "
                      f"{' '.join(map(str, args.seeds))}:", ""] + lines) + "\n"
    with open(os.path.join(args.outdir, "variants.md"), "w") as f:
        f.write(text)
    print(text, end="")


if __name__ == "__main__":
    main()
