"""The Glider object: sketches in, a flying glider and its slotted plates out.

A Glider (Part::FeaturePython) links a fuselage sketch (side view) and Wing
objects (each with a top-view sketch). Its recompute runs the whole loop:

1. read the sketches into plate outlines (:mod:`.outline`, mm -> m once);
2. build the glider of ``spec/formats.md`` and let the engine validate it;
3. optimise the unlocked mounts (``pteromys.optimize``, warm-started from the
   previous recompute) when ``AutoOptimise`` is on, else evaluate as mounted;
4. build the slotted plates (``pteromys.slotted_plates``) placed as
   assembled, as the Glider's Shape;
5. write the results into read-only properties and ``ResultData`` (plain
   JSON, for the flight view and for reopened documents).

Bad input never raises out of ``execute``: the reason goes to ``Status`` and
``Problems``, the last good Shape and results stay. The proxy keeps only a
warm-start cache in memory; documents store no engine objects.

Proxy path ``pteromys_freecad.glider.Glider`` is saved in documents: never rename.
"""
import json
import math
import time

import FreeCAD as App

from . import backend as E
from . import outline as O
from . import props as P
from . import wing as W

SCHEMA = 1
MM = O.MM

#: Material presets: name -> (thickness mm, density kg/m^3). Densities are
#: typical; weigh a sheet of yours and use "Custom" for better predictions.
MATERIALS = {
    "Foam core board 1 mm": (1.0, 180.0),   # the paper's gliders (Umetani et al. 2014, section 7)
    "Foam core board 3 mm": (3.0, 95.0),
    "Foam core board 5 mm": (5.0, 70.0),
    "Depron 3 mm": (3.0, 40.0),
    "Depron 6 mm": (6.0, 33.0),
    "Balsa 1.5 mm": (1.5, 160.0),
    "Balsa 3 mm": (3.0, 160.0),
    "Birch plywood 1 mm": (1.0, 680.0),
    "Acrylic 2 mm": (2.0, 1190.0),
    "Custom": None,
}
MATERIAL_NAMES = list(MATERIALS)

#: Slot defaults (the engine's fabrication defaults: laser kerf, sliding fit, web).
DEFAULT_KERF_MM = 0.2
DEFAULT_CLEARANCE_MM = 0.05
DEFAULT_MIN_WEB_MM = 2.0

_OUT = dict(mode=P.READONLY, output=True)

