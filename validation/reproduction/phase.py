"""The phase diagram at the paper's size (prm/phase_diagram_f50.prm, run by
run.py into OUTDIR/output/phase_diagram_f50): the majority phase of each
cell from its runs' summaries (so a sweep still under way is read too), the
paper's three features checked, and the factor on kappa_theta that maps the
smallest classic kappa_theta onto the paper's."""
import collections
import json
import os
import re

SWEEP_PRM = "phase_diagram_f50.prm"
SWEEP_DIR = os.path.join("output", "phase_diagram_f50")
PAPER_CLASSIC_KAPPA = 0.027  # the paper's smallest kappa_theta of the classic phase
REENTRANT_MU = (0.2, 0.35)  # the paper's re-entrance: plastic, classic, plastic with growing kappa_theta
CASE = re.compile(r"kappa([0-9.eE+-]+)_mu([0-9.eE+-]+)_seed(\d+)$")
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
COLOURS = {"spiral": "tab:blue", "classic": "tab:green", "plastic": "tab:red"}


def read_cells(sweep_dir):
    """{(kappa, mu): Counter of the morphologies of its finished, unfailed
    runs, plus the keys 'finished' and 'failed'}."""
    cells = collections.defaultdict(collections.Counter)
    if not os.path.isdir(sweep_dir):
        return cells
    for name in os.listdir(sweep_dir):
        m = CASE.match(name)
        if not m:
            continue
        cell = cells[(float(m.group(1)), float(m.group(2)))]
        try:
            with open(os.path.join(sweep_dir, name, "summary.json")) as f:
                summary = json.load(f)
        except (OSError, ValueError):
            continue
        if summary.get("interrupted", False):
            continue
        cell["finished"] += 1
        if summary["failed"]:
            cell["failed"] += 1
        else:
            cell[summary["morphology"]] += 1
    return cells


def leaders(cell):
    """The phases with most votes (several on a tie; empty if none voted)."""
    votes = {phase: n for phase, n in cell.items() if phase in COLOURS}
    top = max(votes.values(), default=0)
    return {phase for phase, n in votes.items() if n == top and n > 0}


def majority(cell):
    """The phase with most votes ('tie' if two share it, 'failed' if every
    finished run failed, None if none finished)."""
    votes = [(n, phase) for phase, n in cell.items() if phase in COLOURS]
    if not votes:
        return "failed" if cell["finished"] else None
    votes.sort(reverse=True)
    return "tie" if len(votes) > 1 and votes[0][0] == votes[1][0] else votes[0][1]


def grid():
    """The sweep file's (yield curvatures, static coefficients, both
    sorted, and realizations per cell)."""
    values = {}
    with open(os.path.join(ROOT, "prm", SWEEP_PRM)) as f:
        for line in f:
            m = re.match(r"\s*set (Yield curvatures|Static coefficients|Realizations)\s*=(.*)", line)
            if m:
                values[m.group(1)] = sorted(float(x) for x in m.group(2).split(","))
    return values["Yield curvatures"], values["Static coefficients"], int(values["Realizations"][0])


def realizations():
    return grid()[2]


