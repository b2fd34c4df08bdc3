"""Sim-to-real gap diagnosis (issue 7; docs/diagnosis.md).

The engine does the work (``diagnose.hpp``, ``effects.hpp``); these wrappers
turn its JSON into dicts. A dataset is a ``dataset.json`` file (spec/formats.md,
"Flight dataset"); the result has the format ``pteromys-diagnosis/1``
(spec/formats.md, "Diagnosis result").

    import pteromys
    result = pteromys.diagnose("flights/dataset.json", progress=lambda p: print(p["message"]))
    print(result["verdict"], result["effects"][0])
    pteromys.diagnosis_report(result, "report_dir")     # index.html with plots
"""
import json as _json

from . import _core

__all__ = ["diagnose", "diagnosis_report", "effect_library", "glider_features", "effect_wrench", "diagnosis_fit",
           "chi2_sf", "chi2_isf", "report_dir_problem"]


def report_dir_problem(path):
    """Why directory ``path`` may not be replaced by a diagnosis report, or
    "" when it may: it does not exist, is empty, or is an earlier report
    (index.html with only report.md, diagnosis.json and PNG plots beside it).
    A report replaces the whole directory, so anything else in it (a
    person's files, the dataset itself) would be lost."""
    return _core.report_dir_problem(str(path))


