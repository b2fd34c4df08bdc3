"""pteromys export: the DXF read back with ezdxf, the STEP read back with FreeCAD.

Expected values are computed here, independently of the engine: plate areas
from the glider files minus the slot rectangles the engine reports (clipped
with Sutherland-Hodgman), wing angles and positions from the mounts. Every
example glider is exported; the ones the engine must refuse, and the broken
corpus, are listed in tests/data/fabrication/expected.json with the words of
their messages.
"""
import json
import math
import os
import shutil
import subprocess
import textwrap

import numpy as np
import pytest

import pteromys
from conftest import BUILD, EXAMPLES, ROOT, load, run

try:
    import ezdxf  # Debian python3-ezdxf: the independent DXF reader
except ImportError as e:  # pragma: no cover  (fails the run, never skips)
    raise RuntimeError("python3-ezdxf is required for the DXF read-back tests (scripts/setup.sh installs it)") from e

FAB = os.path.join(ROOT, "tests", "data", "fabrication")
EXPECTED = load(os.path.join(FAB, "expected.json"))
REFUSED = {os.path.realpath(p): c for p, c in ((os.path.join(FAB, c["glider"]), c) for c in EXPECTED.values())
           if not c["args"] and os.path.realpath(p) in {os.path.realpath(e) for e in EXAMPLES}}
BUILDABLE = [p for p in EXAMPLES if os.path.realpath(p) not in REFUSED]
# Designs with wings on the fuselage's edge (mounts as `pteromys optimize` left them):
# their slots open to the edge where a closed one would leave a thin web.
EDGE = [os.path.join(FAB, "edge_mounted_tail.glider.json"), os.path.join(FAB, "edge_mounted_canard.glider.json")]
BUILT = BUILDABLE + EDGE
KERF_MM = 0.2  # the command's default (pteromys export --help)
T_MM = 1.0     # every example is 1 mm board


def name_of(path):
    return os.path.basename(path).split(".")[0]


# ------------------------------------------------------- independent geometry

