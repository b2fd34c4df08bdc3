#!/usr/bin/env python3
"""How the second round's standard does on the archived blind runs, and
what a weaker one would do (issue 7, docs/diagnosis.md, "A second effect").

When an effect B is the verdict, every other candidate E is refitted with B
and must pass the first round's tests again, the 5 % margin now on B's
held-out RMSE. After B has closed most of the gap that margin is a large
part of what is left, so one may ask whether a second effect should rather
be judged by the share of the *remaining excess* it closes,

    excess share = (rmse_B^2 - rmse_E|B^2) / (rmse_B^2 - noise^2),

(held-out mean squares; rmse_B the held-out RMSE the candidate's shrink is
measured against, B's fit or B re-tuned alone where the candidate was
re-checked; noise^2 the tracking noise's). This script reads
the latest archived run of every case (bench/diagnosis/runs and
runs-escalate, first and second searches apart; run_blind.py's archive),
and for every run whose verdict names an effect:

1. lists the runs whose `also` is not empty, with whether each entry is in
   the truth (the standard as built);
2. for every candidate given the verdict that passes the held-out
   chi-square test and the guards (glider, bound, plausibility), prints its
   RMSE shrink and its excess share, marked TRUE when it is the dataset's
   other true effect, and summarises the two groups;
3. for every two-effect dataset whose verdict is one of its effects, the
   other one given the verdict, whatever it passed, with its note.

It reads stored results only; it cannot say what the diagnosis would have
fitted under another rule.

    /usr/bin/python3 bench/diagnosis/second_effect.py [--all] [ROOT ...] [--escalated ROOT]
"""
import argparse
import gzip
import json
import os
import statistics
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from run_blind import ARCHIVE, ARCHIVE_ESCALATE, ARCHIVE_SUFFIX, case_of  # noqa: E402


def commit_time(commit, cache={}):
    """Commit time of an archive folder's commit (0 when git does not know it)."""
    if commit not in cache:
        r = subprocess.run(["git", "-C", HERE, "log", "-1", "--format=%ct", commit], capture_output=True, text=True)
        cache[commit] = int(r.stdout.strip() or 0) if r.returncode == 0 else 0
    return cache[commit]


def latest_runs(roots):
    """{(case, second search?): (commit, path)}: the newest archived run of each case."""
    out = {}
    for root, escalated in roots:
        if not os.path.isdir(root):
            continue
        for commit in os.listdir(root):
            d = os.path.join(root, commit)
            for fn in os.listdir(d):
                if not fn.endswith(ARCHIVE_SUFFIX):
                    continue
                key = (fn[:-len(ARCHIVE_SUFFIX)], escalated)
                if key not in out or commit_time(commit) > commit_time(out[key][0]):
                    out[key] = (commit, os.path.join(d, fn))
    return out


