#!/usr/bin/python3
"""The finished runs of the reproduction study, kept in the repository
(validation/reproduction/runs/) so that the report can be regenerated, and
the phase-diagram sweep continued, on a machine that does not hold the run
directories.

    validation/reproduction/archive.py save OUTDIR     # OUTDIR's finished runs into runs/
    validation/reproduction/archive.py restore OUTDIR  # runs/ into OUTDIR, where not there

A run is kept as its summary.json and the columns phi, force and loops of
its series.csv (what analysis.py and the sweep's tables read), the values'
text unchanged. A restored run counts as finished for run.py and for
`wirefem sweep`, which then skip it. Interrupted and unfinished runs are
neither saved nor restored."""
import csv
import json
import os
import shutil
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ARCHIVE = os.path.join(HERE, "runs")
COLUMNS = ("phi", "force", "loops")
SWEEP = os.path.join("output", "phase_diagram_f50")


def finished(run_dir):
    """Whether run_dir holds a run that ended (not interrupted)."""
    try:
        with open(os.path.join(run_dir, "summary.json")) as f:
            return not json.load(f).get("interrupted", True)
    except (OSError, ValueError):
        return False


def run_dirs(root):
    """The relative paths of the run directories under root: the studies'
    <study>_s<seed> and the sweep's cases."""
    found = []
    for base in (".", SWEEP):
        d = os.path.join(root, base)
        if not os.path.isdir(d):
            continue
        for name in sorted(os.listdir(d)):
            if os.path.isfile(os.path.join(d, name, "summary.json")):
                found.append(os.path.normpath(os.path.join(base, name)))
    return found


def keep(src, dst):
    """src's summary and the series' columns COLUMNS into dst (written
    beside and renamed, so an interrupted save leaves no half run)."""
    tmp = dst + ".part"
    shutil.rmtree(tmp, ignore_errors=True)
    os.makedirs(tmp)
    shutil.copyfile(os.path.join(src, "summary.json"), os.path.join(tmp, "summary.json"))
    with open(os.path.join(src, "series.csv"), newline="") as f, \
            open(os.path.join(tmp, "series.csv"), "w", newline="") as g:
        out = csv.writer(g, lineterminator="\n")
        out.writerow(COLUMNS)
        for row in csv.DictReader(f):
            out.writerow([row[c] for c in COLUMNS])
    shutil.rmtree(dst, ignore_errors=True)
    os.rename(tmp, dst)


def save(outdir, archive=ARCHIVE):
    """Every finished run of outdir not yet kept, or kept from an older
    summary; returns how many were written."""
    n = 0
    for rel in run_dirs(outdir):
        src, dst = os.path.join(outdir, rel), os.path.join(archive, rel)
        if not finished(src):
            continue
        if finished(dst) and open(os.path.join(src, "summary.json"), "rb").read() == \
                open(os.path.join(dst, "summary.json"), "rb").read():
            continue
        os.makedirs(os.path.dirname(dst), exist_ok=True)
        keep(src, dst)
        n += 1
    return n


def restore(outdir, archive=ARCHIVE):
    """Every kept run whose directory in outdir holds no finished run;
    returns how many were copied. An unfinished run there (a checkpoint of
    an interrupted one) is replaced by the finished one kept."""
    n = 0
    for rel in run_dirs(archive):
        src, dst = os.path.join(archive, rel), os.path.join(outdir, rel)
        if finished(dst) or not finished(src):
            continue
        shutil.rmtree(dst, ignore_errors=True)
        shutil.copytree(src, dst)
        n += 1
    return n


def self_test():
    import tempfile

    with tempfile.TemporaryDirectory() as t:
        out, arc = os.path.join(t, "out"), os.path.join(t, "arc")
        for rel, interrupted in (("a_s1", False), (os.path.join(SWEEP, "kappa0.1_mu0_seed1"), False),
                                 ("b_s1", True)):
            d = os.path.join(out, rel)
            os.makedirs(d)
            with open(os.path.join(d, "summary.json"), "w") as f:
                json.dump({"interrupted": interrupted}, f)
            with open(os.path.join(d, "series.csv"), "w") as f:
                f.write("t,phi,force,loops,energy\n0,0.10,1.5e+00,2,9\n1,0.125,2.0,3,9\n")
        assert save(out, arc) == 2 and save(out, arc) == 0
        with open(os.path.join(arc, "a_s1", "series.csv")) as f:
            assert f.read() == "phi,force,loops\n0.10,1.5e+00,2\n0.125,2.0,3\n"
        assert not os.path.exists(os.path.join(arc, "b_s1"))
        fresh = os.path.join(t, "fresh")
        assert restore(fresh, arc) == 2 and restore(fresh, arc) == 0
        assert finished(os.path.join(fresh, SWEEP, "kappa0.1_mu0_seed1"))
    print("archive self-test: ok")


def main():
    if len(sys.argv) == 2 and sys.argv[1] == "--self-test":
        self_test()
        return
    if len(sys.argv) != 3 or sys.argv[1] not in ("save", "restore"):
        sys.exit(__doc__.split("\n\n")[1])
    n = (save if sys.argv[1] == "save" else restore)(os.path.abspath(sys.argv[2]))
    print(f"archive: {n} runs {'kept in' if sys.argv[1] == 'save' else 'restored from'} {ARCHIVE}")


if __name__ == "__main__":
    main()
