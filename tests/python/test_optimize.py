"""pteromys optimize: the command-line contract and the Python API (issue 3)."""
import json
import os

import pytest

import pteromys
from conftest import BROKEN_DIR, EXAMPLES, load, run


def zero_angles(path, tmp_path):
    g = load(path)
    for w in g["wings"]:
        w["mount"]["angle_deg"] = 0.0
    p = tmp_path / "start.glider.json"
    p.write_text(json.dumps(g))
    return p


@pytest.mark.parametrize("path", EXAMPLES, ids=os.path.basename)
def test_optimize_writes_a_flyable_glider_and_report(path, tmp_path):
    start = zero_angles(path, tmp_path)
    out, rep = tmp_path / "out.glider.json", tmp_path / "report.json"
    r = run(["optimize", start, "-o", out, "--json", rep])
    assert r.returncode == 0, r.stderr
    g = load(out)
    assert g["format"] == "pteromys-glider/1"
    report = load(rep)
    assert report["format"] == "pteromys-report/1" and report["flyable"], report["reasons"]
    # The written glider is a valid glider file whose evaluation agrees with the report.
    ev = tmp_path / "eval.json"
    assert run(["evaluate", out, "--json", ev]).returncode == 0
    assert load(ev)["launches"] == report["launches"]
    assert [m["angle_deg"] for m in report["mounts"]] == [w["mount"]["angle_deg"] for w in g["wings"]]
    opt = report["optimisation"]
    assert opt["cost"]["total"] <= opt["cost_start"]["total"]
    for l in report["launches"][:4]:
        assert l["stable"] and l["distance_m"] >= 5.0


def test_locks_from_the_command_line(tmp_path):
    start = zero_angles(EXAMPLES[0], tmp_path)
    out = tmp_path / "out.glider.json"
    r = run(["optimize", start, "-o", out, "--lock", "main.angle,tail.x"])
    assert r.returncode == 0, r.stderr
    a, b = load(start), load(out)
    assert b["wings"][0]["mount"]["angle_deg"] == a["wings"][0]["mount"]["angle_deg"]
    assert b["wings"][1]["mount"]["x_m"] == a["wings"][1]["mount"]["x_m"]


def test_bad_lock_name_is_named(tmp_path):
    r = run(["optimize", EXAMPLES[0], "-o", tmp_path / "o.json", "--lock", "rudder.angle"])
    assert r.returncode != 0 and "rudder.angle" in r.stderr
    assert not (tmp_path / "o.json").exists()


@pytest.mark.parametrize("value", ["2.5", "0"])
def test_a_fractional_or_zero_evaluation_budget_is_refused(tmp_path, value):
    # 2.5 was cut to 2 evaluations without a word
    r = run(["optimize", EXAMPLES[0], "-o", tmp_path / "o.json", "--max-evaluations", value])
    assert r.returncode != 0
    assert "--max-evaluations must be a whole number between 1 and 10000000" in r.stderr
    assert not (tmp_path / "o.json").exists()


def test_missing_output_option():
    r = run(["optimize", EXAMPLES[0]])
    assert r.returncode != 0 and "-o" in r.stderr


def test_broken_glider_leaves_nothing(tmp_path):
    r = run(["optimize", os.path.join(BROKEN_DIR, "wing_off_fuselage.glider.json"), "-o", tmp_path / "o.json",
             "--json", tmp_path / "r.json"])
    assert r.returncode != 0 and "does not touch the fuselage" in r.stderr
    assert list(tmp_path.iterdir()) == []


def test_paper_cost_and_baseline_algorithm(tmp_path):
    """--w4 0 is the paper's cost exactly; --algorithm steepest is the paper's method."""
    start = zero_angles(EXAMPLES[0], tmp_path)
    rep = tmp_path / "r.json"
    r = run(["optimize", start, "-o", tmp_path / "o.json", "--json", rep, "--w4", "0", "--algorithm", "steepest"])
    assert r.returncode == 0, r.stderr
    o = load(rep)["optimisation"]
    assert o["algorithm"] == "steepest"
    c = o["cost"]
    assert c["total"] == pytest.approx(100 * c["c1"] + c["c2"] + c["c3"], rel=1e-12)


def test_python_optimize_and_warm_start():
    g = pteromys.glider_dict(EXAMPLES[1])
    for w in g["wings"]:
        w["mount"]["angle_deg"] = 0.0
    a = pteromys.optimize(g)
    assert a["report"]["flyable"] and len(a["flights"]) == 6
    g2 = a["glider"]
    g2["wings"][0]["outline_m"] = [[x * 1.02, z] for x, z in g2["wings"][0]["outline_m"]]
    b = pteromys.optimize(g2, warm_start=a["state"])
    assert b["report"]["flyable"]
    with pytest.raises(pteromys.InputError, match="no such variable"):
        pteromys.optimize(g, locks=["nose.angle"])


@pytest.mark.parametrize("kw, words", [
    # the standard launches' height: evaluate and the commands refuse > 100 m
    ({"height": 150.0}, "height must be between 0 and 100 m"),
    ({"height": float("nan")}, "height must be a finite number"),
    ({"dz": 0.5}, "dz must be in \\(0, 0.1\\] m"),
    # an infinite weight made every cost infinite or NaN, and the optimiser
    # stopped at once with the design unchanged
    ({"w1": float("inf")}, "cost weights must be finite and non-negative"),
    ({"w4": float("nan")}, "static-margin weight and target must be finite and non-negative"),
    ({"min_overlap": 1.5}, "minimum root overlap must be a fraction between 0 and 1"),
    ({"speed_range": (3.0, float("inf"))}, "region Omega must have finite"),
    ({"angle_range_deg": (float("-inf"), 10.0)}, "angle bounds must be finite"),
    ({"min_wing_gap_mm": float("inf")}, "minimum gap between wings must be finite"),
    ({"max_evaluations": 0}, "number of evaluations must be at least 1"),
])
def test_python_optimize_refuses_options_it_cannot_use(kw, words):
    with pytest.raises(pteromys.InputError, match=words):
        pteromys.optimize(pteromys.glider_dict(EXAMPLES[1]), **kw)
