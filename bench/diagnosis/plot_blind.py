#!/usr/bin/env python3
"""Figures of the blind validation (issue 7, docs/diagnosis.md, *Blind
validation*), drawn from what the docs already state and the archive holds,
so that they cannot drift from the counted figures:

- the top-1 figure: the true effect's held-out shrink against its oracle's
  for every case of docs/diagnosis.md's top-1 table, marked by verdict,
  beside the confusion matrix recounted from the same table;
- the tally at the issue's size (printed): the table's cases flown again
  with every training glider (CASE-g20 in the archive) and their verdicts;
- the tally with the second search (printed): the table's `unexplained`
  misses diagnosed again with --escalate (archived apart, in
  bench/diagnosis/runs-escalate) and how many of them it names;
- the strengths figure: the true effect's fitted strength on all gliders
  and in each fold, in the reference simulator's units (1 = the strength
  the data were made with), for the table's cases whose run at the table's
  commit is archived (bench/diagnosis/runs).

    /usr/bin/python3 bench/diagnosis/plot_blind.py [--docs docs/diagnosis.md]
        [--archive bench/diagnosis/runs] [--archive-escalate bench/diagnosis/runs-escalate]
        [--out docs/img]

Writes OUT/blind_top1.png and OUT/blind_strengths.png and prints what it
drew. Needs matplotlib (Debian's python3-matplotlib).
"""
import argparse
import collections
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, HERE)
import run_blind as rb  # noqa: E402  (the case names, strengths and archive)

TOP1_HEADER = "| case | oracle | verdict | true effect's shrink | commit |"
VERDICTS = ["camera", "downwash", "finite_span", "launch_rotation", "pitch_damping", "wind", "none", "unexplained"]


def percent(cell):
    return float(cell.strip().rstrip(" %").replace("\u2212", "-"))  # the docs write a minus sign


def top1_rows(text):
    """The rows of the top-1 table: dicts case, effect, oracle, verdict,
    shrink (percent) and commit (the first word of the commit cell)."""
    lines = text.splitlines()
    try:
        head = next(i for i, line in enumerate(lines) if line.startswith(TOP1_HEADER))
    except StopIteration:
        raise ValueError("the top-1 table (%s) is not in the docs" % TOP1_HEADER)
    rows = []
    for line in lines[head + 2:]:
        if not line.startswith("|"):
            break
        c = [x.strip() for x in line.strip().strip("|").split("|")]
        rows.append({"case": c[0], "effect": c[0].split("-")[0], "oracle": percent(c[1]), "verdict": c[2],
                     "shrink": percent(c[3]), "commit": c[4].split(",")[0].split()[0]})
    if not rows:
        raise ValueError("the top-1 table has no rows")
    return rows


def confusion(rows):
    """{true effect: Counter(verdict)} of the table."""
    m = collections.defaultdict(collections.Counter)
    for r in rows:
        m[r["effect"]][r["verdict"]] += 1
    return m


def strengths(rows, archive_dir):
    """For each table row whose run at the table's commit is archived: the
    true effect's fitted strength on all gliders and per fold, in the
    reference's units (the camera: scale and roll, each against its own
    nominal). Returns (found, missing): found a list of dicts case, effect,
    named, all (list of values, one per parameter), folds (list of lists)."""
    stored = {(name, os.path.basename(os.path.dirname(p))): r for name, p, r in rb.archived(archive_dir)}
    found, missing = [], []
    for row in rows:
        r = stored.get((row["case"], row["commit"]))
        if r is None:
            missing.append(row["case"])
            continue
        e = next(x for x in r["effects"] if x["name"] == row["effect"])

        def values(params):
            s = rb.strength_of(row["effect"], params)
            return list(s) if isinstance(s, tuple) else [s]
        found.append({"case": row["case"], "effect": row["effect"], "named": row["verdict"] == row["effect"],
                      "all": values(e.get("parameters", {})),
                      "folds": [values(p) for p in e.get("fold_parameters", [])]})
    return found, missing


def true_shrink(name, r):
    """The held-out shrink in percent of the true effect of case `name`
    (its first word) in result r; NaN when r has no such candidate."""
    e = next((x for x in r.get("effects", []) if x["name"] == name.split("-")[0]), None)
    return 100.0 * e["shrink"] if e and e.get("shrink") is not None else float("nan")


