#!/usr/bin/env python3
"""The paper's fitting experiment (section 5, Fig. 11 and 13) on reference data.

    PYTHONPATH=build/python /usr/bin/python3 bench/fit/run_experiment.py [--build build] [--out out/fit] [--ship]

1. Flights: `pteromys generate` (the reference simulator, every aerodynamic
   effect on) flies the 20 training gliders of examples/training, 6 hand
   launches each (5-9 m/s, 0-10 deg up, from 1.5 m), tracked at 30 fps from
   release for 15-20 frames with +-5 cm noise (seed 1); the 4 held-out gliders
   of examples/heldout likewise (seed 2). The same launches are also recorded
   with 0.1 mm noise ("exact"), to show the model error without the noise.
2. Fits (`pteromys fit`): the default (greedy; a centre is kept while it
   lowers the Bayesian information criterion), the same run to 10 centres
   (the paper's count), the exact data to 10 centres, and the paper's scheme
   (launches fitted to the first 10 points, alternated with the coefficients).
3. Held-out flights: each model's launch is fitted to the first 10 points and
   the rest predicted (the paper's protocol), and to all points; against the
   empirical flat-plate element and ballistic motion.
4. Plots in docs/img/fit_*.png, numbers in OUT/summary.json (docs/fitting.md
   quotes them). With --ship the default fit is written to
   engine/models/fitted.model.json with its provenance.

Progress of each step goes to stderr; the whole run takes a few minutes.
"""
import argparse
import json
import math
import os
import shutil
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

try:
    import pteromys  # noqa: E402
except ImportError:  # pragma: no cover
    sys.exit("run_experiment.py needs the pteromys module: PYTHONPATH=build/python /usr/bin/python3 " + __file__)

GENERATE = ["--flights-per-glider", "6", "--speed", "5:9", "--climb", "0:10", "--frame-rate", "30",
            "--points", "15-20"]
NOISE = 0.05
EXACT = 0.0001


def log(msg):
    print(f"[experiment {time.strftime('%H:%M:%S')}] {msg}", file=sys.stderr, flush=True)


