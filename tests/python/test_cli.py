"""The command-line contract of spec/formats.md for evaluate and simulate."""
import csv
import math
import os

import pytest

from conftest import EXAMPLES, BROKEN_DIR, broken_cases, load, run


def polygon_area_centroid(pts):
    """Shoelace area and centroid (independent of the engine)."""
    a = cx = cy = 0.0
    n = len(pts)
    for i in range(n):
        x0, y0 = pts[i]
        x1, y1 = pts[(i + 1) % n]
        c = x0 * y1 - x1 * y0
        a += c
        cx += (x0 + x1) * c
        cy += (y0 + y1) * c
    a /= 2
    return abs(a), (cx / (6 * a), cy / (6 * a))


def expected_mass_and_cg(g):
    t = g["material"]["thickness_m"]
    rho = g["material"]["density_kg_m3"]
    a, (cx, cy) = polygon_area_centroid(g["fuselage"]["outline_m"])
    m = rho * t * a
    sx, sy = m * cx, m * cy
    for w in g["wings"]:
        aw, (wx, _wz) = polygon_area_centroid(w["outline_m"])
        mw = rho * t * aw
        th = math.radians(w["mount"]["angle_deg"])
        px = w["mount"]["x_m"] + wx * math.cos(th)
        py = w["mount"]["y_m"] + wx * math.sin(th)
        m += mw
        sx += mw * px
        sy += mw * py
    for b in g.get("ballast", []):
        m += b["mass_kg"]
        sx += b["mass_kg"] * b["x_m"]
        sy += b["mass_kg"] * b["y_m"]
    return m, (sx / m, sy / m)


def test_help_lists_the_commands():
    r = run(["--help"])
    assert r.returncode == 0
    for c in ("evaluate", "simulate"):
        assert c in r.stdout
    for c in ("evaluate", "simulate"):
        h = run([c, "--help"])
        assert h.returncode == 0 and "usage: pteromys " + c in h.stdout


def test_unknown_command_fails_with_one_line():
    r = run(["fly-to-the-moon"])
    assert r.returncode != 0
    assert len(r.stderr.strip().splitlines()) == 1


@pytest.mark.parametrize("path", EXAMPLES, ids=os.path.basename)
def test_evaluate_writes_the_spec_report(path, tmp_path):
    out = tmp_path / "report.json"
    r = run(["evaluate", path, "--json", out])
    assert r.returncode == 0, r.stderr
    rep = load(out)
    assert rep["format"] == "pteromys-report/1"
    g = load(path)
    m, (cx, cy) = expected_mass_and_cg(g)
    assert rep["mass_kg"] == pytest.approx(m, rel=1e-9)
    assert rep["cg_m"] == pytest.approx([cx, cy], abs=1e-9)
    assert rep["inertia_kg_m2"] > 0
    assert [w["wing"] for w in rep["mounts"]] == [w["name"] for w in g["wings"]]
    assert isinstance(rep["flyable"], bool) and isinstance(rep["reasons"], list)
    if not rep["flyable"]:
        assert rep["reasons"], "an unflyable design must say why"
    got = [(l["speed_m_s"], l["angle_deg"], l["height_m"]) for l in rep["launches"]]
    assert got == [(7, 0, 1.5), (7, 10, 1.5), (9, 0, 1.5), (9, 10, 1.5), (11, 0, 1.5), (11, 10, 1.5)]
    for l in rep["launches"]:
        assert l["flight_time_s"] > 0 and isinstance(l["stable"], bool)


def test_evaluate_launch_height_option(tmp_path):
    out = tmp_path / "r.json"
    assert run(["evaluate", EXAMPLES[0], "--json", out, "--height", "2.5"]).returncode == 0
    assert {l["height_m"] for l in load(out)["launches"]} == {2.5}


@pytest.mark.parametrize("path", EXAMPLES[:3], ids=os.path.basename)
def test_simulate_writes_trajectories(path, tmp_path):
    out = tmp_path / "traj.csv"
    r = run(["simulate", path, "--csv", out])
    assert r.returncode == 0, r.stderr
    with open(out) as f:
        header = f.readline().strip()
        rows = list(csv.reader(f))
    assert header == "launch,t_s,x_m,y_m,pitch_deg,speed_m_s"
    launches = sorted({int(r[0]) for r in rows})
    assert launches == [0, 1, 2, 3, 4, 5]
    speeds = [7, 7, 9, 9, 11, 11]
    for k in launches:
        first = next(r for r in rows if int(r[0]) == k)
        assert float(first[1]) == 0 and float(first[2]) == 0 and float(first[3]) == pytest.approx(1.5)
        assert float(first[5]) == pytest.approx(speeds[k])


@pytest.mark.parametrize("every", ["0", "2.5", "-1"])
def test_simulate_refuses_an_every_that_is_not_a_positive_whole_number(every, tmp_path):
    out = tmp_path / "traj.csv"
    r = run(["simulate", EXAMPLES[0], "--csv", out, "--every", every])
    assert r.returncode == 2 and "--every must be a positive whole number" in r.stderr, r.stderr
    assert not out.exists()


def test_simulate_requires_csv():
    r = run(["simulate", EXAMPLES[0]])
    assert r.returncode != 0 and "--csv" in r.stderr


@pytest.mark.parametrize("name,fragment", broken_cases())
def test_broken_files_are_rejected_by_the_command(name, fragment, tmp_path):
    out = tmp_path / "r.json"
    r = run(["evaluate", os.path.join(BROKEN_DIR, name), "--json", out])
    assert r.returncode != 0
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1, r.stderr
    assert fragment in lines[0]
    assert not out.exists(), "no output may be left behind"
    assert list(tmp_path.iterdir()) == []


def test_unwritable_output_is_reported_before_work(tmp_path):
    r = run(["evaluate", EXAMPLES[0], "--json", tmp_path / "no-such-dir" / "r.json"])
    assert r.returncode != 0 and "does not exist" in r.stderr


def test_bad_options_are_named(tmp_path):
    for args, frag in [(["--dz", "abc"], "--dz"), (["--dt", "-1"], "--dt"), (["--frobnicate"], "--frobnicate"),
                       (["--model", "/nonexistent.json"], "no such file"), (["--integrator", "euler"], "verlet")]:
        r = run(["evaluate", EXAMPLES[0], "--json", tmp_path / "r.json"] + args)
        assert r.returncode != 0 and frag in r.stderr, (args, r.stderr)


def test_model_option_changes_the_physics(tmp_path):
    """A flat-plate model with half the lift slope must change the report."""
    import json
    model = tmp_path / "half.model.json"
    model.write_text(json.dumps({"format": "pteromys-model/1", "type": "flat_plate",
                                 "params": {"section_lift_slope_per_rad": 2.8}}))
    a, b = tmp_path / "a.json", tmp_path / "b.json"
    assert run(["evaluate", EXAMPLES[0], "--json", a]).returncode == 0
    assert run(["evaluate", EXAMPLES[0], "--json", b, "--model", model]).returncode == 0
    ra, rb = load(a), load(b)
    assert ra["launches"][0]["distance_m"] != rb["launches"][0]["distance_m"]