def features(cells):
    """The paper's three features on the cells that have all their runs."""
    kappas, mus, n = grid()
    done = {key: majority(c) for key, c in cells.items() if c["finished"] >= n}
    # 1. No spiral cell next to a classic one (neighbours along either axis).
    pairs = [(a, b) for a, b in neighbours(kappas, mus) if a in done and b in done]
    borders = [(a, b) for a, b in pairs if {done[a], done[b]} == {"spiral", "classic"}]
    # 2. Re-entrance: along kappa_theta at REENTRANT_MU, a plastic cell, a
    # classic one above it and a plastic one above that. True or False when
    # the majorities decide it whatever the cells still to come and the
    # ties (cells whose leading phases share the votes) turn out to be;
    # None while they could go either way.
    reentrant = {}
    for m in mus:
        if not REENTRANT_MU[0] < m < REENTRANT_MU[1]:
            continue
        column = [done.get((k, m)) for k in kappas]
        found = sequence(column, lambda c, phase: c == phase)
        tops = [leaders(cells[(k, m)]) if (k, m) in done else set(COLOURS) for k in kappas]
        possible = sequence(tops, lambda c, phase: phase in c)
        reentrant[m] = (column, found if found or not possible else None)
    # 3. The smallest kappa_theta of a classic cell; final once every cell
    # below it is complete.
    classic = sorted(k for (k, m), p in done.items() if p == "classic")
    smallest = classic[0] if classic else None
    below = max((k for k in kappas if smallest is not None and k < smallest), default=None)
    settled = smallest is not None and all((k, m) in done for k in kappas if k < smallest for m in mus)
    return {"kappas": kappas, "mus": mus, "realizations": n, "done": done, "pairs": len(pairs),
            "borders": borders, "reentrant": reentrant, "smallest": smallest, "below": below,
            "settled": settled, "complete": len(done) == len(kappas) * len(mus) > 0}


def sequence(column, holds):
    """Whether some cells i < j < k of the column hold plastic, classic and
    plastic (holds(cell, phase))."""
    return any(holds(column[i], "plastic") and holds(column[j], "classic") and
               any(holds(c, "plastic") for c in column[j + 1:])
               for j in range(len(column)) for i in range(j))


def neighbours(kappas, mus):
    for i, k in enumerate(kappas):
        for j, m in enumerate(mus):
            if i + 1 < len(kappas):
                yield (k, m), (kappas[i + 1], m)
            if j + 1 < len(mus):
                yield (k, m), (k, mus[j + 1])


def plot(cells, f, filename):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 5))
    for i, k in enumerate(f["kappas"]):
        for j, m in enumerate(f["mus"]):
            c = cells[(k, m)]
            p = majority(c)
            voters = sum(n for phase, n in c.items() if phase in COLOURS)
            share = c[p] / voters if p in COLOURS else 0.0
            done = c["finished"] >= f["realizations"]
            ax.add_patch(plt.Rectangle((j, i), 1, 1, color=COLOURS.get(p, "lightgrey"),
                                       alpha=(0.3 + 0.7 * share) if done else 0.15))
            text = ", ".join(f"{n}{phase[0]}" for phase, n in sorted(c.items()) if phase in COLOURS)
            if c["failed"]:
                text += f"{', ' if text else ''}{c['failed']} failed"
            ax.text(j + 0.5, i + 0.5, (text or "-") + ("" if done else f"\n({c['finished']} of {f['realizations']} done)"),
                    ha="center", va="center", fontsize=7)
    ax.set_xlim(0, len(f["mus"]))
    ax.set_ylim(0, len(f["kappas"]))
    ax.set_xticks([j + 0.5 for j in range(len(f["mus"]))], [f"{m:g}" for m in f["mus"]])
    ax.set_yticks([i + 0.5 for i in range(len(f["kappas"]))], [f"{k:g}" for k in f["kappas"]])
    ax.set_xlabel("mu_st")
    ax.set_ylabel("kappa_theta (1/d)")
    ax.set_title("f = 50, s = 0.05: majority phase (s spiral, c classic, p plastic)", fontsize=9)
    fig.tight_layout()
    fig.savefig(filename, dpi=120)
    plt.close(fig)


