"""Glider templates: fully constrained sketches with named dimensions.

``new_glider()`` builds a fuselage (side view), a main wing and a tail
(top views) close to the paper's foam-board gliders, so that a newcomer can
edit a dimension and see the glider change. Named constraints (editable in
the sketcher or from a macro with ``sketch.setDatum(name, value)``):

- fuselage: ``Length``, ``NoseLength``, ``NoseTop``, ``NoseBottom``,
  ``BoomTop``, ``FinStart``, ``FinFront``, ``FinHeight``, ``TailBottom``;
- wings: ``RootChord``, ``TipChord``, ``Span`` (tip to tip), ``Sweep``
  (how far the tip's leading edge lies behind the root's).

Wing sketches keep the root leading edge on the sketch origin, which is the
wing's mount point, and stay mirror-symmetric by constraint. The tail's x
is locked (it stays at the end of the boom); everything else of the mounts is
free for the optimiser.
"""
import FreeCAD as App

from . import outline as O

FUSELAGE_MM = [(0.0, 0.0), (-30.0, 12.0), (-240.0, 10.0), (-280.0, 35.0), (-300.0, 35.0), (-300.0, -4.0), (-30.0, -10.0)]

#: name -> (root chord, tip chord, span, sweep) [mm], mount (x, y, angle) [mm, mm, deg]
WINGS = {
    "main": ((75.0, 40.0, 420.0, 18.0), (-55.0, 4.0, 1.0)),
    "tail": ((40.0, 30.0, 150.0, 20.0), (-255.0, 6.0, 0.0)),
}
BALLAST = (3.0, -12.0, 0.0)  # grams, x mm, y mm: a lump of modelling clay on the nose


def _constraint(kind, *args):
    import Sketcher
    return Sketcher.Constraint(kind, *args)


def _named(sketch, kind, name, *args):
    i = sketch.addConstraint(_constraint(kind, *args))
    sketch.renameConstraint(i, name)
    return i


def _vertex(k, n):
    """(geometry id, position id) of polygon vertex k: the start of edge k."""
    return k % n, 1


def fuselage_sketch(doc, name="FuselageSketch", points_mm=FUSELAGE_MM):
    """The side-view sketch of the template fuselage, fully constrained."""
    sk = doc.addObject("Sketcher::SketchObject", name)
    sk.Placement = App.Placement(App.Vector(0, 0, 0), App.Rotation(App.Vector(1, 0, 0), 90))
    O.add_polygon(sk, [(x * O.MM, y * O.MM) for x, y in points_mm])
    n = len(points_mm)
    V = lambda k: _vertex(k, n)  # noqa: E731
    sk.addConstraint(_constraint("Coincident", *V(0), -1, 1))      # nose on the origin
    sk.addConstraint(_constraint("Horizontal", 3))                  # fin top
    sk.addConstraint(_constraint("Vertical", 4))                    # tail end
    p = points_mm
    _named(sk, "DistanceX", "NoseLength", *V(1), -1, 1, -p[1][0])
    _named(sk, "DistanceY", "NoseTop", -1, 1, *V(1), p[1][1])
    _named(sk, "DistanceX", "FinStart", *V(2), -1, 1, -p[2][0])
    _named(sk, "DistanceY", "BoomTop", -1, 1, *V(2), p[2][1])
    _named(sk, "DistanceX", "FinFront", *V(3), -1, 1, -p[3][0])
    _named(sk, "DistanceY", "FinHeight", -1, 1, *V(3), p[3][1])
    _named(sk, "DistanceX", "Length", *V(4), -1, 1, -p[4][0])
    _named(sk, "DistanceY", "TailBottom", *V(5), -1, 1, -p[5][1])
    _named(sk, "DistanceX", "NoseBottomX", *V(6), -1, 1, -p[6][0])
    _named(sk, "DistanceY", "NoseBottom", *V(6), -1, 1, -p[6][1])
    return sk


def wing_points_mm(root, tip, span, sweep):
    h = span / 2.0
    return [(0.0, 0.0), (-sweep, h), (-sweep - tip, h), (-root, 0.0), (-sweep - tip, -h), (-sweep, -h)]


def wing_sketch(doc, name, root, tip, span, sweep, at=(0.0, 0.0)):
    """A top-view wing sketch (tapered, swept), fully constrained and symmetric.

    `at` = (x, y) [mm] puts the sketch where the wing sits in the 3D view
    (cosmetic: only the sketch's own coordinates are read).
    """
    sk = doc.addObject("Sketcher::SketchObject", name)
    sk.Placement = App.Placement(App.Vector(at[0], 0, at[1]), App.Rotation())
    pts = wing_points_mm(root, tip, span, sweep)
    O.add_polygon(sk, [(x * O.MM, y * O.MM) for x, y in pts])
    n = 6
    V = lambda k: _vertex(k, n)  # noqa: E731
    sk.addConstraint(_constraint("Coincident", *V(0), -1, 1))          # root leading edge = wing origin
    sk.addConstraint(_constraint("PointOnObject", *V(3), -1))          # root trailing edge on the axis
    sk.addConstraint(_constraint("Symmetric", *V(1), *V(5), -1))       # mirror-symmetric about sketch X
    sk.addConstraint(_constraint("Symmetric", *V(2), *V(4), -1))
    sk.addConstraint(_constraint("Horizontal", 1))                     # tip edge along the flight direction
    _named(sk, "DistanceX", "RootChord", *V(3), *V(0), root)
    _named(sk, "DistanceX", "TipChord", *V(2), *V(1), tip)
    _named(sk, "DistanceY", "Span", *V(5), *V(1), span)
    _named(sk, "DistanceX", "Sweep", *V(1), *V(0), sweep)
    return sk


def new_glider(doc=None, name="Glider", recompute=True, auto_optimise=True):
    """Create the template glider (fuselage, main wing, tail) and recompute it.

    Returns the Glider object. Everything is undoable as one step in the GUI.
    """
    from . import glider as G
    from . import wing as W
    doc = doc or App.ActiveDocument or App.newDocument("Glider")
    fus = fuselage_sketch(doc, "FuselageSketch")
    fus.Label = "Fuselage (side view)"
    wings = []
    for wname, ((root, tip, span, sweep), mount) in WINGS.items():
        label = "MainWing" if wname == "main" else "Tail"
        sk = wing_sketch(doc, label + "Sketch", root, tip, span, sweep, at=(mount[0], mount[1]))
        sk.Label = "%s (top view)" % ("Main wing" if wname == "main" else "Tail")
        w = W.make_wing(sk, wname, mount, doc=doc, label="Main wing" if wname == "main" else "Tail")
        if wname == "tail":
            # The tail stays at the end of the boom: the optimiser tilts it and may
            # move it up or down, and moves and tilts the main wing. (Unlocked, it
            # may slide the tail forward under the main wing, which cannot be built.)
            w.LockX = True
        wings.append(w)
    g = G.make_glider(fus, wings, name=name, doc=doc, auto_optimise=auto_optimise)
    g.BallastGrams, g.BallastX, g.BallastY = BALLAST
    if App.GuiUp:
        for o in [fus] + [w.Sketch for w in wings]:
            o.ViewObject.Visibility = False
    if recompute:
        doc.recompute()
    return g


def default_wing_sketch(doc, name="WingSketch", at=(0.0, 0.0)):
    """A small tapered wing to start a new wing from (root 40, tip 30, span 150, sweep 15 mm)."""
    return wing_sketch(doc, name, 40.0, 30.0, 150.0, 15.0, at=at)
