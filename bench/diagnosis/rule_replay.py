#!/usr/bin/env python3
"""Replay the diagnosis's per-effect decision on stored results, and
alternatives to it, without diagnosing again (issue 7, docs/diagnosis.md).

Every `diagnosis.json` under the given directories (blind-benchmark case
directories, EFFECT-STRENGTH-sSEED or null-sSEED, as run_blind.py writes
them) holds each candidate's likelihood-ratio result, held-out shrink and
chi-square, glider guard, launch-rate test and plausibility. The rule as
built (docs/diagnosis.md, "Which effect") is

    significant = LR passed (Holm) and shrink >= margin and held-out
                  delta chi2 > its threshold and the launch rates share a
                  direction (launch rotation only) and the glider guard
                  passed and the fit is plausible

This script first checks that it reproduces every stored `significant` flag
(a replay that does not is refused: the stored results come from another
rule), then counts, for each alternative rule, the null datasets where some
candidate would become significant (false discoveries) and the
single-effect datasets where the true effect would (and where another one
would). It answers "what would this rule have done on every case we ran"
before anyone spends hours of blind runs on it; it cannot say what a rule
would do on fits the diagnosis would then have made differently (a rule
that changes which candidates are stepped, for instance).

    /usr/bin/python3 bench/diagnosis/rule_replay.py out/s25 out/nulls-402578c ...
    /usr/bin/python3 bench/diagnosis/rule_replay.py bench/diagnosis/runs   # the archived runs

Compressed results archived by run_blind.py (COMMIT/CASE.diagnosis.json.gz)
are read as well.
"""
import argparse
import glob
import gzip
import json
import math
import os
import statistics
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from run_blind import ARCHIVE_SUFFIX, archived, case_of  # noqa: E402  (the benchmark's case names and archive)


# The fits' ranges (engine/src/effects.cpp, docs/diagnosis.md "The bound
# guard"), in the reported units of `fold_parameters`.
RANGES = {"strength": (0.0, 3.0), "wind_m_s": (-15.0, 15.0),
          "pitch_rate_deg_s": (-20 * 180 / math.pi, 20 * 180 / math.pi), "scale_error": (-0.5, 0.5),
          "roll_deg": (-0.5 * 180 / math.pi, 0.5 * 180 / math.pi)}


def bound_share(e, r):
    """The bound guard's figure (fold_bound_share in the engine) from a
    stored result: each fold's held-out gain from the per-glider held-out
    RMSEs and points, the share of folds fitted in the outer tenth of the
    range. None when the result lacks the per-glider figures."""
    cv = e.get("cross_validation", {})
    per, per0 = cv.get("glider_holdout_rmse_m"), cv.get("glider_baseline_holdout_rmse_m")
    folds = r.get("cross_validation", {}).get("held_out_gliders")
    pts = {g["glider"]: g["points"] for g in r.get("where", {}).get("gliders", [])}
    fp = e.get("fold_parameters")
    if not per or not per0 or not folds or not pts or not fp or len(fp) != len(folds):
        return None
    edge = total = 0.0
    for gl, par in zip(folds, fp):
        gain = max(0.0, sum(pts[g] * (per0[g] ** 2 - per[g] ** 2) for g in gl))
        at = False
        for k, v in par.items():
            lo, hi = RANGES[k]
            if k == "strength" and e["name"] == "fuselage_drag":
                hi = 10.0
            at = at or (hi > 0 and v >= 0.9 * hi) or (lo < 0 and v <= 0.9 * lo)
        total += gain
        edge += gain if at else 0.0
    return edge / total if total > 0 else 0.0


# The loss guard's share of held-out gliders improved (a mirror of the glider
# guard, replayed only): 7 of 8. With no effect each glider comes out better
# or worse about equally often, so 7 or more of 8 with probability 0.035.
LOSS_GUARD_SHARE = 7 / 8


