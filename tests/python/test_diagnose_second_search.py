"""The second search concluded after a first result (issue 7; docs/diagnosis.md,
"Second search"): `pteromys.diagnose(..., theory_starts=True, first=result)`,
what the FreeCAD command runs when asked to search again after an
`unexplained` verdict. Its own file (and so its own ctest entry and
timeout): it makes four diagnoses.
"""
import pytest

from conftest import load, run
from test_diagnose import FAST, _generate


@pytest.fixture(scope="module")
def camera_first(tmp_path_factory):
    """test_diagnose.py's camera case (a camera 9 % too close and rolled 6
    degrees, 10 frames per second, 2 cm noise) and its plain diagnosis, to
    stand for a first search."""
    tmp = tmp_path_factory.mktemp("second_camera")
    ds = _generate(tmp, "data", "camera", "camera=3", extra=["--frame-rate", "10", "--noise-m", "0.02"])
    out = tmp / "diagnosis.json"
    r = run(["diagnose", ds, "--json", out] + FAST)
    assert r.returncode == 0, r.stderr[-3000:]
    return ds, load(out)


@pytest.fixture(scope="module")
def kept_second(camera_first):
    """The second search after the fixture's result taken as an
    `unexplained` first search (what the FreeCAD command runs), and its
    progress (stage, message)."""
    import pteromys
    ds, plain = camera_first
    first = dict(plain, verdict="unexplained", escalation={"ran": False})
    msgs = []
    k = pteromys.diagnose(str(ds), max_centres=2, folds=3, threads=2, theory_starts=True, first=first,
                          progress=lambda p: msgs.append((p["stage"], p["message"])))
    return k, msgs


def test_a_second_search_after_a_first_result_is_concluded_against_its_baseline(tmp_path, camera_first,
                                                                                 kept_second):
    """theory_starts with first= (the FreeCAD command's second search after
    an `unexplained` first search): the second search is the plain
    --theory-starts diagnosis (an independent CLI run), concluded as
    --escalate concludes its own. The fixture's result, taken as the first
    search's `unexplained`, has a baseline the named effect beats by far:
    the second result stands, with the first search recorded and the shrink
    against the first baseline 1 - effect / first baseline. Given a first
    baseline only 2 % worse than the effect (effect / 0.98), under the 5 %
    margin: the first result stands (`unexplained`), naming the effect as
    demoted and saying why before its own summary."""
    import pteromys
    ds, plain = camera_first
    out = tmp_path / "second.json"
    r = run(["diagnose", ds, "--json", out, "--theory-starts"] + FAST)
    assert r.returncode == 0, r.stderr[-3000:]
    second = load(out)
    # camera at three times its nominal size: the second search names it,
    # else the demotion below has nothing to act on
    assert second["verdict"] == "camera", second["summary"]
    eff = next(e for e in second["effects"] if e["name"] == "camera")["holdout_rmse_m"]
    first = dict(plain, verdict="unexplained", escalation={"ran": False})
    base = plain["baseline"]["holdout_rmse_m"]
    assert 1 - eff / base > 0.05  # so it stands
    k, msgs = kept_second
    assert k["verdict"] == "camera" and k["effects"] == second["effects"]
    esc = k["escalation"]
    assert esc["ran"] is True and esc["first_verdict"] == "unexplained" and esc["demoted"] == ""
    assert esc["first_best"] == plain["effects"][0]["name"]
    assert esc["first_holdout_rmse_m"] == pytest.approx(base, rel=1e-12)
    assert esc["shrink_against_first"] == pytest.approx(1 - eff / base, rel=1e-9)
    assert k["summary"].startswith("Searched from the baseline, no candidate closed the gap; started at their "
                                   "theoretical sizes, camera does. ")
    # timed as --escalate times both searches
    assert k["timings"]["first_search_s"] == plain["timings"]["total_s"]
    assert k["timings"]["total_s"] == pytest.approx(k["timings"]["first_search_s"] + k["timings"]["second_search_s"])
    assert [m for m in msgs if m[0] == "done"] == [msgs[-1]] and msgs[-1][1].startswith("camera: ")
    # a first baseline the effect beats by only 2 %; its summary ends, as
    # an `unexplained` one made without the second search does, by
    # pointing to it, which the demoted result no longer does
    hint = (" A second search with every aerodynamic correction also started at its theoretical size (--escalate; "
            "Python escalate=True) can still find an effect the step from strength 0 misses; it takes several "
            "times as long.")
    first2 = dict(first, baseline=dict(plain["baseline"], holdout_rmse_m=eff / 0.98), summary=plain["summary"] + hint)
    msgs = []
    k2 = pteromys.diagnose(str(ds), max_centres=2, folds=3, threads=2, theory_starts=True, first=first2,
                           progress=lambda p: msgs.append((p["stage"], p["message"])))
    assert k2["verdict"] == "unexplained" and k2["effects"] == plain["effects"]
    esc = k2["escalation"]
    assert esc["ran"] is True and esc["demoted"] == "camera"
    assert esc["shrink_against_first"] == pytest.approx(0.02, rel=1e-9)
    assert k2["summary"].endswith(plain["summary"]) and "--escalate" not in k2["summary"]
    assert k2["summary"].startswith("Searched twice, from the baseline and from every aerodynamic correction's "
                                    "theoretical size: the second search fitted camera")
    assert "2.0 % better than the first search's" in k2["summary"] and "under the 5.0 % margin" in k2["summary"]
    assert k2["timings"]["second_search_s"] > 0 and k2["timings"]["first_search_s"] == plain["timings"]["total_s"]
    assert k2["timings"]["total_s"] == pytest.approx(k2["timings"]["first_search_s"] + k2["timings"]["second_search_s"])
    assert [m for m in msgs if m[0] == "done"] == [msgs[-1]] and msgs[-1][1].startswith("unexplained: Searched twice")


def test_a_stability_check_after_a_second_search_searches_twice_again(camera_first, kept_second):
    """The FreeCAD command's check of a verdict the second search named
    (stability=2, first= that result, the second search's options): the
    re-run makes both searches again, as --escalate does, so that its
    verdict, too, has to beat its own first search's baseline; a re-run
    from the theoretical sizes alone would skip that test. Seen in its
    progress: every start from a theoretical size belongs to a second
    search, and starts from strength 0 come first. Its sentence says so."""
    import pteromys
    ds, plain = camera_first
    k, _ = kept_second
    assert k["verdict"] == "camera" and k["escalation"]["ran"] is True
    msgs = []
    c = pteromys.diagnose(str(ds), max_centres=2, folds=3, threads=2, theory_starts=True, stability=2, first=k,
                          progress=lambda p: msgs.append((p["stage"], p["message"])))
    head = "stability check 1/1 (step 1.9 ms): "
    assert msgs and all(m.startswith(head) for _, m in msgs), msgs[:3]
    body = [m[len(head):] for stage, m in msgs if stage != "done"]
    theory = [m for m in body if "from its theoretical size" in m or ("switched on" in m and "theoretical" in m)]
    assert all(m.startswith("second search: ") for m in theory), theory[:3]
    # the re-run's first search is a plain one: it starts from strength 0
    assert not body[0].startswith("second search: ")
    st = c["stability"]
    assert [x["dt_s"] for x in st["runs"]] == pytest.approx([0.002, 0.0019])
    assert st["runs"][0]["verdict"] == "camera"
    assert st["sentence"].startswith("Re-run, both searches each time, with the simulation step changed slightly")
    assert c["verdict"] == "camera" and c["effects"] == k["effects"] and c["escalation"] == k["escalation"]
