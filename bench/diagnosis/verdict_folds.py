#!/usr/bin/env python3
"""Would a fold-agreement guard on named verdicts stop the wrong names?

A replay of the archived blind runs (bench/diagnosis/runs), a question and
not a rule of the diagnosis. For every distinct archived run whose verdict
names an effect (a re-run that reproduced an earlier run's folds counts
once), it measures how consistently the four
cross-validation folds fitted that effect, as camera_folds.py does for the
camera:

    agreement = |mean of the fold values| / (their population standard deviation)

(the lesser over the effect's parameters), and sorts the named verdicts into
right (the verdict is the true effect, or one of the two of a two-effect
case) and wrong (another effect, or any effect on null data). It then
counts, for a few thresholds, how many wrong names a guard "demote the
verdict to `unexplained` when the agreement is under the threshold" would
stop and how many right names it would lose.

    /usr/bin/python3 bench/diagnosis/verdict_folds.py [--archive bench/diagnosis/runs] [--out DIR]

Prints a table (markdown) and the sweep, and writes OUT/verdict_folds.png
(needs python3-matplotlib).
"""
import argparse
import gzip
import json
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import camera_folds  # noqa: E402  (its agreement measure, shared)

THRESHOLDS = (0.75, 1.0, 1.25, 1.5, 2.0, 3.0)


def truth_of(case):
    """The effects a case carries: () for null data, else the names before
    the strength (two-effect cases are named 'a+b-sSEED')."""
    if case.startswith("null"):
        return ()
    return tuple(case.split("-")[0].split("+"))


def named_runs(archive):
    """One row per distinct archived result whose verdict names an effect:
    runs of the same case with the same verdict and the same fold values (a
    re-run on later code that reproduced the earlier one) count once, their
    commits listed together. Row: case, commits, verdict, truth, right, the
    verdict effect's fold values (first parameter), the lesser agreement,
    its held-out shrink."""
    rows = {}
    for d in sorted(os.listdir(archive)):
        folder = os.path.join(archive, d)
        if not os.path.isdir(folder):
            continue
        for f in sorted(os.listdir(folder)):
            if not f.endswith(".diagnosis.json.gz"):
                continue
            case = f[: -len(".diagnosis.json.gz")]
            with gzip.open(os.path.join(folder, f), "rt") as fh:
                run = json.load(fh)
            verdict = run["verdict"]
            if verdict in ("none", "unexplained"):
                continue
            eff = next(e for e in run["effects"] if e["name"] == verdict)
            folds = eff.get("fold_parameters") or []
            if len(folds) < 2:
                continue
            names = list(folds[0])
            key = (case, verdict, tuple(round(fp[k], 4) for fp in folds for k in names))
            if key in rows:
                rows[key]["commits"].append(d)
                continue
            agree = min(camera_folds.agreement([fp[k] for fp in folds]) for k in names)
            truth = truth_of(case)
            rows[key] = {"case": case, "commits": [d], "verdict": verdict, "truth": truth,
                         "right": verdict in truth, "folds": [fp[names[0]] for fp in folds],
                         "agreement": agree, "shrink": eff["shrink"]}
    return list(rows.values())


def sweep(rows, thresholds=THRESHOLDS):
    """For each threshold: (threshold, wrong names stopped, wrong names, right names lost, right names)."""
    wrong = [r for r in rows if not r["right"]]
    right = [r for r in rows if r["right"]]
    return [(t, sum(1 for r in wrong if r["agreement"] < t), len(wrong),
             sum(1 for r in right if r["agreement"] < t), len(right)) for t in thresholds]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--archive", default=os.path.join(HERE, "runs"))
    ap.add_argument("--out", help="folder for verdict_folds.png")
    a = ap.parse_args(argv)
    rows = named_runs(a.archive)
    print("| case | commits | verdict | right | folds | agreement | shrink |")
    print("|---|---|---|---|---|---|---|")
    for r in sorted(rows, key=lambda r: r["agreement"]):
        print("| %s | %s | %s | %s | %s | %.2f | %.1f %% |" % (
            r["case"], " ".join(r["commits"]), r["verdict"], "yes" if r["right"] else "**no**",
            ", ".join("%.3g" % v for v in r["folds"]), r["agreement"], 100 * r["shrink"]))
    print()
    for t, stopped, nw, lost, nr in sweep(rows):
        print("guard at agreement %.2f: stops %d of %d wrong names, loses %d of %d right ones" % (t, stopped, nw, lost, nr))
    if a.out:
        try:
            import matplotlib
            matplotlib.use("Agg")
            import matplotlib.pyplot as plt
        except ImportError:
            print("verdict_folds: no plot: python3-matplotlib is not installed", file=sys.stderr)
            return 1
        os.makedirs(a.out, exist_ok=True)
        fig, ax = plt.subplots(figsize=(8, 3.8))
        for y, right, colour, label in ((1, True, "tab:green", "right name"), (0, False, "tab:red", "wrong name")):
            sel = [r for r in rows if r["right"] == right]
            ax.scatter([min(r["agreement"], 20) for r in sel], [y] * len(sel), c=colour, alpha=0.6,
                       label="%s (%d)" % (label, len(sel)))
            if not right:  # labels stacked downwards, left to right, so none overlap
                for i, r in enumerate(sorted(sel, key=lambda r: r["agreement"])):
                    ax.annotate(r["case"] + " → " + r["verdict"], (min(r["agreement"], 20), y),
                                textcoords="offset points", xytext=(4, -12 - 10 * i), fontsize=6,
                                ha="left", arrowprops={"arrowstyle": "-", "lw": 0.4, "color": "0.5"})
        ax.set_xscale("log")
        ax.set_yticks([0, 1])
        ax.set_yticklabels(["wrong", "right"])
        ax.set_ylim(-1.6, 1.5)
        ax.set_xlabel("fold agreement of the named effect, |mean| / s.d. of its four fold values (capped at 20)")
        ax.set_title("Named verdicts of the archived blind runs (distinct runs)")
        ax.legend(loc="upper left", fontsize=7)
        fig.tight_layout()
        path = os.path.join(a.out, "verdict_folds.png")
        fig.savefig(path, dpi=120)
        print("wrote", path)
    return 0


if __name__ == "__main__":
    sys.exit(main())
