#!/usr/bin/env python3
"""Figures of the reference simulator's effects (docs/reference_simulator.md).

1. docs/img/reference_effects.png: one launch of two training gliders with every
   effect off (what the wing-element model assumes), each aerodynamic effect
   alone at strength 1, and all of them; and the pitching moment against the
   angle of attack (static stability) with and without downwash.
2. docs/img/reference_ground_effect.png: lift of a rectangular A = 6 plate at
   4 deg against height, the lattice's image system against lifting-line theory
   with McCormick's induced-drag factor phi = (16 h/b)^2 / (1 + (16 h/b)^2)
   (McCormick, Aerodynamics, Aeronautics and Flight Mechanics, 1979).

Prints the flight distances as a Markdown table.
Run:  PYTHONPATH=build/python /usr/bin/python3 bench/validation/reference_effects.py
"""
import math
import os

import numpy as np

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import pteromys  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
IMG = os.path.join(ROOT, "docs", "img")
AERO = ["pitch_damping", "downwash", "finite_span", "fuselage_drag", "ground_effect", "added_mass"]
GLIDERS = ["t17-canard", "t05-tapered-strong"]


def trajectories():
    fig, axes = plt.subplots(1, 3, figsize=(18, 5))
    rows = []
    for ax, name in zip(axes[:2], GLIDERS):
        path = os.path.join(ROOT, "examples", "training", name + ".glider.json")
        runs = [("baseline (all off)", "baseline")] + [(e, e) for e in AERO] + [("all six (physics)", "physics")]
        for label, spec in runs:
            f = pteromys.reference_simulate(path, speed=8.0, climb_deg=5.0, effects=spec)
            s = f["samples"]
            style = dict(lw=2.2, color="k") if spec == "physics" else dict(lw=2.2, color="0.6") if spec == "baseline" else dict(lw=1.1)
            ax.plot(s[:, 1], s[:, 2], label=label, **style)
            rows.append((name, label, f["distance_m"], f["flight_time_s"], f["max_alpha_deg"], f["end"]))
        ax.set_title(f"{name}: 8 m/s, 5 deg up, from 1.5 m")
        ax.set_xlabel("x [m]")
        ax.set_ylabel("y [m]")
        ax.set_aspect("equal", adjustable="datalim")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    # static stability: moment about the CG against alpha
    path = os.path.join(ROOT, "examples", "training", "t05-tapered-strong.glider.json")
    a = np.linspace(-6, 16, 45)
    for spec, label in (("baseline", "all off"), ("downwash", "downwash only"), ("finite_span", "finite span only"),
                        ("physics", "all six")):
        _, _, m = pteromys.reference_forces(path, 8.0, a, effects=spec)
        axes[2].plot(a, 1000 * m, label=label)
    axes[2].axhline(0, color="k", lw=0.8)
    axes[2].set_title("t05-tapered-strong: pitching moment about the CG at 8 m/s")
    axes[2].set_xlabel("angle of attack [deg]")
    axes[2].set_ylabel("moment [mN m] (nose-up +)")
    axes[2].grid(alpha=0.3)
    axes[2].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(IMG, "reference_effects.png"), dpi=110)
    plt.close(fig)
    return rows


def ground_effect():
    A, c = 6.0, 0.05
    b = A * c
    outline = pteromys.planform("rectangular", A, c)
    g = {"format": "pteromys-glider/1", "name": "plate", "material": {"thickness_m": 0.001, "density_kg_m3": 180},
         "fuselage": {"outline_m": [[0.0, -0.004], [0.0, 0.004], [-0.3, 0.004], [-0.3, -0.004]]},
         "wings": [{"name": "w", "outline_m": outline.tolist(), "mount": {"x_m": 0.0, "y_m": 0.0, "angle_deg": 0.0}}],
         "ballast": []}
    hb = np.geomspace(0.1, 3.0, 25)
    alpha = 4.0
    _, l_inf, _ = pteromys.reference_forces(g, 8.0, alpha, effects="finite_span,ground_effect", height_m=None)
    _, l_h, _ = pteromys.reference_forces(g, 8.0, alpha, effects="finite_span,ground_effect", height_m=hb * b)
    _, l_2d, _ = pteromys.reference_forces(g, 8.0, alpha, effects="ground_effect", height_m=hb * b)
    _, l_2dinf, _ = pteromys.reference_forces(g, 8.0, alpha, effects="ground_effect", height_m=None)
    # lifting line: CL_alpha = a0 / (1 + a0 phi / (pi A e)), e from the lattice (rectangle)
    pot = pteromys.reference_potential(outline, 4.0, span_panels=20)
    e = pot["cl"] ** 2 / (math.pi * A * pot["cdi"])
    a0 = 2 * math.pi
    phi = (16 * hb) ** 2 / (1 + (16 * hb) ** 2)
    ll = (a0 / (1 + a0 * phi / (math.pi * A * e))) / (a0 / (1 + a0 / (math.pi * A * e)))
    fig, ax = plt.subplots(figsize=(7, 4.5))
    ax.plot(hb, l_h / l_inf, "o-", ms=3, label="lattice with ground images (finite span)")
    ax.plot(hb, ll, "k--", label="lifting line x McCormick's phi(h/b)")
    ax.plot(hb, l_2d / l_2dinf, "s-", ms=3, label="2D strips with bound-vortex images")
    ax.set_xscale("log")
    ax.set_xlabel("height of the plate / span, h/b")
    ax.set_ylabel("lift / lift in free air (A = 6, 4 deg)")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(IMG, "reference_ground_effect.png"), dpi=110)
    plt.close(fig)
    return list(zip(hb, l_h / l_inf, ll))


def main():
    os.makedirs(IMG, exist_ok=True)
    rows = trajectories()
    print("| glider | effects | distance [m] | time [s] | max alpha [deg] | end |")
    print("|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r[0]} | {r[1]} | {r[2]:.2f} | {r[3]:.2f} | {r[4]:.1f} | {r[5]} |")
    print()
    print("| h/b | lattice L/L_inf | lifting line x phi |")
    print("|---|---|---|")
    for hb, a, b in ground_effect()[::4]:
        print(f"| {hb:.2f} | {a:.3f} | {b:.3f} |")


if __name__ == "__main__":
    main()
