"""The Wing object: one wing sketch (top view) with its mount and locks.

A Wing links a sketch drawn in the wing's own plane (sketch X = wing x toward
the nose, sketch Y = span z) and holds the wing's mount: where its origin
(the sketch origin) sits in the glider's side view and its mounting angle.
The ``Mount*`` properties are the design values: the start of the
optimisation, and the mount itself when optimisation is off or the variable
is locked. The ``Mounted*`` properties (read-only) are the mount actually
used for the flight and the plates, written by the Glider on recompute.

Proxy path ``pteromys_freecad.wing.Wing`` is saved in documents: never rename.
"""
import FreeCAD as App

from . import props as P

SCHEMA = 1

#: Joint choices (property values) and the engine's names for them.
JOINTS = ["Auto", "ThroughSlot", "CrossLap", "Halves"]
JOINT_NAMES = {"Auto": None, "ThroughSlot": "through_slot", "CrossLap": "cross_lap", "Halves": "halves"}

PROPERTIES = [
    P.Prop("App::PropertyLink", "Sketch", "Wing", "Top-view sketch of the wing (sketch X toward the nose, Y along the span)"),
    P.Prop("App::PropertyString", "WingName", "Wing", "Name of the wing in glider files and reports (unique per glider)", "wing"),
    P.Prop("App::PropertyBool", "HalfOutline", "Wing",
           "The sketch holds one half of the wing (sketch Y >= 0); it is mirrored about the sketch X axis", False),
    P.Prop("App::PropertyEnumeration", "Joint", "Wing",
           "How the wing is joined to the fuselage: Auto (the engine chooses one that can be assembled), "
           "ThroughSlot (a tilted hole in the fuselage), CrossLap (half slots in both plates), "
           "Halves (the wing is cut in two and pushed in from both sides)", JOINTS),
    P.Prop("App::PropertyDistance", "MountX", "Mount",
           "Design mount: glider x of the wing origin (positive toward the nose)", 0.0),
    P.Prop("App::PropertyDistance", "MountY", "Mount", "Design mount: glider y of the wing origin (up)", 0.0),
    P.Prop("App::PropertyAngle", "MountAngle", "Mount",
           "Design mounting angle (positive raises the leading edge)", 0.0),
    P.Prop("App::PropertyBool", "LockX", "Locks", "Keep MountX as designed when optimising", False),
    P.Prop("App::PropertyBool", "LockY", "Locks", "Keep MountY as designed when optimising", False),
    P.Prop("App::PropertyBool", "LockAngle", "Locks", "Keep MountAngle as designed when optimising", False),
    P.Prop("App::PropertyDistance", "MountedX", "Result", "Mount used for flight and plates: glider x (read-only)",
           0.0, P.READONLY, True),
    P.Prop("App::PropertyDistance", "MountedY", "Result", "Mount used for flight and plates: glider y (read-only)",
           0.0, P.READONLY, True),
    P.Prop("App::PropertyAngle", "MountedAngle", "Result", "Mounting angle used for flight and plates (read-only)",
           0.0, P.READONLY, True),
    P.Prop("App::PropertyArea", "PlanformArea", "Result", "Planform area of the wing outline (read-only)",
           0.0, P.READONLY, True),
    P.Prop("App::PropertyLength", "Span", "Result", "Span of the wing outline (read-only)", 0.0, P.READONLY, True),
    P.Prop("App::PropertyInteger", "SchemaVersion", "Wing", "Version of this object's properties (for migration)",
           SCHEMA, P.HIDDEN),
]


class Wing:
    """Proxy of a wing (App::FeaturePython). Holds no engine objects."""

    def __init__(self, obj):
        obj.Proxy = self
        P.ensure(obj, PROPERTIES)
        self.Type = "PteromysWing"

    def onDocumentRestored(self, obj):
        migrate(obj)

    def execute(self, obj):
        # The Glider reads the sketch and writes the results; nothing to do here.
        pass

    def onChanged(self, obj, prop):
        pass

    # No engine state: documents store nothing from the proxy.
    def dumps(self):
        return None

    def loads(self, state):
        self.Type = "PteromysWing"

    __getstate__ = dumps

    def __setstate__(self, state):
        self.loads(state)


def migrate(obj):
    """Bring a wing of an older document to the current schema (idempotent)."""
    added = P.ensure(obj, PROPERTIES)
    if obj.SchemaVersion < SCHEMA:
        obj.SchemaVersion = SCHEMA
    return added


def is_wing(obj):
    return obj is not None and getattr(getattr(obj, "Proxy", None), "Type", None) == "PteromysWing"


def make_wing(sketch, name="wing", mount=(0.0, 0.0, 0.0), half=False, doc=None, label=None):
    """Create a Wing object for `sketch` with design mount (x_mm, y_mm, angle_deg).

    The wing is not attached to any glider; use :func:`pteromys_freecad.add_wing`
    to create and attach in one step.
    """
    doc = doc or (sketch.Document if sketch is not None else App.ActiveDocument)
    obj = doc.addObject("App::FeaturePython", "Wing")
    Wing(obj)
    obj.Label = label or ("Wing " + name)
    obj.Sketch = sketch
    obj.WingName = name
    obj.HalfOutline = bool(half)
    obj.MountX, obj.MountY, obj.MountAngle = float(mount[0]), float(mount[1]), float(mount[2])
    obj.MountedX, obj.MountedY, obj.MountedAngle = obj.MountX, obj.MountY, obj.MountAngle
    if App.GuiUp:
        from .gui import view_wing
        view_wing.ViewProviderWing(obj.ViewObject)
    return obj