def loss_guard_figures(e, r, share=LOSS_GUARD_SHARE):
    """(shrink, held-out delta chi2, glider) with the held-out glider the
    candidate makes worse by the most squared error left out of both sums,
    for a candidate that improves at least `share` of the held-out gliders
    and makes at least one worse; None otherwise or without the per-glider
    figures. The chi-square's scale is the one the stored held-out delta
    chi2 was measured with (recovered from it and the per-glider sums; the
    tracking noise where that cannot be done)."""
    cv = e.get("cross_validation", {})
    per, per0 = cv.get("glider_holdout_rmse_m"), cv.get("glider_baseline_holdout_rmse_m")
    pts = {g["glider"]: g["points"] for g in r.get("where", {}).get("gliders", [])}
    if not per or not per0 or not pts or set(per) != set(per0) or not set(per) <= set(pts):
        return None
    improved = sum(1 for g in per if per[g] < per0[g])
    if improved < share * len(per):
        return None
    loss = {g: pts[g] * (per[g] ** 2 - per0[g] ** 2) for g in per}
    worst = max(loss, key=loss.get)
    if loss[worst] <= 0:
        return None
    sse = sum(pts[g] * per[g] ** 2 for g in per)
    sse0 = sum(pts[g] * per0[g] ** 2 for g in per)
    rest0 = sse0 - pts[worst] * per0[worst] ** 2
    if rest0 <= 0:
        return None
    shrink = 1 - math.sqrt(max(0.0, sse - pts[worst] * per[worst] ** 2) / rest0)
    d = cv.get("delta_chi2")
    scale = (sse0 - sse) / d if d and sse0 != sse and (sse0 - sse) / d > 0 else None
    if scale is None:
        sigma = r.get("dataset", {}).get("tracking_sigma_m")
        if not sigma:
            return None
        scale = sigma * sigma
    return shrink, (sse0 - sse + loss[worst]) / scale, worst


def fields(e, options, r=None):
    lr = e.get("likelihood_ratio", {})
    cv = e.get("cross_validation", {})
    rate = e.get("rate_mean")
    return {
        "name": e["name"],
        "lr_pass": bool(lr.get("pass", False)),
        "p": lr.get("p_value", 1.0),
        "shrink": e.get("shrink", 0.0),
        "ho_dchi2": cv.get("delta_chi2", float("nan")),
        "ho_threshold": cv.get("threshold", float("nan")),
        "robust_pass": bool(cv.get("robust_pass", True)),
        "robust_shrink": cv.get("robust_shrink", float("nan")),
        "improved": cv.get("gliders_improved", 0),
        "gliders": cv.get("gliders", 0),
        "rate_pass": bool(rate.get("pass", False)) if isinstance(rate, dict) else True,
        "rate_test": isinstance(rate, dict),
        "rates_confirm": bool(options.get("launch_rates_confirm", False)),
        "plausible": bool(e.get("plausible", True)),
        "collinearity": e.get("coefficient_collinearity", 0.0),
        "margin": options.get("min_shrink", 0.05),
        "ho_test": bool(options.get("holdout_chi2_test", True)),
        "limit": options.get("collinearity_limit", 0.95),
        "guard_on": bool(options.get("glider_guard", True)),
        "bound_pass": bool(cv.get("bound_pass", True)),
        "bound_on": bool(options.get("bound_guard", False)),
        "bound_share": bound_share(e, r) if r is not None else None,
        "likelihood_reference": r is not None and likelihood_reference(r) == e["name"],
        "loss_guard": loss_guard_figures(e, r) if r is not None else None,
    }


def likelihood_reference(r):
    """The candidate the engine's likelihood ratios are measured from
    (likelihood_reference, since 2026-11-30): fitted on all gliders with
    every parameter at 0 (not per-flight launch rotation) and a fit better
    than the baseline's by more than 0.2 chi-square units (the sum of
    squares is the RMSE squared times the dataset's points; without the
    dataset's points and noise, any better fit), the best such; None when
    there is none."""
    base = r.get("baseline", {}).get("fit_rmse_m")
    per_flight = r.get("options", {}).get("launch_rotation_per_flight", True)
    if base is None:
        return None
    ds = r.get("dataset", {})
    n, sigma = ds.get("points"), ds.get("tracking_sigma_m")
    sse = (lambda rmse: rmse * rmse * n) if n and sigma else (lambda rmse: rmse * rmse)
    best, ref = None, sse(base) - (0.2 * sigma * sigma if n and sigma else 0.0)
    for e in r["effects"]:
        params = e.get("parameters") or {}
        if not params or any(v != 0 for v in params.values()):
            continue
        if e["name"] == "launch_rotation" and per_flight:
            continue
        if sse(e.get("fit_rmse_m", float("inf"))) < ref:
            best, ref = e["name"], sse(e["fit_rmse_m"])
    return best


def margin(f):
    """The shrink an effect must reach (shrink_margin in the engine): the
    margin, or for per-flight launch rotation confirmed by its rates
    (launch_rates_confirm, since 2026-11-30) just above zero."""
    return 0.0 if f["rates_confirm"] and f["rate_test"] and f["name"] == "launch_rotation" else f["margin"]


def built(f):
    """The rule as built."""
    ho = (not f["ho_test"]) or f["ho_dchi2"] > f["ho_threshold"]
    shrink = f["shrink"] >= margin(f) and (f["shrink"] > 0 or not f["rates_confirm"])
    return f["lr_pass"] and shrink and ho and f["rate_pass"] and f["robust_pass"] and \
        f["plausible"] and f["bound_pass"]


