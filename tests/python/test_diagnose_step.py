"""The diagnosis's simulation step (issue 7, speed).

A diagnosis's cost is proportional to the number of simulation steps, and
its residuals are weighed by the tracking noise; the step is sound only
while the integration error stays far under that noise. This checks the
default step of `pteromys diagnose` (DiagFitOptions::dt) and twice it (the
`--dt` docs/diagnosis.md, *Speed*, measured at the issue's size) against an
independent computation: the same flights by classical Runge-Kutta at
0.5 ms. The flights are the blind benchmark's recording protocol (trimmed
gliders thrown at 1-1.3 times their glide speed, 30-45 points at 30 fps,
1 cm noise), flown with the fitted coefficient model.
"""
import importlib
import inspect
import math
import os

import numpy as np

import pteromys
from conftest import ROOT, bench_module, run

NOISE_M = 0.01  # the blind protocol's tracking noise (what `pteromys track` measures on video)
GLIDERS = ["t01-rectangular", "t03-rectangular-long", "t04-tapered-mild", "t06-swept-15",
           "t09-forward-swept-15", "t11-delta", "t12-elliptic", "t14-straight-trailing-edge", "t17-canard",
           "t19-dart"]


def _dt_error():
    return bench_module("dt_error")


def _rms(e):
    return math.sqrt(float(np.mean(e ** 2)))


def test_the_diagnosis_step_and_twice_it_stay_far_under_the_tracking_noise(tmp_path):
    dt = inspect.signature(pteromys.diagnose).parameters["dt"].default
    diagnosis_fit = importlib.import_module("pteromys.diagnose").diagnosis_fit
    assert dt == inspect.signature(diagnosis_fit).parameters["dt"].default
    gliders = [os.path.join(ROOT, "examples", "training", g + ".glider.json") for g in GLIDERS]
    r = run(["generate"] + gliders + ["-o", tmp_path / "data", "--seed", "5", "--quiet", "--flights-per-glider", "4",
                                      "--frame-rate", "30", "--points", "30-45", "--noise-m", str(NOISE_M),
                                      "--retrim", "2", "--speed-relative", "1:1.3", "--effects", "baseline"])
    assert r.returncode == 0, r.stderr
    model = pteromys.load_model(os.path.join(ROOT, "engine", "models", "fitted.model.json"))
    steps = [dt / 2, dt, 2 * dt]
    errs, worst, n, skipped, noise = _dt_error().step_errors(str(tmp_path / "data" / "dataset.json"), steps,
                                                             ref_dt=0.0005, model=model)
    assert noise == NOISE_M
    assert n == 4 * len(GLIDERS)
    # Most flights are flown to their last tracked point (the others leave
    # the model's range or reach the ground first and are not compared).
    assert n - skipped >= 0.6 * n, (n, skipped)
    for h in (dt, 2 * dt):
        # Under 3 % of the noise in RMS (a thousandth of its variance: nothing
        # a likelihood ratio over a few thousand points resolves) and under a
        # fifth of it at the worst point.
        assert _rms(errs[h]) < 0.03 * NOISE_M, (h, _rms(errs[h]))
        assert worst[h][0] < 0.2 * NOISE_M, (h, worst[h])
        # And it is discretisation error: Verlet is second order, so halving
        # the step divides it by about four.
        ratio = _rms(errs[h]) / _rms(errs[h / 2])
        assert 3.0 < ratio < 5.0, (h, ratio)
