#!/usr/bin/python3
"""The paper's numbers beside this code's, from one command: the runs it
needs (reused when finished, so the study can be run in pieces) and a
report with figures.

    validation/reproduction/run.py WIREFEM OUTDIR [--jobs N]

Done so far: phi_c, beta and gamma of the paper's two classic scenes at
f = 25 over 9 realizations (seeds 1-9), as the paper measured them: the
inlet force averaged over the realizations at equal phi before the fit;
the same from the FEM (3 seeds each) with each wall-friction law
(FEM/Friction law = regularised and = spring, the default: 6-8 minutes a
run, the elastic scene under the spring law about 20); the elastic classic
scene at f = 50 (3 seeds, about 4 minutes a run).
Each scene is prm/classic.prm with

- "Fig. 5" (elastoplastic classic): Yield curvature 0.08, Hardening
  slope 0.05 (kappa_theta 0.08, s 0.05, mu_st 5);
- "elastic classic": Plasticity off (mu_st 5).

The fits (analysis.py): log F = log A + beta log(phi_c - phi) by least
squares (scipy, errors scaled by chi^2/dof) on the realization-averaged
force over phi from half of the earliest jamming to the earliest jamming
(all 9 realizations still running), with phi_c free (kept above the
window) and with phi_c fixed at the paper's value (the window then ends
0.005 below it); the window's start moved to 0.4 and 0.6 of the earliest
jamming shows how beta depends on it. OUTDIR/report.md and
OUTDIR/force_average.png are the report.
"""
import argparse
import os
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, HERE)
import analysis  # noqa: E402

BASE = ["Output/VTU interval=0", "Output/Progress=off"]


def run_case(wirefem, outdir, study, seed):
    """One realization into OUTDIR/<study>_s<seed>; a finished one is kept."""
    st = analysis.STUDIES[study]
    out = os.path.join(outdir, f"{study}_s{seed}")
    if analysis.finished(out):
        return out
    # An interrupted run (its checkpoint kept) is resumed, anything else
    # started over.
    again = "--resume" if os.path.exists(os.path.join(out, "checkpoint.bin")) else "--replace"
    cmd = [wirefem, os.path.join(ROOT, "prm", "classic.prm"), again, "--set", f"Output/Directory={out}",
           "--set", f"Injection/Seed={seed}"]
    sets = (BASE + [f"Cavity/Radius={st['radius']}", f"Model={st['model']}"] + analysis.SCENES[st["scene"]]["sets"] +
            st.get("sets", []))
    for s in sets:
        cmd += ["--set", s]
    with open(out + ".log", "w") as log:
        subprocess.run(cmd, stdout=log, stderr=subprocess.STDOUT, check=False)
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("wirefem")
    parser.add_argument("outdir")
    parser.add_argument("--jobs", type=int, default=1)
    parser.add_argument("--only", nargs="*", choices=list(analysis.STUDIES), help="run only these studies "
                        "(the report takes every finished run)")
    args = parser.parse_args()
    wirefem = os.path.abspath(args.wirefem)
    os.makedirs(args.outdir, exist_ok=True)
    cases = [(study, seed) for study in (args.only or analysis.STUDIES) for seed in analysis.STUDIES[study]["seeds"]]
    with ThreadPoolExecutor(max_workers=args.jobs) as pool:
        for out in pool.map(lambda c: run_case(wirefem, args.outdir, *c), cases):
            print("done:", out, flush=True)
    analysis.report(args.outdir)
    print(f"report: {os.path.join(args.outdir, 'report.md')}")


if __name__ == "__main__":
    main()
