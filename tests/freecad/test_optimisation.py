"""Automatic optimisation in the recompute loop (needs pteromys.optimize, issue 3).

A design that cannot fly as drawn must fly after optimisation; the reference
is the engine's own verdict on the written glider file through the separate
`pteromys` command, and the lock is checked exactly.
"""
import json
import subprocess

import pytest

from conftest import PTEROMYS_BIN, TEMPLATE_FACTS, feature_reason, require


def test_optimisation_makes_a_badly_mounted_glider_fly(fc, tmp_path):
    """The tail set at +6 deg (nose-down trim) cannot fly; optimisation finds mounts that do,
    keeps a locked variable, and the command line confirms the optimised file flies."""
    reason = feature_reason("optimize")
    out = tmp_path / "opt.glider.json"
    r = fc(TEMPLATE_FACTS + '''
doc = App.newDocument("T")
g = pf.new_glider(doc, auto_optimise=False)
tail = [w for w in g.Wings if w.WingName == "tail"][0]
main = [w for w in g.Wings if w.WingName == "main"][0]
tail.MountAngle = 6.0
main.LockAngle = True
doc.recompute()
RESULT["as_designed"] = facts(g)
g.AutoOptimise = True
doc.recompute()
RESULT["optimised"] = facts(g)
if not g.Problems:
    pf.export_glider_file(g, %r)
# a small edit afterwards: warm-started re-optimisation
main.Sketch.setDatum("Span", App.Units.Quantity("440 mm"))
doc.recompute()
RESULT["edited"] = facts(g)
''' % str(out))
    d = r["as_designed"]["results"]
    assert d["problems"] == [] and d["flyable"] is False, d["status"]
    o = r["optimised"]["results"]
    if reason:
        assert reason in " ".join(o["warnings"]), o["warnings"]
        pytest.fail("cannot test optimisation: " + reason)
    assert o["problems"] == [], o["problems"]
    assert o["optimised"] is True
    assert o["flyable"] is True, o["reasons"]
    mw = r["optimised"]["wings"]
    assert mw["main"]["mounted"][2] == pytest.approx(mw["main"]["design"][2], abs=1e-9)   # locked
    assert abs(mw["tail"]["mounted"][2] - 6.0) > 0.5                                      # moved
    # Independent confirmation through the command line on the written file.
    rep = tmp_path / "rep.json"
    p = subprocess.run([PTEROMYS_BIN, "evaluate", str(out), "--json", str(rep)], capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    cli = json.loads(rep.read_text())
    assert cli["flyable"] is True, cli["reasons"]
    assert [l["distance_m"] for l in cli["launches"]] == pytest.approx(o["launch_distances_m"], rel=1e-6)
    e = r["edited"]["results"]
    assert e["problems"] == [] and e["flyable"] is True, e["status"]


def test_optimise_now_stores_the_result_in_the_design(fc):
    """With automatic optimisation off, 'Optimise now' writes the optimised
    mounts into the design values (MountX...), which then stay as they are;
    a locked variable keeps its design value; optimising the ballast moves it."""
    require("optimize")
    r = fc('''
doc = App.newDocument("O")
g = pf.new_glider(doc, auto_optimise=False)
W = {w.WingName: w for w in g.Wings}
W["tail"].MountAngle = 6.0
W["main"].LockY = True
doc.recompute()
RESULT["before"] = pf.results(g)
res = pf.optimise_now(g)
RESULT["after"] = res
RESULT["design"] = {n: [w.MountX.Value, w.MountY.Value, w.MountAngle.getValueAs("deg").Value] for n, w in W.items()}
RESULT["mounted"] = {n: [w.MountedX.Value, w.MountedY.Value, w.MountedAngle.getValueAs("deg").Value] for n, w in W.items()}
doc.recompute()                         # nothing changed: the stored design stays as it is
RESULT["again"] = pf.results(g)
g.OptimiseBallast = True
g.BallastX = -60.0                      # a poor start far behind the nose
doc.recompute()
pf.optimise_now(g)
RESULT["ballast_x"] = [g.BallastX.Value, g.BallastPlacedX.Value]
RESULT["ballast_flyable"] = g.Flyable
''')
    b, a = r["before"], r["after"]
    assert b["flyable"] is False and a["flyable"] is True, a["status"]
    assert a["optimised"] is False            # automatic optimisation stays off: the design itself flies now
    for n in ("main", "tail"):
        assert r["mounted"][n] == pytest.approx(r["design"][n], abs=1e-9)
    assert r["design"]["main"][1] == pytest.approx(4.0, abs=1e-12)                    # LockY held
    assert r["again"]["launch_distances_m"] == pytest.approx(a["launch_distances_m"], rel=1e-12)
    bx, placed = r["ballast_x"]
    assert bx == pytest.approx(placed, abs=1e-9) and abs(bx + 60.0) > 1.0 and r["ballast_flyable"]