def wide_runs(rows, archive_dir):
    """The table's cases flown again at the issue's size (run_blind.py's
    CASE-g20, every training glider): for each table row, the archived runs
    of its -g20 case (any commit). Returns a list of dicts case, effect,
    narrow (the table's verdict), runs (a list of (commit, verdict, the true
    effect's held-out shrink in percent)), oracles ({commit: the oracle's
    held-out shrink in percent} of the runs made with the oracle) and
    margins ({commit: the run's shrink margin in percent}, the same runs), in the
    table's order; rows with no such run have runs == []."""
    by_name, oracles, margins = collections.defaultdict(list), collections.defaultdict(dict), collections.defaultdict(dict)
    for name, p, r in rb.archived(archive_dir):
        if name.endswith(rb.WIDE):
            commit = os.path.basename(os.path.dirname(p))
            by_name[name[:-len(rb.WIDE)]].append((commit, r["verdict"], true_shrink(name, r)))
            if r.get("oracle", {}).get("shrink") is not None:
                oracles[name[:-len(rb.WIDE)]][commit] = 100.0 * r["oracle"]["shrink"]
                margins[name[:-len(rb.WIDE)]][commit] = 100.0 * r.get("options", {}).get("min_shrink", 0.05)
    return [{"case": row["case"], "effect": row["effect"], "narrow": row["verdict"], "runs": by_name.get(row["case"], []),
             "oracles": oracles.get(row["case"], {}), "margins": margins.get(row["case"], {})} for row in rows]


def wide_under_margin(wide):
    """The flown cases that the table's own rule would not count at the
    issue's size: flown with the oracle, and its held-out shrink under the
    run's margin (options.min_shrink, 5 % by default) in every such run
    (even the known physics, added to the baseline, does not close the
    margin there). Cases flown without the oracle are never in it: their
    oracle is not known."""
    return [w["case"] for w in wide if w["runs"] and w["oracles"] and
            all(o < w["margins"][c] for c, o in w["oracles"].items())]


def named_every_run(w):
    """Whether every -g20 run of a wide_runs row names its true effect."""
    return all(v == w["effect"] for _, v, _ in w["runs"])


def wide_tally(wide):
    """(flown, named in every run, named in some run, not flown): the counts
    of wide_runs' rows; a case flown more than once counts as named in
    every run only if each of its runs names the true effect."""
    flown = [w for w in wide if w["runs"]]
    every = sum(1 for w in flown if named_every_run(w))
    some = sum(1 for w in flown if any(v == w["effect"] for _, v, _ in w["runs"]))
    return len(flown), every, some, len(wide) - len(flown)


def wide_rule_tally(wide):
    """The table's own rule applied at the issue's size: (nameable, named)
    where nameable counts the flown cases that are not wide_under_margin
    (their oracle at -g20 reaches the margin, or they were flown without
    the oracle, so not known to fall under it) and named those of them
    whose every -g20 run names the true effect."""
    under = set(wide_under_margin(wide))
    kept = [w for w in wide if w["runs"] and w["case"] not in under]
    return len(kept), sum(1 for w in kept if named_every_run(w))


def wide_escalate_tally(wide, escalate_dir):
    """The table's rule at the issue's size with the second search
    (--escalate runs of CASE-g20 archived in escalate_dir): (nameable,
    named, misses, searched again, named by it). nameable and named are
    wide_rule_tally's; misses are the nameable cases not named in every
    run whose every run not naming the true effect is `unexplained` (the
    only verdict the second search follows); searched again those of them
    with an archived -g20 second search (escalation.ran), named by it those
    whose every such run names the true effect. With the second search the
    count is named + named by it, of nameable."""
    nameable, named = wide_rule_tally(wide)
    under = set(wide_under_margin(wide))
    esc = collections.defaultdict(list)
    for name, _, r in rb.archived(escalate_dir):
        if name.endswith(rb.WIDE) and r.get("escalation", {}).get("ran"):
            esc[name[:-len(rb.WIDE)]].append(r["verdict"])
    misses = [w for w in wide if w["runs"] and w["case"] not in under and not named_every_run(w) and
              all(v == "unexplained" for _, v, _ in w["runs"] if v != w["effect"])]
    searched = [w for w in misses if esc.get(w["case"])]
    named2 = sum(1 for w in searched if all(v == w["effect"] for v in esc[w["case"]]))
    return nameable, named, len(misses), len(searched), named2


