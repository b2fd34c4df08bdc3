"""Pteromys for FreeCAD: the macro and console API of the workbench.

Everything the toolbar does is a function here, usable headless
(``freecadcmd``) and from the Python console or macros::

    import FreeCAD as App
    import pteromys_freecad as pf

    doc = App.newDocument("Dart")
    g = pf.new_glider(doc)                        # fuselage, main wing, tail
    g.Wings[0].Sketch.setDatum("Span", App.Units.Quantity("460 mm"))
    doc.recompute()                               # re-evaluate, re-optimise, rebuild plates
    print(pf.results(g)["flyable"], g.LaunchDistances)
    pf.export_dxf(g, "/tmp/dart.dxf"); pf.export_step(g, "/tmp/dart.step")

Units: sketches, lengths and mounts in millimetres and degrees (FreeCAD's
units); results dicts and glider files in SI as in ``spec/formats.md``.
See docs/workbench.md for the full reference.
"""
import FreeCAD as App

from .backend import EngineMissing, engine, feature_missing
from .fileio import (ExportError, export_dxf, export_glider_file, export_step,
                     import_glider_file, sketch_from_outline)
from .glider import MATERIALS, Glider, is_glider, make_glider, result_data
from .outline import OutlineError, add_closed_curves, mirror_half_outline, outline_from_sketch
from .template import default_wing_sketch, new_glider
from .wing import Wing, is_wing, make_wing

__version__ = "0.1.0"

__all__ = [
    # objects and templates
    "new_glider", "make_glider", "make_wing", "add_wing", "default_wing_sketch", "gliders", "active_glider",
    "is_glider", "is_wing", "Glider", "Wing", "MATERIALS",
    # running and reading
    "optimise_now", "results", "result_data", "save_flight_plot",
    # files
    "import_glider_file", "export_glider_file", "export_dxf", "export_step", "ExportError",
    # sketches
    "outline_from_sketch", "mirror_half_outline", "sketch_from_outline", "add_closed_curves", "OutlineError",
    # engine
    "engine", "feature_missing", "EngineMissing",
]


def gliders(doc=None):
    """All Glider objects of a document (default: the active one)."""
    doc = doc or App.ActiveDocument
    return [o for o in (doc.Objects if doc else []) if is_glider(o)]


def active_glider(doc=None):
    """The selected glider (or the glider of a selected sketch/wing), else the document's only/last glider."""
    doc = doc or App.ActiveDocument
    if doc is None:
        return None
    if App.GuiUp:
        import FreeCADGui as Gui
        for o in Gui.Selection.getSelection(doc.Name):
            if is_glider(o):
                return o
            for p in o.InList:
                if is_glider(p):
                    return p
                for q in p.InList:
                    if is_glider(q):
                        return q
    gs = gliders(doc)
    return gs[-1] if gs else None


def add_wing(glider, sketch=None, name=None, mount=None, half=False, recompute=True):
    """Add a wing to `glider` and return the Wing object.

    Without `sketch`, a small tapered wing sketch is created to edit.
    `mount` = (x_mm, y_mm, angle_deg) of the wing origin; by default just
    ahead of the fuselage's tail end, on the fuselage's top edge.
    """
    doc = glider.Document
    names = {w.WingName for w in glider.Wings if is_wing(w)}
    if name is None:
        k = len(names) + 1
        name = "wing%d" % k
        while name in names:
            k += 1
            name = "wing%d" % k
    elif name in names:
        raise ValueError("glider '%s' already has a wing named '%s'" % (glider.Label, name))
    if mount is None:
        mount = _default_mount(glider)
    if sketch is None:
        sketch = default_wing_sketch(doc, "WingSketch", at=(mount[0], mount[1]))
        sketch.Label = "%s (top view)" % name
        if App.GuiUp:
            sketch.ViewObject.Visibility = False
    w = make_wing(sketch, name, mount, half=half, doc=doc)
    glider.Wings = list(glider.Wings) + [w]
    if recompute:
        doc.recompute()
    return w