PROPERTIES = [
    # -- design
    P.Prop("App::PropertyLink", "Fuselage", "Glider", "Side-view sketch of the fuselage (sketch X toward the nose, Y up)"),
    P.Prop("App::PropertyLinkList", "Wings", "Glider", "Wing objects of this glider (each links a top-view sketch)"),
    P.Prop("App::PropertyEnumeration", "Material", "Material",
           "Sheet material preset; choosing one sets Thickness and Density", MATERIAL_NAMES),
    P.Prop("App::PropertyLength", "Thickness", "Material", "Plate thickness", 1.0),
    P.Prop("App::PropertyFloat", "Density", "Material", "Plate density [kg/m^3]", 180.0),
    P.Prop("App::PropertyFloat", "BallastGrams", "Ballast", "Ballast mass (a paperclip is about 0.5-1.5 g) [g]; 0 = none", 0.0),
    P.Prop("App::PropertyDistance", "BallastX", "Ballast", "Glider x of the ballast (design value)", 0.0),
    P.Prop("App::PropertyDistance", "BallastY", "Ballast", "Glider y of the ballast", 0.0),
    P.Prop("App::PropertyBool", "OptimiseBallast", "Ballast",
           "Let the optimiser move the ballast along x (BallastX is then its start)", False),
    P.Prop("App::PropertyLength", "LaunchHeight", "Flight", "Height of the hand launches", 1500.0),
    P.Prop("App::PropertyBool", "AutoOptimise", "Flight",
           "Optimise the unlocked wing mounts on every recompute so that the glider flies", True),
    P.Prop("App::PropertyFile", "ModelFile", "Flight",
           "Aerodynamic model (*.model.json); empty = the model shipped with Pteromys"),
    P.Prop("App::PropertyLength", "ChordTolerance", "Sketches",
           "Largest distance between a sketch curve (arc, B-spline) and the polygon that replaces it", 0.1),
    P.Prop("App::PropertyLength", "Kerf", "Fabrication", "Width of the laser cut (slots are compensated)", DEFAULT_KERF_MM),
    P.Prop("App::PropertyLength", "Clearance", "Fabrication", "Extra slot width for an easy fit", DEFAULT_CLEARANCE_MM),
    P.Prop("App::PropertyLength", "MinWeb", "Fabrication", "Least material left beside a slot", DEFAULT_MIN_WEB_MM),
    P.Prop("App::PropertyBool", "Slotted", "Fabrication", "Cut the interlocking slots into the plates", True),
    # -- results (read-only)
    P.Prop("App::PropertyString", "Status", "Result", "Summary of the last recompute", "", **_OUT),
    P.Prop("App::PropertyStringList", "Problems", "Result", "Why the input cannot be evaluated (empty when it can)", [], **_OUT),
    P.Prop("App::PropertyBool", "Flyable", "Result", "The glider is pitch-stable and glides (see Reasons)", False, **_OUT),
    P.Prop("App::PropertyStringList", "Reasons", "Result", "Why the glider does not fly, in plain words", [], **_OUT),
    P.Prop("App::PropertyStringList", "Warnings", "Result", "Model limits met by this design and notes", [], **_OUT),
    P.Prop("App::PropertyStringList", "Mounts", "Result", "Mounting positions and angles used, per wing", [], **_OUT),
    P.Prop("App::PropertySpeed", "TrimSpeed", "Result", "Speed of the steady (trimmed) glide; 0 when none", 0.0, **_OUT),
    P.Prop("App::PropertyFloat", "GlideRatio", "Result", "Lift/drag of the steady glide; 0 when none", 0.0, **_OUT),
    P.Prop("App::PropertyFloat", "StaticMargin", "Result",
           "(x_cg - x_neutral point) / reference chord; positive = pitch-stable", 0.0, **_OUT),
    P.Prop("App::PropertyFloatList", "LaunchDistances", "Result",
           "Distance flown [m] by the six standard launches: 7, 9, 11 m/s at 0 and 10 deg up", [], **_OUT),
    P.Prop("App::PropertyBoolList", "LaunchStable", "Result", "Stability of the six standard launches", [], **_OUT),
    P.Prop("App::PropertyStringList", "FabricationProblems", "Result",
           "Why the plates cannot be slotted as designed (they are then shown without slots)", [], **_OUT),
    P.Prop("App::PropertyStringList", "Assembly", "Result",
           "How to assemble the plates, step by step (from the slotted plates)", [], **_OUT),
    P.Prop("App::PropertyFloat", "MassGrams", "Result", "Mass of plates and ballast [g]", 0.0, **_OUT),
    P.Prop("App::PropertyVectorDistance", "CenterOfGravity", "Result", "Centre of gravity (glider x, y)", None, **_OUT),
    P.Prop("App::PropertyDistance", "BallastPlacedX", "Result", "Ballast x used (optimised when OptimiseBallast)", 0.0, **_OUT),
    P.Prop("App::PropertyFloat", "OptimisationCost", "Result", "Design cost after optimisation (lower is better)", 0.0, **_OUT),
    P.Prop("App::PropertyInteger", "OptimisationEvaluations", "Result", "Cost evaluations of the last optimisation", 0, **_OUT),
    P.Prop("App::PropertyFloat", "RecomputeMilliseconds", "Result", "Time of the last recompute [ms]", 0.0, **_OUT),
    P.Prop("App::PropertyString", "ResultData", "Result",
           "Report, trajectories and mounted glider of the last good recompute (JSON)", "", mode=P.HIDDEN, output=True),
    P.Prop("App::PropertyInteger", "SchemaVersion", "Glider", "Version of this object's properties (for migration)",
           SCHEMA, P.HIDDEN),
]

RESULT_NAMES = [p.name for p in PROPERTIES if p.output]


