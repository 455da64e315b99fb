#!/usr/bin/python3
"""Validation case 6 (measured, not asserted): the injection force of the
spiral scene against the tight-spiral estimate.

The estimate. An elastic, frictionless wire of diameter d wound into a
tight spiral against the wall of a disc of radius R, with turns from R down
to an inner radius rho, stores (each turn 2 pi rho_k long at curvature
1/rho_k, turns d apart)

    E = sum_k pi EI / rho_k  ~  (pi EI / d) ln(R / rho),

and holds L = (pi / d)(R^2 - rho^2), i.e. rho^2 = R^2 (1 - phi) with
phi = d L / (pi R^2). Quasi-statically the injection does the work dE, so the
force (the mean of the two inlets; their work is F dL with L the total
injected length) is

    F_ts = dE/dL = EI / (2 rho^2) = EI / (2 R^2 (1 - phi)),
    E_ts(phi) = (pi EI / (2 d)) ln(1 / (1 - phi)):

phi_c = 1 and exponent -1.

The runs. For each run directory (spiral scenes, `wirefem prm/spiral.prm`
with overrides), per window of phi: the mean inlet force, the slopes
d(stored energy)/dL and d(dissipated energy)/dL from series.csv, and
F_ts; figure and results.json in OUTDIR.

    validation/spiral_force/analyze.py OUTDIR RUN_DIR [RUN_DIR ...]

(EI = 60, the value of prm/spiral.prm.)
"""
import json
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import study  # noqa: E402

WINDOW = 0.05
EI = 60.0  # the bending stiffness of prm/spiral.prm


def stored_energy(row):
    return row["energy_bending"] + row["energy_stretching"] + row["energy_contact"]


def tight_spiral_energy(phi):
    return math.pi * EI / 2.0 * math.log(1.0 / (1.0 - phi))


def read(run):
    rows = study.read_series(run)
    with open(os.path.join(run, "summary.json")) as f:
        summary = json.load(f)
    return rows, summary


def windows(rows, radius, EI):
    out = []
    phi0 = rows[0]["phi"]
    a = math.ceil(phi0 / WINDOW) * WINDOW
    while True:
        inside = [r for r in rows if a <= r["phi"] < a + WINDOW]
        if len(inside) < 3:
            break
        first, last = inside[0], inside[-1]
        dl = last["injected_length"] - first["injected_length"]
        dissipated = lambda r: r["damping_dissipation"] + r["friction_dissipation"] + r["plastic_dissipation"]  # noqa: E731
        phi = 0.5 * (first["phi"] + last["phi"])
        out.append({"phi": phi,
                    "force": sum(r["force"] for r in inside) / len(inside),
                    "stored_slope": (stored_energy(last) - stored_energy(first)) / dl,
                    "dissipated_slope": (dissipated(last) - dissipated(first)) / dl,
                    "kinetic_slope": (last["energy_kinetic"] - first["energy_kinetic"]) / dl,
                    "tight_spiral_force": EI / (2.0 * radius ** 2 * (1.0 - phi)),
                    "bending_energy": last["energy_bending"],
                    "tight_spiral_energy": tight_spiral_energy(last["phi"])})
        a += WINDOW
    return out


def main():
    outdir, runs = sys.argv[1], sys.argv[2:]
    os.makedirs(outdir, exist_ok=True)
    results = []
    for run in runs:
        rows, summary = read(run)
        radius = summary["cavity_radius"]
        # Each channel's speed, from the injected length (both channels) at the end.
        speed = 0.5 * (rows[-1]["injected_length"] - rows[-2]["injected_length"]) / (rows[-1]["time"] - rows[-2]["time"])
        ws = windows(rows, radius, EI)
        results.append({"run": run, "radius": radius, "speed": speed, "phi_final": summary["phi_final"],
                        "windows": ws})
        print(f"{run}: f = {radius:g}, speed {speed:.3g}, phi_final {summary['phi_final']:.3f}")
        print("   phi   force  F_ts  force/F_ts  dE_stored/dL  dD/dL  E_bend/E_ts")
        for w in ws:
            print(f"  {w['phi']:.3f} {w['force']:.4f} {w['tight_spiral_force']:.4f} "
                  f"{w['force'] / w['tight_spiral_force']:6.2f} {w['stored_slope']:9.4f} "
                  f"{w['dissipated_slope']:9.4f} {w['bending_energy'] / w['tight_spiral_energy']:8.2f}")
    with open(os.path.join(outdir, "results.json"), "w") as f:
        json.dump({"validation": "spiral_force", "asserted": False, "runs": results}, f, indent=2)
    plot(results, os.path.join(outdir, "spiral_force.png"))


def plot(results, filename):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (a, b) = plt.subplots(1, 2, figsize=(11, 4.5))
    for i, r in enumerate(results):
        ws = r["windows"]
        phi = [w["phi"] for w in ws]
        scale = lambda w: 1.0 / w["tight_spiral_force"]  # noqa: E731
        label = f"f = {r['radius']:g}, speed {r['speed']:.2g}"
        a.plot(phi, [w["force"] * scale(w) for w in ws], "o-", color=f"C{i}", label=label + ": force")
        a.plot(phi, [w["stored_slope"] * scale(w) for w in ws], "s:", color=f"C{i}", ms=4,
               label=label + ": d(stored)/dL")
        b.plot(phi, [w["bending_energy"] / w["tight_spiral_energy"] for w in ws], "o-", color=f"C{i}", label=label)
    a.axhline(1.0, color="k", lw=1)
    a.set_yscale("log")
    a.set_xlabel("phi")
    a.set_ylabel("/ F_ts = EI / (2 R^2 (1 - phi))")
    a.set_title("inlet force (window means) against the tight spiral")
    a.legend(fontsize=6)
    b.axhline(1.0, color="k", lw=1)
    b.set_xlabel("phi")
    b.set_ylabel("bending energy / E_ts")
    b.set_title("stored bending energy against the tight spiral")
    b.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(filename, dpi=100)


if __name__ == "__main__":
    main()