def section(outdir):
    """The report's phase-diagram rows and figure."""
    sweep_dir = os.path.join(outdir, SWEEP_DIR)
    cells = read_cells(sweep_dir)
    where = f"discrete, f 50, {realizations()} seeds per cell (`prm/{SWEEP_PRM}`)"
    if not cells:
        return ["", "## Phase diagram (f = 50)", "", f"No runs yet ({where})."]
    f = features(cells)
    plot(cells, f, os.path.join(outdir, "phase_f50.png"))
    total = len(f["kappas"]) * len(f["mus"])
    state = "all cells" if f["complete"] else f"{len(f['done'])} of {total} cells complete, the rest to come"
    rows = ["", "## Phase diagram (f = 50)", "",
            f"{where}: {state}. Failed runs (a numerical limit, energy balance above 1%) do not vote.", "",
            "| feature | paper | this code |", "|---|---|---|"]
    if f["borders"]:
        pairs = "; ".join(f"(kappa {a[0]:g}, mu {a[1]:g}) next to (kappa {b[0]:g}, mu {b[1]:g})" for a, b in f["borders"])
        rows.append(f"| no direct spiral-classic border | none | **{len(f['borders'])} found**: {pairs} |")
    elif f["pairs"]:
        rows.append(f"| no direct spiral-classic border | none | none among the {f['pairs']} neighbouring pairs of "
                    "complete cells |")
    else:
        rows.append("| no direct spiral-classic border | none | not yet: no two neighbouring cells complete |")
    for m, (column, yes) in sorted(f["reentrant"].items()):
        seq = " -> ".join(tie_votes(cells[(k, m)]) if p == "tie" else (p or "to come")
                          for k, p in zip(f["kappas"], column))
        if yes is None:
            verdict = ("not yet complete" if None in column else
                       f"undecided with {f['realizations']} realizations: a tie could go either way")
        else:
            verdict = "re-entrant" if yes else "**not re-entrant**"
        rows.append(f"| re-entrance along kappa_theta at mu_st {m:g} | plastic -> classic -> plastic, 0.2 < mu_st "
                    f"< 0.35 | {verdict}: {seq} (kappa {', '.join(f'{k:g}' for k in f['kappas'])}) |")
    if f["smallest"] is None:
        smallest = "no classic cell yet"
    elif f["below"] is None:
        smallest = f"{f['smallest']:g}, the smallest on the grid"
    else:
        smallest = f"{f['smallest']:g} (the grid point below, {f['below']:g}, is not classic)"
    if f["smallest"] is not None and not f["settled"]:
        smallest += "; provisional: cells below it are still to come"
    rows.append(f"| smallest kappa_theta of the classic phase | about {PAPER_CLASSIC_KAPPA} | {smallest} |")
    if f["smallest"] is not None and f["below"] is not None:
        rows.append(f"| factor on kappa_theta mapping this diagram's classic edge onto the paper's | 1 | between "
                    f"{f['below'] / PAPER_CLASSIC_KAPPA:.2g} and {f['smallest'] / PAPER_CLASSIC_KAPPA:.2g} (the "
                    "grid's resolution) |")
    rows += ["", "![phase diagram](phase_f50.png)"]
    return rows


def tie_votes(cell):
    """'tie (1 spiral, 1 classic, ...)' for a cell whose leaders share its votes."""
    votes = [f"{cell[p]} {p}" for p in COLOURS if cell[p]] + ([f"{cell['failed']} failed"] if cell["failed"] else [])
    return "tie (" + ", ".join(votes) + ")"


def differences(outdir):
    cells = read_cells(os.path.join(outdir, SWEEP_DIR))
    if not cells:
        return []
    f = features(cells)
    rows = [f"- phase diagram (f 50): a spiral cell next to a classic one (the paper has no such border): "
            f"(kappa {a[0]:g}, mu {a[1]:g}) and (kappa {b[0]:g}, mu {b[1]:g})." for a, b in f["borders"]]
    if f["smallest"] is None:
        return rows + ["- phase diagram (f 50): no classic cell among the complete ones yet."]
    return rows + [f"- phase diagram (f 50): the classic phase starts at kappa_theta {f['smallest']:g}, "
                   f"{f['smallest'] / PAPER_CLASSIC_KAPPA:.2g} times the paper's {PAPER_CLASSIC_KAPPA}"
                   f"{'' if f['settled'] else ' (provisional)'}."]


