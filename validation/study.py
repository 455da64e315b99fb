"""What the validation drivers share: running wirefem on a prm file, the
discretisations of both models, convergence orders and their checks, the
results file and the convergence / work-precision figure."""
import csv
import json
import math
import os
import subprocess

# (model label, prm overrides, discretisation key, lengths, expected order,
# check) for a rod of length 20: the discrete model and FEM degrees 1-3.
# The order between the two finest discretisations must be
# "equal": within ORDER_SLACK of the order (discrete model, p = 1);
# "at least": the max-norm rate p + 1 less ORDER_SLACK (p >= 2; at a node 2p
# is expected).
DISCRETISATIONS = [
    ("discrete", [], "Discrete/Segment length", [2.0, 1.0, 0.5, 0.25], 2.0, "equal"),
    ("fem p=1", ["Model=fem", "FEM/Degree=1", "Cantilever/Tolerance=1e-10"], "FEM/Element length",
     [5.0, 2.5, 1.25, 0.625, 0.3125], 2.0, "equal"),
    ("fem p=2", ["Model=fem", "FEM/Degree=2", "Cantilever/Tolerance=1e-10"], "FEM/Element length",
     [10.0, 5.0, 2.5, 1.25], 3.0, "at least"),
    ("fem p=3", ["Model=fem", "FEM/Degree=3", "Cantilever/Tolerance=1e-10"], "FEM/Element length",
     [10.0, 5.0, 2.5, 1.25], 4.0, "at least"),
]
ORDER_SLACK = 0.2
# Errors below this are round-off and equilibrium tolerance, not
# discretisation: no order is measured from them.
FLOOR = 1e-9


def mean_sem(xs):
    """(mean, standard error of the mean, n) of the finite values of xs;
    the error is nan for one value, and all are nan for none."""
    xs = [x for x in xs if x is not None and math.isfinite(x)]
    if not xs:
        return float("nan"), float("nan"), 0
    m = sum(xs) / len(xs)
    if len(xs) == 1:
        return m, float("nan"), 1
    var = sum((x - m) ** 2 for x in xs) / (len(xs) - 1)
    return m, math.sqrt(var / len(xs)), len(xs)


def finished(out):
    """Whether out holds a run that ended (summary.json, not interrupted;
    only injection runs can be interrupted, so a summary without the key
    is a finished one)."""
    try:
        with open(os.path.join(out, "summary.json")) as f:
            return not json.load(f).get("interrupted", False)
    except (OSError, ValueError):
        return False


def run(wirefem, prm, sets, out, reuse=False, log=None):
    """Runs wirefem on prm with the overrides into out and returns its
    summary. With reuse, a finished run in out is taken as it is (to redo
    an analysis, or to run a study in pieces) and an interrupted one with
    its checkpoint is resumed. Without log, the output is dropped and a
    non-zero exit status raises; with it, the output goes to that file
    (appended to on a resume), a run that ended by a numerical limit (exit
    3, its summary says why) is returned, and anything else that did not
    finish (bad input, a refused resume, an interruption) raises."""
    # The keys a run was made with, beside it: a run made with others is not
    # reused or resumed but made again.
    keys_file, keys = out + ".keys.json", [prm] + list(sets)
    try:
        with open(keys_file) as f:
            same = json.load(f) == keys
    except (OSError, ValueError):
        same = not os.path.exists(keys_file)  # runs made before the record are taken as they are
    if not (reuse and same and finished(out)):
        again = "--resume" if reuse and same and os.path.exists(os.path.join(out, "checkpoint.bin")) else "--replace"
        with open(keys_file, "w") as f:
            json.dump(keys, f)
        cmd = [wirefem, prm, again, "--set", f"Output/Directory={out}"]
        for s in sets:
            cmd += ["--set", s]
        if log is None:
            subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
        else:
            with open(log, "a" if again == "--resume" else "w") as f:
                rc = subprocess.run(cmd, stdout=f, stderr=subprocess.STDOUT, check=False).returncode
            if rc not in (0, 3) or not finished(out):
                raise RuntimeError(f"{out}: wirefem stopped with exit status {rc} and no finished run; see {log}")
    with open(os.path.join(out, "summary.json")) as f:
        return json.load(f)


