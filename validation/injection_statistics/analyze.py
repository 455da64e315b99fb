#!/usr/bin/python3
"""Work-precision of the injection statistics (measured, not asserted): how
much phi at jamming and the loop count at fixed phi move when the time step
or the injection speed changes, against how much they scatter between
realizations (seeds), and what each setting costs.

The runs are the classic scene at f = 25 (`wirefem prm/classic.prm --set
Cavity/Radius=25 --set Injection/Speed=V --set "Discrete/Time step
factor=F" --set Injection/Seed=S`), one directory per run named
v<V>_f<F>_s<S>; run.sh next to this file makes them.

    validation/injection_statistics/analyze.py OUTDIR RUNS_DIR
"""
import json
import math
import os
import re
import statistics
import sys

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import study  # noqa: E402

PHIS = (0.2, 0.3, 0.4)


def loops_at(rows, phi):
    best = min(rows, key=lambda r: abs(r["phi"] - phi))
    return best["loops"] if abs(best["phi"] - phi) < 0.01 else float("nan")


def mean_std(xs):
    xs = [x for x in xs if not math.isnan(x)]
    if not xs:
        return float("nan"), float("nan")
    m = sum(xs) / len(xs)
    s = math.sqrt(sum((x - m) ** 2 for x in xs) / (len(xs) - 1)) if len(xs) > 1 else float("nan")
    return m, s


def main():
    outdir, runs_dir = sys.argv[1], sys.argv[2]
    os.makedirs(outdir, exist_ok=True)
    groups = {}
    for name in sorted(os.listdir(runs_dir)):
        m = re.fullmatch(r"(?:r\d+_)?v([0-9.]+)_f([0-9.]+)_s(\d+)", name)
        path = os.path.join(runs_dir, name)
        if not m or not os.path.exists(os.path.join(path, "summary.json")):
            continue
        with open(os.path.join(path, "summary.json")) as f:
            s = json.load(f)
        rows = study.read_series(path)
        key = (s["cavity_radius"], float(m.group(1)), float(m.group(2)))
        groups.setdefault(key, []).append({
            "seed": int(m.group(3)), "phi_final": s["phi_final"], "jammed": s["jammed"],
            "loops": {f"{p:g}": loops_at(rows, p) for p in PHIS}, "wall_time_s": s["wall_time_s"],
            "steps": s["steps"], "balance_error": s["energy"]["balance_error"],
            "curvature_ratio": s.get("curvature_ratio"), "symmetry": s.get("symmetry")})
    table = []
    print("   f  speed  dt factor  runs  phi_jam (mean +- sd)   " +
          "  ".join(f"loops@{p:g}" for p in PHIS) + "   wall time (median)")
    for (radius, speed, factor), runs in sorted(groups.items(), key=lambda kv: (kv[0][0], -kv[0][1], -kv[0][2])):
        phi = mean_std([r["phi_final"] for r in runs])
        loops = {p: mean_std([r["loops"][f"{p:g}"] for r in runs]) for p in PHIS}
        median = statistics.median(r["wall_time_s"] for r in runs)
        table.append({"radius": radius, "speed": speed, "time_step_factor": factor, "runs": runs, "phi_jam": phi,
                      "loops": {f"{p:g}": loops[p] for p in PHIS}, "median_wall_time_s": median})
        print(f"{radius:4g}  {speed:5g}  {factor:9g}  {len(runs):4d}  {phi[0]:.4f} +- {phi[1]:.4f}        " +
              "  ".join(f"{loops[p][0]:5.1f}+-{loops[p][1]:4.1f}" for p in PHIS) + f"   {median:.0f} s")
    with open(os.path.join(outdir, "results.json"), "w") as f:
        json.dump({"study": "injection_statistics", "asserted": False, "groups": table}, f, indent=2)
    plot(table, os.path.join(outdir, "injection_statistics.png"))


def plot(table, filename):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (a, b, c) = plt.subplots(1, 3, figsize=(15, 4.5))
    for i, g in enumerate(table):
        label = f"f = {g['radius']:g}, speed {g['speed']:g}, dt factor {g['time_step_factor']:g}"
        t = [r["wall_time_s"] for r in g["runs"]]
        a.plot(t, [r["phi_final"] for r in g["runs"]], "o", color=f"C{i}", label=label)
        sd = g["phi_jam"][1] if not math.isnan(g["phi_jam"][1]) else 0.0
        a.errorbar([g["median_wall_time_s"]], [g["phi_jam"][0]], yerr=[sd], fmt="s", color=f"C{i}",
                   capsize=4, ms=8, mfc="none")
        b.plot(t, [r["loops"]["0.3"] for r in g["runs"]], "o", color=f"C{i}", label=label)
    for radius in sorted({g["radius"] for g in table}):
        gs = sorted((g for g in table if g["radius"] == radius and g["time_step_factor"] == 0.25),
                    key=lambda g: g["speed"])
        c.errorbar([g["speed"] for g in gs], [g["phi_jam"][0] for g in gs],
                   yerr=[0.0 if math.isnan(g["phi_jam"][1]) else g["phi_jam"][1] for g in gs],
                   fmt="o-", capsize=4, label=f"f = {radius:g}")
    for ax in (a, b):
        ax.set_xscale("log")
        ax.set_xlabel("wall time (s)")
    a.set_ylabel("phi at jamming")
    a.set_title("classic scene: phi at jamming (dots: seeds; squares: mean +- sd)")
    a.title.set_fontsize(9)
    a.legend(fontsize=6)
    b.set_ylabel("loops at phi = 0.3")
    b.set_title("loops at phi = 0.3")
    c.set_xscale("log")
    c.set_xlabel("injection speed (each channel)")
    c.set_ylabel("phi at jamming (mean +- sd over seeds)")
    c.set_title("toward the quasi-static limit (dt factor 0.25)")
    c.title.set_fontsize(9)
    c.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(filename, dpi=100)


if __name__ == "__main__":
    main()
