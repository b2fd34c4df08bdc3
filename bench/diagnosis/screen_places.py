#!/usr/bin/env python3
"""Would one more profiled place have started the true effect from its step?
(issue 7, docs/diagnosis.md, "The search's parts and their switches";
bench/diagnosis/blind_results.md, 53rd session).

In every profiled fit (all gliders, and each fold's training gliders) the
diagnosis refits at most `--profiled-candidates` candidates (default 3) from
the linearised step of the centre values; the others start where the
baseline's coefficients leave them. Which ones get a place is decided by a
screen of the linearised gains (Delta chi-square over the baseline's step),
stored in every result since 2026-12-04 as `linearised_delta_chi2` (all
gliders) and `fold_linearised_delta_chi2` (each fold). This script replays
that screen, as engine/src/diagnose.cpp's step screen orders it:

- on all gliders: the candidates whose gain passes the likelihood-ratio
  threshold chi2_isf(alpha / candidates, parameters), largest first;
- in a fold: those that pass it there, then the ones given a place on all
  gliders (carried, `carry_steps`), then the other gains over the folds'
  laxer screen (`step_alpha`: at 1, any positive gain), each group largest
  first;

and the first N of that list get a place. `--carried-first` weighs an
order that is not the engine's (in a fold the carried candidates first,
whether they pass there or not), with `--then M` places. For each archived single-effect
run (the newest of each case, first searches only) it prints whether the
true effect had a place on all gliders and in each fold with N places and
with N + 1, the verdict, and whether the extra place changes the truth's
starts. The gains do not depend on N (they are computed before any
candidate fit), so this part of the replay is exact; what the fits would
then have given is not stored anywhere, so which verdicts would change is
for runs to say: `--pilot DIR` reads the results of runs made with the
extra place (run_blind.py --diagnose-args "--profiled-candidates N+1") and
sets their verdicts beside the archived ones.

    /usr/bin/python3 bench/diagnosis/screen_places.py [--places 3] [--pilot out/pc4]
"""
import argparse
import gzip
import json
import math
import os
import statistics
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from run_blind import ARCHIVE, case_of  # noqa: E402
from second_effect import latest_runs  # noqa: E402


def chi2_isf(p, dof):
    """The chi-square quantile exceeded with probability p, for the 1 and 2
    degrees of freedom the library's screened effects have (closed forms:
    the normal quantile squared; -2 ln p)."""
    if dof == 1:
        return statistics.NormalDist().inv_cdf(1 - p / 2) ** 2
    if dof == 2:
        return -2 * math.log(p)
    raise ValueError("no closed form here for %d degrees of freedom" % dof)


def places(gains, dofs, alpha, n_candidates, n, carried=None, step_alpha=1.0, carried_first=False):
    """The candidates given one of `n` places: `gains` {name: linearised
    Delta chi2, None when not screened}; `carried` None on all gliders, else
    the names given a place there (a fold). `carried_first` (not the
    engine's order, an alternative to weigh): in a fold the carried
    candidates come first, passing or not, then the other passing gains,
    then the other positive ones."""
    strict, car, weak = [], [], []
    for name, g in gains.items():
        if g is None:
            continue
        passes_strict = g > chi2_isf(alpha / n_candidates, dofs[name])
        if carried is None:
            if passes_strict:
                strict.append((g, name))
            continue
        lax = 0.0 if step_alpha >= 1 else chi2_isf(step_alpha / n_candidates, dofs[name])
        if name in carried and (carried_first or not passes_strict):
            car.append((g, name))
        elif passes_strict:
            strict.append((g, name))
        elif g > lax:
            weak.append((g, name))
    groups = (car, strict, weak) if carried_first else (strict, car, weak)  # on all gliders car is empty
    ordered = [name for group in groups for _, name in sorted(group, reverse=True)]
    return ordered[:n]


def places_of(result, n, carried_first=False):
    """The candidates given a place with `n` places, as the screen orders
    them (or with `carried_first`, see places): (on all gliders, [in fold
    i]); None when the result lacks the stored gains."""
    effects = result["effects"]
    if any(e.get("fold_linearised_delta_chi2") is None for e in effects):
        return None
    opts = result.get("options", {})
    alpha = opts.get("alpha", 0.01)
    step_alpha = opts.get("step_alpha", 1.0)
    dofs = {e["name"]: len(e.get("parameters") or {}) or 1 for e in effects}
    all_g = {e["name"]: e.get("linearised_delta_chi2") for e in effects}
    on_all = places(all_g, dofs, alpha, len(effects), n)
    carried = set(on_all) if opts.get("carry_steps", True) else set()
    folds = len(effects[0]["fold_linearised_delta_chi2"])
    in_folds = [places({e["name"]: e["fold_linearised_delta_chi2"][i] for e in effects}, dofs, alpha, len(effects), n,
                       carried, step_alpha, carried_first) for i in range(folds)]
    return on_all, in_folds