class Glider:
    """Proxy of the Glider (Part::FeaturePython)."""

    def __init__(self, obj):
        obj.Proxy = self
        P.ensure(obj, PROPERTIES)
        obj.Material = "Foam core board 1 mm"
        self.Type = "PteromysGlider"

    # -- persistence: nothing of the engine is stored
    def dumps(self):
        return None

    def loads(self, state):
        self.Type = "PteromysGlider"

    __getstate__ = dumps

    def __setstate__(self, state):
        self.loads(state)

    def onDocumentRestored(self, obj):
        self.Type = "PteromysGlider"
        migrate(obj)

    # -- material presets
    def onChanged(self, obj, prop):
        if "Restore" in obj.State or getattr(self, "_in_preset", False):
            return
        try:
            if prop == "Material":
                preset = MATERIALS.get(obj.Material)
                if preset:
                    self._in_preset = True
                    try:
                        P.set_if_changed(obj, "Thickness", preset[0])
                        P.set_if_changed(obj, "Density", preset[1])
                    finally:
                        self._in_preset = False
            elif prop in ("Thickness", "Density") and hasattr(obj, "Material"):
                preset = MATERIALS.get(obj.Material)
                if preset and (abs(P.quantity_mm(obj.Thickness) - preset[0]) > 1e-9 or abs(obj.Density - preset[1]) > 1e-9):
                    self._in_preset = True
                    try:
                        obj.Material = "Custom"
                    finally:
                        self._in_preset = False
        except AttributeError:
            pass  # properties still being added

    # -- the recompute
    def execute(self, obj):
        t0 = time.perf_counter()
        try:
            recompute(obj, self)
        except Exception as e:  # never let an unexpected error escape into FreeCAD
            import traceback
            App.Console.PrintError("Pteromys: unexpected error in '%s': %s\n%s" % (obj.Label, e, traceback.format_exc()))
            _set_problems(obj, ["internal error (please report): %s" % e])
        obj.RecomputeMilliseconds = (time.perf_counter() - t0) * 1000.0

    # in-memory cache only
    def warm_start(self, key):
        c = getattr(self, "_warm", None)
        return c[1] if c and c[0] == key else None

    def set_warm_start(self, key, state):
        self._warm = (key, state)

    def model(self, path):
        """Coefficient model for `path` (cached by path and modification time)."""
        import os
        if not path:
            return None
        if not os.path.isfile(path):
            raise O.OutlineError("model file '%s' does not exist" % path)
        key = (path, os.path.getmtime(path))
        c = getattr(self, "_model", None)
        if c and c[0] == key:
            return c[1]
        m = E.engine().load_model(path)
        self._model = (key, m)
        return m


def migrate(obj):
    """Bring a glider of an older document to the current schema (idempotent).

    Adds properties that older versions lacked (with their defaults) and
    records the schema. Future renames go here, with value conversion.
    """
    added = P.ensure(obj, PROPERTIES)
    if obj.SchemaVersion < SCHEMA:
        obj.SchemaVersion = SCHEMA
    if added:
        App.Console.PrintLog("Pteromys: '%s' migrated (added %s)\n" % (obj.Label, ", ".join(added)))
    return added


def is_glider(obj):
    return obj is not None and getattr(getattr(obj, "Proxy", None), "Type", None) == "PteromysGlider"


# ----------------------------------------------------------------- reading the design

def wings_of(obj):
    return [w for w in (obj.Wings or []) if W.is_wing(w)]