def rates_confirm(f):
    """As built, with per-flight launch rotation confirmed by its rates
    (launch_rates_confirm, on by default since 2026-11-30): its held-out
    rates sharing a direction at alpha / m and any held-out shrink above
    zero stand for the margin. Replays results of binaries from before it."""
    return built(dict(f, rates_confirm=True))


def heldout_for_collinear(f):
    """As built, but an effect the coefficients imitate (collinearity above
    the limit) may pass on the held-out gliders alone: its likelihood ratio
    on the training gliders is what the re-tuned coefficients hide."""
    if f["collinearity"] > f["limit"]:
        g = dict(f, lr_pass=True)
        return built(g)
    return built(f)


def heldout_only(f):
    """The held-out tests alone (no likelihood-ratio test)."""
    return built(dict(f, lr_pass=True))


def heldout_robust(f):
    """The held-out tests alone, with the shrink without the glider it rests
    on most also above the margin (not only a majority of gliders)."""
    return built(dict(f, lr_pass=True)) and f["robust_shrink"] >= f["margin"]


def guard_three_quarters(f):
    """As built, with the glider guard of 2026-11-29 (glider_guard_pass in
    the engine): a gain that rests on one glider (robust shrink under the
    margin) needs at least three quarters of the held-out gliders improved,
    not a bare majority. Replays results of binaries from before the change
    under it (on later ones it is the rule as built)."""
    if not f["guard_on"] or f["gliders"] <= 0:  # diagnosed with --no-glider-guard, or no per-glider figures
        return built(f)
    return built(dict(f, robust_pass=f["robust_pass"] and glider_guard(f)))


def glider_guard(f):
    """The glider guard's condition at f's margin (glider_guard_pass in the
    engine): the shrink without the glider the gain rests on reaches the
    margin, or at least three quarters of the held-out gliders are better."""
    return f["robust_shrink"] >= f["margin"] or 4 * f["improved"] >= 3 * f["gliders"]


def bound_guard(f):
    """As built, with the bound guard of 2026-11-29 (fold_bound_share in the
    engine): not significant when more than half of the held-out gain comes
    from folds fitted in the outer tenth of the range. Replays results of
    binaries from before it (it cannot replay what the held-out-led steps,
    on by default since then, would have added)."""
    if f["bound_on"] or f["bound_share"] is None:
        return built(f)
    return built(dict(f, bound_pass=f["bound_share"] <= 0.5))


def reference_rule(f):
    """As built, with the likelihood ratios measured from a candidate's fit
    at 0 that beats the baseline's (likelihood_reference in the engine,
    since 2026-11-30): that candidate's own ratio is then 0 and it fails the
    training test. The others' ratios would shrink too, which this replay
    leaves out (it can only under-count what the rule takes back)."""
    return built(dict(f, lr_pass=False)) if f["likelihood_reference"] else built(f)


def loss_guard(f):
    """As built, but a held-out loss that rests on one glider does not sink
    an effect that improves nearly all the others (a mirror of the glider
    guard; replayed, not built): where a candidate improves at least 7 of 8
    of the held-out gliders, its shrink and held-out delta chi2 are also
    measured without the glider it makes worse by the most, and it passes
    when either measure does. (Blind pitch damping s28's second search:
    strength 1.02, 7 of 8 gliders better, but t06-swept-15 from 35 to 43 mm,
    so -6.0 % pooled; 8.6 % without it.)"""
    if built(f) or f["loss_guard"] is None:
        return built(f)
    shrink, dchi2, _ = f["loss_guard"]
    return built(dict(f, shrink=max(f["shrink"], shrink), ho_dchi2=max(f["ho_dchi2"], dchi2)))


# Effects applied alike to every flight of the session (EffectLevel Session
# and Observation in engine/src/effects.cpp).
SESSION_WIDE = ("wind", "camera")


def launch_withheld(r):
    """The launch withhold (launch_withheld in the engine, on by default
    since 2026-11-30) on a stored result: its verdict names wind or the
    camera, and launch rotation passed its likelihood-ratio test, is not
    significant and (per-flight rates) its rates' mean has p under alpha.
    A result of a binary with the withhold already carries it in
    ``withheld`` (and one that ran with it on and has none was not
    withheld: since 2026-12-02 its exemption may have kept the verdict)."""
    if r.get("withheld"):
        return True
    if r.get("options", {}).get("launch_withhold") is True:
        return False
    return old_rule(r)


