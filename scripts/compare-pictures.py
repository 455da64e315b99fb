#!/usr/bin/python3
"""A grid of final pictures, one row per model (or any label), captioned
with phi and the loops and morphology `wirefem analyze` finds.

    scripts/compare-pictures.py [--radius=R] WIREFEM OUT.png LABEL=DIR,DIR,... [LABEL=DIR,...]

A DIR may be written TITLE::DIR to head its caption with TITLE instead of
the scene name. Captions give phi, loops, morphology, the curvature ratio
A/B and the symmetry score.

--radius gives the cavity radius of runs whose summary.json does not
record it (runs of older versions).

Each DIR is a run's output directory (final.png, summary.json). The
figure docs/figures/models-f25.png was made with
    scripts/compare-pictures.py build/wirefem docs/figures/models-f25.png \\
        discrete=out/c,out/s,out/p FEM=out/fc,out/fs,out/fp
where out/* are the three paper scenes at f = 25 in each model.
"""
import json
import subprocess
import sys

from PIL import Image, ImageDraw

SIZE = 330


def main():
    args = sys.argv[1:]
    fallback_radius = None
    if args and args[0].startswith("--radius="):
        fallback_radius = args.pop(0).partition("=")[2]
    if len(args) < 3:
        sys.exit(__doc__)
    exe, out = args[0], args[1]
    rows = [(a.partition("=")[0], a.partition("=")[2].split(",")) for a in args[2:]]
    cols = max(len(dirs) for _, dirs in rows)
    img = Image.new("RGB", (cols * SIZE + 70, len(rows) * (SIZE + 30)), "white")
    draw = ImageDraw.Draw(img)
    for r, (label, dirs) in enumerate(rows):
        y0 = r * (SIZE + 30)
        draw.text((8, y0 + SIZE // 2), label, fill="black")
        for c, entry in enumerate(dirs):
            title, _, run = entry.rpartition("::")
            summary = json.load(open(f"{run}/summary.json"))
            radius = summary.get("cavity_radius", fallback_radius)
            cmd = [exe, "analyze", run] + (["--radius", str(radius)] if radius else [])
            shape = json.loads(subprocess.check_output(cmd))
            picture = Image.open(f"{run}/final.png").convert("RGB")
            w, h = picture.size
            # The picture's own caption is cut off: it may come from an older
            # loop counter; the caption below is from `wirefem analyze`.
            picture = picture.crop((0, 0, w, int(h * 0.955))).resize((SIZE, int(SIZE * 0.955)))
            img.paste(picture, (70 + c * SIZE, y0))
            # JSON has no infinity: A/B without curvature in the ring is null.
            ratio = "inf" if shape["curvature_ratio"] is None else f"{shape['curvature_ratio']:.2f}"
            draw.text((80 + c * SIZE, y0 + int(SIZE * 0.955) + 2),
                      f"{title or summary.get('scene', '')}  phi={summary['phi_final']:.3f}  "
                      f"loops={shape['loops']}  {shape['morphology']}\n"
                      f"A/B={ratio}  symmetry={shape['symmetry']:.2f}", fill="black")
    img.save(out, optimize=True)
    print(out)


if __name__ == "__main__":
    main()