def git(*args):
    try:
        return subprocess.run(["git", "-C", ROOT] + list(args), capture_output=True, text=True, check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "unknown"


def run(cmd):
    log(" ".join(cmd))
    t = time.time()
    r = subprocess.run(cmd, stderr=subprocess.PIPE, text=True)
    if r.returncode != 0:
        sys.exit(f"failed ({r.returncode}): {' '.join(cmd)}\n{r.stderr}")
    lines = [ln for ln in r.stderr.splitlines() if "iteration" not in ln]
    for ln in lines[-6:]:
        log("  " + ln)
    return time.time() - t


def load(p):
    with open(p) as f:
        return json.load(f)


def glider_planform_plot(out_png):
    """Top views of the main wings (and tails) of every training and held-out glider."""
    paths = sorted(os.listdir(os.path.join(ROOT, "examples", "training")))
    paths = [os.path.join(ROOT, "examples", "training", p) for p in paths if p.endswith(".glider.json")]
    held = sorted(os.listdir(os.path.join(ROOT, "examples", "heldout")))
    paths += [os.path.join(ROOT, "examples", "heldout", p) for p in held if p.endswith(".glider.json")]
    n = len(paths)
    cols = 8
    rows = math.ceil(n / cols)
    fig, axes = plt.subplots(rows, cols, figsize=(2.0 * cols, 2.2 * rows), dpi=100)
    for ax, p in zip(axes.flat, paths):
        g = load(p)
        for w, c in zip(g["wings"], ("#1f77b4", "#ff7f0e", "#2ca02c")):
            o = np.array(w["outline_m"] + [w["outline_m"][0]])
            ax.fill(o[:, 1], o[:, 0] + w["mount"]["x_m"], color=c, alpha=0.6, lw=0.8)
        f = np.array(g["fuselage"]["outline_m"])
        ax.plot([0, 0], [f[:, 0].min(), f[:, 0].max()], color="k", lw=1.2)
        ax.set_aspect("equal")
        ax.set_xlim(-0.32, 0.32)
        ax.set_ylim(-0.45, 0.02)
        ax.set_xticks([])
        ax.set_yticks([])
        held_out = "heldout" in p
        ax.set_title(g["name"], fontsize=7, color="#b00" if held_out else "k")
    for ax in list(axes.flat)[n:]:
        ax.axis("off")
    fig.suptitle("Fitting experiment gliders: 20 training (black titles), 4 held out (red); top views, nose up",
                 fontsize=10)
    fig.tight_layout()
    fig.savefig(out_png)
    plt.close(fig)


def noise_floor(rep):
    """Expected RMS distance of the noise alone once every launch is fitted:
    sigma^2 (n - p) / points, n = 2 x points residuals, p = 5 per flight."""
    n = 2 * rep["points"]
    p = 5 * rep["flights"]
    return NOISE * math.sqrt((n - p) / rep["points"])


def error_vs_centres_plot(runs, out_png):
    fig, axes = plt.subplots(1, 2, figsize=(12.5, 4.4), dpi=110)
    styles = {"default": ("o-", "#d62728", 2.2), "all10": ("s--", "#ff9896", 1.2), "exact": ("^-", "#1f77b4", 1.6),
              "paper": ("d:", "#7f7f7f", 1.2)}
    panels = {"exact": 0, "all10": 1, "paper": 1, "default": 1}
    for key in ("all10", "paper", "default", "exact"):
        label, rep = runs[key]
        ax = axes[panels[key]]
        x = [h["centres"] for h in rep["history"]]
        y = [100 * h["rmse_m"] for h in rep["history"]]
        m, c, lw = styles[key]
        ax.plot(x, y, m, color=c, label=label, ms=5, lw=lw)
        for h in rep["history"]:
            if not h["accepted"]:
                ax.plot([h["centres"]], [100 * h["rmse_m"]], "x", color="k", ms=10, mew=2)
    floor = 100 * noise_floor(runs["default"][1])
    axes[1].axhline(floor, color="k", lw=0.8, ls="--", label=f"noise alone after the launch fits ({floor:.2f} cm)")
    axes[0].set_title("Model error alone: flights tracked with 0.1 mm noise", fontsize=10)
    axes[1].set_title("The paper's setting: +-5 cm tracking noise", fontsize=10)
    for ax in axes:
        ax.set_xlabel("RBF centres (0 = the flat-plate prior alone, launches fitted)")
        ax.set_ylabel("RMS distance, tracked to simulated [cm]")
        ax.grid(alpha=0.3)
        ax.set_xlim(-0.3, 10.5)
        ax.legend(fontsize=7.5)
    axes[0].set_ylim(0, None)
    fig.suptitle("Fitting error against the number of centres (paper Fig. 11a): 120 reference flights of 20 "
                 "training gliders; x = centre dropped by the stopping rule (BIC)", fontsize=10)
    fig.tight_layout()
    fig.savefig(out_png)
    plt.close(fig)


def coefficient_plot(model_paths, out_png, ref_outline):
    alpha = np.linspace(0, 30, 121)
    fig, axes = plt.subplots(1, 3, figsize=(13, 4.0), dpi=110)
    flat = pteromys.flat_plate_model()
    curves = [("empirical flat-plate element", flat, "#2ca02c", "-")]
    for label, p, c, ls in model_paths:
        curves.append((label, pteromys.load_model(p), c, ls))
    for re, lw in ((1.0e4, 1.0), (2.5e4, 2.0)):
        for label, m, c, ls in curves:
            cd, cl, cm = m.eval(alpha, re, 0.0, 0.0)
            lab = f"{label}, Re {re:.3g}" if lw == 2.0 else None
            axes[0].plot(alpha, cl, ls, color=c, lw=lw, label=lab)
            axes[1].plot(alpha, cd, ls, color=c, lw=lw)
            axes[2].plot(alpha, cm, ls, color=c, lw=lw)
    # The reference simulator's polar of a whole rectangular wing (t01's main
    # wing, aspect ratio 6.7) as the "wind tunnel" of this experiment.
    cl, cd, cm = pteromys.reference_polar(np.array(ref_outline), alpha, reynolds=2.5e4)
    axes[0].plot(alpha, cl, "k:", lw=1.5, label="reference simulator: rectangular wing AR 6.7, Re 2.5e4")
    axes[1].plot(alpha, cd, "k:", lw=1.5)
    for ax, name in zip(axes, ("lift coefficient $c_l$", "drag coefficient $c_d$", "moment coefficient $c_m$ (1/4 chord)")):
        ax.set_xlabel("angle of attack [deg]")
        ax.set_title(name, fontsize=10)
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=7, loc="lower right")
    fig.suptitle("Coefficients of a rectangular wing element ($\\xi_l = \\xi_t = 0$): fitted RBF model against the "
                 "empirical flat-plate element (paper Fig. 11b); thin lines Re 1e4, thick 2.5e4", fontsize=10)
    fig.tight_layout()
    fig.savefig(out_png)
    plt.close(fig)