def self_test():
    """features() on made-up diagrams over the sweep file's grid."""
    kappas, mus, n = grid()

    def diagram(phase_of, missing=()):
        cells = collections.defaultdict(collections.Counter)
        for k in kappas:
            for m in mus:
                if (k, m) not in missing:
                    cells[(k, m)].update({"finished": n, phase_of(k, m): n})
        return cells

    def paper_like(k, m):
        if m == 0:
            return "spiral" if k > 1 else "plastic"
        if m < 0.2 or k < PAPER_CLASSIC_KAPPA:
            return "plastic"
        return "plastic" if m < 0.35 and k > 0.1 else "classic"

    f = features(diagram(paper_like))
    assert f["complete"] and not f["borders"] and f["pairs"] == 2 * len(kappas) * len(mus) - len(kappas) - len(mus)
    assert [yes for _, yes in f["reentrant"].values()] == [True], f["reentrant"]
    assert (f["smallest"], f["below"], f["settled"]) == (0.027, 0.01, True), f
    # A classic cell next to a spiral one.
    f = features(diagram(lambda k, m: "classic" if m > 0 and k > 1 else paper_like(k, m)))
    assert f["borders"] == [((3.1416, 0.0), (3.1416, 0.1))], f["borders"]
    # Classic from 0.027 up to the elastic end: no re-entrance.
    f = features(diagram(lambda k, m: "classic" if m >= 0.2 and k > 0.02 else paper_like(k, m)))
    assert [yes for _, yes in f["reentrant"].values()] == [False], f["reentrant"]
    # Classic from the smallest kappa on: no grid point below it.
    f = features(diagram(lambda k, m: "classic" if m >= 0.2 else paper_like(k, m)))
    assert (f["smallest"], f["below"]) == (0.01, None), f
    # Spiral below the classic stretch is not the paper's re-entrance.
    f = features(diagram(lambda k, m: "spiral" if m == 0.3 and k < 0.02 else paper_like(k, m)))
    assert [yes for _, yes in f["reentrant"].values()] == [False], f["reentrant"]
    # Ties above the classic cell: one of them may be plastic, so the
    # majorities do not decide it; a tie of spiral and classic cannot make
    # it re-entrant.
    cells = diagram(lambda k, m: "classic" if m == 0.3 and 0.02 < k < 0.1 else paper_like(k, m))
    for k in (0.16, 0.3, 3.1416):
        cells[(k, 0.3)] = collections.Counter({"finished": n, "spiral": 1, "classic": 1, "plastic": 1})
    assert majority(cells[(0.16, 0.3)]) == "tie" and leaders(cells[(0.16, 0.3)]) == set(COLOURS)
    assert [yes for _, yes in features(cells)["reentrant"].values()] == [None]
    for k in (0.16, 0.3, 3.1416):
        cells[(k, 0.3)] = collections.Counter({"finished": n, "failed": 1, "spiral": 1, "classic": 1})
    assert [yes for _, yes in features(cells)["reentrant"].values()] == [False]
    assert tie_votes(cells[(0.16, 0.3)]) == "tie (1 spiral, 1 classic, 1 failed)"
    # Cells still to come: nothing is decided from them.
    f = features(diagram(paper_like, missing={(0.01, 0.3), (0.01, 0.45)}))
    assert not f["complete"] and not f["settled"] and f["smallest"] == 0.027
    assert [yes for _, yes in f["reentrant"].values()] == [None], f["reentrant"]
    # A cell whose runs all failed is complete, and not classic.
    cells = diagram(paper_like)
    cells[(0.04, 5.0)] = collections.Counter({"finished": n, "failed": n})
    assert majority(cells[(0.04, 5.0)]) == "failed" and features(cells)["smallest"] == 0.027
    f = features(diagram(lambda k, m: "plastic"))
    assert f["smallest"] is None and not f["borders"]
    print("phase.py self-test: passed")


if __name__ == "__main__":
    import sys

    if sys.argv[1:] == ["--self-test"]:
        self_test()
    else:
        sys.exit("usage: phase.py --self-test (the study itself runs from run.py)")