def old_rule(r):
    """The withhold's condition without its exemption, on the stored
    verdict and launch rotation's stored tests."""
    if r.get("verdict") not in SESSION_WIDE:
        return False
    alpha = r.get("options", {}).get("alpha", 0.01)
    for e in r["effects"]:
        if e["name"] != "launch_rotation":
            continue
        rate = e.get("rate_mean")
        rates_one_way = not isinstance(rate, dict) or rate.get("p_value", 1.0) < alpha
        return bool(e.get("likelihood_ratio", {}).get("pass")) and not e.get("significant") and rates_one_way
    return False


DOMINANCE = 5.0  # DiagnoseOptions::launch_withhold_dominance


def launch_dominance(r, effect):
    """The launch withhold's exemption (launch_dominance in the engine) on
    a stored result: the shares of the baseline's all-glider misfit that
    `effect` and launch rotation close (1 - fit_rmse_m / baseline
    fit_rmse_m), or None when a figure is missing."""
    base = r.get("baseline", {}).get("fit_rmse_m")
    fit = {e["name"]: e.get("fit_rmse_m") for e in r.get("effects", [])}
    if not base or fit.get(effect) is None or fit.get("launch_rotation") is None:
        return None
    return 1 - fit[effect] / base, 1 - fit["launch_rotation"] / base


def dominates(gains, k=DOMINANCE):
    """Whether the session-wide effect's share exceeds k times launch
    rotation's (the engine's rule; k 0 never exempts)."""
    return gains is not None and k > 0 and gains[0] > 0 and gains[0] > k * max(gains[1], 0.0)


def exemption_verdict(r):
    """The verdict of a stored result under the withhold's exemption
    (2026-12-02): a verdict the launch withhold took back whose all-glider
    fit closes more than DOMINANCE times launch rotation's share of the
    baseline's misfit is given back (the rule acts after every fit, so
    this is what the run would have said with it); any other verdict, and
    the verdicts of binaries with the exemption, as stored."""
    w = r.get("withheld")
    if not w or "launch_withhold_dominance" in r.get("options", {}):
        return r.get("verdict")
    return w["effect"] if dominates(launch_dominance(r, w["effect"])) else r.get("verdict")


def launch_verdict(r):
    """The verdict of a stored result under the launch rules of 2026-11-30
    (launch_rates_confirm and launch_withhold, as in the engine): launch
    rotation significant by its rates takes the verdict from wind, the
    camera, `unexplained` or `none` (no other effect significant: none of
    the others' decisions change); a session-wide verdict beside a launch
    rotation that only fits becomes `unexplained`; an aerodynamic verdict
    stands (launch rotation would at most join `also`). Results of binaries
    with the rules are returned as stored."""
    opts = r.get("options", {})
    if "launch_rates_confirm" in opts or "verdict" not in r:
        return r.get("verdict")
    lr = [e for e in r["effects"] if e["name"] == "launch_rotation"]
    if lr and rates_confirm(fields(lr[0], opts)) and (r["verdict"] in SESSION_WIDE + ("unexplained", "none")):
        return "launch_rotation"
    return "unexplained" if launch_withheld(r) else r["verdict"]


RULES = [("as built", built), ("held-out alone for collinear effects", heldout_for_collinear),
         ("held-out alone", heldout_only), ("held-out alone, robust shrink", heldout_robust),
         ("glider guard at three quarters", guard_three_quarters), ("bound guard", bound_guard),
         ("launch rotation confirmed by its rates", rates_confirm),
         ("likelihood ratios from a candidate's fit at 0", reference_rule),
         ("loss guard (7 of 8 gliders better: the shrink without the one made worst)", loss_guard)]


def replayed_verdict(r, margin):
    """The verdict a stored result would get with the held-out margin at
    `margin`: of its candidates significant under the rule as built with
    that margin (the glider guard recomputed with it too: the shrink
    without the glider the gain rests on at least the margin, or three
    quarters of the held-out gliders better), the one with the largest
    held-out shrink; None when none is. An approximation of the engine's
    verdict, which also weighs a second round, the launch withhold and
    alternatives; margin_sweep reports how often it agrees with the stored
    verdicts at the margin they were made with."""
    best = None
    for e in r.get("effects", []):
        f = dict(fields(e, r.get("options", {}), r), margin=margin)
        if f["guard_on"] and f["gliders"] > 0:
            f["robust_pass"] = glider_guard(f)  # the stored pass was decided at the run's own margin
        if built(f) and (best is None or f["shrink"] > best[1]):
            best = (f["name"], f["shrink"])
    return best[0] if best else None