def prediction_sets(dataset, models, points):
    out = {}
    for key, m in models.items():
        if m == "ballistic":
            out[key] = pteromys.predict_flights(dataset, ballistic=True, launch_points=points)
        else:
            out[key] = pteromys.predict_flights(dataset, model=m, launch_points=points)
    return out


def rmse(preds, after=False):
    s, n = 0.0, 0
    for p in preds:
        d = p["simulated"] - p["tracked"]
        k = p["launch_points"] if after else 0
        s += float((d[k:] ** 2).sum())
        n += len(d) - k
    return math.sqrt(s / n) if n else 0.0


def by_glider(preds, after=False):
    g = {}
    for p in preds:
        g.setdefault(p["glider"], []).append(p)
    return {k: rmse(v, after) for k, v in sorted(g.items())}


def trajectory_plot(sets, out_png, title, pick=0):
    gliders = sorted({p["glider"] for p in sets["fitted"]})
    fig, axes = plt.subplots(1, len(gliders), figsize=(4.2 * len(gliders), 3.6), dpi=110)
    axes = np.atleast_1d(axes)
    colours = {"fitted": ("#d62728", "fitted RBF model"), "flat_plate": ("#2ca02c", "empirical flat-plate element"),
               "ballistic": ("#7f7f7f", "ballistic (no air)")}
    for ax, g in zip(axes, gliders):
        flights = [i for i, p in enumerate(sets["fitted"]) if p["glider"] == g]
        i = flights[min(pick, len(flights) - 1)]
        tr = sets["fitted"][i]["tracked"]
        m = sets["fitted"][i]["launch_points"]
        if m == 0:
            ax.plot(tr[:, 0], tr[:, 1], "o", color="#1f77b4", ms=4, label="tracked (launch fitted to all)")
        else:
            ax.plot(tr[:m, 0], tr[:m, 1], "o", color="#1f77b4", ms=4, mfc="none", label="tracked (launch fitted here)")
            ax.plot(tr[m:, 0], tr[m:, 1], "o", color="#1f77b4", ms=4, label="tracked (predicted)")
        for key, (c, lab) in colours.items():
            p = sets[key][i]
            ax.plot(p["simulated"][:, 0], p["simulated"][:, 1], "-", color=c, lw=1.6,
                    label=f"{lab}: {100 * p['rmse_m']:.1f} cm")
        ax.set_title(f"{g} ({sets['fitted'][i]['flight']})", fontsize=9)
        ax.set_xlabel("x [m]")
        ax.set_ylabel("y [m]")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=6.5, loc="lower left")
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    fig.savefig(out_png)
    plt.close(fig)


def heldout_bar_plot(tables, out_png):
    fig, axes = plt.subplots(1, len(tables), figsize=(6.2 * len(tables), 3.8), dpi=110)
    axes = np.atleast_1d(axes)
    colours = {"fitted": "#d62728", "flat_plate": "#2ca02c", "ballistic": "#7f7f7f"}
    for ax, (title, table) in zip(axes, tables):
        gliders = list(table["fitted"].keys())
        x = np.arange(len(gliders))
        for j, key in enumerate(("fitted", "flat_plate", "ballistic")):
            v = [100 * table[key][g] for g in gliders]
            ax.bar(x + (j - 1) * 0.27, v, 0.27, color=colours[key], label=key.replace("_", " "))
        ax.set_xticks(x)
        ax.set_xticklabels(gliders, fontsize=8)
        ax.set_ylabel("RMS error after the first 10 points [cm]")
        ax.set_yscale("log")
        ax.set_title(title, fontsize=9)
        ax.grid(alpha=0.3, axis="y")
        ax.legend(fontsize=8)
    fig.suptitle("Held-out gliders (not in training): prediction error of the flight after the launch fit "
                 "(paper Fig. 13)", fontsize=10)
    fig.tight_layout()
    fig.savefig(out_png)
    plt.close(fig)


