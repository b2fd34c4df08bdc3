#!/usr/bin/env python3
"""How consistently the camera candidate's values come back across the
cross-validation folds, for every archived blind run (bench/diagnosis/runs):
a question, not a rule of the diagnosis.

At 20 gliders the camera cases s24, s30 and s37 were lost (docs/diagnosis.md,
*At the issue's size*): their oracles' held-out shrink falls to the 5 %
margin, while the fitted camera (roll and scale error) is right. A camera is
one for the whole dataset, so where it is real each fold should find about
the same roll and scale; where a camera only soaks up a model's misfit, the
folds should scatter. This script measures that, per run, as

    agreement = |mean of the four fold values| / (their standard deviation)

for the roll and the scale error, and groups the runs by their truth (the
camera cases, the null data, every other effect). It changes nothing in the
diagnosis; a rule built on it would need the null benchmark re-flown.

    /usr/bin/python3 bench/diagnosis/camera_folds.py [--archive bench/diagnosis/runs] [--out DIR]

Prints a table (markdown) and writes OUT/camera_folds.png (needs
python3-matplotlib).
"""
import argparse
import gzip
import json
import os
import statistics
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
# The diagnosis's default plausible camera (engine/src/effects.cpp, the
# camera's parameters): a scale error up to 0.15, a roll up to 10 degrees.
PLAUSIBLE_SCALE, PLAUSIBLE_ROLL_DEG = 0.15, 10.0
# The proposed rule's agreement threshold, and the repository commit at
# which it was proposed (the archive then is the data it was chosen on).
RULE_AGREEMENT = 3.0
RULE_CHOSEN_AT = "069ceef"


def agreement(values):
    """|mean| / population standard deviation of the fold values (inf when
    they are all equal and not zero, 0 when all are zero)."""
    m = statistics.mean(values)
    sd = statistics.pstdev(values)
    if sd == 0:
        return 0.0 if m == 0 else float("inf")
    return abs(m) / sd


def truth_of(case):
    """The group of a case name: 'camera' (the camera alone), 'null', or 'other'."""
    if case.startswith("null"):
        return "null"
    if case.split("-")[0] == "camera":  # not a two-effect case such as camera+wind
        return "camera"
    return "other"


def _heldout_pass(cv):
    """The held-out chi-square test of the decision rule: the held-out
    improvement above its threshold (False when either is missing)."""
    d, t = cv.get("delta_chi2"), cv.get("threshold")
    return d is not None and t is not None and d > t


def rule_would_name(x, threshold=RULE_AGREEMENT):
    """The rule proposed on 2026-12-05 (docs/diagnosis.md, "The camera's
    folds agree where the camera is real"), replayed on a stored run: the
    camera is named under the shrink margin when no effect was named (verdict
    none or unexplained), its fit is plausible in every fold and on all
    gliders, its folds agree (the lesser agreement at least `threshold`), its
    likelihood ratio passed, its held-out gain is above its chi-square
    threshold and positive, and the glider and bound guards pass. The engine
    does not apply it; this says what it would do."""
    return (x["verdict"] in ("none", "unexplained") and x["plausible"] and x["engine_plausible"] and
            min(x["roll_agreement"], x["scale_agreement"]) >= threshold and x["lr_pass"] and
            x["heldout_pass"] and x["shrink"] > 0 and x["guards_pass"])


def seen_when_chosen(root, commit=RULE_CHOSEN_AT):
    """The archived runs (commit/file) that existed when the rule was chosen:
    the archive's files at repository commit `commit` (git ls-tree). Runs
    archived since are out of sample. None when git or the commit is not
    available (a shallow clone): then nothing is called fresh."""
    import subprocess
    try:
        out = subprocess.run(["git", "-C", root, "ls-tree", "-r", "--name-only", commit, "bench/diagnosis/runs"],
                             capture_output=True, text=True, check=True).stdout
    except (OSError, subprocess.CalledProcessError):
        return None
    return {"/".join(l.split("/")[-2:]) for l in out.splitlines() if l.endswith(".diagnosis.json.gz")}


