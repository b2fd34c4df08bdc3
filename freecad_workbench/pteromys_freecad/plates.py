"""Plates (engine plate dicts) -> FreeCAD solids, placed as assembled.

A plate dict (``pteromys.slotted_plates``) gives an outline and holes in the
plate's 2D frame [m] and a 4x4 transform from plate-local (u, v, w) to the
glider frame (x, y, z) [m], w across the thickness (the plate spans
w in [-t/2, t/2]). Here each plate becomes a prism of that thickness, moved
by the transform with its translation converted to millimetres. The result
is a compound in the glider frame (mm); the Glider's Placement puts the
glider frame into the document (by default glider y -> FreeCAD Z).
"""
import math

import FreeCAD as App
import Part

MM = 1e-3


def _wire(points_m, w_mm):
    pts = [App.Vector(float(u) / MM, float(v) / MM, w_mm) for u, v in points_m]
    return Part.makePolygon(pts + [pts[0]])


def plate_solid(plate):
    """A plate dict -> Part.Solid in the glider frame (mm)."""
    t_mm = float(plate["thickness_m"]) / MM
    outer = _wire(plate["outline"], -0.5 * t_mm)
    wires = [outer] + [_wire(h, -0.5 * t_mm) for h in plate.get("holes", []) if len(h) >= 3]
    if len(wires) == 1:
        face = Part.Face(outer)
    else:
        face = Part.makeFace(wires, "Part::FaceMakerBullseye")
    solid = face.extrude(App.Vector(0, 0, t_mm))
    T = [[float(v) for v in row] for row in plate["transform"]]
    det = (T[0][0] * (T[1][1] * T[2][2] - T[1][2] * T[2][1]) - T[0][1] * (T[1][0] * T[2][2] - T[1][2] * T[2][0])
           + T[0][2] * (T[1][0] * T[2][1] - T[1][1] * T[2][0]))
    if det < 0:
        # The slab is symmetric in w: flipping w turns a reflection into a rotation.
        for r in range(3):
            T[r][2] = -T[r][2]
        det = -det
    m = App.Matrix()
    m.A11, m.A12, m.A13, m.A14 = T[0][0], T[0][1], T[0][2], T[0][3] / MM
    m.A21, m.A22, m.A23, m.A24 = T[1][0], T[1][1], T[1][2], T[1][3] / MM
    m.A31, m.A32, m.A33, m.A34 = T[2][0], T[2][1], T[2][2], T[2][3] / MM
    if abs(det - 1.0) > 1e-6:
        raise ValueError("plate '%s': its transform is not a rigid motion (det %.6g)" % (plate.get("name", "?"), det))
    solid.Placement = App.Placement(m)
    return solid


def plates_compound(plates):
    """Compound of the solids of all plates (glider frame, mm)."""
    return Part.makeCompound([plate_solid(p) for p in plates])


def unslotted_plates(glider):
    """Plates of a glider dict placed as the spec mounts them, without slots.

    Used only when the engine build has no ``slotted_plates`` (the Glider then
    says so in its status): fuselage in the x-y plane (w = z); a wing's
    outline (x, z) turned about z by its mounting angle and moved to its mount.
    """
    t = glider["material"]["thickness_m"]
    out = [{"name": "fuselage", "kind": "fuselage", "outline": glider["fuselage"]["outline_m"], "holes": [],
            "transform": [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]], "thickness_m": t}]
    for w in glider["wings"]:
        a = math.radians(w["mount"]["angle_deg"])
        c, s = math.cos(a), math.sin(a)
        # local (u, v, w) = (wing x, wing z, wing y across the thickness)
        T = [[c, 0, -s, w["mount"]["x_m"]], [s, 0, c, w["mount"]["y_m"]], [0, 1, 0, 0], [0, 0, 0, 1]]
        out.append({"name": w["name"], "kind": "wing", "outline": w["outline_m"], "holes": [], "transform": T,
                    "thickness_m": t})
    return out