def escalate_runs(rows, archive_dir):
    """The table's cases diagnosed again with the second search
    (run_blind.py --diagnose-args="--escalate", archived apart in
    run_blind.ARCHIVE_ESCALATE): for each table row, a list of (commit,
    first verdict, verdict, the true effect's held-out shrink in percent) of
    its archived runs in which the second search ran (any commit); a run
    whose first search named something or said `none` did not search again
    and is not listed. Rows with no such run have runs == []."""
    by_name = collections.defaultdict(list)
    for name, p, r in rb.archived(archive_dir):
        esc = r.get("escalation", {})
        if not esc.get("ran"):
            continue
        by_name[name].append((os.path.basename(os.path.dirname(p)), esc.get("first_verdict"), r["verdict"],
                              true_shrink(name, r)))
    return [{"case": row["case"], "effect": row["effect"], "table": row["verdict"], "runs": by_name.get(row["case"], [])}
            for row in rows]


def escalate_tally(esc):
    """(misses, searched again, named, table hits with them): of
    escalate_runs' rows, those whose table verdict is `unexplained` (the
    only verdict after which the second search runs), those of them with an
    archived second search, those whose every such run names the true
    effect, and the table's hits plus those named."""
    misses = [w for w in esc if w["table"] == "unexplained"]
    tried = [w for w in misses if w["runs"]]
    named = sum(1 for w in tried if all(v == w["effect"] for _, _, v, _ in w["runs"]))
    hits = sum(1 for w in esc if w["table"] == w["effect"])
    return len(misses), len(tried), named, hits + named


def against_first_baseline(esc, escalate_dir, archive_dir):
    """The second search's shrink measured against the first search's
    baseline instead of its own. The second search refits the baseline
    with more starts, so its own baseline can be better or worse than the
    first's, and its shrink (against its own) is then smaller or larger
    than what the model it names gains over the model the default would
    leave the user with. For each second-search run of escalate_runs' rows
    (same order): a dict case, commit, verdict, own (the shrink in percent
    against its own baseline), first (against the first search's baseline:
    1 - the true effect's held-out RMSE / that baseline's held-out RMSE,
    taken from the run's own escalation.first_holdout_rmse_m, which
    engines since f5a5c54 record, else from the default's run at the same
    commit archived in archive_dir), the two baselines' held-out RMSE in
    metres (own_base, first_base) and oracle (the default run's oracle
    shrink in percent, against that run's baseline: the first search's
    when the engine is deterministic, as on one thread; NaN when the
    default ran without the oracle or is not archived). A run whose engine
    demoted the true effect (escalation.demoted) gives only its recorded
    shrink against the first baseline (own and own_base NaN); one that
    demoted another effect, and runs with neither a recorded first
    baseline nor an archived default run, are left out."""
    default = {(name, os.path.basename(os.path.dirname(p))): r for name, p, r in rb.archived(archive_dir)}
    second = {(name, os.path.basename(os.path.dirname(p))): r for name, p, r in rb.archived(escalate_dir)}
    out = []
    for w in esc:
        for commit, _, verdict, own in w["runs"]:
            d, r = default.get((w["case"], commit)), second.get((w["case"], commit))
            if r is not None and r.get("escalation", {}).get("demoted"):
                # the engine kept the first search's result (since
                # f5a5c54): its effects are the first's, and the second
                # search's figure is only the recorded shrink against the
                # first baseline, of the effect it demoted
                esc_r = r["escalation"]
                if esc_r["demoted"] == w["effect"] and esc_r.get("shrink_against_first") is not None:
                    out.append({"case": w["case"], "commit": commit, "verdict": verdict, "own": float("nan"),
                                "first": 100.0 * esc_r["shrink_against_first"], "own_base": float("nan"),
                                "first_base": esc_r["first_holdout_rmse_m"],
                                "oracle": 100.0 * d["oracle"]["shrink"]
                                if d and d.get("oracle", {}).get("shrink") is not None else float("nan")})
                continue
            e = next((x for x in r.get("effects", []) if x["name"] == w["effect"]), None) if r else None
            # the run's own record of its first search (engines since
            # f5a5c54), else the default's run at the same commit
            first_base = (r or {}).get("escalation", {}).get("first_holdout_rmse_m") or \
                (d["baseline"]["holdout_rmse_m"] if d else None)
            if first_base is None or e is None or e.get("holdout_rmse_m") is None:
                continue
            d = d or {}
            out.append({"case": w["case"], "commit": commit, "verdict": verdict, "own": own,
                        "first": 100.0 * (1.0 - e["holdout_rmse_m"] / first_base),
                        "own_base": r["baseline"]["holdout_rmse_m"], "first_base": first_base,
                        "oracle": 100.0 * d["oracle"]["shrink"] if d.get("oracle", {}).get("shrink") is not None
                        else float("nan")})
    return out


