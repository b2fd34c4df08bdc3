#!/usr/bin/env python3
"""Would a shorter second search have found the same effects? (issue 7,
docs/diagnosis.md, "With the second search").

The second search (`--escalate`, after a first search's `unexplained`) runs
the whole diagnosis again with every aerodynamic correction (pitch damping,
downwash, finite span, fuselage drag, ground effect, added mass) also
started at its theoretical size; in the archived runs it took 1.4-5
times as long as the first. A cheaper one would start only a shortlist of them there: those the
first search found most promising. This script asks, of the archived second
searches, where the true effect stood among the aerodynamic corrections in
the first search that preceded it:

- by the first search's held-out RMSE shrink (the ranking of the report);
- by its linearised Delta chi-square on all gliders (the screen that chose
  which candidates the first search refitted with the centre values).

For every second search of a single-effect case whose truth is an
aerodynamic correction it reads the first search of the same case from the
first-search archive (the same commit when archived, otherwise the latest,
said in the table), and prints the truth's two ranks and whether the second
search named it. The summary counts, for a shortlist of the k best by
shrink, how many of the second search's hits it would have held.

It reads stored results only: a second search with a shortlist would also
differ in what it fits for the other candidates (they would keep their
first-search fits), which no archive holds; the counts say which effects
would still have been started at their size, not what the verdicts would
have been.

    /usr/bin/python3 bench/diagnosis/second_search_ranks.py [--first ROOT] [--second ROOT]
"""
import argparse
import gzip
import json
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from run_blind import ARCHIVE, ARCHIVE_ESCALATE, ARCHIVE_SUFFIX, case_of  # noqa: E402
from second_effect import latest_runs  # noqa: E402

AERO = ("pitch_damping", "downwash", "finite_span", "fuselage_drag", "ground_effect", "added_mass")


def load(path):
    with gzip.open(path, "rt") as f:
        return json.load(f)


def order(effects, key):
    """The aerodynamic corrections of `effects`, largest `key` first (a
    missing value last)."""
    aero = [e for e in effects if e["name"] in AERO]
    return [e["name"] for e in sorted(aero, key=lambda e: -(key(e) if key(e) is not None else -1e300))]


def rank(names, truth):
    """1-based rank of `truth` in `names` (an order()); None when the truth
    was not fitted."""
    return names.index(truth) + 1 if truth in names else None


def first_search_of(name, commit, first_root):
    """(commit, result) of the first search of case `name`: the one archived
    at `commit` if there is one, otherwise the latest; None if none."""
    same = os.path.join(first_root, commit, name + ARCHIVE_SUFFIX)
    if os.path.isfile(same):
        return commit, load(same)
    latest = latest_runs([(first_root, False)]).get((name, False))
    return (latest[0], load(latest[1])) if latest else None


def rows(first_root, second_root):
    """One row per archived second search of a single-effect case whose truth
    is an aerodynamic correction: (case, first commit, second commit,
    second verdict, named right?, rank by shrink, rank by linearised
    Delta chi2, first search's best as the second search recorded it,
    first search's best as archived, the aerodynamic corrections by shrink,
    by the screen)."""
    out = []
    for (name, _), (commit, path) in sorted(latest_runs([(second_root, True)]).items()):
        case = case_of(name)
        if case is None or len(case["truth"]) != 1 or case["truth"][0] not in AERO:
            continue
        r2 = load(path)
        if not r2.get("escalation", {}).get("ran"):
            continue
        truth = case["truth"][0]
        first = first_search_of(name, commit, first_root)
        if first is None:
            continue
        c1, r1 = first
        effects = r1["effects"]
        shrinks = [e for e in effects if e.get("shrink") is not None]
        best = max(shrinks, key=lambda e: e["shrink"])["name"] if shrinks else ""
        by_shrink = order(effects, lambda e: e.get("shrink"))
        by_screen = order(effects, lambda e: e.get("linearised_delta_chi2"))
        out.append((name, c1, commit, r2["verdict"], r2["verdict"] == truth,
                    rank(by_shrink, truth), rank(by_screen, truth),
                    r2["escalation"].get("first_best", ""), best, by_shrink, by_screen))
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--first", default=ARCHIVE, help="archive of first searches (default bench/diagnosis/runs)")
    ap.add_argument("--second", default=ARCHIVE_ESCALATE,
                    help="archive of second searches (default bench/diagnosis/runs-escalate)")
    args = ap.parse_args(argv)
    rs = rows(args.first, args.second)
    print("%d archived second searches of single aerodynamic effects with their first search" % len(rs))
    print("   %-28s %-17s %-16s %-6s %-7s %-11s %s" % ("case", "first / second", "second's verdict", "right",
                                                     "shrink", "linearised", "first search's best"))
    for name, c1, c2, v, right, rs_, rl, fb, best, _, _ in rs:
        note = fb if fb == best else "%s (archived run: %s)" % (fb, best)
        print("   %-28s %-17s %-16s %-6s %-7s %-11s %s" % (
            name, "%s / %s" % (c1, c2) if c1 != c2 else c1, v, "yes" if right else "no",
            rs_ if rs_ is not None else "-", rl if rl is not None else "-", note))
    hits = [x for x in rs if x[4]]
    misses = [x for x in rs if not x[4]]
    print("\nthe second search named the truth in %d of %d" % (len(hits), len(rs)))
    for k in range(1, len(AERO) + 1):
        print("   a shortlist of the %d aerodynamic correction(s) with the largest first-search shrink holds the "
              "truth in %d of the %d hits (and in %d of the %d misses)" % (
                  k, sum(1 for x in hits if x[5] is not None and x[5] <= k), len(hits),
                  sum(1 for x in misses if x[5] is not None and x[5] <= k), len(misses)))
    for k in (1, 2, 3):
        print("   by the linearised screen, the %d best hold it in %d of the %d hits" % (
            k, sum(1 for x in hits if x[6] is not None and x[6] <= k), len(hits)))
    for k in (1, 2):
        either = [x for x in hits if (x[5] is not None and x[5] <= k) or (x[6] is not None and x[6] <= k)]
        sizes = [len(set(x[9][:k]) | set(x[10][:k])) for x in rs]
        print("   the %d best by shrink and the %d best by the screen together hold it in %d of the %d hits "
              "(%d of the %d misses); they are %.1f of the 6 corrections on average (%d-%d)" % (
                  k, k, len(either), len(hits),
                  sum(1 for x in misses if (x[5] is not None and x[5] <= k) or (x[6] is not None and x[6] <= k)),
                  len(misses), sum(sizes) / max(len(sizes), 1), min(sizes, default=0), max(sizes, default=0)))

if __name__ == "__main__":
    main()