def replay(result, truth, n, carried_first=False):
    """(truth placed on all gliders, [truth placed in fold i]) with n places;
    None when the result lacks the stored gains."""
    p = places_of(result, n, carried_first)
    if p is None:
        return None
    return truth in p[0], [truth in f for f in p[1]]


def rows(archive=ARCHIVE, n=3, then=None, carried_first=False):
    """One row per newest archived single-effect first search with stored
    gains: (case, commit, truth, verdict, replay with n places in the
    engine's order, with `then` places (default n + 1) in the engine's order
    or, with `carried_first`, carried first in the folds)."""
    out = []
    for (name, _), (commit, path) in sorted(latest_runs([(archive, False)]).items()):
        case = case_of(name)
        if case is None or len(case["truth"]) != 1:
            continue
        with gzip.open(path, "rt") as f:
            r = json.load(f)
        truth = case["truth"][0]
        a, b = replay(r, truth, n), replay(r, truth, n + 1 if then is None else then, carried_first)
        if a is None:
            continue
        out.append((name, commit, truth, r.get("verdict"), a, b))
    return out


def changes(rows):
    """{20 or 8 (gliders): {"hit": [case], "miss": [case], "lost_hit": n,
    "lost_miss": n}}: the runs of rows() whose truth's starts the
    alternative changes, by whether the archived verdict was the truth, and
    how many of each in which the truth loses places (direction)."""
    out = {}
    for name, _, truth, verdict, a, b in rows:
        if a != b:
            size = 20 if name.endswith("-g20") else 8
            kind = "hit" if verdict == truth else "miss"
            d = out.setdefault(size, {"hit": [], "miss": [], "lost_hit": 0, "lost_miss": 0})
            d[kind].append(name)
            d["lost_" + kind] += direction(a, b) == "loses"
    return out


def direction(a, b):
    """Whether the truth has more places (on all gliders and in the folds)
    in replay b than in a: "gains", "loses", or "moves" (as many)."""
    na, nb = int(a[0]) + sum(a[1]), int(b[0]) + sum(b[1])
    return "gains" if nb > na else "loses" if nb < na else "moves"


def count(n, word):
    return "%d %s" % (n, word if n == 1 else word + ("es" if word.endswith("s") else "s"))


def marks(placed):
    on_all, folds = placed
    return ("A" if on_all else "-") + "".join("x" if f else "." for f in folds)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--places", type=int, default=3, help="the places of the archived runs (default 3)")
    ap.add_argument("--archive", default=ARCHIVE)
    ap.add_argument("--pilot", action="append", default=[],
                    help="a run_blind.py --out directory of runs made with one more place (repeatable)")
    ap.add_argument("--then", type=int, help="the places to compare with (default --places + 1)")
    ap.add_argument("--carried-first", action="store_true",
                    help="compare with an order that is not the engine's: in a fold the candidates carried from "
                         "all gliders first, then the other passing gains, then the other positive ones")
    args = ap.parse_args(argv)
    n = args.places
    then = n + 1 if args.then is None else args.then
    if n < 1 or then < 1:
        ap.error("--places and --then must be at least 1 (got %d and %d)" % (n, then))
    change = ("the carried-first order with %d places" % then if args.carried_first else
              "the extra place" if then == n + 1 else "%d places" % then)
    pilot = {}
    for d in args.pilot:
        for name in sorted(os.listdir(d)):
            p = os.path.join(d, name, "diagnosis.json")
            if os.path.isfile(p):
                with open(p) as f:
                    pilot[name] = json.load(f)
    print("truth's places: A = on all gliders, then one mark per fold (x = a place); "
          "%d places, then %d%s" % (n, then, ", carried first in the folds" if args.carried_first else ""))
    found = rows(args.archive, n, then, args.carried_first)
    for name, commit, truth, verdict, a, b in found:
        hit = verdict == truth
        moved = a != b
        extra = ""
        if name in pilot:
            pr = pilot[name]
            extra = "  with %d: %s%s" % (pr["options"].get("profiled_candidates"), pr.get("verdict"),
                                       " (right)" if pr.get("verdict") == truth else "")
        print("%-28s %s %-15s %-4s %s -> %s%s%s" % (name, commit, verdict, "hit" if hit else "miss", marks(a),
                                                    marks(b), "  changes" if moved else "", extra))
    for size, d in sorted(changes(found).items(), reverse=True):
        print("%d gliders: %s changes the truth's starts in %s and %s (%s); the truth loses places in %d of the "
              "hits and %d of the misses"
              % (size, change, count(len(d["hit"]), "hit"), count(len(d["miss"]), "miss"),
                 ", ".join(d["miss"]) or "no miss",
                 d["lost_hit"], d["lost_miss"]))
    for name, pr in sorted(pilot.items()):
        c = case_of(name)
        if c is not None and not c["truth"]:
            print("%-28s null, with %d: %s" % (name, pr["options"].get("profiled_candidates"), pr.get("verdict")))


if __name__ == "__main__":
    main()
