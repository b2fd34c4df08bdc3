#!/usr/bin/env python3
"""Integration error of the diagnosis's flight simulation against its time step.

The diagnosis simulates every tracked flight thousands of times (velocity
Verlet, one force evaluation a step), so its cost is proportional to the
number of steps. This measures what a larger step costs in accuracy: every
flight of a dataset is flown from its true launch (the dataset's
``true_*`` columns) with the wing-element model and the glider files of the
dataset, by Verlet at each step asked for, and by classical Runge-Kutta at
``--ref-dt`` (0.5 ms) as the reference; the position error at the tracked
times is compared with the dataset's tracking noise.

    PYTHONPATH=build/python /usr/bin/python3 bench/diagnosis/dt_error.py DATASET.json [--dt 0.002,0.004,0.005]
"""
import argparse
import csv
import json
import math
import os
import sys

import numpy as np

import pteromys as pt


def step_errors(dataset, steps, ref_dt=0.0005, model=None):
    """Position errors [m] at the tracked times of every flight of `dataset`
    flown from its true launch by Verlet at each step of `steps`, against
    Runge-Kutta at `ref_dt`. Returns (errors: {dt: array}, worst: {dt: (m,
    flight)}, flights, flights not counted, tracking noise or None)."""
    with open(dataset) as f:
        ds = json.load(f)
    base = os.path.dirname(os.path.abspath(dataset))
    gliders = {k: pt.load_glider(os.path.join(base, v)) for k, v in ds["gliders"].items()}
    flights = {}
    with open(os.path.join(base, ds.get("flights_csv", "flights.csv"))) as f:
        for r in csv.DictReader(f):
            flights.setdefault(r["flight"], []).append(r)
    gen = {}
    gpath = os.path.join(base, "generation.json")
    if os.path.exists(gpath):
        with open(gpath) as f:
            gen = json.load(f)
    noise = (gen.get("camera") or {}).get("noise_sigma_m")
    errs = {dt: [] for dt in steps}
    worst = {dt: (0.0, "") for dt in steps}
    skipped = 0
    for name, rows in sorted(flights.items()):
        r0 = rows[0]
        g = gliders[r0["glider"]]
        t_rel = np.array([float(r["t_s"]) for r in rows]) - float(r0["true_release_t_s"])
        kw = dict(speed=float(r0["true_speed_m_s"]), climb_deg=float(r0["true_climb_deg"]),
                  pitch_deg=float(r0["true_pitch_deg"]), pitch_rate_deg_s=float(r0["true_pitch_rate_deg_s"]),
                  height=float(r0["true_height_m"]), model=model, t_max=float(t_rel[-1]) + 0.05)

        def flown(dt, integrator):
            fl = pt.simulate(g, dt=dt, integrator=integrator, **kw)
            s = np.asarray(fl["samples"])
            if s[-1, 0] < t_rel[-1]:
                return None  # ended (ground, range) before the last tracked point
            return np.c_[np.interp(t_rel, s[:, 0], s[:, 1]), np.interp(t_rel, s[:, 0], s[:, 2])]

        ref = flown(ref_dt, "rk4")
        verlet = {dt: flown(dt, "verlet") for dt in steps} if ref is not None else {}
        if ref is None or any(p is None for p in verlet.values()):
            skipped += 1
            continue
        for dt in steps:
            e = np.hypot(*(verlet[dt] - ref).T)
            errs[dt].extend(e.tolist())
            if e.max() > worst[dt][0]:
                worst[dt] = (float(e.max()), name)
    return {dt: np.array(v) for dt, v in errs.items()}, worst, len(flights), skipped, noise


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("dataset")
    ap.add_argument("--dt", default="0.002,0.004,0.005", help="Verlet steps to measure [s]")
    ap.add_argument("--ref-dt", type=float, default=0.0005, help="Runge-Kutta reference step [s]")
    ap.add_argument("--model", default=None, help="coefficient model (default: the shipped one)")
    args = ap.parse_args()
    if not os.path.isfile(args.dataset):
        sys.exit("dt_error.py: no dataset at %s" % args.dataset)
    try:
        steps = [float(s) for s in args.dt.split(",") if s.strip()]
    except ValueError:
        sys.exit("dt_error.py: --dt must be a comma-separated list of steps in seconds, got %r" % args.dt)
    if not steps or not all(0 < h <= 0.05 for h in steps + [args.ref_dt]):
        sys.exit("dt_error.py: every step (--dt, --ref-dt) must lie in (0, 0.05] s")
    model = pt.load_model(args.model) if args.model else None
    errs, worst, n, skipped, noise = step_errors(args.dataset, steps, args.ref_dt, model)
    print("%s: %d flights, Verlet against Runge-Kutta at %g s (flights the model flies into the ground or out of "
          "its range before their last tracked point: %d, not counted)" % (args.dataset, n, args.ref_dt, skipped))
    if noise:
        print("tracking noise of the dataset: %.1f mm" % (noise * 1000))
    print("| Verlet step | points | RMS error | 99th percentile | largest (flight) |")
    print("|---|---|---|---|---|")
    for dt in steps:
        e = errs[dt]
        if not len(e):
            print("| %g s | 0 | | | |" % dt)
            continue
        print("| %g s | %d | %.3f mm | %.3f mm | %.3f mm (%s) |" % (
            dt, len(e), 1000 * math.sqrt(float(np.mean(e ** 2))), 1000 * float(np.percentile(e, 99)),
            1000 * worst[dt][0], worst[dt][1]))


if __name__ == "__main__":
    sys.exit(main())
