"""Sketches <-> plate outlines: the one place where FreeCAD's millimetres meet the engine's metres.

A plate outline is read from a sketch in the sketch's own 2D coordinates
(its placement in the 3D view does not matter):

- fuselage sketch: side view, sketch X = glider x (toward the nose),
  sketch Y = glider y (up);
- wing sketch: top view, sketch X = wing x (toward the nose), sketch Y = span
  z. A wing must be mirror-symmetric about the sketch X axis (Y = 0), or be
  drawn as a half (Y >= 0) and mirrored (see :func:`mirror_half_outline`).

Every sketch curve (lines, arcs, circles, ellipses, B-splines) is
discretised so that no point of the curve is farther than the chordal
tolerance from the polygon. Construction geometry is ignored. An outline must
be one closed wire; open, branched or multiple wires are rejected with a
message naming the sketch. Points come back in metres.
"""
import math

MM = 1e-3  # metres per millimetre: the single unit conversion of the workbench


class OutlineError(ValueError):
    """A sketch cannot be turned into a plate outline; the message says why."""


def _fmt_mm(v):
    return "(%.1f, %.1f) mm" % (v.x, v.y)


def sketch_local_shape(sketch):
    """The sketch's shape in its own 2D frame (sketch X, Y; mm)."""
    shape = sketch.Shape.copy()
    pl = sketch.getGlobalPlacement() if hasattr(sketch, "getGlobalPlacement") else sketch.Placement
    shape.transformShape(pl.inverse().toMatrix())
    return shape


def _edge_points(edge, tol_mm):
    """Points of one edge from its start to its end (mm, FreeCAD vectors)."""
    if getattr(edge.Curve, "TypeId", "") in ("Part::GeomLine", "Part::GeomLineSegment"):
        return [edge.Vertexes[0].Point, edge.Vertexes[-1].Point] if len(edge.Vertexes) > 1 else []
    pts = edge.discretize(Deflection=tol_mm)
    if len(pts) < 2:
        pts = edge.discretize(Number=8)
    return pts


def wire_points_mm(wire, tol_mm):
    """Ordered points of a closed wire (mm), without the repeated closing point."""
    edges = wire.OrderedEdges if hasattr(wire, "OrderedEdges") else wire.Edges
    chains = [_edge_points(e, tol_mm) for e in edges]
    chains = [c for c in chains if len(c) >= 2]
    if not chains:
        return []
    eps = max(1e-6, tol_mm * 1e-3)
    # Orient the first chain so that its end meets the second chain.
    if len(chains) > 1:
        a, b = chains[0], chains[1]
        if min((a[0] - b[0]).Length, (a[0] - b[-1]).Length) < min((a[-1] - b[0]).Length, (a[-1] - b[-1]).Length):
            chains[0] = list(reversed(a))
    pts = list(chains[0])
    for c in chains[1:]:
        if (c[-1] - pts[-1]).Length < (c[0] - pts[-1]).Length:
            c = list(reversed(c))
        pts.extend(c[1:] if (c[0] - pts[-1]).Length < 1e-3 else c)
    if (pts[0] - pts[-1]).Length < 1e-3:
        pts.pop()
    # Drop repeated points (zero-length steps) that discretisation may give.
    out = []
    for p in pts:
        if not out or (p - out[-1]).Length > eps:
            out.append(p)
    if len(out) > 1 and (out[0] - out[-1]).Length <= eps:
        out.pop()
    return out


def sketch_wires(sketch, what):
    """The wires of a sketch in its own frame, with checks that name `what`."""
    if sketch is None:
        raise OutlineError("%s has no sketch: link a closed sketch" % what)
    try:
        shape = sketch_local_shape(sketch)
    except Exception as e:  # a deleted or broken object
        raise OutlineError("%s: sketch '%s' cannot be read (%s)" % (what, getattr(sketch, "Label", "?"), e))
    if shape.isNull() or not shape.Edges:
        raise OutlineError("%s: sketch '%s' is empty; draw a closed outline" % (what, sketch.Label))
    return shape