def _default_mount(glider):
    try:
        pts = outline_from_sketch(glider.Fuselage, "fuselage", 0.5)
        xs = [p[0] for p in pts]
        x = min(xs) + 0.35 * (max(xs) - min(xs))
        # top edge of the fuselage at x, less 3 mm so that the root sits inside
        ys = [p[1] for p in pts]
        return (x * 1e3, (min(ys) + 0.5 * (max(ys) - min(ys))) * 1e3, 0.0)
    except Exception:
        return (0.0, 0.0, 0.0)


def optimise_now(glider, apply=True, recompute=True):
    """Optimise the unlocked mounts from the design values (a cold start).

    With `apply`, the optimised mounts (and ballast x, when optimised) are
    written into the design properties (``MountX``... ``BallastX``), so that
    they stay when automatic optimisation is off. Returns the results dict
    of :func:`results` after the recompute. Raises RuntimeError with a plain
    reason when the build has no optimiser or the input is bad.
    """
    from . import glider as G
    from . import props as P
    missing = feature_missing("optimize")
    if missing:
        raise RuntimeError(missing)
    pt = engine()
    design, problems = G.read_design(glider)
    if not problems:
        problems = list(pt.validation_problems(design))
    if problems:
        raise RuntimeError("cannot optimise '%s': %s" % (glider.Label, problems[0]))
    try:
        res = G.solve(pt, design, glider, glider.Proxy, optimise=True, cold=True)
    except G.E.input_error_types() as e:
        raise RuntimeError("cannot optimise '%s': %s" % (glider.Label, e))
    if apply and res.get("optimised"):
        by_name = {w["name"]: w["mount"] for w in res["glider"]["wings"]}
        for w in G.wings_of(glider):
            m = by_name.get(w.WingName)
            if m:
                P.set_if_changed(w, "MountX", m["x_m"] * 1e3)
                P.set_if_changed(w, "MountY", m["y_m"] * 1e3)
                P.set_if_changed(w, "MountAngle", m["angle_deg"])
        if glider.OptimiseBallast and res["glider"].get("ballast"):
            P.set_if_changed(glider, "BallastX", res["glider"]["ballast"][0]["x_m"] * 1e3)
    if recompute:
        glider.touch()
        glider.Document.recompute()
    return results(glider)


def results(glider):
    """The Glider's results as a plain dict (SI units, as in spec/formats.md).

    Keys: status, problems (input errors; empty when the input is good),
    flyable, reasons, warnings, trim_speed_m_s, glide_ratio, static_margin,
    launch_distances_m, launch_stable, mass_kg, cg_m, mounts ({wing:
    {x_m, y_m, angle_deg}}), optimised, recompute_ms, report (the full
    report of the last good recompute) and glider (its mounted glider dict).
    """
    data = result_data(glider)
    g = data.get("glider") or {}
    return {
        "status": glider.Status,
        "problems": list(glider.Problems),
        "flyable": bool(glider.Flyable),
        "reasons": list(glider.Reasons),
        "warnings": list(glider.Warnings),
        "trim_speed_m_s": float(glider.TrimSpeed.getValueAs("m/s")),
        "glide_ratio": float(glider.GlideRatio),
        "static_margin": float(glider.StaticMargin),
        "launch_distances_m": list(glider.LaunchDistances),
        "launch_stable": list(glider.LaunchStable),
        "mass_kg": glider.MassGrams * 1e-3,
        "cg_m": [glider.CenterOfGravity.x * 1e-3, glider.CenterOfGravity.y * 1e-3],
        "mounts": {w["name"]: dict(w["mount"]) for w in g.get("wings", [])},
        "optimised": bool(data.get("optimised")),
        "recompute_ms": float(glider.RecomputeMilliseconds),
        "report": data.get("report"),
        "glider": g or None,
    }


def save_flight_plot(glider, path, title=None):
    """PNG of the six launches (height over distance) of the last good recompute.

    Works headless (matplotlib, Agg). Raises ValueError when there is nothing to plot.
    """
    data = result_data(glider)
    if not data.get("report"):
        raise ValueError("glider '%s' has no flight results yet: %s" % (glider.Label, glider.Status or "not computed"))
    import numpy as np
    engine()  # puts the engine on sys.path
    from pteromys import plot as ptplot  # the engine's plotting helper
    flights = [np.array([[0.0, x, y] for x, y in f]) for f in data["flights"]]
    ptplot.plot_launches(data["report"], flights, str(path), title=title)
    return str(path)