def read_design(obj):
    """(glider dict in spec units, problems). Outlines from sketches, mounts from the design values."""
    problems = []
    tol = P.quantity_mm(obj.ChordTolerance)
    name = obj.Label or "glider"
    fus = None
    try:
        fus = O.outline_from_sketch(obj.Fuselage, "fuselage", tol)
    except O.OutlineError as e:
        problems.append(str(e))
    wings = []
    names = set()
    wing_objs = wings_of(obj)
    if not wing_objs:
        problems.append("the glider has no wing: add one (Add wing)")
    for w in (obj.Wings or []):
        if not W.is_wing(w):
            problems.append("'%s' in Wings is not a Pteromys wing" % w.Label)
    for w in wing_objs:
        wname = (w.WingName or "").strip()
        if not wname:
            problems.append("wing object '%s' has an empty WingName" % w.Label)
            continue
        if wname in names:
            problems.append("two wings are named '%s'; wing names must be unique" % wname)
        names.add(wname)
        what = "wing '%s'" % wname
        try:
            outline = O.outline_from_sketch(w.Sketch, what, tol, half=w.HalfOutline)
        except O.OutlineError as e:
            problems.append(str(e))
            continue
        for prop in ("MountX", "MountY", "MountAngle"):
            v = P.quantity_deg(getattr(w, prop)) if prop == "MountAngle" else P.quantity_mm(getattr(w, prop))
            if not math.isfinite(v):
                problems.append("%s: %s is not a finite number (%r)" % (what, prop, v))
        wings.append({"name": wname, "outline_m": [list(p) for p in outline],
                      "mount": {"x_m": P.quantity_mm(w.MountX) * MM, "y_m": P.quantity_mm(w.MountY) * MM,
                                "angle_deg": P.quantity_deg(w.MountAngle)}})
    t_mm = P.quantity_mm(obj.Thickness)
    for prop, v in (("Thickness", t_mm), ("Density", obj.Density), ("BallastGrams", obj.BallastGrams),
                    ("BallastX", P.quantity_mm(obj.BallastX)), ("BallastY", P.quantity_mm(obj.BallastY)),
                    ("LaunchHeight", P.quantity_mm(obj.LaunchHeight))):
        if not math.isfinite(v):
            problems.append("the glider's %s is not a finite number (%r)" % (prop, v))
    if not (t_mm > 0):
        problems.append("the plate thickness must be positive (Thickness = %g mm)" % t_mm)
    if not (obj.Density > 0):
        problems.append("the plate density must be positive (Density = %g kg/m^3)" % obj.Density)
    if obj.BallastGrams < 0:
        problems.append("the ballast mass cannot be negative (BallastGrams = %g g)" % obj.BallastGrams)
    if not (P.quantity_mm(obj.LaunchHeight) > 0):
        problems.append("the launch height must be positive")
    elif P.quantity_mm(obj.LaunchHeight) > 100000:
        # the engine's standard launches are from 0-100 m (evaluate --height)
        problems.append("the launch height must be at most 100 m (LaunchHeight = %g m)"
                        % (P.quantity_mm(obj.LaunchHeight) * MM))
    ballast = []
    if obj.BallastGrams > 0:
        ballast.append({"name": "ballast", "mass_kg": obj.BallastGrams * 1e-3,
                        "x_m": P.quantity_mm(obj.BallastX) * MM, "y_m": P.quantity_mm(obj.BallastY) * MM})
    g = {"format": "pteromys-glider/1", "name": name,
         "material": {"thickness_m": t_mm * MM, "density_kg_m3": float(obj.Density)},
         "fuselage": {"outline_m": [list(p) for p in fus] if fus else []},
         "wings": wings, "ballast": ballast}
    return g, problems


def locks_of(obj):
    """Lock strings for pteromys.optimize ("WING.x", "WING.y", "WING.angle")."""
    locks = []
    for w in wings_of(obj):
        for prop, var in (("LockX", "x"), ("LockY", "y"), ("LockAngle", "angle")):
            if getattr(w, prop):
                locks.append("%s.%s" % (w.WingName, var))
    return locks


def joints_of(obj):
    """{wing name: engine joint name} for wings whose joint is not Auto."""
    out = {}
    for w in wings_of(obj):
        name = W.JOINT_NAMES.get(getattr(w, "Joint", "Auto"))
        if name:
            out[w.WingName] = name
    return out


def fabrication_options(obj):
    return dict(kerf_mm=P.quantity_mm(obj.Kerf), clearance_mm=P.quantity_mm(obj.Clearance),
                min_web_mm=P.quantity_mm(obj.MinWeb))


def all_locked(obj):
    return all(w.LockX and w.LockY and w.LockAngle for w in wings_of(obj)) and not obj.OptimiseBallast


# ----------------------------------------------------------------- the loop

def _set_problems(obj, problems):
    obj.Problems = list(problems)
    kept = " (showing the last good design)" if (obj.ResultData and not obj.Shape.isNull()) else ""
    obj.Status = "Input error: %s%s" % (problems[0], kept)


def solve(pt, glider, obj, proxy, optimise=None, cold=False):
    """Evaluate or optimise a glider dict; returns a plain result dict.

    Keys: glider (mounted dict), report, flights (arrays), notes, and for an
    optimisation cost, evaluations, seconds.
    """
    height = P.quantity_mm(obj.LaunchHeight) * MM
    model = proxy.model(obj.ModelFile) if proxy is not None else None
    optimise = obj.AutoOptimise if optimise is None else optimise
    notes = []
    if optimise and not all_locked(obj):
        missing = E.feature_missing("optimize")
        if missing:
            notes.append(missing + "; the wings stay where designed")
        else:
            locks = locks_of(obj)
            key = (tuple(w["name"] for w in glider["wings"]), tuple(locks), bool(obj.OptimiseBallast),
                   obj.ModelFile, height)
            warm = None if cold or proxy is None else proxy.warm_start(key)
            try:
                res = pt.optimize(pt.glider(glider), model=model, locks=locks, optimise_ballast=bool(obj.OptimiseBallast),
                                  height=height, warm_start=warm)
            except E.input_error_types():
                if warm is None:
                    raise
                res = pt.optimize(pt.glider(glider), model=model, locks=locks, optimise_ballast=bool(obj.OptimiseBallast),
                                  height=height, warm_start=None)
            if proxy is not None:
                proxy.set_warm_start(key, res.get("state"))
            g = res["glider"]
            if not isinstance(g, dict):
                g = pt.glider_dict(g)
            cost = res.get("cost", 0.0)
            terms = dict(cost) if isinstance(cost, dict) else {"total": float(cost)}
            return {"glider": g, "report": res["report"], "flights": list(res["flights"]), "notes": notes,
                    "cost": float(terms.get("total", 0.0)), "cost_terms": terms,
                    "evaluations": int(res.get("evaluations", 0)), "seconds": float(res.get("seconds", 0.0)),
                    "stop_reason": str(res.get("stop_reason", "")), "optimised": True}
    report, flights = pt.evaluate(pt.glider(glider), model=model, height=height)
    return {"glider": glider, "report": report, "flights": flights, "notes": notes, "optimised": False}