def outline_from_sketch(sketch, what, tol_mm=0.1, half=False):
    """Plate outline of a sketch as a list of (u, v) in metres.

    `what` names the part in messages (for example "wing 'tail'"). With
    `half`, the sketch holds one half of a symmetric wing (Y >= 0, an open
    chain from axis to axis or a closed outline with its root edge on Y = 0)
    and the full outline is returned.
    """
    if not (tol_mm > 0):
        raise OutlineError("the chord tolerance must be positive (got %g mm)" % tol_mm)
    shape = sketch_wires(sketch, what)
    label = sketch.Label
    wires = shape.Wires
    used = sum(len(w.Edges) for w in wires)
    if used < len(shape.Edges):
        raise OutlineError("%s: sketch '%s' has %d loose edge(s) outside its outline; delete them or make them construction geometry"
                           % (what, label, len(shape.Edges) - used))
    if half and len(wires) == 1 and not wires[0].isClosed():
        pts = _open_chain_mm(wires[0], tol_mm)
        return mirror_half_outline([(p.x * MM, p.y * MM) for p in pts], what=what, chain=True)
    closed = [w for w in wires if w.isClosed()]
    opened = [w for w in wires if not w.isClosed()]
    if opened:
        ends = []
        for w in opened:
            vs = w.Vertexes
            ends += [_fmt_mm(v.Point) for v in (vs[0], vs[-1])] if vs else []
        if closed:
            raise OutlineError("%s: sketch '%s' has %d loose edge(s) outside its closed outline (ends at %s); "
                               "delete them or make them construction geometry"
                               % (what, label, sum(len(w.Edges) for w in opened), ", ".join(ends[:4])))
        raise OutlineError("%s: sketch '%s' is not closed: its outline has free ends at %s; join them (coincident constraint)"
                           % (what, label, ", ".join(ends[:4])))
    if len(closed) != 1:
        raise OutlineError("%s: sketch '%s' has %d closed outlines; a plate needs exactly one (no holes, no separate pieces)"
                           % (what, label, len(closed)))
    w = closed[0]
    for v in w.Vertexes:
        if sum(1 for e in w.Edges if any((x.Point - v.Point).Length < 1e-6 for x in e.Vertexes)) > 2:
            raise OutlineError("%s: sketch '%s' outline branches at %s; it must be one simple loop" % (what, label, _fmt_mm(v.Point)))
    pts = wire_points_mm(w, tol_mm)
    if len(pts) < 3:
        raise OutlineError("%s: sketch '%s' outline has fewer than 3 corners" % (what, label))
    poly = [(p.x * MM, p.y * MM) for p in pts]
    _check_simple(poly, what, label)
    if half:
        return mirror_half_outline(poly, what=what)
    return poly


def _open_chain_mm(wire, tol_mm):
    pts = wire_points_mm(wire, tol_mm)
    return pts


def _segments_cross(p1, p2, p3, p4):
    def orient(a, b, c):
        v = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
        return 0 if abs(v) < 1e-18 else (1 if v > 0 else -1)
    o1, o2, o3, o4 = orient(p1, p2, p3), orient(p1, p2, p4), orient(p3, p4, p1), orient(p3, p4, p2)
    if o1 != o2 and o3 != o4:
        return True
    def on(a, b, c):
        return min(a[0], b[0]) <= c[0] <= max(a[0], b[0]) and min(a[1], b[1]) <= c[1] <= max(a[1], b[1])
    return (o1 == 0 and on(p1, p2, p3)) or (o2 == 0 and on(p1, p2, p4)) or \
           (o3 == 0 and on(p3, p4, p1)) or (o4 == 0 and on(p3, p4, p2))


def self_intersection(poly):
    """First pair of crossing non-adjacent edges (i, j) of a closed polygon, or None.

    A quick screen so that the message can name the sketch; the engine's
    exact check (CGAL) runs afterwards on every glider anyway.
    """
    n = len(poly)
    if n > 400:  # O(n^2) screen only for small outlines; the engine checks all
        return None
    for i in range(n):
        a, b = poly[i], poly[(i + 1) % n]
        for j in range(i + 2, n):
            if i == 0 and j == n - 1:
                continue
            if _segments_cross(a, b, poly[j], poly[(j + 1) % n]):
                return i, j
    return None


def _check_simple(poly, what, label):
    hit = self_intersection(poly)
    if hit:
        i, _ = hit
        p = poly[i]
        raise OutlineError("%s: sketch '%s' outline crosses itself near (%.1f, %.1f) mm; a plate outline must be a simple loop"
                           % (what, label, p[0] / MM, p[1] / MM))


