#!/usr/bin/python3
"""Finished runs classified before `coiled_fraction` existed, classified
again from their final shapes with the current spiral test.

    validation/reproduction/relabel.py WIREFEM OUTDIR

The spiral test changed from "each half winds at least 0.75 turns the same
way" to "at least half of the wire is coiled" (docs/analysis.md,
Morphology). For each finished run under OUTDIR (the studies' run
directories and the sweep's cases, as archive.py finds them) whose
summary.json has no `coiled_fraction`, `WIREFEM analyze` reads the last VTU
file of the run and its `morphology` and `coiled_fraction` replace the
summary's. Nothing else of the summary changes. A run is left alone, and
named, when it has no VTU file or when the analysis of its shape does not
reproduce the run's own curvature ratio and windings (then the shape is not
the one the run ended with). Run it before archive.py save, which keeps the
rewritten summaries."""
import glob
import json
import math
import os
import subprocess
import sys

import archive

SAME = ("curvature_ratio", "winding_left", "winding_right")


def same(a, b):
    if a is None or b is None:
        return a is b
    return math.isclose(a, b, rel_tol=1e-9, abs_tol=1e-12)


def relabel(wirefem, run_dir):
    """'changed', 'unchanged', or why the run was left alone."""
    path = os.path.join(run_dir, "summary.json")
    with open(path) as f:
        summary = json.load(f)
    if "coiled_fraction" in summary:
        return "current"
    if not glob.glob(os.path.join(run_dir, "wire_*.vtu")):
        return "no VTU file"
    shape = json.loads(subprocess.run([wirefem, "analyze", run_dir], check=True, capture_output=True,
                                      text=True).stdout)
    if not all(same(summary.get(k), shape.get(k)) for k in SAME):
        return "its last VTU file is not the shape it ended with"
    before = summary["morphology"]
    summary["morphology"] = shape["morphology"]
    summary["coiled_fraction"] = shape["coiled_fraction"]
    with open(path + ".part", "w") as f:
        json.dump(summary, f, indent=2, sort_keys=True)
        f.write("\n")
    os.replace(path + ".part", path)
    return "unchanged" if before == summary["morphology"] else f"{before} -> {summary['morphology']}"


def main(argv):
    if len(argv) != 3:
        sys.exit(__doc__)
    wirefem, outdir = argv[1], argv[2]
    counts = {}
    for rel in archive.run_dirs(outdir):
        run_dir = os.path.join(outdir, rel)
        if not archive.finished(run_dir):
            continue
        result = relabel(wirefem, run_dir)
        counts[result] = counts.get(result, 0) + 1
        if result not in ("current", "unchanged"):
            print(f"{rel}: {result}")
    print(", ".join(f"{n} {what}" for what, n in sorted(counts.items())))


if __name__ == "__main__":
    main(sys.argv)