def area(p):
    p = np.asarray(p, float)
    if len(p) < 3:
        return 0.0
    x, y = p[:, 0], p[:, 1]
    return 0.5 * abs(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


def perimeter(p):
    p = np.asarray(p, float)
    return float(np.sum(np.linalg.norm(np.roll(p, -1, axis=0) - p, axis=1)))


def clip_halfplane(poly, a, b):
    """Part of poly where a . p <= b (Sutherland-Hodgman, one edge)."""
    out = []
    n = len(poly)
    for i in range(n):
        p, q = np.asarray(poly[i], float), np.asarray(poly[(i + 1) % n], float)
        fp, fq = np.dot(a, p) - b, np.dot(a, q) - b
        if fp <= 0:
            out.append(p)
        if (fp < 0 < fq) or (fq < 0 < fp):
            out.append(p + (q - p) * fp / (fp - fq))
    return out


def clip_convex(poly, clip):
    """poly (any simple polygon) cut by a convex polygon (counter-clockwise)."""
    clip = np.asarray(clip, float)
    if np.cross(clip[1] - clip[0], clip[2] - clip[1]) < 0:
        clip = clip[::-1]
    out = [np.asarray(v, float) for v in poly]
    for i in range(len(clip)):
        e0, e1 = clip[i], clip[(i + 1) % len(clip)]
        d = e1 - e0
        a = np.array([d[1], -d[0]])  # outward normal of a ccw edge
        out = clip_halfplane(out, a, np.dot(a, e0))
        if not out:
            break
    return out


def expected_area_m2(g, plate):
    """Finished area of a plate from the glider file and the reported slots."""
    t = g["material"]["thickness_m"]
    if plate["kind"] == "fuselage":
        base = g["fuselage"]["outline_m"]
    else:
        base = next(w["outline_m"] for w in g["wings"] if w["name"] == plate["wing"])
    if plate["half"]:
        c = plate["joints"][0]["split_x_m"]
        s = 1.0 if plate["half"] == "right" else -1.0
        big = 10.0
        outer = clip_halfplane(base, np.array([0.0, -s]), -t / 2)  # s z >= t/2
        tab = clip_convex(base, [[c if s > 0 else -big, -t / 2], [big if s > 0 else c, -t / 2],
                                 [big if s > 0 else c, t / 2], [c if s > 0 else -big, t / 2]])
        return area(outer) + area(tab)
    rects = [sl["rect"] for j in plate["joints"] for sl in j["slots"] if sl["plate"] == plate["name"]]
    # plate minus the union of the slots: inclusion-exclusion (pieces of one
    # slot overlap pairwise by a few micrometres; no point lies in three)
    a = area(base) - sum(area(clip_convex(base, r)) for r in rects)
    for i in range(len(rects)):
        for k in range(i + 1, len(rects)):
            inner = clip_convex(base, rects[i])
            if len(inner) >= 3:
                a += area(clip_convex(inner, rects[k]))
    return a


def point_in_polygon(p, q):
    p = np.asarray(p, float)
    x, y = q
    inside = False
    for i in range(len(p)):
        (x0, y0), (x1, y1) = p[i], p[i - 1]
        if (y0 > y) != (y1 > y) and x < x0 + (y - y0) * (x1 - x0) / (y1 - y0):
            inside = not inside
    return inside


def edges_cross(a, b):
    """True when any edge of polygon a intersects any edge of polygon b."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    A0, A1 = a, np.roll(a, -1, axis=0)
    B0, B1 = b, np.roll(b, -1, axis=0)
    for p, q in zip(A0, A1):
        d = q - p
        r, s = B0, B1
        o1 = np.cross(d, r - p)
        o2 = np.cross(d, s - p)
        e = s - r
        o3 = np.cross(e, p - r)
        o4 = np.cross(e, q - r)
        # bounding boxes of the two segments must meet too (collinear, disjoint edges)
        boxes = ((np.minimum(r[:, 0], s[:, 0]) <= max(p[0], q[0])) & (np.maximum(r[:, 0], s[:, 0]) >= min(p[0], q[0])) &
                 (np.minimum(r[:, 1], s[:, 1]) <= max(p[1], q[1])) & (np.maximum(r[:, 1], s[:, 1]) >= min(p[1], q[1])))
        if np.any((o1 * o2 <= 0) & (o3 * o4 <= 0) & boxes):
            return True
    return False


# ------------------------------------------------------------------ exports

@pytest.fixture(scope="module")
def exported(tmp_path_factory):
    """Every buildable example exported by the command with default options."""
    d = tmp_path_factory.mktemp("export")
    out = {}
    for path in BUILT:
        n = name_of(path)
        dxf, step, js = d / (n + ".dxf"), d / (n + ".step"), d / (n + ".json")
        r = run(["export", path, "--dxf", dxf, "--step", step, "--json", js])
        assert r.returncode == 0, f"{n}: {r.stderr}"
        out[n] = {"glider": load(path), "path": path, "dxf": str(dxf), "step": str(step), "summary": load(js),
                  "plates": pteromys.slotted_plates(path)}
    return out


def test_every_example_is_exported_or_refused_in_words(exported):
    assert len([p for p in BUILDABLE if name_of(p) in exported]) + len(REFUSED) == len(EXAMPLES)
    assert len(BUILDABLE) >= 10
    for path, case in REFUSED.items():
        r = run(["export", path, "--json", os.devnull])
        assert r.returncode == 2
        for words in case["message"]:
            assert words in r.stderr, r.stderr
    kinds = {j["type"] for e in exported.values() for j in e["summary"]["joints"]}
    assert {"through_slot", "cross_lap", "halves", "notch"} <= kinds, kinds
    # wings on the fuselage's top edge: slots opened to the edge (part of the outline, not holes)
    e = exported["edge_mounted_tail"]
    tail = next(j for j in e["summary"]["joints"] if j["wing"] == "tail")
    assert tail["type"] in ("halves", "notch")
    assert any(s["open"] for p in e["plates"] for j in p["joints"] if j["wing"] == "tail" for s in j["slots"])


def read_dxf(path):
    doc = ezdxf.readfile(path)
    msp = doc.modelspace()
    cut, sheets, lines, texts = [], [], [], []
    for e in msp:
        t, layer = e.dxftype(), e.dxf.layer
        if layer == "CUT":
            assert t == "LWPOLYLINE", f"{t} on CUT"
            assert e.closed, "open outline on CUT"
            cut.append(np.array([(p[0], p[1]) for p in e.get_points("xy")]))
        elif layer == "ENGRAVE":
            assert t in ("LINE", "TEXT"), f"{t} on ENGRAVE"
            if t == "LINE":
                lines.append(((e.dxf.start.x, e.dxf.start.y), (e.dxf.end.x, e.dxf.end.y)))
            else:
                p = e.dxf.align_point if e.dxf.hasattr("align_point") else e.dxf.insert
                texts.append((e.dxf.text, (p.x, p.y), e.dxf.height))
        elif layer == "SHEET":
            assert t in ("LWPOLYLINE", "TEXT"), f"{t} on SHEET"
            if t == "LWPOLYLINE":
                sheets.append(np.array([(p[0], p[1]) for p in e.get_points("xy")]))
        else:
            raise AssertionError(f"entity {t} on undocumented layer {layer}")
    return doc, cut, sheets, lines, texts


def split_parts(cut):
    """Outlines (not inside another polyline) and, per outline, its holes."""
    outer, holes = [], {}
    for i, p in enumerate(cut):
        owner = [j for j, q in enumerate(cut) if j != i and point_in_polygon(q, p[0]) and area(q) > area(p)]
        if owner:
            holes.setdefault(min(owner, key=lambda j: area(cut[j])), []).append(i)
        else:
            outer.append(i)
    return outer, holes


@pytest.mark.parametrize("path", BUILT, ids=name_of)
def test_dxf_declares_millimetres_and_documented_layers(exported, path):
    doc, cut, sheets, lines, texts = read_dxf(exported[name_of(path)]["dxf"])
    assert doc.header["$INSUNITS"] == 4  # millimetres
    assert {"CUT", "ENGRAVE", "SHEET"} <= {l.dxf.name for l in doc.layers}
    assert cut and sheets and lines and texts


@pytest.mark.parametrize("path", BUILT, ids=name_of)
def test_dxf_parts_lie_on_sheets_without_overlap(exported, path):
    e = exported[name_of(path)]
    _, cut, sheets, _, _ = read_dxf(e["dxf"])
    outer, holes = split_parts(cut)
    assert len(outer) == len(e["plates"])
    assert e["summary"]["sheets"] == len(sheets)
    for i in outer:
        for j in outer:
            if i < j:
                assert not edges_cross(cut[i], cut[j]), "two parts overlap"
                assert not point_in_polygon(cut[j], cut[i][0]) and not point_in_polygon(cut[i], cut[j][0])
        # inside one sheet, 5 mm margin
        lo, hi = cut[i].min(axis=0), cut[i].max(axis=0)
        assert any(lo[0] >= s[:, 0].min() + 5 - 1e-6 and hi[0] <= s[:, 0].max() - 5 + 1e-6 and
                   lo[1] >= s[:, 1].min() + 5 - 1e-6 and hi[1] <= s[:, 1].max() - 5 + 1e-6 for s in sheets)
        assert max(s[:, 0].max() - s[:, 0].min() for s in sheets) == pytest.approx(600)
        assert max(s[:, 1].max() - s[:, 1].min() for s in sheets) == pytest.approx(900)


def dxf_regions(path):
    """{engraved label: (area mm^2 of outline minus holes, total cut perimeter mm)}."""
    _, cut, _, _, texts = read_dxf(path)
    outer, holes = split_parts(cut)
    regions = {}
    for text, pos, _h in texts:
        owners = [i for i in outer if point_in_polygon(cut[i], pos)]
        if len(owners) == 1:
            i = owners[0]
            hs = holes.get(i, [])
            regions.setdefault(text, (area(cut[i]) - sum(area(cut[k]) for k in hs),
                                      perimeter(cut[i]) + sum(perimeter(cut[k]) for k in hs)))
    return regions


@pytest.mark.parametrize("path", BUILT, ids=name_of)
def test_dxf_part_areas_are_plate_minus_slots_within_the_kerf(exported, path):
    """Cut region = finished part grown by kerf/2: A_cut = A + (kerf/2) P, up to
    the corner terms (kerf/2)^2 sum tan(turn/2), bounded here by 1 mm^2."""
    e = exported[name_of(path)]
    regions = dxf_regions(e["dxf"])
    for plate in e["plates"]:
        assert plate["label"] in regions, f"label {plate['label']!r} not engraved inside a part"
        a_cut, per = regions[plate["label"]]
        want = expected_area_m2(e["glider"], plate) * 1e6
        assert a_cut - want == pytest.approx(KERF_MM / 2 * per, abs=1.0), plate["name"]


@pytest.mark.parametrize("path", BUILT, ids=name_of)
def test_dxf_without_kerf_has_exactly_the_plate_minus_slot_areas(path, tmp_path):
    out = tmp_path / "p.dxf"
    summary = pteromys.export(path, dxf=str(out), kerf_mm=0.0)
    assert summary["files"] == [str(out)]
    regions = dxf_regions(str(out))
    g = load(path)
    for plate in pteromys.slotted_plates(path, kerf_mm=0.0):
        want = expected_area_m2(g, plate) * 1e6
        assert regions[plate["label"]][0] == pytest.approx(want, rel=1e-9, abs=1e-6), plate["name"]


@pytest.mark.parametrize("path", BUILT, ids=name_of)
def test_dxf_engraving_lies_on_the_parts(exported, path):
    e = exported[name_of(path)]
    _, cut, _, lines, texts = read_dxf(e["dxf"])
    outer, holes = split_parts(cut)

    def on_material(q):
        for i in outer:
            if point_in_polygon(cut[i], q):
                return not any(point_in_polygon(cut[k], q) for k in holes.get(i, []))
        return False

    for a, b in lines:
        assert on_material(((a[0] + b[0]) / 2, (a[1] + b[1]) / 2))
    for text, pos, _h in texts:
        assert on_material(pos), text
    words = [t for t, _, _ in texts]
    assert "CG" in words
    assert any(w.startswith("paperclip") for w in words)
    for wing in e["glider"]["wings"]:
        assert wing["name"] in words  # wing position label on the fuselage


# ----------------------------------------------------------------- STEP (FreeCAD)

FREECAD_PROBE = textwrap.dedent("""
    import json, os
    import FreeCAD, Part
    files = json.load(open(os.environ["PTEROMYS_FC_IN"]))
    res = {}
    for name, path in files.items():
        shape = Part.read(path)
        solids = shape.Solids
        out = {"valid": shape.isValid(), "solids": []}
        for s in solids:
            faces = [f for f in s.Faces if f.Surface.__class__.__name__ == "Plane"]
            big = max(faces, key=lambda f: f.Area)
            n = big.normalAt(0, 0)
            out["solids"].append({"volume": s.Volume, "valid": s.isValid(), "normal": [n.x, n.y, n.z],
                                  "vertices": [[v.X, v.Y, v.Z] for v in s.Vertexes]})
        common = []
        for i in range(len(solids)):
            for j in range(i + 1, len(solids)):
                common.append([i, j, solids[i].common(solids[j]).Volume])
        out["common"] = common
        res[name] = out
    json.dump(res, open(os.environ["PTEROMYS_FC_OUT"], "w"))
""")


def freecad_read(files, tmp):
    exe = shutil.which("freecadcmd")
    assert exe, "freecadcmd is not installed (scripts/setup.sh installs Debian's freecad)"
    script, inp, out = tmp / "probe.py", tmp / "in.json", tmp / "out.json"
    script.write_text(FREECAD_PROBE)
    inp.write_text(json.dumps(files))
    # freecadcmd would open extra arguments as documents: file names go by environment
    r = subprocess.run([exe, str(script)], capture_output=True, text=True, timeout=900,
                       env=dict(os.environ, QT_QPA_PLATFORM="offscreen", PTEROMYS_FC_IN=str(inp),
                                PTEROMYS_FC_OUT=str(out)))
    assert out.exists(), f"freecadcmd did not read the STEP files:\n{r.stdout[-2000:]}\n{r.stderr[-2000:]}"
    return json.loads(out.read_text())


@pytest.fixture(scope="module")
def freecad_steps(exported, tmp_path_factory):
    return freecad_read({n: e["step"] for n, e in exported.items()}, tmp_path_factory.mktemp("fc"))


@pytest.mark.parametrize("path", BUILT, ids=name_of)
def test_step_has_one_valid_solid_per_plate_of_area_times_thickness(exported, freecad_steps, path):
    n = name_of(path)
    e, fc = exported[n], freecad_steps[n]
    assert fc["valid"]
    assert len(fc["solids"]) == len(e["plates"])
    assert e["summary"]["step_solids"] == [p["name"] for p in e["plates"]]
    for plate, solid in zip(e["plates"], fc["solids"]):
        assert solid["valid"]
        want = expected_area_m2(e["glider"], plate) * 1e6 * T_MM  # mm^3
        assert solid["volume"] == pytest.approx(want, rel=1e-6), plate["name"]


@pytest.mark.parametrize("path", BUILT, ids=name_of)
def test_step_solids_do_not_interpenetrate(freecad_steps, path):
    for i, j, v in freecad_steps[name_of(path)]["common"]:
        assert v < 1e-6, f"solids {i} and {j} share {v} mm^3"


@pytest.mark.parametrize("path", BUILT, ids=name_of)
def test_step_wings_sit_at_their_mounting_angle_and_position(exported, freecad_steps, path):
    """Angle from the normal of the wing solid's largest face (within 0.05 deg);
    position: the planform's outer corners, placed by the mount (x, y) and
    turned by the angle, are vertices of the solid within 0.1 mm."""
    n = name_of(path)
    e, fc = exported[n], freecad_steps[n]
    for plate, solid in zip(e["plates"], fc["solids"]):
        if plate["kind"] != "wing":
            continue
        w = next(w for w in e["glider"]["wings"] if w["name"] == plate["wing"])
        nx, ny, nz = solid["normal"]
        if ny < 0:
            nx, ny = -nx, -ny
        assert abs(nz) < 1e-9
        assert math.degrees(math.atan2(-nx, ny)) == pytest.approx(w["mount"]["angle_deg"], abs=0.05)
        th = math.radians(w["mount"]["angle_deg"])
        verts = np.array(solid["vertices"])
        checked = 0
        for x, z in w["outline_m"]:
            if abs(z) < 0.005 or (plate["half"] == "right" and z < 0) or (plate["half"] == "left" and z > 0):
                continue
            for side in (-0.5, 0.5):
                want = np.array([(w["mount"]["x_m"] + x * math.cos(th)) * 1000 + side * T_MM * math.sin(th),
                                 (w["mount"]["y_m"] + x * math.sin(th)) * 1000 - side * T_MM * math.cos(th),
                                 z * 1000])
                assert np.min(np.linalg.norm(verts - want, axis=1)) < 0.1
                checked += 1
        assert checked >= 4


def test_fused_step_is_one_valid_solid(tmp_path):
    path = os.path.join(ROOT, "examples", "gliders", "swept-back.glider.json")
    out = tmp_path / "fused.step"
    r = run(["export", path, "--step", out, "--fused"])
    assert r.returncode == 0, r.stderr
    fc = freecad_read({"fused": str(out)}, tmp_path)["fused"]
    assert fc["valid"] and len(fc["solids"]) == 1
    g = load(path)
    t = g["material"]["thickness_m"]
    # sum of the plates minus each wing's t x t bar where it crosses the fuselage
    total = (area(g["fuselage"]["outline_m"]) + sum(area(w["outline_m"]) for w in g["wings"])) * t
    assert fc["solids"][0]["volume"] == pytest.approx(total * 1e9, rel=0.01)
    assert fc["solids"][0]["volume"] < total * 1e9


# ------------------------------------------------------------- refusals

@pytest.mark.parametrize("case", sorted(EXPECTED), ids=str)
def test_refusals_say_why_and_write_nothing(case, tmp_path):
    c = EXPECTED[case]
    glider = os.path.join(FAB, c["glider"])
    r = run(["export", glider, "--dxf", tmp_path / "a.dxf", "--step", tmp_path / "a.step",
             "--json", tmp_path / "a.json"] + c["args"])
    assert r.returncode == 2, r.stdout + r.stderr
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1, r.stderr
    for words in c["message"]:
        assert words in lines[0]
    assert os.listdir(tmp_path) == [], "a refused export left files behind"


def test_python_raises_input_error_with_the_same_words():
    c = EXPECTED["swept_wing_through_slot"]
    with pytest.raises(pteromys.InputError) as e:
        pteromys.slotted_plates(os.path.join(FAB, c["glider"]), joint="through_slot")
    for words in c["message"]:
        assert words in str(e.value)
    with pytest.raises(ValueError):  # InputError is a ValueError
        pteromys.slotted_plates(os.path.join(FAB, c["glider"]), joint={"main": "through_slot"})
    with pytest.raises(pteromys.InputError, match="kerf_mm must be a finite number"):
        pteromys.slotted_plates(EXAMPLES[0], kerf_mm=float("nan"))
    with pytest.raises(pteromys.InputError, match="nothing to write"):
        pteromys.export(EXAMPLES[0])


# ------------------------------------------------------------- Python API

def test_slotted_plates_follow_the_documented_shapes():
    g = load(os.path.join(ROOT, "examples", "gliders", "tapered.glider.json"))
    plates = pteromys.slotted_plates(g, kerf_mm=0.15, clearance_mm=-0.05, min_web_mm=1.5)
    assert [p["kind"] for p in plates][0] == "fuselage"
    t = g["material"]["thickness_m"]
    for p in plates:
        o = p["outline"]
        assert o.ndim == 2 and o.shape[1] == 2
        signed = 0.5 * np.sum(o[:, 0] * np.roll(o[:, 1], -1) - o[:, 1] * np.roll(o[:, 0], -1))
        assert signed > 0  # counter-clockwise
        for h in p["holes"]:
            hs = 0.5 * np.sum(h[:, 0] * np.roll(h[:, 1], -1) - h[:, 1] * np.roll(h[:, 0], -1))
            assert hs < 0  # clockwise
        M = p["transform"]
        assert M.shape == (4, 4)
        assert np.allclose(M[:3, :3] @ M[:3, :3].T, np.eye(3), atol=1e-12)
        assert np.linalg.det(M[:3, :3]) == pytest.approx(1.0)
        assert p["thickness_m"] == t
        for m in p["marks"]:
            assert m["kind"] in ("line", "cross", "text")
            assert m["points"].shape[1] == 2
        for j in p["joints"]:
            assert j["type"] in ("through_slot", "notch", "cross_lap", "halves")
            for s in j["slots"]:
                # slot width = thickness + clearance
                assert s["width_m"] == pytest.approx(t - 0.05e-3, abs=1e-15)
        # cut path = finished part grown by kerf / 2 = 0.075 mm
        grow = area(p["cut_outline"]) - area(o)
        assert grow == pytest.approx(0.075e-3 * perimeter(o), rel=0.02)
    for w in g["wings"]:
        p = next(p for p in plates if p["wing"] == w["name"])
        th = math.radians(w["mount"]["angle_deg"])
        # a wing point (x, z) sits at (x_m + x cos, y_m + x sin, z) (docs/theory.md)
        x, z = w["outline_m"][1]
        P = p["transform"] @ np.array([x, z, 0.0, 1.0])
        assert P[:3] == pytest.approx([w["mount"]["x_m"] + x * math.cos(th), w["mount"]["y_m"] + x * math.sin(th), z])


def test_python_export_writes_both_files_and_a_summary(tmp_path):
    g = pteromys.load_glider(os.path.join(ROOT, "examples", "gliders", "canard.glider.json"))
    s = pteromys.export(g, dxf=tmp_path / "c.dxf", step=tmp_path / "c.step", sheet_mm=(500, 300),
                        joint={"canard": "halves"})
    assert sorted(os.listdir(tmp_path)) == ["c.dxf", "c.step"]
    assert s["sheets"] >= 1 and s["sheet_mm"] == [500, 300]
    assert [j["type"] for j in s["joints"]][0] == "halves"
    assert len(s["assembly"]) >= 3
    plan = pteromys.fabrication_plan(g)
    assert [j["wing"] for j in plan["joints"]] == ["canard", "main"]


def test_help_documents_export():
    r = run(["--help"])
    assert "export" in r.stdout
    h = run(["export", "--help"])
    assert h.returncode == 0 and "usage: pteromys export GLIDER" in h.stdout
    for opt in ("--dxf", "--step", "--fused", "--kerf", "--clearance", "--min-web", "--sheet", "--joint"):
        assert opt in h.stdout


def test_layout_plot_is_drawn_from_the_dxf(exported, tmp_path):
    from pteromys import fabrication
    e = exported["tapered"]
    png = fabrication.plot_layout(e["dxf"], str(tmp_path / "layout.png"))
    assert os.path.getsize(png) > 10000
    png = fabrication.plot_assembly(e["path"], str(tmp_path / "assembly.png"))
    assert os.path.getsize(png) > 10000


def test_thickness_override_changes_slots_and_solids_not_the_mass(tmp_path):
    """A measured 1.2 mm board: slots 1.25 mm wide (clearance 0.05), solids 1.2 mm thick."""
    path = os.path.join(ROOT, "examples", "gliders", "tapered.glider.json")
    plates = pteromys.slotted_plates(path, thickness_mm=1.2)
    for p in plates:
        assert p["thickness_m"] == pytest.approx(1.2e-3)
        for j in p["joints"]:
            for s in j["slots"]:
                assert s["width_m"] == pytest.approx(1.25e-3)
    s = pteromys.export(path, step=tmp_path / "t.step", thickness_mm=1.2)
    for p, v in zip(plates, s["step_volumes_mm3"]):  # tapered: through slot and cross-lap, no halves
        assert v == pytest.approx(expected_area_m2(load(path), p) * 1e6 * 1.2, rel=1e-6)
    g = load(path)
    assert pteromys.mass_properties(g)["mass_kg"] == pytest.approx(
        pteromys.mass_properties(path)["mass_kg"])  # fabrication never changes the design


def test_independent_helpers_measure_what_they_claim():
    """The test's own geometry, on shapes with known answers."""
    sq = [[0, 0], [2, 0], [2, 2], [0, 2]]
    assert area(sq) == 4 and perimeter(sq) == 8
    assert area(clip_convex(sq, [[1, -1], [3, -1], [3, 3], [1, 3]])) == pytest.approx(2)
    assert area(clip_halfplane(sq, np.array([0.0, 1.0]), 0.5)) == pytest.approx(1)
    assert edges_cross(sq, [[1, 1], [3, 1], [3, 3], [1, 3]])
    assert not edges_cross(sq, [[0, 3], [2, 3], [2, 5], [0, 5]])  # collinear x edges, apart
    assert point_in_polygon(sq, (1, 1)) and not point_in_polygon(sq, (3, 1))