def scene_run(wirefem, scene, sets, out):
    """run() on prm/SCENE with the progress line and VTU files off: a
    finished run in out is reused, an interrupted one resumed, and the
    output goes to out.log."""
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    quiet = ["Output/Progress=off", "Output/VTU interval=0"]
    return run(wirefem, os.path.join(root, "prm", scene), quiet + list(sets), out, reuse=True, log=out + ".log")


def read_series(out):
    """The rows of out/series.csv, each a dict of floats."""
    with open(os.path.join(out, "series.csv")) as f:
        return [{k: float(v) for k, v in r.items()} for r in csv.DictReader(f)]


def add_orders(rows, keys, skip=()):
    """order_<key> on each row from the previous one (errors above FLOOR)."""
    for a, b in zip(rows, rows[1:]):
        for key in keys:
            if key in skip or min(a[key], b[key]) <= FLOOR:
                continue
            b["order_" + key[6:]] = math.log(a[key] / b[key]) / math.log(a["h"] / b["h"])


def check(label, rows, tolerance, order, how, failures):
    """Appends to failures what misses its tolerance (finest row) or order."""
    finest = rows[-1]
    for key, tol in tolerance.items():
        if finest[key] > tol:
            failures.append(f"{label}: {key} {finest[key]:.3e} > {tol:g} at h = {finest['h']}")
    # The order is asserted where it is asymptotic: between the two finest
    # discretisations (the coarser pairs are reported, not checked).
    for r in rows[-1:]:
        for key in [k for k in r if k.startswith("order_")]:
            ok = abs(r[key] - order) <= ORDER_SLACK if how == "equal" else r[key] >= order - ORDER_SLACK
            if not ok:
                failures.append(f"{label}: {key} {r[key]:.2f} at h = {r['h']}, expected "
                                f"{'' if how == 'equal' else '>= '}{order} (slack {ORDER_SLACK})")


def print_rows(label, rows, keys):
    print(label)
    for r in rows:
        parts = [f"{k[6:]} error {r[k]:.3e} (order {r.get('order_' + k[6:], float('nan')):.2f})" for k in keys]
        print(f"  h = {r['h']:<7} " + ", ".join(parts) + f", {r['wall_time_s']:.3f} s")


def write(outdir, summary):
    with open(os.path.join(outdir, "results.json"), "w") as f:
        json.dump(summary, f, indent=2)
    for msg in summary["failures"]:
        print("FAILED:", msg)


def plot(results, cases, key, length, title, filename):
    """Error against h / L and against wall time for the given cases."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (a, b) = plt.subplots(1, 2, figsize=(11, 4.5))
    colours = {"discrete": "C0", "fem p=1": "C1", "fem p=2": "C2", "fem p=3": "C3"}
    styles = ["o-", "s--", "^:"]
    for c in results:
        if c["case"] not in cases:
            continue
        style = styles[cases.index(c["case"]) % len(styles)]
        h = [r["h"] / length for r in c["rows"]]
        e = [max(r[key], 1e-16) for r in c["rows"]]
        t = [r["wall_time_s"] for r in c["rows"]]
        label = f"{c['model']}, {c['case']}"
        a.loglog(h, e, style, color=colours[c["model"]], label=label)
        b.loglog(t, e, style, color=colours[c["model"]], label=label)
    a.set_xlabel("lambda_0 / L or h / L")
    a.set_ylabel(key.replace("_", " "))
    a.set_title(title + ": convergence")
    b.set_xlabel("wall time (s)")
    b.set_ylabel(key.replace("_", " "))
    b.set_title(title + ": work-precision")
    a.legend(fontsize=6)
    fig.tight_layout()
    fig.savefig(filename, dpi=100)
