#!/usr/bin/python3
"""Cavity shape and injection angle against morphology: the paper's three
scenes at f = 25 (every shape has the circle's area) with 3 seeds, for
channels turned 0, 30, 60 and 90 degrees from the wall's normal on the
circle (90: Injection/Channels = tangential) and for ellipses of aspect
ratio 1 (the circle), 1.5 and 2 with facing channels, and for one channel
on the circle (the wire's other end free), discrete model.

    validation/shapes/run.py WIREFEM OUTDIR [--jobs N] [--seeds S...] [--radius F]

Runs go to OUTDIR/<scene>_<geometry>_s<seed> and are reused when finished
(the study can be run in pieces); the table and the figure of final states
(seed 1 of each) are written beside this script as REPORT.md and
final_states.png.
"""
import argparse
import json
import math
import os
import sys
from concurrent.futures import ThreadPoolExecutor

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.dirname(HERE))
import study  # noqa: E402

SCENES = [("spiral", "prm/spiral.prm"), ("classic", "prm/classic.prm"), ("plastic", "prm/plastic.prm")]
GEOMETRIES = [
    ("circle_0", "circle, channels at 0 deg", []),
    ("circle_30", "circle, 30 deg", ["Injection/Channel angle=30"]),
    ("circle_60", "circle, 60 deg", ["Injection/Channel angle=60"]),
    ("circle_90", "circle, 90 deg (tangential)", ["Injection/Channels=tangential"]),
    ("ellipse_1.5", "ellipse 1.5, 0 deg", ["Cavity/Shape=ellipse", "Cavity/Aspect ratio=1.5"]),
    ("ellipse_2", "ellipse 2, 0 deg", ["Cavity/Shape=ellipse", "Cavity/Aspect ratio=2"]),
    ("circle_one", "circle, one channel, 0 deg", ["Injection/Channel positions=0.5"]),
]


def runs(seeds, radius):
    for scene, prm in SCENES:
        for key, _, sets in GEOMETRIES:
            for seed in seeds:
                yield scene, key, seed, prm, [f"Cavity/Radius={radius}", f"Injection/Seed={seed}",
                                              "Output/Progress=off"] + sets


def mean_sd(xs, digits=3):
    xs = [x for x in xs if x is not None and math.isfinite(x)]
    if not xs:
        return "-"
    m = sum(xs) / len(xs)
    if len(xs) == 1:
        return f"{m:.{digits}f}"
    sd = math.sqrt(sum((x - m) ** 2 for x in xs) / (len(xs) - 1))
    return f"{m:.{digits}f} +- {sd:.{digits}f}"


def report(results, seeds, radius, command):
    lines = ["# Cavity shape and injection angle", "",
             f"Discrete model, f = {radius} (every shape has the area of the circle of radius f), seeds "
             f"{', '.join(map(str, seeds))}; each scene's prm file with the keys of its geometry "
             "(`run.py` lists them). Regenerate with", "", f"    {command}", "",
             "phi and loops: mean +- standard deviation over the seeds at the end of the run (jamming, "
             "or the scene's maximum packing density 0.6); morphology: the label of each seed "
             "(docs/analysis.md says what the labels mean in a cavity that is not a circle). With one "
             "channel, symmetry is the share of the wire its mirror image about the channel's axis "
             "covers (random strewing scores about phi/2), not the two-channel score.", "",
             "| scene | geometry | morphology | phi at the end | jammed | loops | symmetry | largest overlap (d) "
             "| worst balance error |", "|---|---|---|---|---|---|---|---|---|"]
    for scene, _ in SCENES:
        for key, label, _ in GEOMETRIES:
            rs = [results[(scene, key, s)] for s in seeds if (scene, key, s) in results]
            if not rs:
                continue
            lines.append(
                f"| {scene} | {label} | {', '.join(r['morphology'] for r in rs)} "
                f"| {mean_sd([r['phi_final'] for r in rs])} | {sum(bool(r['jammed']) for r in rs)} of {len(rs)} "
                f"| {mean_sd([r['loops'] for r in rs], 1)} | {mean_sd([r['symmetry'] for r in rs], 2)} "
                f"| {max(r['max_penetration'] for r in rs):.3f} "
                f"| {max(abs(r['energy']['balance_error']) for r in rs):.1e} |")
    lines += ["", "![final states, seed 1](final_states.png)", "",
              "*Final states of seed 1: rows are the scenes (spiral, classic, plastic), columns the "
              "geometries in the table's order.*", ""]
    return "\n".join(lines)


def montage(outdir, seeds, path):
    from PIL import Image, ImageDraw
    tile = 220
    img = Image.new("RGB", (tile * len(GEOMETRIES), tile * len(SCENES) + 20), "white")
    draw = ImageDraw.Draw(img)
    for i, (scene, _) in enumerate(SCENES):
        for j, (key, label, _) in enumerate(GEOMETRIES):
            png = os.path.join(outdir, f"{scene}_{key}_s{seeds[0]}", "final.png")
            if os.path.exists(png):
                img.paste(Image.open(png).convert("RGB").resize((tile, tile)), (j * tile, 20 + i * tile))
            if i == 0:
                draw.text((j * tile + 5, 4), label, fill="black")
    img.convert("L").save(path, optimize=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("wirefem")
    ap.add_argument("outdir")
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--seeds", type=int, nargs="+", default=[1, 2, 3])
    ap.add_argument("--radius", type=float, default=25)
    a = ap.parse_args()
    os.makedirs(a.outdir, exist_ok=True)
    todo = list(runs(a.seeds, a.radius))

    def one(item):
        scene, key, seed, prm, sets = item
        out = os.path.join(os.path.abspath(a.outdir), f"{scene}_{key}_s{seed}")
        summary = study.run(os.path.abspath(a.wirefem), os.path.join(ROOT, prm), sets, out, reuse=True,
                            log=out + ".log")
        print(f"{scene} {key} seed {seed}: {summary['morphology']}, phi {summary['phi_final']:.4f}, "
              f"{summary['loops']} loops", flush=True)
        return (scene, key, seed), summary

    with ThreadPoolExecutor(max_workers=a.jobs) as pool:
        results = dict(pool.map(one, todo))
    command = "validation/shapes/run.py build/wirefem OUTDIR --jobs 2"
    if a.seeds != [1, 2, 3] or a.radius != 25:
        command += f" --seeds {' '.join(map(str, a.seeds))} --radius {a.radius:g}"
    with open(os.path.join(HERE, "REPORT.md"), "w") as f:
        f.write(report(results, a.seeds, a.radius, command))
    montage(os.path.abspath(a.outdir), a.seeds, os.path.join(HERE, "final_states.png"))
    json.dump({f"{k[0]}_{k[1]}_s{k[2]}": v for k, v in results.items()},
              open(os.path.join(a.outdir, "results.json"), "w"), indent=1)


if __name__ == "__main__":
    main()