def diagnose(dataset, folds=4, effects=None, trim=True, model=None, alpha=0.01, min_shrink=0.05,
             holdout_chi2_test=True, none_tolerance=0.3, collinearity_limit=0.95, max_centres=10, polish=0,
             insertion_tries=1, full_fit=True, iterations=8, ground_y=0.0, dt=0.002, dz=0.005, launch_window_s=0.25,
             near_ground_m=0.3, worst_flights=6, launch_rotation="per-flight", second_effect=True, profile=True,
             profile_min_gliders=6, profiled_candidates=3, glider_guard=True, bound_guard=True,
             launch_withhold=True, launch_rates_confirm=True, launch_withhold_dominance=5.0,
             heldout_steps=True, heldout_fold_start=True, zeroed_reference=True, escalate=False,
             prefer_identifiable=False, step_alpha=1.0, carry_steps=True, leader_start=True, leader_reached=0.5,
             theory_starts=False,
             hold_theory=False, step_per_flight=False, refit_unstepped=True, oracle=None, plausible=None, threads=0,
             stability=0, first=None, progress=None):
    """Diagnose the gap between the wing-element model and the tracked flights of ``dataset``.

    ``effects``: candidate names, a list or one comma-separated string (default: the whole library,
    ``effect_library()``).
    ``model``: an RBF model (or path) the coefficient fits start from, or a
    flat-plate model used as their prior. ``folds``: leave-gliders-out folds.
    ``dt``, ``dz``: simulation step [s] and wing-element spacing [m], as the
    command's --dt and --dz.
    ``alpha``: family-wise level of the likelihood-ratio tests (Holm).
    ``launch_rotation``: "per-flight" (each flight's own pitch rate at its
    first point is fitted) or "common" (one rate for the session).
    ``second_effect``: when an effect is the verdict, test every other one
    added to it (result keys ``also``, ``alternatives``, ``replaced``).
    ``profile`` (default True): without polish, also refit the candidates whose
    linearised gain with the RBF centre values re-tuned passes the test from
    that step, jointly with the centre values (docs/diagnosis.md, "Profiled
    starts"); False is faster and finds only what fixed coefficients show.
    ``profile_min_gliders``: profiled starts only in fits to at least this many
    gliders (all gliders, a fold's training gliders); fewer overfit them.
    ``profiled_candidates`` (default 3): at most this many candidates per fit,
    the largest linearised gains first, are refitted from their step (each
    costs about a fixed-coefficient fit); a verdict's effect not among them on
    all gliders is refitted from its step there for its reported strength.
    ``glider_guard`` (default True): an effect whose held-out shrink falls
    below ``min_shrink`` with one held-out glider left out and that improves
    fewer than three quarters of the held-out gliders is not significant.
    ``bound_guard`` (default True): an effect more than half of whose
    held-out gain comes from folds whose fit ran to the outer tenth of its
    range is not significant.
    ``launch_withhold`` (default True): a wind or camera verdict beside a
    launch rotation that fits the training flights (its rates turning one
    way) but is not significant is withheld: the verdict is "unexplained"
    and result key ``withheld`` names the effect; when launch rotation is
    significant it is the verdict instead.
    ``launch_withhold_dominance`` (default 5.0): such a verdict is not
    withheld when its fit to all gliders closes more than this many times
    the share of the baseline's misfit that launch rotation's closes (a
    launch habit, fitted flight by flight, would explain the training
    flights about as well as its imitation); 0 always withholds.
    ``launch_rates_confirm`` (default True): per-flight launch rotation is
    confirmed by its held-out rates sharing a direction, with any held-out
    shrink above zero, rather than held to ``min_shrink``.
    ``heldout_steps`` (default True): a candidate the held-out gliders
    confirm but whose gain on all gliders was under the screen is refitted
    from its linearised step there before its likelihood-ratio test.
    ``zeroed_reference`` (default True): the likelihood ratios' reference
    also considers each candidate's fit to all gliders with its values set
    to 0 and the launches refitted (a baseline-model fit), not only those
    fitted exactly at 0.
    ``escalate`` (default False): when the first search leaves a real gap
    unexplained, search again with every aerodynamic correction also
    started at its theoretical size (several times slower).
    ``prefer_identifiable`` (default False, experimental): when the best
    significant effect is indistinguishable from re-tuned coefficients and a
    significant one that is not predicts the held-out gliders not
    significantly worse (paired over gliders), the verdict names the latter
    (result key ``passed_over``).
    ``step_alpha``, ``carry_steps``, ``leader_start``, ``leader_reached``, ``heldout_fold_start``, ``theory_starts``,
    ``hold_theory``, ``insertion_tries``,
    ``step_per_flight``, ``refit_unstepped``, ``oracle`` (e.g.
    ``"finite_span=1"``) and ``plausible`` (e.g. ``"camera=0.05:3"``) are
    the CLI's ``--step-alpha``, ``--carry-steps``/``--no-carry-steps``, ``--no-leader-start``,
    ``--leader-reached``, ``--no-heldout-fold-start``,
    ``--theory-starts``, ``--hold-theory``, ``--insertion-tries``, ``--step-per-flight``,
    ``--no-unstepped-refit``, ``--oracle`` and ``--plausible``
    (docs/diagnosis.md, *Using it* for ``oracle`` and ``plausible``,
    *The search's parts and their switches* for the rest).
    ``stability`` (default 0: none): run the diagnosis this many times in
    all (2 to 7), the re-runs with the simulation step changed by 5 %,
    10 %, ... either way, and report whether the verdict stayed the same
    (result key ``stability``, its sentence appended to ``summary``; the
    verdict is the first run's); the CLI's ``--stability``.
    ``first`` (with ``stability``): a result of this ``dataset`` made
    before with the same options (the dict this function returned); it
    stands for the first run, so only the re-runs are made, and it is
    returned with its stability check added (what the FreeCAD command
    does when asked to check a verdict after the diagnosis). With
    ``theory_starts`` instead: the `unexplained` result of a first search
    (made without theoretical-size starts) that this second search
    follows; the second search is then concluded as ``escalate``
    concludes its own (what the FreeCAD command does when asked to search
    again): its result, with ``escalation`` recording the first search,
    unless the effect it names predicts the held-out gliders less than
    ``min_shrink`` better than the first search's baseline, in which case
    ``first`` is returned (`unexplained`), its ``escalation`` saying what
    the second search found (``demoted``) and its summary why.
    ``progress(dict)`` gets keys stage, step, steps, elapsed_s, message.
    The engine runs without the GIL. Returns the result dict
    (format ``pteromys-diagnosis/1``: baseline, effects sorted best first,
    verdict, summary, where, ...).
    """
    if isinstance(effects, str):  # "wind,camera", as the CLI's --effects
        effects = [e.strip() for e in effects.split(",") if e.strip()]
    # the engine's own conversion names no parameter ("Unable to cast Python
    # instance"): say which one and what it takes
    if effects is not None and (not hasattr(effects, "__iter__") or
                                not all(isinstance(e, str) for e in effects)):
        raise _core.InputError("effects must be effect names (strings such as \"wind\") or one comma-separated "
                               "string, not %r" % (effects,))
    for name, v, example in (("oracle", oracle, "finite_span=1"), ("plausible", plausible, "camera=0.05:3")):
        if v is not None and not isinstance(v, str):
            raise _core.InputError("%s must be a string such as \"%s\", not %s" % (name, example, type(v).__name__))
    opts = dict(folds=folds, effects=list(effects) if effects is not None else None, trim=bool(trim), model=model,
                alpha=alpha, min_shrink=min_shrink, holdout_chi2_test=bool(holdout_chi2_test),
                none_tolerance=none_tolerance, collinearity_limit=collinearity_limit, max_centres=max_centres,
                insertion_tries=insertion_tries,
                polish=polish, full_fit=bool(full_fit), iterations=iterations, ground_y=ground_y, dt=dt, dz=dz,
                launch_window_s=launch_window_s, near_ground_m=near_ground_m, worst_flights=worst_flights,
                launch_rotation=str(launch_rotation), second_effect=bool(second_effect), profile=bool(profile),
                profile_min_gliders=profile_min_gliders, profiled_candidates=profiled_candidates,
                glider_guard=bool(glider_guard), bound_guard=bool(bound_guard),
                launch_withhold=bool(launch_withhold), launch_rates_confirm=bool(launch_rates_confirm),
                launch_withhold_dominance=float(launch_withhold_dominance),
                heldout_steps=bool(heldout_steps), heldout_fold_start=bool(heldout_fold_start),
                zeroed_reference=bool(zeroed_reference),
                escalate=bool(escalate),
                prefer_identifiable=bool(prefer_identifiable), step_alpha=step_alpha, carry_steps=bool(carry_steps),
                leader_start=bool(leader_start), leader_reached=float(leader_reached),
                theory_starts=bool(theory_starts), hold_theory=bool(hold_theory),
                step_per_flight=bool(step_per_flight), refit_unstepped=bool(refit_unstepped), oracle=oracle,
                plausible=plausible, threads=threads, stability=stability)
    if first is not None:
        opts["first"] = _json.dumps(first)
    return _json.loads(_core._diagnose(str(dataset), opts, progress))


