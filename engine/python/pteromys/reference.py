"""The reference ("reality") simulator: a vortex lattice of all wings with
post-stall flat-plate sections and switchable physical effects (issue 6).

Formulas, sources and validation: ``docs/reference_simulator.md`` and
``docs/validation.md``. Effects are named as the diagnosis library names them
(``effect_names()``); an ``effects`` argument is ``"physics"`` (the six
aerodynamic effects on), ``"baseline"`` (everything off: what the paper's
wing-element model assumes), ``"all"`` or a comma list of names, and
``strengths`` a dict ``{"downwash": 0.5}`` or a string ``"downwash=0.5"``.

Planform helpers build the wind-tunnel wings of the validation data
(Torres & Mueller 2004; Polhamus 1966) as ``(n, 2)`` arrays of ``(x, z)`` [m],
x toward the leading edge, origin at the root leading edge.
"""
import math

import numpy as _np

from ._core import (  # noqa: F401  (re-exported API)
    effect_names,
    effect_switches,
    generate_dataset,
    reference_forces,
    reference_loads,
    reference_polar,
    reference_potential,
    reference_simulate,
)

__all__ = [
    "effect_names", "effect_switches", "generate_dataset", "reference_forces", "reference_loads",
    "reference_polar", "reference_potential", "reference_simulate", "planform",
]


def _half_to_full(le, te):
    """Full outline from the z >= 0 leading edge (root to tip) and trailing edge (root to tip)."""
    right = list(le) + list(reversed(te))
    # drop repeated tip points
    out = []
    for p in right:
        if not out or abs(out[-1][0] - p[0]) > 1e-12 or abs(out[-1][1] - p[1]) > 1e-12:
            out.append(p)
    left = [(x, -z) for x, z in reversed(out) if z > 1e-12]
    # the root points (z = 0) appear once each
    return _np.array(out + left)


def planform(kind, aspect_ratio, root_chord=0.2, n=64):
    """Outline of a flat-plate wing of the validation data sets.

    kind: ``rectangular``; ``elliptical`` (an ellipse: straight mid-chord
    line, as Torres & Mueller's); ``zimmerman`` (two half ellipses joined at
    the quarter chord: leading-edge semi-axis c/4, trailing-edge 3c/4);
    ``inverse_zimmerman`` (joined at the three-quarter chord); ``delta``
    (sharp delta, apex forward, straight trailing edge).
    aspect_ratio: b^2 / S. root_chord [m]. Returns an (m, 2) array (x, z).
    """
    A = float(aspect_ratio)
    c = float(root_chord)
    if A <= 0 or c <= 0:
        raise ValueError("aspect_ratio and root_chord must be positive")
    if kind == "rectangular":
        b = A * c
        return _np.array([[0.0, 0.0], [0.0, b / 2], [-c, b / 2], [-c, 0.0], [-c, -b / 2], [0.0, -b / 2]])
    if kind == "delta":
        b = A * c / 2  # S = b c / 2
        return _np.array([[0.0, 0.0], [-c, b / 2], [-c, 0.0], [-c, -b / 2]])
    if kind in ("elliptical", "zimmerman", "inverse_zimmerman"):
        # S = pi b c / 4 for all three (each edge is a quarter ellipse)
        b = math.pi * A * c / 4  # A = b^2 / S = 4 b / (pi c)
        f = {"elliptical": 0.5, "zimmerman": 0.25, "inverse_zimmerman": 0.75}[kind]
        x_join = -f * c
        le, te = [], []
        for i in range(n + 1):
            th = 0.5 * math.pi * i / n
            z = (b / 2) * math.sin(th)
            k = math.cos(th)
            le.append((x_join + f * c * k, z))
            te.append((x_join - (1 - f) * c * k, z))
        return _half_to_full(le, te)
    raise ValueError(f"unknown planform kind '{kind}'")