def names(also):
    return [a if isinstance(a, str) else a.get("name") for a in also or []]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("roots", nargs="*", help="archives of first searches (COMMIT/CASE.diagnosis.json.gz; "
                    "default: bench/diagnosis/runs and, as second searches, runs-escalate)")
    ap.add_argument("--escalated", action="append", default=[], help="an archive of second searches")
    ap.add_argument("--all", action="store_true", help="print every candidate, not only the ten largest shares")
    args = ap.parse_args(argv)
    roots = [(r, False) for r in args.roots] + [(r, True) for r in args.escalated]
    runs = latest_runs(roots or [(ARCHIVE, False), (ARCHIVE_ESCALATE, True)])
    named, with_also, rows, seconds = 0, [], [], []
    for (name, escalated), (commit, path) in sorted(runs.items()):
        case = case_of(name)
        if case is None:
            continue
        with gzip.open(path, "rt") as f:
            r = json.load(f)
        v = r["verdict"]
        if v in ("none", "unexplained"):
            continue
        named += 1
        truth = case["truth"]
        if names(r.get("also")):
            with_also.append((name, escalated, commit, v, names(r.get("also")), truth))
        noise = r["baseline"]["noise_rmse_m"]
        for e in r["effects"]:
            g = e.get("given_verdict")
            if not g or e["name"] == v:
                continue
            re = g["holdout_rmse_m"]
            rb = re / (1.0 - g["shrink"])
            if len(truth) == 2 and e["name"] in truth:  # a two-effect dataset's other effect, whatever it passed
                seconds.append((name, escalated, v, e["name"], g["shrink"],
                                (rb ** 2 - re ** 2) / max(rb ** 2 - noise ** 2, 1e-12), g.get("note", "")))
            cv = g["cross_validation"]
            if not (cv["delta_chi2"] > cv["threshold"] and g.get("robust_pass", True) and g.get("bound_pass", True)
                    and g.get("plausible", True)):
                continue
            # the held-out RMSE the shrink was measured against (B's fit, or B
            # re-tuned alone where the candidate was re-checked): rb above
            share = (rb ** 2 - re ** 2) / max(rb ** 2 - noise ** 2, 1e-12)
            rows.append((share, g["shrink"], name, escalated, v, e["name"], e["name"] in truth, g["significant"]))
    print("%d archived runs name an effect (the latest run of each case; first and second searches apart)" % named)
    print("\n1. runs with a second effect in `also` (the standard as built): %d" % len(with_also))
    for name, esc, commit, v, also, truth in with_also:
        right = [a for a in also if a in truth]
        print("   %-28s %s %s  verdict %-15s also %-24s %s" % (
            name, "second search" if esc else "first search ", commit, v, ",".join(also),
            "right" if right and len(right) == len(also) else
            "partly right (%s; not in the truth: %s)" % (",".join(right), ",".join(a for a in also if a not in truth))
            if right else "WRONG (truth %s)" % "+".join(truth)))
    rows.sort(key=lambda x: -x[0])
    true_rows = [x for x in rows if x[6]]
    wrong_rows = [x for x in rows if not x[6]]
    print("\n2. candidates given the verdict that pass the held-out test and the guards: %d "
          "(%d in the truth, %d not)" % (len(rows), len(true_rows), len(wrong_rows)))
    for label, group in (("in the truth", true_rows), ("not in the truth", wrong_rows)):
        if group:
            s = [x[0] for x in group]
            print("   %-18s excess share median %5.1f %%, largest %5.1f %%; RMSE shrink median %4.1f %%" % (
                label, 100 * statistics.median(s), 100 * max(s), 100 * statistics.median(x[1] for x in group)))
    print("   %-9s %-28s %-8s %-15s %-15s %7s %7s %s" % ("", "case", "search", "verdict", "candidate", "excess",
                                                       "shrink", "significant"))
    for x in rows if args.all else rows[:10]:
        print("   %-9s %-28s %-8s %-15s %-15s %6.1f%% %6.1f%% %s" % (
            "TRUE" if x[6] else "", x[2], "second" if x[3] else "first", x[4], x[5], 100 * x[0], 100 * x[1],
            "yes" if x[7] else "no"))
    for thr in (0.05, 0.10, 0.20):
        print("   an excess-share standard of %2.0f %% would pass %d of %d wrong candidates and %d of %d true ones" % (
            100 * thr, sum(1 for x in wrong_rows if x[0] >= thr), len(wrong_rows),
            sum(1 for x in true_rows if x[0] >= thr), len(true_rows)))
    print("\n3. two-effect datasets whose verdict is one of the two: the other given it, whatever it passed: %d"
          % len(seconds))
    for name, esc, v, e, shrink, share, note in seconds:
        print("   %-28s %-8s verdict %-8s %-15s shrink %5.1f%%, excess %5.1f%%: %s" % (
            name, "second" if esc else "first", v, e, 100 * shrink, 100 * share, note))


if __name__ == "__main__":
    main()