def whole_flights(model_path):
    """The six standard launches of every training and held-out glider flown
    to the ground by the reference simulator (every aerodynamic effect), the
    flat-plate element and the fitted model: distances and stability."""
    rows = []
    for folder in ("training", "heldout"):
        d = os.path.join(ROOT, "examples", folder)
        for name in sorted(os.listdir(d)):
            if not name.endswith(".glider.json"):
                continue
            g = os.path.join(d, name)
            for v in (7.0, 9.0, 11.0):
                for a in (0.0, 10.0):
                    ref = pteromys.reference_simulate(g, v, a, 1.5, effects="physics", record_every=50)
                    flat = pteromys.simulate(g, v, a, 1.5, model=pteromys.flat_plate_model(), record_every=50)
                    fit = pteromys.simulate(g, v, a, 1.5, model=model_path, record_every=50)
                    rows.append({"glider": name[:-12], "set": folder, "speed": v, "climb": a,
                                 "reference": (ref["distance_m"], ref["stable"]),
                                 "flat_plate": (flat["distance_m"], flat["stable"]),
                                 "fitted": (fit["distance_m"], fit["stable"])})
    out = {}
    for key in ("flat_plate", "fitted"):
        both = [r for r in rows if r["reference"][1] and r[key][1]]
        err = [abs(r[key][0] - r["reference"][0]) for r in both]
        out[key] = {"launches": len(rows), "stable_in_reference": sum(r["reference"][1] for r in rows),
                    "stable_in_model": sum(r[key][1] for r in rows),
                    "stability_disagrees": sum(r[key][1] != r["reference"][1] for r in rows),
                    "mean_abs_distance_error_m": float(np.mean(err)) if err else None,
                    "median_abs_distance_error_m": float(np.median(err)) if err else None}
    return rows, out


