#!/usr/bin/env python3
"""Validates the empirical flat-plate wing element against measured flat-plate wings.

Reads /work/shared/realdata (or $PTEROMYS_REALDATA) directly, never copies it.
For every Torres & Mueller (2004) and Pelletier & Mueller (2000) wing, the
element model is evaluated with its aspect ratio set to the wing's (the model
represents a whole flat-plate wing of that aspect ratio) at the data's
Reynolds number (1e5 and 1.4e5, from the file headers), and compared with the
measured C_L and C_D. Prints and writes an RMS table (markdown) and plots.

usage: PYTHONPATH=build/python /usr/bin/python3 bench/realdata/validate_flat_plate.py [OUT_DIR]
"""
import csv
import glob
import math
import os
import re
import sys

import numpy as np

import pteromys

DATA = os.environ.get("PTEROMYS_REALDATA", "/work/shared/realdata")
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def read(path):
    a_cl, cl, a_cd, cd = [], [], [], []
    with open(path) as f:
        rows = [r for r in csv.reader(line for line in f if not line.startswith("#"))]
    header = rows[0]
    ia, il, idd = header.index("alpha_deg"), header.index("CL"), header.index("CD")
    for r in rows[1:]:
        a = float(r[ia])
        if r[il].strip():
            a_cl.append(a)
            cl.append(float(r[il]))
        if r[idd].strip():
            a_cd.append(a)
            cd.append(float(r[idd]))
    return np.array(a_cl), np.array(cl), np.array(a_cd), np.array(cd)


def datasets():
    out = []
    for p in sorted(glob.glob(os.path.join(DATA, "torres_mueller2004_digitized_*_AR*.csv"))):
        m = re.search(r"digitized_(.+)_AR([0-9.]+)\.csv", p)
        out.append(("Torres & Mueller 2004", m.group(1), float(m.group(2)), 1.0e5, p))
    for p in sorted(glob.glob(os.path.join(DATA, "pelletier_mueller2000_*_AR*.csv"))):
        m = re.search(r"_AR([0-9.]+)\.csv", p)
        out.append(("Pelletier & Mueller 2000", "rectangular", float(m.group(1)), 1.4e5, p))
    return out


def main(out_dir=None):
    out_dir = out_dir or os.path.join(ROOT, "docs", "img")
    os.makedirs(out_dir, exist_ok=True)
    sets = datasets()
    if not sets:
        sys.exit(f"no data found in {DATA}")
    rows = []
    curves = {}
    for src, planform, ar, re_, path in sets:
        a_cl, cl, a_cd, cd = read(path)
        m = pteromys.flat_plate_model(aspect_ratio=ar)
        res = {}
        for lo, hi, tag in ((0, 10, "attached"), (0, 25, "to 25 deg")):
            sel = (np.abs(a_cl) <= hi) & (np.abs(a_cl) >= lo)
            _, cl_m, _ = m.eval(a_cl[sel], re_)
            res["cl " + tag] = float(np.sqrt(np.mean((cl_m - cl[sel]) ** 2))) if sel.any() else float("nan")
            sel = (np.abs(a_cd) <= hi) & (np.abs(a_cd) >= lo)
            cd_m, _, _ = m.eval(a_cd[sel], re_)
            res["cd " + tag] = float(np.sqrt(np.mean((cd_m - cd[sel]) ** 2))) if sel.any() else float("nan")
        # Lift slope over |alpha| <= 6 deg: measured (least squares) vs model.
        sel = np.abs(a_cl) <= 6
        slope_meas = float(np.sum(a_cl[sel] * cl[sel]) / np.sum(a_cl[sel] ** 2)) * 180 / math.pi
        slope_model = float(m.eval(np.array([1.0]), re_)[1][0]) * 180 / math.pi
        rows.append((src, planform, ar, re_, slope_meas, slope_model, res))
        curves[(src, planform, ar)] = (a_cl, cl, a_cd, cd, m, re_)

    lines = ["| source | planform | AR | Re | dC_L/dα measured [1/rad] | model | RMS C_L, \\|α\\|≤10° | RMS C_L, \\|α\\|≤25° | RMS C_D, \\|α\\|≤10° | RMS C_D, \\|α\\|≤25° |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for src, pf, ar, re_, sm, smod, r in rows:
        lines.append(f"| {src} | {pf} | {ar:g} | {re_:.1e} | {sm:.2f} | {smod:.2f} | {r['cl attached']:.3f} | "
                     f"{r['cl to 25 deg']:.3f} | {r['cd attached']:.3f} | {r['cd to 25 deg']:.3f} |")
    table = "\n".join(lines)
    print(table)
    with open(os.path.join(out_dir, "flat_plate_validation_table.md"), "w") as f:
        f.write(table + "\n")

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    for planform in ("rectangular", "elliptical", "zimmerman", "inverse_zimmerman"):
        keys = [k for k in curves if k[1] == planform and k[0].startswith("Torres")]
        if not keys:
            continue
        fig, ax = plt.subplots(1, 2, figsize=(10, 4), dpi=100)
        for i, k in enumerate(sorted(keys, key=lambda k: k[2])):
            a_cl, cl, a_cd, cd, m, re_ = curves[k]
            col = plt.cm.viridis(i / max(1, len(keys) - 1))
            aa = np.linspace(0, 40, 161)
            cdm, clm, _ = m.eval(aa, re_)
            ax[0].plot(a_cl, cl, ".", color=col, ms=3)
            ax[0].plot(aa, clm, "-", color=col, lw=1, label=f"AR {k[2]:g}")
            ax[1].plot(a_cd, cd, ".", color=col, ms=3)
            ax[1].plot(aa, cdm, "-", color=col, lw=1)
        for a, name in zip(ax, ("$C_L$", "$C_D$")):
            a.set_xlabel("angle of attack [deg]")
            a.set_ylabel(name)
            a.set_xlim(0, 40)
            a.grid(alpha=0.3)
        ax[0].legend(fontsize=7)
        fig.suptitle(f"Flat-plate element (lines) vs Torres & Mueller 2004 {planform} wings (dots)", fontsize=10)
        fig.tight_layout()
        fig.savefig(os.path.join(out_dir, f"flat_plate_{planform}.png"))
        plt.close(fig)
    return rows


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else None)