def margin_sweep(rows, runs, margins, order=None):
    """What another held-out margin would do to the top-1 count, replayed on
    stored results. rows: the top-1 table's rows (plot_blind.top1_rows:
    case, effect, oracle in percent, verdict, commit); runs: {case: {commit:
    result}} of archived eight-glider runs (CASE-g20 and others are not
    asked for). The table counts a case when its oracle closes at least the
    margin, so a margin moves both sides of the rate. For each margin m, a
    dict: table (nameable, named) over the table's rows whose run at the
    row's commit is archived, the oracle from that run (the table's figure
    when the run has none); outside (nameable, named) over the archived
    single effects at strength 1 that are not in the table (their oracle was
    under the table's margin) whose oracle reaches m, each by its run with
    an oracle (the latest by `order`, commits oldest first, where it has
    several; without the order that is refused as ambiguous); nulls
    (runs naming an effect, runs) over every archived null run; agree (the
    table's archived rows whose replayed verdict at the margin the run was
    made with names the true effect exactly when the table's does, of
    them; the same for every margin)."""
    rank = {c: i for i, c in enumerate(order or [])}
    table = {row["case"] for row in rows}
    archived_rows = []  # (row, its run, its oracle's shrink)
    for row in rows:
        r = runs.get(row["case"], {}).get(row["commit"].split(",")[0].strip())
        if r is not None:
            o = (r.get("oracle") or {}).get("shrink")
            archived_rows.append((row, r, row["oracle"] / 100 if o is None else o))
    agree = sum((replayed_verdict(r, r.get("options", {}).get("min_shrink", 0.05)) == row["effect"]) ==
                (row["verdict"] == row["effect"]) for row, r, _ in archived_rows)
    nulls = [r for name, by_commit in runs.items() if name.startswith("null-") for r in by_commit.values()]
    out = []
    for m in margins:
        nameable = [(row, r) for row, r, o in archived_rows if o >= m]
        n, named = len(nameable), sum(replayed_verdict(r, m) == row["effect"] for row, r in nameable)
        on = onamed = 0
        for name, by_commit in runs.items():
            c = case_of(name)
            if c is None or name in table or not c["truth"] or len(c["truth"]) != 1 or name.endswith("-g20"):
                continue
            if list(c["strength"].values()) != [1.0]:
                continue
            with_oracle = [k for k, r in by_commit.items() if (r.get("oracle") or {}).get("shrink") is not None]
            if not with_oracle:
                continue
            if len(with_oracle) > 1 and not all(k in rank for k in with_oracle):
                raise ValueError("%s has runs with an oracle at %s: which is the latest needs the repository's "
                                 "history (order)" % (name, ", ".join(sorted(with_oracle))))
            r = by_commit[max(with_oracle, key=lambda k: rank.get(k, -1))]
            o = r["oracle"]["shrink"]
            if o < m:
                continue
            on += 1
            onamed += replayed_verdict(r, m) == c["truth"][0]
        out.append({"margin": m, "table": (n, named), "outside": (on, onamed),
                    "nulls": (sum(1 for r in nulls if replayed_verdict(r, m)), len(nulls)),
                    "agree": (agree, len(archived_rows))})
    return out


def chi2_isf(p, dof):
    """The chi-square quantile exceeded with probability p, for 1 or 2
    degrees of freedom (the candidates' strengths, the camera's scale and
    roll): z(p/2)^2 and -2 ln p exactly."""
    if dof == 1:
        z = statistics.NormalDist().inv_cdf(1 - p / 2)
        return z * z
    if dof == 2:
        return -2 * math.log(p)
    raise ValueError("chi2_isf: %d degrees of freedom" % dof)


def screen_leaders(r):
    """The all-glider screen's leaders from a stored result (the keys
    `linearised_delta_chi2` exist since commit b3d9a3e): among the
    candidates whose linearised gain passes the test's screen (over the
    chi-square quantile at alpha / m, as the engine's leader), the one with
    the largest gain (the leader as built) and the one whose fit to all
    gliders is best (lowest fit_rmse_m, the alternative weighed on
    2026-12-04). None when the result holds no gains or none passes."""
    effects = r.get("effects", [])
    if not any(isinstance(e.get("linearised_delta_chi2"), (int, float)) for e in effects):
        return None
    alpha = r.get("options", {}).get("alpha", 0.01)
    m = len(effects)
    passing = [e for e in effects if isinstance(e.get("linearised_delta_chi2"), (int, float)) and
               e["linearised_delta_chi2"] > chi2_isf(alpha / m, max(1, len(e.get("parameters", {}))))]
    if not passing:
        return None
    by_gain = max(passing, key=lambda e: e["linearised_delta_chi2"])
    by_fit = min(passing, key=lambda e: e.get("fit_rmse_m", float("inf")))
    return by_gain["name"], by_fit["name"]