def distance_plot(rows, out_png):
    fig, axes = plt.subplots(1, 2, figsize=(10, 4.4), dpi=110, sharey=True)
    for ax, key, c in zip(axes, ("flat_plate", "fitted"), ("#2ca02c", "#d62728")):
        for r in rows:
            ok = r[key][1] and r["reference"][1]
            ax.plot(r["reference"][0], r[key][0], "o" if ok else "x", color=c if ok else "k", ms=4,
                    mfc=c if r["set"] == "training" else "none")
        lim = max(max(r["reference"][0], r[key][0]) for r in rows) * 1.05
        ax.plot([0, lim], [0, lim], "k-", lw=0.6)
        ax.set_xlabel("distance in the reference simulator [m]")
        ax.set_title(("empirical flat-plate element" if key == "flat_plate" else "fitted model (shipped)") +
                     "\nfilled: training, open: held out, x: unstable in one of the two", fontsize=9)
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("distance predicted [m]")
    fig.suptitle("Whole flights: the six standard launches of the 24 gliders flown to the ground", fontsize=10)
    fig.tight_layout()
    fig.savefig(out_png)
    plt.close(fig)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "fit"))
    ap.add_argument("--img", default=os.path.join(ROOT, "docs", "img"))
    ap.add_argument("--ship", action="store_true", help="write engine/models/fitted.model.json")
    ap.add_argument("--threads", default="2")
    a = ap.parse_args()
    exe = os.path.join(a.build, "bin", "pteromys")
    if not os.path.exists(exe):
        sys.exit(f"pteromys not built at {exe}")
    os.makedirs(a.out, exist_ok=True)
    os.makedirs(a.img, exist_ok=True)
    summary = {"commit": git("rev-parse", "--short", "HEAD"), "dirty": bool(git("status", "--porcelain", "--",
                                                                               "engine", "examples")),
               "noise_m": NOISE}
    t0 = time.time()

    # 1. Flights.
    data = {}
    for name, folder, seed, noise, per in (("train", "training", 1, NOISE, 6), ("heldout", "heldout", 2, NOISE, 6),
                                           ("train_exact", "training", 1, EXACT, 6),
                                           ("heldout_exact", "heldout", 2, EXACT, 6),
                                           ("more", "training", 11, NOISE, 24)):
        d = os.path.join(a.out, name)
        if os.path.exists(d):
            shutil.rmtree(d)
        cmd = [exe, "generate", os.path.join(ROOT, "examples", folder), "-o", d, "--seed", str(seed),
               "--noise-m", str(noise), "--threads", a.threads] + GENERATE
        cmd[cmd.index("--flights-per-glider") + 1] = str(per)
        summary.setdefault("generate_s", {})[name] = run(cmd)
        data[name] = os.path.join(d, "dataset.json")
        summary.setdefault("generate_commands", {})[name] = "pteromys " + " ".join(cmd[1:]).replace(ROOT + "/", "")
    ds = load(data["train"])
    flights = {}
    with open(os.path.join(os.path.dirname(data["train"]), ds["flights_csv"])) as f:
        next(f)
        for line in f:
            flights.setdefault(line.split(",", 1)[0], 0)
            flights[line.split(",", 1)[0]] += 1
    summary["train_flights"] = len(flights)
    summary["train_points"] = sum(flights.values())

    # 2. Fits.
    fits = {"default": (data["train"], []), "all10": (data["train"], ["--stop", "none"]),
            "exact": (data["train_exact"], ["--stop", "none"]),
            "paper": (data["train"], ["--launch-points", "10", "--stop", "none"]),
            "more": (data["more"], [])}
    reports = {}
    for key, (dset, extra) in fits.items():
        model = os.path.join(a.out, f"{key}.model.json")
        report = os.path.join(a.out, f"{key}.fit.json")
        hold = data["heldout_exact"] if key == "exact" else data["heldout"]
        cmd = [exe, "fit", dset, "-o", model, "--json", report, "--holdout", hold, "--threads", a.threads] + extra
        summary.setdefault("fit_wall_s", {})[key] = run(cmd)
        summary.setdefault("fit_commands", {})[key] = "pteromys " + " ".join(cmd[1:]).replace(ROOT + "/", "")
        reports[key] = load(report)

    # 3. Numbers.
    for key, rep in reports.items():
        h = rep["holdout"]
        summary.setdefault("fits", {})[key] = {
            "fit_rmse_m": rep["fit_rmse_m"], "prior_rmse_m": rep["prior_rmse_m"], "centres": rep["centres"],
            "flights": rep["flights"], "points": rep["points"], "stop_reason": rep["stop_reason"],
            "total_s": rep["timings"]["total_s"],
            "history": [(x["centres"], x["rmse_m"], x["accepted"]) for x in rep["history"]],
            "holdout_first_10": {k: h["launch_first_10"][k] for k in ("fitted", "flat_plate", "ballistic")},
            "holdout_all_points": {k: h["launch_all_points"][k] for k in ("fitted", "flat_plate", "ballistic")},
            "flights_outside_model_range": rep["flights_outside_model_range"],
            "max_alpha_deg": max(f["max_alpha_deg"] for f in rep["per_flight"]),
        }

    # 4. Against the truth: the same held-out (and training) launches recorded
    # with 0.1 mm noise, so that the error is the model's, not the camera's.
    log("predictions against noise-free flights")
    models = {"flat_plate": pteromys.flat_plate_model(), "ballistic": "ballistic"}
    for key in fits:
        models[key] = os.path.join(a.out, f"{key}.model.json")
    truth = {}
    for key, m in models.items():
        h10 = prediction_sets(data["heldout_exact"], {key: m}, 10)[key]
        hall = prediction_sets(data["heldout_exact"], {key: m}, 0)[key]
        tall = prediction_sets(data["train_exact"], {key: m}, 0)[key]
        truth[key] = {"heldout_after_10_m": rmse(h10, after=True), "heldout_all_points_m": rmse(hall),
                      "train_all_points_m": rmse(tall), "heldout_by_glider_after_10_m": by_glider(h10, after=True)}
    summary["truth"] = truth

    # 5. Plots.
    log("plots")
    glider_planform_plot(os.path.join(a.img, "fit_gliders.png"))
    error_vs_centres_plot({
        "default": ("+-5 cm noise, stopping rule (shipped)", reports["default"]),
        "all10": ("+-5 cm noise, to 10 centres", reports["all10"]),
        "paper": ("+-5 cm noise, paper's scheme (launch on first 10 points)", reports["paper"]),
        "exact": ("0.1 mm noise (model error alone), to 10 centres", reports["exact"]),
    }, os.path.join(a.img, "fit_error_vs_centres.png"))
    t01 = load(os.path.join(ROOT, "examples", "training", "t01-rectangular.glider.json"))
    coefficient_plot([("fitted (shipped, +-5 cm data)", models["default"], "#d62728", "-"),
                      ("fitted to exact data, 10 centres", models["exact"], "#1f77b4", "--")],
                     os.path.join(a.img, "fit_coefficients.png"), t01["wings"][0]["outline_m"])
    three = {"fitted": models["default"], "flat_plate": models["flat_plate"], "ballistic": "ballistic"}
    noisy_sets = prediction_sets(data["heldout"], three, 10)
    exact_sets = prediction_sets(data["heldout_exact"], three, 10)
    trajectory_plot(noisy_sets, os.path.join(a.img, "fit_heldout_trajectories.png"),
                    "Held-out gliders as tracked (+-5 cm): launch fitted to the first 10 points (open), the rest "
                    "predicted by the shipped model, the flat-plate element, ballistic motion (paper Fig. 13)")
    trajectory_plot(exact_sets, os.path.join(a.img, "fit_heldout_trajectories_exact.png"),
                    "The same held-out launches without tracking noise (0.1 mm): the models' own error")
    heldout_bar_plot([("as tracked (+-5 cm noise)", {k: by_glider(v, after=True) for k, v in noisy_sets.items()}),
                      ("without noise (0.1 mm): the model error", {k: by_glider(v, after=True)
                                                                    for k, v in exact_sets.items()})],
                     os.path.join(a.img, "fit_heldout_errors.png"))
    train_sets = prediction_sets(data["train_exact"], three, 0)
    keep = {"t01-rectangular", "t08-swept-45", "t10-forward-swept-30", "t11-delta"}
    train_sets = {k: [p for p in v if p["glider"] in keep] for k, v in train_sets.items()}
    trajectory_plot(train_sets, os.path.join(a.img, "fit_training_flights.png"),
                    "Training flights without noise: launch fitted to all points; the shipped model against the "
                    "flat-plate element (paper Fig. 12)", pick=2)

    log("whole flights of the standard launches")
    whole = {}
    for key in ("default", "more", "exact"):
        rows_k, w = whole_flights(models[key])
        whole["flat_plate"] = w["flat_plate"]
        whole[key] = w["fitted"]
        if key == "default":
            rows = rows_k
    summary["whole_flights"] = whole
    distance_plot(rows, os.path.join(a.img, "fit_distances.png"))

    summary["total_s"] = time.time() - t0
    with open(os.path.join(a.out, "summary.json"), "w") as f:
        json.dump(summary, f, indent=1)
    log(f"summary: {os.path.join(a.out, 'summary.json')}")

    # 5. Ship.
    if a.ship:
        m = load(os.path.join(a.out, "default.model.json"))
        prov = m["provenance"]
        prov["dataset_file"] = os.path.relpath(prov["dataset"], ROOT)
        prov.update({
            "experiment": "bench/fit/run_experiment.py (docs/fitting.md)",
            "dataset": "reference simulator flights: " + summary["generate_commands"]["train"],
            "command": summary["fit_commands"]["default"],
            "commit": summary["commit"] + ("+uncommitted changes" if summary["dirty"] else ""),
            "heldout_rmse_after_10_points_m": reports["default"]["holdout"]["launch_first_10"]["fitted"]["rmse_after_m"],
        })
        path = os.path.join(ROOT, "engine", "models", "fitted.model.json")
        with open(path + ".tmp", "w") as f:
            json.dump(m, f, indent=2)
            f.write("\n")
        os.replace(path + ".tmp", path)
        log(f"shipped {path}")
    print(json.dumps({k: summary[k] for k in ("commit", "train_flights", "train_points", "fit_wall_s", "total_s")},
                     indent=1))
    print("fit      centres  fit RMSE  prior | noise-free flights: held-out after 10  held-out all  training all [cm]")
    for key in ["flat_plate", "ballistic"] + list(fits):
        t = truth[key]
        f = summary["fits"].get(key)
        head = (f"{key:10s} {f['centres']:5d}  {100 * f['fit_rmse_m']:7.2f}  {100 * f['prior_rmse_m']:6.2f}" if f
                else f"{key:10s} {'':5s}  {'':7s}  {'':6s}")
        print(f"{head} | {100 * t['heldout_after_10_m']:8.2f}  {100 * t['heldout_all_points_m']:12.2f}  "
              f"{100 * t['train_all_points_m']:12.2f}")
    print("whole flights:", json.dumps(whole, indent=1))


if __name__ == "__main__":
    main()