def build_plates(pt, glider, obj):
    """(plates, notes, fabrication problems) for a mounted glider dict.

    When the engine cannot slot the plates (no joint can hold a wing, webs too
    thin...), the design itself is still valid: the plates are shown without
    slots and the reason is returned as a fabrication problem.
    """
    if obj.Slotted:
        missing = E.feature_missing("slotted_plates")
        if missing:
            return _plain(glider), [missing + "; the plates are shown without slots"], []
        try:
            plates = pt.slotted_plates(pt.glider(glider), joint=joints_of(obj) or None, **fabrication_options(obj))
            return list(plates), [], []
        except E.input_error_types() as e:
            return _plain(glider), [], [str(e)]
    return _plain(glider), [], []


def _plain(glider):
    from . import plates as PL
    return PL.unslotted_plates(glider)


def recompute(obj, proxy):
    """The whole loop for one Glider (see the module docstring)."""
    clock = [time.perf_counter()]
    timing = {}

    def lap(name):
        now = time.perf_counter()
        timing[name] = (now - clock[0]) * 1000.0
        clock[0] = now

    try:
        pt = E.engine()
    except E.EngineMissing as e:
        _set_problems(obj, [str(e)])
        return
    design, problems = read_design(obj)
    lap("sketches_ms")
    if not problems:
        problems = list(pt.validation_problems(design))
    lap("validation_ms")
    if problems:
        _set_problems(obj, problems)
        return
    bad = E.input_error_types()
    try:
        res = solve(pt, design, obj, proxy)
    except bad as e:
        _set_problems(obj, [str(e)])
        return
    lap("optimise_ms" if res.get("optimised") else "evaluate_ms")
    notes = list(res["notes"])
    try:
        plates, pnotes, fab_problems = build_plates(pt, res["glider"], obj)
        notes += pnotes
        lap("plates_ms")
        from . import plates as PL
        shape = PL.plates_compound(plates)
    except (bad + (RuntimeError,)) as e:
        _set_problems(obj, ["plates: %s" % e])
        return
    if shape.isNull() or not shape.Solids:
        _set_problems(obj, ["plates: the engine returned no solid plate"])
        return
    lap("solids_ms")
    res["timing"] = timing
    obj.FabricationProblems = fab_problems
    apply_results(obj, res, notes, [{"name": p.get("name"), "kind": p.get("kind"), "holes": len(p.get("holes", [])),
                                     "outline_points": len(p.get("outline", []))} for p in plates])
    obj.Assembly = assembly_steps(plates)
    pl = obj.Placement
    obj.Shape = shape
    obj.Placement = pl


def assembly_steps(plates):
    """Plain-words assembly steps from the joints of slotted plates (empty without slots)."""
    seen = {}
    for p in plates:
        for j in p.get("joints", []) or []:
            key = (j.get("step", 0), j.get("wing", ""))
            if key not in seen and j.get("how"):
                seen[key] = "%d. %s (%s): %s" % (j.get("step", 0), j.get("wing", ""),
                                                 str(j.get("type", "")).replace("_", " "), j["how"])
    return [seen[k] for k in sorted(seen)]


def _downsample(arr, limit=250):
    """(x, y) pairs of a trajectory, at most `limit` points, keeping the last."""
    n = len(arr)
    step = max(1, int(math.ceil(n / float(limit))))
    idx = list(range(0, n, step))
    if idx and idx[-1] != n - 1:
        idx.append(n - 1)
    return [[round(float(arr[i][1]), 4), round(float(arr[i][2]), 4)] for i in idx]


