"""Glider files (spec/formats.md) and fabrication exports for Glider objects.

- :func:`import_glider_file` builds sketches, wings and a Glider from a
  ``.glider.json`` file (outlines become closed, editable polylines; the
  file's mounts become the design mounts).
- :func:`export_glider_file` writes the glider as last recomputed (its
  outlines and the mounts actually used, optimised or not).
- :func:`export_dxf` / :func:`export_step` write the slotted plates through
  ``pteromys.export`` (laser-cut DXF, 3D-print/CAD STEP).

Exports refuse a glider whose current input has errors rather than write
stale parts; the message names the problem.
"""
import os

import FreeCAD as App

from . import backend as E
from . import glider as G
from . import outline as O


class ExportError(ValueError):
    """An export cannot be done; the message says why."""


def _touched(o):
    return "Touched" in o.State


def _fresh_glider_dict(obj):
    """The mounted glider dict of an up-to-date Glider, or ExportError."""
    if not G.is_glider(obj):
        raise ExportError("'%s' is not a Pteromys glider" % getattr(obj, "Label", obj))
    if _touched(obj) or any(_touched(o) for o in obj.OutListRecursive):
        obj.Document.recompute()
    if obj.Problems:
        raise ExportError("glider '%s' has input errors, fix them first: %s" % (obj.Label, obj.Problems[0]))
    data = G.result_data(obj)
    if not data.get("glider"):
        raise ExportError("glider '%s' has not been computed successfully yet" % obj.Label)
    return data["glider"]


def _check_target(path, exts):
    exts = (exts,) if isinstance(exts, str) else tuple(exts)
    if not path:
        raise ExportError("no output file given")
    path = os.path.abspath(os.path.expanduser(str(path)))
    d = os.path.dirname(path)
    if not os.path.isdir(d):
        raise ExportError("the folder '%s' does not exist" % d)
    if not path.lower().endswith(exts):
        raise ExportError("the file name must end in %s: '%s'" % (" or ".join(exts), path))
    return path


def export_glider_file(obj, path):
    """Write `obj` as a ``.glider.json`` file (mounts as used); returns the path."""
    path = _check_target(path, ".json")
    g = _fresh_glider_dict(obj)
    pt = E.engine()
    pt.save_glider(pt.glider(g), path)
    return path


def _fabrication_kwargs(obj):
    kw = G.fabrication_options(obj)
    joints = G.joints_of(obj)
    if joints:
        kw["joint"] = joints
    return kw


def _export(obj, dxf=None, step=None, **kw):
    missing = E.feature_missing("export")
    if missing:
        raise ExportError(missing)
    g = _fresh_glider_dict(obj)
    if obj.FabricationProblems:
        raise ExportError("the plates of '%s' cannot be slotted: %s" % (obj.Label, obj.FabricationProblems[0]))
    pt = E.engine()
    args = _fabrication_kwargs(obj)
    args.update(kw)
    try:
        return pt.export(pt.glider(g), dxf=dxf, step=step, **args)
    except E.input_error_types() as e:
        raise ExportError(str(e))


def export_dxf(obj, path, sheet_mm=None, **kw):
    """Laser-cut DXF of the slotted plates (millimetres); returns the engine's summary dict."""
    path = _check_target(path, ".dxf")
    if sheet_mm is not None:
        kw["sheet_mm"] = tuple(sheet_mm)
    return _export(obj, dxf=path, **kw)


def export_step(obj, path, fused=False, **kw):
    """STEP of the slotted plates as assembled; returns the engine's summary dict."""
    path = _check_target(path, (".step", ".stp"))
    return _export(obj, step=path, fused=fused, **kw)


def sketch_from_outline(doc, name, points_m, placement=None, label=None):
    """A sketch holding a closed polyline through `points_m` ((u, v) in metres)."""
    sk = doc.addObject("Sketcher::SketchObject", name)
    if placement is not None:
        sk.Placement = placement
    O.add_polygon(sk, points_m)
    if label:
        sk.Label = label
    return sk


def import_glider_file(path, doc=None, name=None, recompute=True, auto_optimise=None):
    """Create sketches, wings and a Glider from a glider file; returns the Glider.

    The file is validated by the engine first (bad files raise
    ``pteromys.InputError`` naming the problem, and nothing is created).
    Automatic optimisation is off unless asked for, so that the file's
    mounts are kept as they are.
    """
    from . import wing as W
    pt = E.engine()
    g = pt.glider_dict(pt.load_glider(str(path)))
    doc = doc or App.ActiveDocument or App.newDocument()
    rot = App.Rotation(App.Vector(1, 0, 0), 90)
    fus = sketch_from_outline(doc, "FuselageSketch", g["fuselage"]["outline_m"], App.Placement(App.Vector(), rot),
                              "Fuselage (side view)")
    wings = []
    for w in g["wings"]:
        m = w["mount"]
        sk = sketch_from_outline(doc, "WingSketch", w["outline_m"],
                                 App.Placement(App.Vector(m["x_m"] / O.MM, 0, m["y_m"] / O.MM), App.Rotation()),
                                 "%s (top view)" % w["name"])
        wings.append(W.make_wing(sk, w["name"], (m["x_m"] / O.MM, m["y_m"] / O.MM, m["angle_deg"]), doc=doc,
                                 label="Wing " + w["name"]))
    obj = G.make_glider(fus, wings, name=name or g.get("name") or "Glider", doc=doc,
                        auto_optimise=bool(auto_optimise))
    mat = g["material"]
    obj.Material = "Custom"
    obj.Thickness = mat["thickness_m"] / O.MM
    obj.Density = mat["density_kg_m3"]
    ballast = g.get("ballast", [])
    if ballast:
        total = sum(b["mass_kg"] for b in ballast)
        # The workbench has one ballast item: several become one at their centre of mass.
        obj.BallastGrams = total * 1e3
        if total > 0:
            obj.BallastX = sum(b["mass_kg"] * b["x_m"] for b in ballast) / total / O.MM
            obj.BallastY = sum(b["mass_kg"] * b["y_m"] for b in ballast) / total / O.MM
        if len(ballast) > 1:
            App.Console.PrintWarning("Pteromys: %d ballast items of '%s' were merged into one at their centre of mass\n"
                                     % (len(ballast), path))
    if App.GuiUp:
        for o in [fus] + [w.Sketch for w in wings]:
            o.ViewObject.Visibility = False
    if recompute:
        doc.recompute()
    return obj