def diagnosis_report(result, directory, quiet=True):
    """Write the readable report (``index.html``, ``report.md`` and PNG plots)
    of a diagnosis result (dict or path of its JSON) into ``directory``.
    Returns the path of index.html."""
    from . import diagnose_report
    if not isinstance(result, dict):
        with open(result) as f:
            result = _json.load(f)
    return diagnose_report.render(result, str(directory), quiet=quiet)


def effect_library():
    """The candidate effects: list of dicts name, description, level, parameters."""
    return _json.loads(_core._effect_specs())


def glider_features(glider, dz=0.005):
    """Geometry features of a glider as the diagnosis uses them (dict)."""
    return _json.loads(_core._glider_features(glider, dz))


def effect_wrench(glider, values, state=None, model=None, height_origin=0.0, dz=0.005):
    """Forces of the baseline model corrected by effects ``values`` (dict
    ``{"pitch_damping": 1.0, "camera": [scale_error, roll_deg], ...}``) in a
    flight ``state`` (dict x_m, y_m, vx_m_s, vy_m_s, pitch_deg, pitch_rate_deg_s)."""
    return _core._effect_wrench(glider, model, dict(values), dict(state or {}), height_origin, dz)


def diagnosis_fit(dataset, values=None, free=(), model=None, flights=None, warm_baseline=True, dt=0.002,
                  iterations=8, threads=0):
    """Fit launches and the ``free`` parameters (effect names, "trim",
    "coefficients") of a corrected model to a dataset's flights; a dict with
    sse_m2, rmse_m, effects, trim_deg, flights, model."""
    return _core._diagnosis_fit(str(dataset), model, dict(values or {}), list(free), flights, warm_baseline, dt,
                                iterations, threads)


def chi2_sf(x, k):
    """Upper tail probability of the chi-square distribution with k degrees of freedom."""
    return _core._chi2_sf(x, k)


def chi2_isf(p, k):
    """Chi-square quantile: x with chi2_sf(x, k) = p."""
    return _core._chi2_isf(p, k)