def apply_results(obj, res, notes, plates_summary=None):
    rep = res["report"]
    g = res["glider"]
    obj.Problems = []
    obj.Flyable = bool(rep["flyable"])
    obj.Reasons = [str(r) for r in rep.get("reasons", [])]
    obj.Warnings = [str(w) for w in rep.get("warnings", [])] + notes
    glide = rep.get("glide") or {}
    obj.TrimSpeed = App.Units.Quantity("%.9g m/s" % glide.get("speed_m_s", 0.0))
    obj.GlideRatio = float(glide.get("glide_ratio", 0.0))
    sm = rep.get("static_margin")
    obj.StaticMargin = float(sm) if sm is not None and math.isfinite(sm) else 0.0
    obj.LaunchDistances = [float(l["distance_m"]) for l in rep["launches"]]
    obj.LaunchStable = [bool(l["stable"]) for l in rep["launches"]]
    obj.MassGrams = float(rep["mass_kg"]) * 1e3
    obj.CenterOfGravity = App.Vector(rep["cg_m"][0] / MM, rep["cg_m"][1] / MM, 0)
    mounts = []
    by_name = {w["name"]: w["mount"] for w in g["wings"]}
    for w in wings_of(obj):
        m = by_name.get(w.WingName)
        if m is None:
            continue
        P.set_if_changed(w, "MountedX", m["x_m"] / MM)
        P.set_if_changed(w, "MountedY", m["y_m"] / MM)
        P.set_if_changed(w, "MountedAngle", m["angle_deg"])
        mounts.append("%s: x = %.2f mm, y = %.2f mm, angle = %.2f deg" % (w.WingName, m["x_m"] / MM, m["y_m"] / MM,
                                                                         m["angle_deg"]))
        try:
            wo = next(x for x in g["wings"] if x["name"] == w.WingName)["outline_m"]
            P.set_if_changed(w, "PlanformArea", abs(O.polygon_area(wo)) / (MM * MM))
            zs = [p[1] for p in wo]
            P.set_if_changed(w, "Span", (max(zs) - min(zs)) / MM)
        except StopIteration:
            pass
    obj.Mounts = mounts
    bx = g["ballast"][0]["x_m"] / MM if g.get("ballast") else P.quantity_mm(obj.BallastX)
    obj.BallastPlacedX = bx
    obj.OptimisationCost = float(res.get("cost", 0.0))
    obj.OptimisationEvaluations = int(res.get("evaluations", 0))
    data = {"format": "pteromys-freecad-result/1", "report": rep,
            "flights": [_downsample(f) for f in res["flights"]], "glider": g,
            "optimised": bool(res.get("optimised")), "notes": notes, "timing": res.get("timing", {}),
            "optimisation": {k: res[k] for k in ("cost_terms", "evaluations", "seconds", "stop_reason") if k in res},
            "plates": plates_summary}
    obj.ResultData = json.dumps(data, separators=(",", ":"))
    if obj.Flyable:
        status = "Flyable" + (" (%s)" % "; ".join(notes) if notes else "")
    else:
        first = obj.Reasons[0] if obj.Reasons else "it does not glide"
        status = "Not flyable: %s" % first
    if obj.FabricationProblems:
        status += "; plates shown without slots: %s" % obj.FabricationProblems[0]
    obj.Status = status


def result_data(obj):
    """The last good result of a Glider as a dict (empty before the first good recompute)."""
    try:
        return json.loads(obj.ResultData) if obj.ResultData else {}
    except ValueError:
        return {}


# ----------------------------------------------------------------- creation

def make_glider(fuselage=None, wings=(), name="Glider", doc=None, auto_optimise=True, material="Foam core board 1 mm"):
    """Create a Glider linking a fuselage sketch and Wing objects (not recomputed)."""
    doc = doc or App.ActiveDocument or App.newDocument()
    obj = doc.addObject("Part::FeaturePython", "Glider")
    Glider(obj)
    obj.Label = name
    obj.Material = material
    obj.Fuselage = fuselage
    obj.Wings = list(wings)
    obj.AutoOptimise = bool(auto_optimise)
    # Shape in the glider frame (x nose, y up, z span); show y up as FreeCAD's Z.
    obj.Placement = App.Placement(App.Vector(0, 0, 0), App.Rotation(App.Vector(1, 0, 0), 90))
    if App.GuiUp:
        from .gui import view_glider
        view_glider.ViewProviderGlider(obj.ViewObject)
    return obj
