#!/usr/bin/python3
"""The paper's numbers beside this code's, from one command: the runs it
needs (reused when finished, so the study can be run in pieces) and a
report with figures.

    validation/reproduction/run.py WIREFEM OUTDIR [--jobs N] [--only STUDY...] [--archive]

Runs kept in the repository (validation/reproduction/runs/, archive.py)
are copied into OUTDIR first and not run again; --archive keeps the runs
finished in OUTDIR there afterwards.

The studies (analysis.STUDIES; run directories OUTDIR/<study>_s<seed>):

- phi_c, beta and gamma of the paper's two classic scenes at f = 25 over
  9 realizations (seeds 1-9), as the paper measured them: the inlet force
  averaged over the realizations at equal phi before the fit; the same
  from the FEM (3 seeds each) with each wall-friction law (FEM/Friction
  law = regularised and = spring, the default: 6-8 minutes a run, the
  elastic scene under the spring law about 20); the elastic classic scene
  at f = 50 (3 seeds, about 4 minutes a run); the FEM with the chain's
  friction law between wires too, with and without FEM/Step error =
  1e-2 (the step set by its error estimates), and with the defaults
  (FEM/Linear solver = auto; 1-3 minutes a run);
- both classic scenes injected slowly (Injection/Speed = 0.01, 9 seeds
  each; about 25 and 40 minutes a run), and from the FEM with
  FEM/Integrator = quasi-static at the scenes' speed (3 seeds each);
- gamma of prm/classic.prm at f = 50 (3 seeds) and of prm/plastic.prm at
  f = 100 (one run, about 3 hours);
- the spiral (prm/spiral.prm at f = 25, 3 seeds, run to phi = 1);
- the phase diagram at f = 50 (prm/phase_diagram_f50.prm, 147 runs, about
  25 core-hours, 10-30 minutes a run; with --jobs N > 1 it runs under
  mpirun -np N) into OUTDIR/output/phase_diagram_f50, checked by phase.py.

Each scene is the prm file named in analysis.SCENES (prm/classic.prm
unless named) with

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
OUTDIR/force_average.png and OUTDIR/phase_f50.png are the report.
"""
import argparse
import os
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.dirname(HERE))
import analysis  # noqa: E402
import archive  # noqa: E402
import phase  # noqa: E402
import study  # noqa: E402

BASE = ["Output/VTU interval=0", "Output/Progress=off"]


def run_case(wirefem, outdir, name, seed):
    """One realization into OUTDIR/<name>_s<seed>; a finished one is kept,
    an interrupted one resumed."""
    st = analysis.STUDIES[name]
    out = os.path.join(outdir, f"{name}_s{seed}")
    scene = analysis.SCENES[st["scene"]]
    sets = (BASE + [f"Cavity/Radius={st['radius']}", f"Model={st['model']}", f"Injection/Seed={seed}"] +
            scene["sets"] + st.get("sets", []))
    study.run(wirefem, os.path.join(ROOT, "prm", scene.get("prm", "classic.prm")), sets, out, reuse=True,
              log=out + ".log")
    return out


def run_sweep(wirefem, outdir, jobs):
    """The phase diagram at f = 50 (OUTDIR/output/phase_diagram_f50; the
    sweep skips finished cases and resumes interrupted ones)."""
    cmd = [wirefem, "sweep", os.path.join(ROOT, "prm", phase.SWEEP_PRM)]
    env = dict(os.environ)
    if jobs > 1:
        cmd = ["mpirun", "-np", str(jobs)] + cmd
        if os.geteuid() == 0:  # Open MPI refuses root without these
            env.update(OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    log_name = os.path.join(outdir, "phase_f50.log")
    try:
        with open(log_name, "a") as log:
            rc = subprocess.run(cmd, cwd=outdir, env=env, stdout=log, stderr=subprocess.STDOUT,
                                check=False).returncode
    except FileNotFoundError as e:  # no mpirun
        rc = str(e)
    if rc != 0:
        print(f"the phase-diagram sweep stopped ({rc}): see {log_name}", flush=True)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("wirefem")
    parser.add_argument("outdir")
    parser.add_argument("--jobs", type=int, default=1)
    parser.add_argument("--only", nargs="*", choices=list(analysis.STUDIES) + ["phase_f50"],
                        help="run only these studies (phase_f50: the phase diagram) "
                        "(the report takes every finished run)")
    parser.add_argument("--archive", action="store_true",
                        help="keep OUTDIR's finished runs in validation/reproduction/runs afterwards")
    args = parser.parse_args()
    wirefem = os.path.abspath(args.wirefem)
    os.makedirs(args.outdir, exist_ok=True)
    print(f"restored {archive.restore(os.path.abspath(args.outdir))} kept runs into {args.outdir}", flush=True)
    only = list(dict.fromkeys(args.only or list(analysis.STUDIES) + ["phase_f50"]))
    cases = [(study, seed) for study in only if study != "phase_f50" for seed in analysis.STUDIES[study]["seeds"]]
    with ThreadPoolExecutor(max_workers=args.jobs) as pool:
        for out in pool.map(lambda c: run_case(wirefem, args.outdir, *c), cases):
            print("done:", out, flush=True)
    if "phase_f50" in only:
        run_sweep(wirefem, os.path.abspath(args.outdir), args.jobs)
    if args.archive:
        print(f"kept {archive.save(os.path.abspath(args.outdir))} runs in {archive.ARCHIVE}", flush=True)
    analysis.report(args.outdir)
    print(f"report: {os.path.join(args.outdir, 'report.md')}")


if __name__ == "__main__":
    main()