def plot_top1(rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    effects = sorted({r["effect"] for r in rows})
    colour = {e: "C%d" % i for i, e in enumerate(effects)}
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(12.0, 5.2), gridspec_kw={"width_ratios": [1.05, 1]})
    # The axes end at 35 %: a case beyond (wind s22, 67 %) is drawn on the
    # edge as a triangle with its values written beside it.
    hi = min(35.0, max(max(r["oracle"] for r in rows), max(r["shrink"] for r in rows)) * 1.08)
    lo = min(0.0, min(r["shrink"] for r in rows)) - 1
    ax.plot([0, hi], [0, hi], ":", color="0.5", lw=1, label="as much as the oracle")
    ax.plot([0, hi], [0, 0.7 * hi], "--", color="0.6", lw=1, label="70 % of the oracle's (the target)")
    ax.axhline(5.0, color="C3", lw=0.8, alpha=0.6)
    ax.text(hi * 0.99, 5.3, "the 5 % margin", color="C3", fontsize=7, ha="right")
    for r in rows:
        kind = ("right" if r["verdict"] == r["effect"] else
                "declined" if r["verdict"] in ("none", "unexplained") else "wrong")
        style = {"right": dict(marker="o", mfc=colour[r["effect"]], mec=colour[r["effect"]]),
                 "declined": dict(marker="o", mfc="white", mec=colour[r["effect"]]),
                 "wrong": dict(marker="X", mfc=colour[r["effect"]], mec="k")}[kind]
        x, y = min(r["oracle"], hi * 0.985), min(r["shrink"], hi * 0.985)
        if (x, y) != (r["oracle"], r["shrink"]):
            style["marker"] = "^"
            ax.annotate("%s (%.1f, %.1f)" % (r["case"].replace("-1-", " "), r["oracle"], r["shrink"]), (x, y),
                        textcoords="offset points", xytext=(-6, -10), fontsize=6, ha="right")
        ax.plot(x, y, ls="", ms=7, **style)
        if kind != "right":
            ax.annotate(r["case"].replace("pitch_damping", "PD").replace("finite_span", "FS").replace("-1-", " ")
                        + ("" if kind == "declined" else " → " + r["verdict"]),
                        (x, y), textcoords="offset points", xytext=(4, -9), fontsize=6)
    for e in effects:
        ax.plot([], [], "o", color=colour[e], label=e)
    ax.plot([], [], "o", mfc="white", mec="k", label="not named (none / unexplained)")
    ax.plot([], [], "X", mfc="0.5", mec="k", label="another effect named")
    hits = sum(1 for r in rows if r["verdict"] == r["effect"])
    ax.set_xlim(0, hi)
    ax.set_ylim(lo, hi)
    ax.set_xlabel("oracle's held-out shrink, % (the baseline plus the true effect at its size)")
    ax.set_ylabel("the true effect's held-out shrink in the diagnosis, %")
    ax.set_title("Top-1: %d of %d named (filled)" % (hits, len(rows)), fontsize=10)
    ax.legend(fontsize=7, loc="upper left")
    ax.set_aspect("equal", adjustable="box")

    m = confusion(rows)
    truths = sorted(m)
    cols = [v for v in VERDICTS if any(m[t][v] for t in truths)]
    grid = [[m[t][v] for v in cols] for t in truths]
    bx.imshow([[g / max(1, sum(row)) for g in row] for row in grid], cmap="Blues", vmin=0, vmax=1, aspect="auto")
    for i, row in enumerate(grid):
        for j, n in enumerate(row):
            if n:
                bx.text(j, i, str(n), ha="center", va="center", fontsize=9,
                        color="white" if n / max(1, sum(row)) > 0.6 else "black")
    bx.set_xticks(range(len(cols)))
    bx.set_xticklabels(cols, rotation=35, ha="right", fontsize=8)
    bx.set_yticks(range(len(truths)))
    bx.set_yticklabels(["%s (%d of %d)" % (t, m[t][t], sum(m[t].values())) for t in truths], fontsize=8)
    bx.set_xlabel("verdict")
    bx.set_ylabel("true effect (named right)")
    bx.set_title("Confusion matrix of the nameable cases", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def plot_strengths(found, n_rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    # One column per parameter: the camera's scale and roll apart.
    labels = []
    for f in found:
        names = [n for n, _ in rb.nominal(f["effect"])] if len(f["all"]) > 1 else [None]
        for k, n in enumerate(names):
            lab = f["effect"] + ("" if n is None else " (%s)" % n)
            if lab not in labels:
                labels.append(lab)
    labels.sort()
    fig, ax = plt.subplots(figsize=(9.0, 4.8))
    per = collections.defaultdict(int)
    for f in found:
        names = [n for n, _ in rb.nominal(f["effect"])] if len(f["all"]) > 1 else [None]
        for k, n in enumerate(names):
            lab = f["effect"] + ("" if n is None else " (%s)" % n)
            x = labels.index(lab) + (per[lab] % 12 - 5.5) * 0.05
            per[lab] += 1
            colour = "C2" if f["named"] else "C3"
            for fold in f["folds"]:
                ax.plot(x, fold[k], ".", color=colour, ms=3, alpha=0.5)
            ax.plot(x, f["all"][k], "o", ms=6, mfc=colour if f["named"] else "white", mec=colour)
    ax.axhline(1.0, color="k", lw=0.8, ls="--")
    ax.text(len(labels) - 0.5, 1.03, "the data's strength", fontsize=7, ha="right")
    ax.plot([], [], "o", mfc="C2", mec="C2", label="on all gliders, case named right")
    ax.plot([], [], "o", mfc="white", mec="C3", label="on all gliders, case missed")
    ax.plot([], [], ".", color="0.4", label="in each fold")
    ax.set_xticks(range(len(labels)))
    ax.set_xticklabels(labels, fontsize=8)
    ax.set_xlim(-0.6, len(labels) - 0.4)
    ax.set_ylabel("fitted strength (1 = the strength the data were made with)")
    ax.set_title("Fitted against true strength: %d of the top-1 table's %d cases (those archived)"
                 % (len(found), n_rows), fontsize=10)
    ax.legend(fontsize=7, loc="upper left")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--docs", default=os.path.join(ROOT, "docs", "diagnosis.md"))
    ap.add_argument("--archive", default=rb.ARCHIVE)
    ap.add_argument("--archive-escalate", default=rb.ARCHIVE_ESCALATE)
    ap.add_argument("--out", default=os.path.join(ROOT, "docs", "img"))
    a = ap.parse_args(argv)
    for d in (a.archive, a.archive_escalate):
        if not os.path.isdir(d):
            ap.error("no archive at %s (a directory of COMMIT/CASE.diagnosis.json.gz)" % d)
    with open(a.docs, encoding="utf-8") as f:
        rows = top1_rows(f.read())
    os.makedirs(a.out, exist_ok=True)
    p1 = os.path.join(a.out, "blind_top1.png")
    plot_top1(rows, p1)
    hits = sum(1 for r in rows if r["verdict"] == r["effect"])
    print("%s: %d cases, %d named right" % (p1, len(rows), hits))
    wide = wide_runs(rows, a.archive)
    flown, every, some, unflown = wide_tally(wide)
    print("at the issue's size (%s, every training glider): %d of the table's %d cases flown, the true effect named "
          "in %d (in every run of each; in some run: %d); %d not flown" % (rb.WIDE, flown, len(rows), every, some,
                                                                          unflown))
    for w in wide:
        if w["runs"]:
            print("  %-22s eight gliders: %-15s %s: %s" % (w["case"], w["narrow"], rb.WIDE, "; ".join(
                "%s (%.1f %%, %s%s)" % (v, sh, c, ", oracle %.1f %%" % w["oracles"][c] if c in w["oracles"] else "")
                for c, v, sh in w["runs"])))
    under = wide_under_margin(wide)
    verdicts = {w["case"]: "/".join(v for _, v, _ in w["runs"]) for w in wide}
    print("  flown with the oracle, the oracle under the margin at %s (not nameable by the table's rule; the "
          "verdicts): %s" % (rb.WIDE, ", ".join("%s (%s)" % (c, verdicts[c]) for c in under) or "none"))
    nameable, named = wide_rule_tally(wide)
    print("  by the table's rule at %s (the flown cases less those under the margin): %d nameable, %d named in every "
          "run" % (rb.WIDE, nameable, named))
    print("  not flown at %s: %s" % (rb.WIDE, ", ".join(w["case"] for w in wide if not w["runs"]) or "none"))
    nameable, named, wmiss, wtried, wnamed2 = wide_escalate_tally(wide, a.archive_escalate)
    print("  with the second search at %s (archived in %s): %d of the %d `unexplained` misses by the table's rule "
          "searched again, %d named; %d of %d (%.0f %%)" % (rb.WIDE, os.path.relpath(a.archive_escalate, ROOT), wtried,
                                                         wmiss, wnamed2, named + wnamed2, nameable,
                                                         100.0 * (named + wnamed2) / nameable if nameable else 0))
    for name, p, r in rb.archived(a.archive_escalate):
        if name.endswith(rb.WIDE) and r.get("escalation", {}).get("ran"):
            print("    %-26s %s: second search %s (%.1f %%)" % (name, os.path.basename(os.path.dirname(p)),
                                                                r["verdict"], true_shrink(name, r)))
    esc = escalate_runs(rows, a.archive_escalate)
    misses, tried, named2, hits2 = escalate_tally(esc)
    print("with the second search (--escalate, archived in %s): %d of the table's %d `unexplained` misses searched "
          "again, %d named; %d of %d (%.0f %%)" % (os.path.relpath(a.archive_escalate, ROOT), tried, misses, named2,
                                                  hits2, len(rows), 100.0 * hits2 / len(rows)))
    for w in esc:
        for c, first, v, sh in w["runs"]:
            print("  %-22s %s: first search %s, second %s (%.1f %%)" % (w["case"], c, first, v, sh))
    print("  not searched again: %s" % (", ".join(w["case"] for w in esc if w["table"] == "unexplained" and
                                                  not w["runs"]) or "none"))
    print("  against the first search's baseline (recorded in the run, else the default's run at the same commit "
          "in %s):" % os.path.relpath(a.archive, ROOT))
    for f in against_first_baseline(esc, a.archive_escalate, a.archive):
        print("  %-22s %s: %-13s %.1f %% against its own baseline (%.2f cm), %.1f %% against the first's (%.2f cm; "
              "oracle %.1f %%)" % (f["case"], f["commit"], f["verdict"], f["own"], 100 * f["own_base"], f["first"],
                                  100 * f["first_base"], f["oracle"]))
    found, missing = strengths(rows, a.archive)
    p2 = os.path.join(a.out, "blind_strengths.png")
    plot_strengths(found, len(rows), p2)
    print("%s: %d cases archived at the table's commit; not archived: %s" % (p2, len(found), ", ".join(missing) or "none"))
    for f in found:
        print("  %-22s %-7s all gliders %s, folds %s" % (
            f["case"], "named" if f["named"] else "missed", ", ".join("%.2f" % v for v in f["all"]),
            "; ".join(", ".join("%.2f" % v for v in fold) for fold in f["folds"])))
    return 0


if __name__ == "__main__":
    sys.exit(main())
