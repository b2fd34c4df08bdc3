"""Aerodynamic coefficients from tracked flights (paper section 5.2).

The engine does the work (``fit.hpp``); these wrappers turn its JSON into
dicts. Datasets are ``dataset.json`` files (spec/formats.md, "Flight
dataset"). Units are SI; angles in degrees where the key ends in ``_deg``.

    import pteromys
    model, report = pteromys.fit("flights/dataset.json", max_centres=10,
                                 progress=lambda p: print(p["message"]))
    model.save("fitted.model.json")
    print(report["fit_rmse_m"], report["centres"])
"""
import json as _json

from . import _core

__all__ = ["fit", "fit_launch", "simulate_track", "predict_flights", "synthetic_dataset"]


def fit(dataset, max_centres=10, model=None, use_prior=True, launch_points=0, fit_pitch_rate=False,
        stop="bic", min_improvement=0.0, rounds=3, iterations=12, candidates=24, robust_m=0.3, regularisation_m=0.01,
        threads=0, dz=0.005, dt=0.002, insertion_tries=1, progress=None):
    """Fit an RBF coefficient model to the flights of a dataset.

    ``model``: an RBF model (or path) to continue from, or a flat-plate model
    used as the prior (default: the built-in flat-plate element).
    ``launch_points``: M of eq. 5 (0 = all points, the default; the paper
    uses 10). ``stop``: "bic" (keep a centre only if it lowers the Bayesian
    information criterion) or "none" (go on to ``max_centres``);
    ``min_improvement``: an extra relative RMSE threshold.
    ``insertion_tries`` (default 1, the greedy rule; experimental): when the
    best-scored centre is not kept while the fit is over twice the tracking
    noise, fit up to this many next-best scored centres in turn before
    stopping (the CLI's ``--insertion-tries``, docs/fitting.md). ``progress(dict)`` is called after every solver iteration with
    keys stage, centres, round, iteration, rmse_m, elapsed_s, message.

    Returns ``(model, report)``: a :class:`pteromys.Model` and the report dict
    (format ``pteromys-fit/1``: fit_rmse_m, centres, flights, history, ...).
    The engine runs without the GIL; ``progress`` is called with it.
    """
    opts = dict(max_centres=max_centres, launch_points=launch_points, fit_pitch_rate=bool(fit_pitch_rate),
                stop=str(stop), min_improvement=min_improvement, rounds=rounds, iterations=iterations, candidates=candidates,
                robust_m=robust_m, regularisation_m=regularisation_m, threads=threads, dz=dz, dt=dt,
                use_prior=bool(use_prior), model=model, insertion_tries=insertion_tries)
    m, text = _core._fit(str(dataset), opts, progress)
    return m, _json.loads(text)


def fit_launch(glider, t, x, y, model=None, points=10, fit_pitch_rate=False, ballistic=False, dz=0.005, dt=0.002):
    """Launch parameters (eq. 5) of one tracked flight: the state at its first point.

    ``t, x, y``: tracked times [s] and centre-of-gravity positions [m] (world
    frame, x along the flight). ``points``: fit to the first M points (0 =
    all). ``ballistic``: no air (the pitch is not fitted). Returns a dict
    t_s, x_m, y_m, speed_m_s, climb_deg (upward), pitch_deg, pitch_rate_deg_s,
    rmse_m (over the fitted points), evaluations.
    """
    return _json.loads(_core._fit_launch(glider, t, x, y, model, points, fit_pitch_rate, ballistic, dz, dt))


def simulate_track(glider, launch, times, model=None, ballistic=False, dz=0.005, dt=0.002):
    """Simulated centre-of-gravity positions at ``times`` [s] of a flight with
    state ``launch`` (a dict as returned by :func:`fit_launch`) at launch['t_s'].

    Returns a dict with ``positions`` (an (n, 2) array [m]), ``max_alpha_deg``
    and ``left_model_range``. The ground is ignored (as in fitting).
    """
    return _core._simulate_track(glider, dict(launch), times, model, ballistic, dz, dt)


def predict_flights(dataset, model=None, ballistic=False, launch_points=10, threads=0):
    """How well a model predicts the flights of a dataset (paper Fig. 13).

    Each flight's launch is fitted to its first ``launch_points`` points
    (0 = all) and the whole flight simulated. Returns one dict per flight:
    flight, glider, t, tracked (n, 2), simulated (n, 2), rmse_m,
    rmse_after_m (points after the first M), launch_points, max_alpha_deg,
    left_model_range, launch.
    """
    return list(_core._predict_flights(str(dataset), model, bool(ballistic), float(launch_points), float(threads)))


def synthetic_dataset(gliders, out_dir, model=None, **options):
    """Write a dataset of flights simulated with a known model (for tests).

    ``gliders``: {key: glider (object, dict or path)}. ``options``:
    flights_per_glider, speed_min/max [m/s], climb_min/max_deg,
    alpha_min/max_deg (release pitch minus path), points_min/max,
    frame_rate_hz, delay_max_s, noise_m (per axis), height, seed. The true
    release state is in the extra columns release_*. Returns the path of
    the dataset.json written in ``out_dir``.
    """
    known = {"flights_per_glider", "speed_min", "speed_max", "climb_min_deg", "climb_max_deg", "alpha_min_deg",
             "alpha_max_deg", "points_min", "points_max", "frame_rate_hz", "delay_max_s", "noise_m", "height", "seed"}
    unknown = sorted(set(options) - known)
    if unknown:  # a misspelt option would otherwise be dropped and its default used
        raise _core.InputError("synthetic_dataset: unknown option(s) %s; known: %s" % (", ".join(unknown),
                                                                                      ", ".join(sorted(known))))
    return _core._synthetic_dataset(dict(gliders), str(out_dir), model, options)
