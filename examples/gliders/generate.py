#!/usr/bin/env python3
"""Generates the example glider files of this folder (run from anywhere).

Every example is a plausible hand-launched glider cut from 1 mm foam-core
board (180 kg/m^3, as the spec's example), span 0.2 to 0.6 m, with a paperclip
of nose ballast. The mounts written here are a designer's first guess (main
wing 2 deg, tail 0 deg); `pteromys optimize` improves them.

Wing outlines are (x, z) with the origin at the root leading edge, so a mount
x_m is where the root leading edge sits on the fuselage.
"""
import json
import math
import os

HERE = os.path.dirname(os.path.abspath(__file__))
MATERIAL = {"thickness_m": 0.001, "density_kg_m3": 180.0}


def r(v):
    return round(v, 6)


def symmetric(half):
    """Full outline from the z >= 0 half given leading edge root -> tip -> trailing edge root.

    `half` runs from the root leading edge (z = 0) over the tip to the root
    trailing edge (z = 0); the mirror half is appended in reverse.
    """
    right = [(r(x), r(z)) for x, z in half]
    left = [(x, -z) for x, z in reversed(right[1:-1])]
    return [list(p) for p in right + left]


def trapezoid(root, tip, half_span, sweep_le_deg=0.0):
    """Tapered, swept wing: leading edge swept by sweep_le_deg, straight edges."""
    dx = half_span * math.tan(math.radians(sweep_le_deg))
    return symmetric([(0.0, 0.0), (-dx, half_span), (-dx - tip, half_span), (-root, 0.0)])


def elliptic(root, half_span, n=16, qc_straight=True):
    """Elliptic planform with a straight quarter-chord line."""
    pts_le, pts_te = [], []
    for i in range(n + 1):
        th = math.pi / 2 * i / n
        z = half_span * math.sin(th)
        c = root * math.cos(th)
        x_qc = -0.25 * root
        pts_le.append((x_qc + 0.25 * c, z))
        pts_te.append((x_qc - 0.75 * c, z))
    # drop the duplicated tip point (c = 0 there)
    half = pts_le + list(reversed(pts_te[:-1]))
    return symmetric(half)


def crescent(root, half_span, sweep_tip, n=12):
    """Crescent (moon) wing: leading and trailing edges bend back toward the tips."""
    le, te = [], []
    for i in range(n + 1):
        s = i / n
        z = half_span * s
        back = sweep_tip * s ** 2
        c = root * (1 - 0.75 * s ** 1.5)
        le.append((-back, z))
        te.append((-back - c, z))
    return symmetric(le + list(reversed(te)))


def fuselage(length=0.30, nose_h=0.012, body_h=0.010, fin_h=0.035, fin_len=0.05, belly=0.010):
    """Side profile: a slim plate with a tail fin; nose tip at x = 0."""
    L = length
    return [[0.0, 0.0], [-0.03, nose_h], [r(-(L - fin_len - 0.01)), body_h], [r(-(L - 0.02)), fin_h],
            [r(-L), fin_h], [r(-L), -0.004], [-0.03, -belly]]


def canard_fuselage(length=0.32):
    """Canard layout: fin at the rear, wing at the back, canard at the nose."""
    return fuselage(length=length)


def glider(name, wings, ballast_kg=0.0015, ballast_x=-0.012, fus=None):
    return {
        "format": "pteromys-glider/1",
        "name": name,
        "material": MATERIAL,
        "fuselage": {"outline_m": fus or fuselage()},
        "wings": [{"name": n, "outline_m": o, "mount": {"x_m": x, "y_m": y, "angle_deg": a}}
                  for (n, o, x, y, a) in wings],
        "ballast": [{"name": "paperclip", "mass_kg": ballast_kg, "x_m": ballast_x, "y_m": 0.0}],
    }


TAIL = trapezoid(0.040, 0.030, 0.075, sweep_le_deg=15)

