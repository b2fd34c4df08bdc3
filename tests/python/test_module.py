"""The Python module: same results as the command, numpy in and out."""
import json
import math
import threading

import numpy as np
import pytest

import pteromys
from conftest import EXAMPLES, load, run


def test_module_reports_what_the_command_reports(tmp_path):
    out = tmp_path / "r.json"
    assert run(["evaluate", EXAMPLES[1], "--json", out]).returncode == 0
    cli = load(out)
    rep, flights = pteromys.evaluate(EXAMPLES[1])
    assert rep["mass_kg"] == cli["mass_kg"]
    assert [l["distance_m"] for l in rep["launches"]] == [l["distance_m"] for l in cli["launches"]]
    assert len(flights) == 6 and flights[0].shape[1] == len(pteromys.TRAJECTORY_COLUMNS)


def test_glider_accepts_dict_text_and_path():
    d = load(EXAMPLES[0])
    for src in (d, json.dumps(d), EXAMPLES[0]):
        g = pteromys.glider(src)
        assert g.wing_names == [w["name"] for w in d["wings"]]
    assert pteromys.glider_dict(EXAMPLES[0])["wings"][0]["mount"] == d["wings"][0]["mount"]


def test_bad_glider_raises_input_error_with_reason():
    d = load(EXAMPLES[0])
    d["wings"][0]["mount"]["y_m"] = 1.0
    with pytest.raises(pteromys.InputError, match="does not touch the fuselage"):
        pteromys.evaluate(d)
    assert issubclass(pteromys.InputError, ValueError)
    assert any("does not touch" in p for p in pteromys.validation_problems(d))


@pytest.mark.parametrize("kw, words", [
    ({"speed": float("nan")}, "speed must be a finite number"),
    ({"speed": -5.0}, "speed must not be negative"),
    ({"climb_deg": float("nan")}, "climb_deg must be a finite number"),
    ({"height": float("inf")}, "height must be a finite number"),
    ({"height": -1.0}, "height must not be negative"),
    ({"t_max": float("inf")}, "t_max must be in \\(0, 600\\] s"),  # reserved t_max / dt samples: was undefined
    ({"t_max": 1e6}, "t_max must be in \\(0, 600\\] s"),
    ({"pitch_deg": float("nan")}, "pitch_deg must be a finite number"),
    ({"pitch_rate_deg_s": float("-inf")}, "pitch_rate_deg_s must be a finite number"),
    ({"record_every": 0}, "record_every must be at least 1"),
    ({"dz": 0.5}, "dz must be in \\(0, 0.1\\] m"),  # was sliced into half-metre elements
    ({"dz": float("nan")}, "dz must be in \\(0, 0.1\\] m"),
])
def test_simulate_refuses_a_launch_it_cannot_fly(kw, words):
    # a NaN launch used to come back as a flight that "diverged (non-finite
    # state) at t = 0.002 s", which blames the simulation for the input
    with pytest.raises(pteromys.InputError, match=words):
        pteromys.simulate(EXAMPLES[0], **kw)


def test_simulate_flies_one_launch_from_any_height():
    # no upper bound on one launch (the standard launches of evaluate take
    # the command's 0-100 m): a level ballistic throw at 7 m/s from 150 m
    # lands after the free fall time sqrt(2 h / g), 7 m/s times that away
    f = pteromys.simulate(EXAMPLES[0], speed=7.0, height=150.0, t_max=60.0, ballistic=True)
    t = math.sqrt(2 * 150.0 / 9.81)
    assert f["end"] == "ground"
    assert f["flight_time_s"] == pytest.approx(t, rel=1e-4) and f["distance_m"] == pytest.approx(7.0 * t, rel=1e-4)


def test_evaluate_refuses_a_non_finite_height_and_a_zero_record_step():
    with pytest.raises(pteromys.InputError, match="height must be a finite number"):
        pteromys.evaluate(EXAMPLES[0], height=float("nan"))
    with pytest.raises(pteromys.InputError, match="height must be between 0 and 100 m"):
        pteromys.evaluate(EXAMPLES[0], height=150.0)
    with pytest.raises(pteromys.InputError, match="record_every must be at least 1"):
        pteromys.evaluate(EXAMPLES[0], record_every=0)
    # the commands' --dz bound, (0, 0.1] m; evaluate and mount took any positive dz
    with pytest.raises(pteromys.InputError, match="dz must be in \\(0, 0.1\\] m"):
        pteromys.evaluate(EXAMPLES[0], dz=1.0)
    with pytest.raises(pteromys.InputError, match="dz must be in \\(0, 0.1\\] m"):
        pteromys.mount(EXAMPLES[0], dz=0.0)


def test_slice_wing_areas_sum_to_planform():
    g = load(EXAMPLES[0])
    outline = np.array(g["wings"][0]["outline_m"])
    el = pteromys.slice_wing(outline, 0.005)
    x, z = outline[:, 0], outline[:, 1]
    shoelace = 0.5 * abs(np.dot(x, np.roll(z, -1)) - np.dot(np.roll(x, -1), z))
    assert el["area"].sum() == pytest.approx(shoelace, rel=1e-12)


def test_model_eval_broadcasts_and_keeps_parity():
    m = pteromys.default_model()
    a = np.linspace(-30, 30, 61)
    cd, cl, cm = m.eval(a, 2e4)
    assert cd.shape == a.shape
    assert np.array_equal(cd, cd[::-1]) and np.array_equal(cl, -cl[::-1]) and np.array_equal(cm, -cm[::-1])


def test_forces_tables_match_direct():
    mg = pteromys.mount(EXAMPLES[0])
    v, gam = np.meshgrid(np.linspace(6, 9, 4), np.linspace(-10, 10, 21))
    t = mg.forces(v, gam)
    d = mg.forces(v, gam, direct=True)
    w = mg.mass_kg * 9.81
    for a, b in zip(t, d):
        assert np.max(np.abs(a - b)) < 2e-3 * max(w, np.max(np.abs(d[1])))


def test_ballistic_flight_from_python_is_a_parabola():
    f = pteromys.simulate(EXAMPLES[0], speed=8, climb_deg=20, ballistic=True)
    s = f["samples"]
    t = s[:-1, 0]
    vx, vy = 8 * math.cos(math.radians(20)), 8 * math.sin(math.radians(20))
    np.testing.assert_allclose(s[:-1, 1], vx * t, atol=1e-10)
    np.testing.assert_allclose(s[:-1, 2], 1.5 + vy * t - 0.5 * 9.81 * t * t, atol=1e-10)


def test_calls_from_threads_give_identical_results():
    """Long calls release the GIL; results must not depend on concurrency."""
    ref = pteromys.evaluate(EXAMPLES[2])[0]
    results = []
    ts = [threading.Thread(target=lambda: results.append(pteromys.evaluate(EXAMPLES[2])[0])) for _ in range(4)]
    for t in ts:
        t.start()
    for t in ts:
        t.join()
    assert all(r == ref for r in results)