def camera_rows(archive):
    """One dict per archived run with the camera among its candidates and
    its fold values: case, commit, verdict, shrink, the fold values and their
    agreement, the values on all gliders, delta chi2 and gliders better."""
    rows = []
    for commit in sorted(os.listdir(archive)):
        d = os.path.join(archive, commit)
        if not os.path.isdir(d):
            continue
        for f in sorted(os.listdir(d)):
            if not f.endswith(".diagnosis.json.gz"):
                continue
            with gzip.open(os.path.join(d, f), "rt") as fh:
                r = json.load(fh)
            cam = [e for e in r.get("effects", []) if e.get("name") == "camera"]
            folds = cam[0].get("fold_parameters") if cam else None
            if not folds:
                continue
            e = cam[0]
            cv = e.get("cross_validation", {})
            roll = [x["roll_deg"] for x in folds]
            scale = [x["scale_error"] for x in folds]
            case = f[: -len(".diagnosis.json.gz")]
            rows.append({
                "case": case, "commit": commit, "truth": truth_of(case), "verdict": r.get("verdict"),
                "shrink": e.get("shrink", 0.0), "roll_folds": roll, "scale_folds": scale,
                "roll_agreement": agreement(roll), "scale_agreement": agreement(scale),
                "roll": e.get("parameters", {}).get("roll_deg"), "scale": e.get("parameters", {}).get("scale_error"),
                "delta_chi2": e.get("likelihood_ratio", {}).get("delta_chi2"),
                "gliders_better": cv.get("gliders_improved"),
                "lr_pass": bool(e.get("likelihood_ratio", {}).get("pass")),
                "heldout_pass": _heldout_pass(cv),
                "guards_pass": bool(cv.get("robust_pass", True)) and bool(cv.get("bound_pass", True)),
                "engine_plausible": bool(e.get("plausible", True)),
            })
            x = rows[-1]
            x["plausible"] = all(abs(v) <= PLAUSIBLE_SCALE for v in scale) and all(abs(v) <= PLAUSIBLE_ROLL_DEG for v in roll)
    return rows


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--archive", default=os.path.join(HERE, "runs"))
    ap.add_argument("--out", default=None, help="folder for camera_folds.png (default: no figure)")
    a = ap.parse_args(argv)
    rows = camera_rows(a.archive)
    if not rows:
        sys.exit("camera_folds: no archived run with the camera's fold values in %s" % a.archive)
    print("| case | commit | truth | verdict | camera's shrink | roll folds (deg) | scale folds | agreement roll / scale | plausible |")
    print("|---|---|---|---|---|---|---|---|---|")
    key = {"camera": 0, "null": 1, "other": 2}
    for x in sorted(rows, key=lambda x: (key[x["truth"]], -min(x["roll_agreement"], x["scale_agreement"]))):
        print("| %s | %s | %s | %s | %.1f %% | %s | %s | %.1f / %.1f | %s |" % (
            x["case"], x["commit"], x["truth"], x["verdict"], 100 * x["shrink"],
            ", ".join("%.2f" % v for v in x["roll_folds"]), ", ".join("%.3f" % v for v in x["scale_folds"]),
            x["roll_agreement"], x["scale_agreement"], "yes" if x["plausible"] else "no"))
    for t in ("camera", "null", "other"):
        for plausible in (True, False):
            sel = [min(x["roll_agreement"], x["scale_agreement"]) for x in rows
                   if x["truth"] == t and x["plausible"] == plausible]
            if sel:
                print("%s, %s: %d runs, the lesser agreement from %.1f to %.1f (median %.1f)" %
                      (t, "a plausible camera in every fold" if plausible else "an implausible camera in some fold", len(sel), min(sel), max(sel),
                       statistics.median(sel)))
    seen = seen_when_chosen(os.path.dirname(os.path.dirname(HERE)))
    for fresh in (False, True):
        if seen is None and fresh:
            print("(git history not available: the runs archived since the rule was chosen are not told apart)")
            continue
        sel = [x for x in rows if seen is None or (x["commit"] + "/" + x["case"] + ".diagnosis.json.gz" not in seen) == fresh]
        label = ("archived since the rule was proposed (%s), out of sample" % RULE_CHOSEN_AT if fresh else
                 "archived when the rule was proposed (the data it was chosen on)" if seen is not None else "all archived")
        n = [x for x in sel if rule_would_name(x)]
        print("The rule (agreement >= %.0f) on the %d runs %s: would name the camera on %d: %s; of them camera cases %d, "
              "null %d, other effects %d" % (RULE_AGREEMENT, len(sel), label, len(n),
                                             ", ".join("%s (%s, %.1f)" % (x["case"], x["commit"],
                                                                          min(x["roll_agreement"], x["scale_agreement"]))
                                                       for x in n) or "none",
                                             sum(x["truth"] == "camera" for x in n), sum(x["truth"] == "null" for x in n),
                                             sum(x["truth"] == "other" for x in n)))
    if a.out:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        os.makedirs(a.out, exist_ok=True)
        fig, ax = plt.subplots(figsize=(6.4, 4.8))
        style = {"camera": ("tab:blue", "o", "camera cases"), "null": ("tab:green", "s", "null data"),
                 "other": ("tab:gray", "x", "other effects")}
        for t, (c, m, label) in style.items():
            sel = [x for x in rows if x["truth"] == t and x["plausible"]]
            if sel:
                ax.scatter([min(x["roll_agreement"], 200) for x in sel], [min(x["scale_agreement"], 200) for x in sel],
                           c=c, marker=m, label="%s (%d)" % (label, len(sel)))
        for x in rows:
            if x["truth"] == "camera" and x["verdict"] != "camera":
                ax.annotate(x["case"] + " (" + x["verdict"] + ")", (x["roll_agreement"], x["scale_agreement"]),
                            fontsize=7, xytext=(4, -8), textcoords="offset points")
        ax.set_xscale("symlog", linthresh=1)
        ax.set_yscale("symlog", linthresh=1)
        ax.set_xlabel("roll: |fold mean| / fold s.d.")
        ax.set_ylabel("scale error: |fold mean| / fold s.d.")
        ax.set_title("The camera candidate's fold values (plausible sizes), archived runs", fontsize=10)
        ax.legend(loc="upper left", fontsize=8)
        fig.tight_layout()
        p = os.path.join(a.out, "camera_folds.png")
        fig.savefig(p, dpi=110)
        print("wrote", p)


if __name__ == "__main__":
    main()