def commit_order():
    """The repository's commits, oldest first, by their 7-character names
    (the archive's directory names); None outside a git checkout."""
    import subprocess
    g = subprocess.run(["git", "-C", HERE, "rev-list", "--reverse", "--abbrev-commit", "--abbrev=7", "HEAD"],
                       capture_output=True, text=True)
    return g.stdout.split() if g.returncode == 0 else None


def archived_runs(archive_dir):
    """{case: {commit: result}} of every run archived in archive_dir."""
    runs = {}
    for name, p, r in archived(archive_dir):
        runs.setdefault(name, {})[os.path.basename(os.path.dirname(p))] = r
    return runs


def print_margin_sweep(args):
    """rule_replay.py --margins: margin_sweep on the archive, printed."""
    import plot_blind  # the table's rows, as its figures read them
    try:
        margins = [float(x) for x in args.margins.split(",")]
    except ValueError:
        sys.exit("--margins: a comma list of numbers, such as 0.05,0.03, not %r" % args.margins)
    if not margins or any(not 0 < m < 1 for m in margins):
        sys.exit("--margins: each margin is a share between 0 and 1 (0.05 is the default's 5 %%), not %r" % args.margins)
    try:
        with open(args.docs, encoding="utf-8") as f:
            rows = plot_blind.top1_rows(f.read())
    except OSError as e:
        sys.exit("--docs: cannot read the top-1 table's document %s (%s)" % (args.docs, e.strerror))
    runs = archived_runs(args.dirs[0])
    if not runs:
        sys.exit("no archived runs under %s" % args.dirs[0])
    res = margin_sweep(rows, runs, margins, commit_order())
    a, n = res[0]["agree"]
    print("The top-1 count replayed at other held-out margins (%d of the table's %d cases archived at their commit; "
          "the replayed verdict agrees with the table's on %d of them at the margin each run was made with).\n" % (n, len(rows), a))
    print("| margin | table: named of nameable | outside the table, nameable at this margin: named of them | "
          "together | null runs naming an effect |")
    print("|---|---|---|---|---|")
    for s in res:
        (tn, th), (on, oh), (fd, nn) = s["table"], s["outside"], s["nulls"]
        print("| %.1f %% | %d of %d | %d of %d | %d of %d (%.1f %%) | %d of %d |" %
              (100 * s["margin"], th, tn, oh, on, th + oh, tn + on, 100 * (th + oh) / max(1, tn + on), fd, nn))
    return 0


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("dirs", nargs="+", help="directories holding case directories (searched recursively)")
    ap.add_argument("--plot-exemption", metavar="PNG",
                    help="also draw the launch withhold's exemption: each withheld (or exempted) effect's share of "
                         "the baseline's all-glider misfit against launch rotation's, with the factor's line")
    ap.add_argument("--margins", metavar="M,M,...",
                    help="instead: replay the top-1 count of docs/diagnosis.md's table (--docs) at these held-out "
                         "margins on the archived runs of the first directory (margin_sweep)")
    ap.add_argument("--docs", default=os.path.join(os.path.dirname(os.path.dirname(HERE)), "docs", "diagnosis.md"))
    args = ap.parse_args(argv)
    if args.margins:
        return print_margin_sweep(args)
    cases = []
    seen = set()
    for d in args.dirs:
        stored = [(p, os.path.basename(os.path.dirname(p)))
                  for p in glob.glob(os.path.join(d, "**", "diagnosis.json"), recursive=True)]
        stored += [(p, os.path.basename(p)[:-len(ARCHIVE_SUFFIX)])  # run_blind.py's archive (bench/diagnosis/runs)
                   for p in glob.glob(os.path.join(d, "**", "*" + ARCHIVE_SUFFIX), recursive=True)]
        for p, name in sorted(stored):
            c = case_of(name)
            if c is None:
                continue
            with (gzip.open if p.endswith(".gz") else open)(p, "rt") as fh:
                r = json.load(fh)
            if not r.get("effects"):
                continue
            key = (name, r.get("bench_commit", ""))
            if key in seen:  # the same case diagnosed by the same binary twice
                continue
            seen.add(key)
            opts = r.get("options", {})
            cases.append((p, name, c["truth"], not c["truth"], r, [fields(e, opts, r) for e in r["effects"]]))
    if not cases:
        sys.exit("no blind-benchmark diagnoses (EFFECT-STRENGTH-sSEED/diagnosis.json, null-sSEED/...) under " +
                 ", ".join(args.dirs))
    # The replay must reproduce the stored decisions.
    bad = []
    for p, name, truth, null, r, fs in cases:
        for f, e in zip(fs, r["effects"]):
            if built(f) != bool(e.get("significant", False)):
                bad.append("%s: %s stored %s, replayed %s" % (p, f["name"], e.get("significant"), built(f)))
    if bad:
        sys.exit("the replay of the built rule disagrees with stored decisions (results of another rule?):\n  " +
                 "\n  ".join(bad))
    nulls = [c for c in cases if c[3]]
    singles = [c for c in cases if not c[3] and len(c[2]) == 1]
    print("%d diagnoses replayed (%d null, %d single-effect); the built rule reproduces every stored decision.\n" %
          (len(cases), len(nulls), len(singles)))
    print("| rule | null datasets with a significant effect | single-effect: true effect significant | "
          "single-effect: another effect significant |")
    print("|---|---|---|---|")
    changes = {}
    for label, rule in RULES:
        fd = [c for c in nulls if any(rule(f) for f in c[5])]
        hit = [c for c in singles if any(rule(f) and f["name"] == c[2][0] for f in c[5])]
        other = [c for c in singles if any(rule(f) and f["name"] != c[2][0] for f in c[5])]
        # Exact one-sided 95 % upper bound on the false-discovery rate (Clopper-Pearson).
        n, k = len(nulls), len(fd)
        bound = upper_bound(k, n) if n else float("nan")
        print("| %s | %d of %d (95 %% bound %.1f %%) | %d of %d | %d of %d |" %
              (label, k, n, 100 * bound, len(hit), len(singles), len(other), len(singles)))
        changes[label] = (fd, hit, other)
    print()
    base_fd, base_hit, base_other = changes["as built"]
    for label, _ in RULES[1:]:
        fd, hit, other = changes[label]
        lines = []
        for what, now, before in (("false discovery", fd, base_fd), ("true effect found", hit, base_hit),
                                  ("another effect significant", other, base_other)):
            before_p = {c[0] for c in before}
            for c in now:
                if c[0] not in before_p:
                    rule = dict(RULES)[label]
                    sig = ", ".join("%s (shrink %.1f %%, without its glider %.1f %%, %d of %d gliders, LR p %.2g%s)" %
                                    (f["name"], 100 * f["shrink"], 100 * f["robust_shrink"], f["improved"],
                                     f["gliders"], f["p"],
                                     "; without the glider it makes worst, %s, %.1f %%, held-out delta chi2 %.1f" % (
                                         f["loss_guard"][2], 100 * f["loss_guard"][0], f["loss_guard"][1])
                                     if rule is loss_guard and f["loss_guard"] else "")
                                    for f in c[5] if rule(f) and not built(f))
                    lines.append("  %s: %s [%s]: %s" % (what, c[1], c[4].get("bench_commit", "?"), sig))
            now_p = {c[0] for c in now}
            for c in before:
                if c[0] not in now_p:
                    rule = dict(RULES)[label]
                    gone = ", ".join("%s (shrink %.1f %%)" % (f["name"], 100 * f["shrink"])
                                     for f in c[5] if built(f) and not rule(f))
                    lines.append("  no longer %s: %s [%s]: %s" % (what, c[1], c[4].get("bench_commit", "?"), gone))
        print("%s, against the rule as built:" % label)
        print("\n".join(lines) if lines else "  no change")
    # The verdict-level rule: which stored verdicts the launch withhold
    # turns into `unexplained`, by truth.
    held = [c for c in cases if launch_withheld(c[4])]
    by_truth = {}
    for c in cases:
        t = "+".join(c[2]) or "none"
        by_truth.setdefault(t, [0, 0])
        by_truth[t][0] += 1
        by_truth[t][1] += c in held
    print("\nlaunch withhold (verdict wind or camera withheld beside a fitting launch rotation), by truth: " +
          ", ".join("%s %d of %d" % (t, k[1], k[0]) for t, k in sorted(by_truth.items())))
    for c in held:
        print("  withheld: %s [%s]: %s" % (c[1], c[4].get("bench_commit", "?"),
                                          c[4].get("withheld", {}).get("effect", c[4]["verdict"])))
    # The exemption (2026-12-03, launch_withhold_dominance): a withheld
    # verdict whose all-glider fit closes more than DOMINANCE times launch
    # rotation's share of the baseline's misfit stands.
    print("\nlaunch withhold's exemption (the withheld effect's share of the baseline's all-glider misfit over "
          "launch rotation's; more than %g: not withheld):" % DOMINANCE)
    # The runs the exemption looked at: those withheld, and those of a
    # binary with the exemption whose verdict the withhold would have taken.
    exempted = [c for c in cases if c not in held and "launch_withhold_dominance" in c[4].get("options", {}) and
                old_rule(c[4])]
    points = []
    for c in held + exempted:
        eff = c[4].get("withheld", {}).get("effect", c[4]["verdict"])
        g = launch_dominance(c[4], eff)
        if g is not None:
            points.append((c[1], eff, g, bool(c[2]) and eff in c[2]))
        if g is None:
            print("  %s [%s]: %s: no fit RMSEs stored" % (c[1], c[4].get("bench_commit", "?"), eff))
            continue
        print("  %s [%s]: %s %.2f %% against launch rotation's %.2f %% (%s times): %s" % (
            c[1], c[4].get("bench_commit", "?"), eff, 100 * g[0], 100 * g[1],
            "%.2f" % (g[0] / g[1]) if g[1] > 0 else "inf",
            ("named, " + ("right" if eff in c[2] else "wrong")) if dominates(g) else "withheld"))
    if not held + exempted:
        print("  none withheld")
    if args.plot_exemption:
        plot_exemption(points, args.plot_exemption)
        print("  plot: %s" % args.plot_exemption)
    # Both launch rules (launch_verdict): every verdict that changes.
    print("\nlaunch rules of 2026-11-30 (rates confirm launch rotation; the withhold), verdicts that change:")
    changed = [(c, launch_verdict(c[4])) for c in cases]
    changed = [(c, v) for c, v in changed if v != c[4].get("verdict")]
    for c, v in changed:
        print("  %s [%s]: %s -> %s%s" % (c[1], c[4].get("bench_commit", "?"), c[4]["verdict"], v,
                                         " (right)" if v in c[2] else ""))
    if not changed:
        print("  none")
    # The leader of the all-glider screen (the candidate whose fit there
    # starts every fold's): by linearised gain as built, or by fit.
    led = [(c, screen_leaders(c[4])) for c in cases if not c[3]]
    led = [(c, l) for c, l in led if l is not None]
    print("\nleader of the all-glider screen, by linearised gain (as built) and by fit to all gliders "
          "(results with stored gains):")
    for c, (by_gain, by_fit) in led:
        print("  %s [%s]: by gain %s, by fit %s; verdict %s" % (c[1], c[4].get("bench_commit", "?"), by_gain, by_fit,
                                                               c[4].get("verdict")))
    if led:
        print("  the truth leads: by gain %d of %d, by fit %d of %d" % (
            sum(l[0] in c[2] for c, l in led), len(led), sum(l[1] in c[2] for c, l in led), len(led)))
    else:
        print("  none (no stored result holds the screen's gains)")
    return 0