EXAMPLES = {
    "rectangular": glider("rectangular", [
        ("main", trapezoid(0.060, 0.060, 0.20), -0.055, 0.004, 2.0),
        ("tail", trapezoid(0.040, 0.040, 0.07), -0.255, 0.006, 0.0)]),
    "tapered": glider("tapered", [
        ("main", trapezoid(0.075, 0.040, 0.21, sweep_le_deg=5), -0.055, 0.004, 2.0),
        ("tail", TAIL, -0.255, 0.006, 0.0)]),
    "swept-back": glider("swept-back", [
        ("main", trapezoid(0.065, 0.045, 0.20, sweep_le_deg=30), -0.045, 0.004, 2.0),
        ("tail", TAIL, -0.255, 0.006, 0.0)], ballast_kg=0.001),
    "forward-swept": glider("forward-swept", [
        ("main", trapezoid(0.060, 0.045, 0.19, sweep_le_deg=-20), -0.085, 0.004, 2.0),
        ("tail", TAIL, -0.255, 0.006, 0.0)], ballast_kg=0.002),
    "delta": glider("delta", [
        ("main", trapezoid(0.150, 0.015, 0.15, sweep_le_deg=40), -0.040, 0.004, 2.0),
        ("tail", trapezoid(0.035, 0.025, 0.06, sweep_le_deg=20), -0.262, 0.006, 0.0)],
        ballast_kg=0.002),
    "elliptic": glider("elliptic", [
        ("main", elliptic(0.075, 0.21), -0.055, 0.004, 2.0),
        ("tail", elliptic(0.045, 0.075), -0.255, 0.006, 0.0)]),
    "crescent": glider("crescent", [
        ("main", crescent(0.075, 0.22, 0.06), -0.050, 0.004, 2.0),
        ("tail", TAIL, -0.255, 0.006, 0.0)], ballast_kg=0.0015),
    "canard": glider("canard", [
        ("canard", trapezoid(0.035, 0.025, 0.08, sweep_le_deg=10), -0.020, 0.004, 2.0),
        ("main", trapezoid(0.070, 0.045, 0.22, sweep_le_deg=10), -0.215, 0.006, 0.0)],
        ballast_kg=0.003, ballast_x=-0.008),
    "tandem": glider("tandem", [
        ("front", trapezoid(0.055, 0.045, 0.16), -0.040, 0.004, 2.0),
        ("rear", trapezoid(0.055, 0.045, 0.16), -0.235, 0.006, 0.0)],
        ballast_kg=0.003, ballast_x=-0.008),
    "three-wing": glider("three-wing", [
        ("canard", trapezoid(0.030, 0.022, 0.06, sweep_le_deg=10), -0.015, 0.004, 2.0),
        ("main", trapezoid(0.065, 0.045, 0.20, sweep_le_deg=8), -0.090, 0.004, 1.0),
        ("tail", TAIL, -0.255, 0.006, 0.0)], ballast_kg=0.0015),
    "big-rectangular": glider("big-rectangular", [
        ("main", trapezoid(0.080, 0.080, 0.29), -0.060, 0.004, 2.0),
        ("tail", trapezoid(0.050, 0.050, 0.10), -0.380, 0.006, 0.0)],
        ballast_kg=0.004, ballast_x=-0.012, fus=fuselage(length=0.43, fin_h=0.045, fin_len=0.06)),
    "small-dart": glider("small-dart", [
        ("main", trapezoid(0.060, 0.025, 0.10, sweep_le_deg=35), -0.040, 0.004, 2.0),
        ("tail", trapezoid(0.030, 0.020, 0.045, sweep_le_deg=25), -0.175, 0.006, 0.0)],
        ballast_kg=0.001, ballast_x=-0.010, fus=fuselage(length=0.20, fin_h=0.03, fin_len=0.04)),
}


def main():
    for key, g in EXAMPLES.items():
        path = os.path.join(HERE, key + ".glider.json")
        with open(path, "w") as f:
            json.dump(g, f, indent=1)
            f.write("\n")
        print("wrote", path)


if __name__ == "__main__":
    main()