def mirror_half_outline(points, what="wing", chain=False, tol=1e-7):
    """Full, mirror-symmetric outline from one half of a wing.

    `points`: (x, z) pairs [m]. Either a closed outline of the half z >= 0
    (or z <= 0) whose root edge lies on z = 0, or (`chain`) an open chain
    that starts and ends on z = 0. Returns the full outline: the half, then
    its mirror image (z -> -z), with the two root points shared.
    """
    pts = [(float(x), float(z)) for x, z in points]
    if len(pts) < 3:
        raise OutlineError("%s: a half outline needs at least 3 points" % what)
    if all(z <= tol for _, z in pts) and any(z < -tol for _, z in pts):
        pts = [(x, -z) for x, z in pts]  # drawn on the other side
    if any(z < -tol for _, z in pts):
        raise OutlineError("%s: the half outline crosses the symmetry axis (sketch Y = 0); draw one side only" % what)
    on_axis = [i for i, (_, z) in enumerate(pts) if abs(z) <= tol]
    if chain:
        if len(on_axis) < 2 or on_axis[0] != 0 or on_axis[-1] != len(pts) - 1:
            raise OutlineError("%s: an open half outline must start and end on the symmetry axis (sketch Y = 0)" % what)
        half = pts
    else:
        # Rotate the ring so that it starts on the axis and then leaves it.
        n = len(pts)
        start = None
        for i in on_axis:
            if pts[(i + 1) % n][1] > tol:
                start = i
                break
        if start is None or len(on_axis) != 2:
            raise OutlineError("%s: a half outline must have its root edge on the symmetry axis (sketch Y = 0), "
                               "with exactly two corners on it (found %d)" % (what, len(on_axis)))
        ring = pts[start:] + pts[:start]
        end = next(k for k in range(1, n) if abs(ring[k][1]) <= tol)
        if end != n - 1:
            raise OutlineError("%s: the half outline touches the symmetry axis in more than one edge" % what)
        half = ring
    half = [(x, 0.0) if abs(z) <= tol else (x, z) for x, z in half]
    if any(abs(z) <= tol for _, z in half[1:-1]):
        raise OutlineError("%s: the half outline touches the symmetry axis between its root corners" % what)
    mirrored = [(x, -z) for x, z in reversed(half[1:-1])]
    return half + mirrored


def polygon_area(poly):
    """Signed area of a polygon [m^2] (counter-clockwise positive)."""
    s = 0.0
    n = len(poly)
    for i in range(n):
        x0, y0 = poly[i]
        x1, y1 = poly[(i + 1) % n]
        s += x0 * y1 - x1 * y0
    return 0.5 * s


def symmetry_error(poly):
    """Largest distance [m] from a mirrored vertex (x, -z) to the outline."""
    def dist_to_seg(p, a, b):
        ax, ay = a
        bx, by = b
        dx, dy = bx - ax, by - ay
        L = dx * dx + dy * dy
        t = 0.0 if L == 0 else max(0.0, min(1.0, ((p[0] - ax) * dx + (p[1] - ay) * dy) / L))
        return math.hypot(p[0] - ax - t * dx, p[1] - ay - t * dy)
    n = len(poly)
    worst = 0.0
    for x, z in poly:
        q = (x, -z)
        worst = max(worst, min(dist_to_seg(q, poly[i], poly[(i + 1) % n]) for i in range(n)))
    return worst


# ---------------------------------------------------------------- writing sketches

def add_polygon(sketch, points_m, constrain=True):
    """Add a closed polygon (points in metres, sketch frame) as line segments.

    Returns the geometry indices. With `constrain`, consecutive segments are
    joined by coincident constraints so that the sketch stays closed when edited.
    """
    import FreeCAD as App
    import Part
    import Sketcher
    pts = [App.Vector(x / MM, y / MM, 0) for x, y in points_m]
    n = len(pts)
    first = sketch.GeometryCount if hasattr(sketch, "GeometryCount") else len(sketch.Geometry)
    geos = [Part.LineSegment(pts[i], pts[(i + 1) % n]) for i in range(n)]
    sketch.addGeometry(geos, False)
    ids = list(range(first, first + n))
    if constrain:
        cons = [Sketcher.Constraint("Coincident", ids[i], 2, ids[(i + 1) % n], 1) for i in range(n)]
        sketch.addConstraint(cons)
    return ids


def add_closed_curves(sketch, curves, tol_mm=1e-4):
    """Add curves (Part lines, arcs, B-splines...) forming one closed loop, in
    loop order, and join touching ends with coincident constraints.

    Ends are matched by position, so a curve may run either way (the sketcher
    stores arcs counter-clockwise). Raises OutlineError when consecutive
    curves do not meet within `tol_mm`. Returns the geometry indices.
    """
    import Sketcher
    first = sketch.GeometryCount if hasattr(sketch, "GeometryCount") else len(sketch.Geometry)
    sketch.addGeometry(list(curves), False)
    n = len(curves)
    ids = list(range(first, first + n))
    cons = []
    for k in range(n):
        a, b = ids[k], ids[(k + 1) % n]
        best = min(((sketch.getPoint(a, pa) - sketch.getPoint(b, pb)).Length, pa, pb) for pa in (1, 2) for pb in (1, 2))
        if best[0] > tol_mm:
            raise OutlineError("sketch '%s': curve %d and curve %d do not meet (gap %.3g mm)"
                               % (sketch.Label, k, (k + 1) % n, best[0]))
        cons.append(Sketcher.Constraint("Coincident", a, best[1], b, best[2]))
    sketch.addConstraint(cons)
    return ids