def plot_exemption(points, path):
    """The exemption's figure: launch rotation's share of the baseline's
    all-glider misfit (x) against the session-wide effect's (y), log-log,
    each run labelled, the true effect filled, with y = DOMINANCE * x."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6.4, 4.8))
    lo, hi = 0.005, 1.0
    ax.plot([lo, hi], [DOMINANCE * lo, DOMINANCE * hi], "k--", lw=1,
            label="%g times launch rotation's share (above: named)" % DOMINANCE)
    ax.plot([lo, hi], [lo, hi], ":", color="0.6", lw=1, label="equal shares")
    for name, eff, (gv, gl), true in points:
        ax.plot(max(gl, lo), gv, "o", ms=7, mfc="C2" if true else "white", mec="C2" if true else "C3")
        ax.annotate("%s (%s)" % (name.replace("launch_rotation", "LR").replace("-1-", " "), eff),
                    (max(gl, lo), gv), textcoords="offset points", xytext=(5, 3), fontsize=7)
    ax.plot([], [], "o", mfc="C2", mec="C2", label="the effect is the truth")
    ax.plot([], [], "o", mfc="white", mec="C3", label="an imitation (truth: launch rotation)")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlim(lo, 0.2)
    ax.set_ylim(lo, hi)
    ax.set_xlabel("launch rotation's share of the baseline's all-glider misfit")
    ax.set_ylabel("the wind's or camera's share")
    ax.set_title("The launch withhold's exemption (blind runs)", fontsize=10)
    ax.legend(fontsize=7, loc="center right")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def upper_bound(k, n, conf=0.95):
    """Clopper-Pearson one-sided upper bound on a binomial rate (bisection on
    the binomial tail; no SciPy needed)."""
    if k >= n:
        return 1.0

    def tail(p):  # P(X <= k | n, p)
        return sum(math.comb(n, i) * p ** i * (1 - p) ** (n - i) for i in range(k + 1))
    lo, hi = 0.0, 1.0
    for _ in range(100):
        mid = (lo + hi) / 2
        if tail(mid) > 1 - conf:
            lo = mid
        else:
            hi = mid
    return hi


if __name__ == "__main__":
    sys.exit(main())
