"""The reference simulator from Python and `pteromys generate` (issue 6).

Datasets are read back with Python's json and csv modules (independent of the
engine's reader); planform areas are checked with the shoelace formula;
physical reference values say where they come from.
"""
import csv
import json
import math
import os

import numpy as np
import pytest

import pteromys
from conftest import ROOT, run

TRAINING = os.path.join(ROOT, "examples", "training")
CANARD = os.path.join(TRAINING, "t17-canard.glider.json")
DELTA = os.path.join(TRAINING, "t11-delta.glider.json")


def read_csv(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    flights = {}
    for r in rows:
        flights.setdefault(r["flight"], []).append(r)
    return rows, flights


def shoelace(p):
    x, z = p[:, 0], p[:, 1]
    return 0.5 * abs(np.dot(x, np.roll(z, -1)) - np.dot(z, np.roll(x, -1)))


# ------------------------------------------------------------ planforms

@pytest.mark.parametrize("kind", ["rectangular", "elliptical", "zimmerman", "inverse_zimmerman", "delta"])
@pytest.mark.parametrize("aspect", [0.5, 1.0, 2.0])
def test_planforms_have_the_requested_aspect_ratio(kind, aspect):
    p = pteromys.planform(kind, aspect, root_chord=0.2, n=400)
    span = 2 * p[:, 1].max()
    area = shoelace(p)
    # the curved planforms are polygons with 400 points per quarter: 0.1 %
    assert span ** 2 / area == pytest.approx(aspect, rel=1e-3)
    assert p[:, 0].max() - p[:, 0].min() == pytest.approx(0.2, rel=1e-9)
    assert p[:, 1].min() == pytest.approx(-p[:, 1].max())


def test_unknown_planform_is_refused():
    with pytest.raises(ValueError):
        pteromys.planform("hexagon", 1.0)


# ------------------------------------------------------------ physics

def test_elliptic_wing_has_the_least_induced_drag():
    """Prandtl: C_Di = C_L^2 / (pi A) for elliptic loading; a rectangle of the
    same aspect ratio has more (Glauert's delta ~ 0.02-0.05 at A = 6)."""
    A = 6.0
    e = pteromys.reference_potential(pteromys.planform("elliptical", A, 0.1, n=200), 4.0, span_panels=20)
    r = pteromys.reference_potential(pteromys.planform("rectangular", A, 0.1), 4.0, span_panels=20)
    assert e["cdi"] / (e["cl"] ** 2 / (math.pi * A)) == pytest.approx(1.0, abs=0.02)
    delta = r["cdi"] / (r["cl"] ** 2 / (math.pi * A)) - 1
    assert 0.01 < delta < 0.08


def test_polar_of_a_flat_plate_is_odd_and_drag_even():
    p = pteromys.planform("rectangular", 2.0, 0.1)
    a = np.array([2.0, 6.0, 12.0, 25.0])
    cl, cd, _ = pteromys.reference_polar(p, a, reynolds=5e4)
    cl_n, cd_n, _ = pteromys.reference_polar(p, -a, reynolds=5e4)
    np.testing.assert_allclose(cl_n, -cl, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(cd_n, cd, rtol=1e-9, atol=1e-12)
    # zero-lift drag: Blasius on both faces 2.656/sqrt(Re) plus edges 0.5 t/c
    cl0, cd0, _ = pteromys.reference_polar(p, np.array([0.0]), reynolds=5e4, thickness_m=0.001)
    assert cl0[0] == pytest.approx(0.0, abs=1e-12)
    assert cd0[0] == pytest.approx(2.656 / math.sqrt(5e4) + 0.5 * 0.001 / 0.1, rel=1e-6)


def test_effect_switches_change_only_what_they_should():
    # ground effect off: no height dependence; pitch damping off: no pitch-rate dependence
    base = pteromys.reference_forces(CANARD, 8.0, 3.0, height_m=0.1, effects="finite_span,downwash")
    high = pteromys.reference_forces(CANARD, 8.0, 3.0, height_m=5.0, effects="finite_span,downwash")
    assert [float(x) for x in base] == [float(x) for x in high]
    spin = pteromys.reference_forces(CANARD, 8.0, 3.0, pitch_rate_deg_s=200.0, effects="finite_span,downwash")
    assert [float(x) for x in spin] == [float(x) for x in base]
    damped = pteromys.reference_forces(CANARD, 8.0, 3.0, pitch_rate_deg_s=200.0)
    still = pteromys.reference_forces(CANARD, 8.0, 3.0)
    assert float(damped[2]) != float(still[2])
    # strengths scale: fuselage drag at strength 2 adds twice the fuselage force
    f0 = pteromys.reference_loads(CANARD, 8.0, 0.0, effects="baseline")
    f1 = pteromys.reference_loads(CANARD, 8.0, 0.0, effects="fuselage_drag")
    f2 = pteromys.reference_loads(CANARD, 8.0, 0.0, effects="baseline", strengths={"fuselage_drag": 2.0})
    d1 = f1["force_body_n"][0] - f0["force_body_n"][0]
    d2 = f2["force_body_n"][0] - f0["force_body_n"][0]
    assert d1 < 0
    assert d2 == pytest.approx(2 * d1, rel=1e-12)
    assert pteromys.effect_switches("baseline", "wind=3")["wind"] == 3.0
    with pytest.raises(ValueError, match="unknown effect"):
        pteromys.reference_forces(CANARD, 8.0, 3.0, effects="downwash,magic")


def test_reference_flight_of_a_training_glider():
    f = pteromys.reference_simulate(CANARD, speed=8.0, climb_deg=5.0)
    assert f["end"] == "ground" and f["stable"]
    s = f["samples"]
    assert s[0, 1] == 0.0 and s[0, 2] == pytest.approx(1.5)
    assert 5.0 < f["distance_m"] < 30.0
    # a headwind (wind effect on, 2 m/s) shortens the flight over the ground
    w = pteromys.reference_simulate(CANARD, speed=8.0, climb_deg=5.0, strengths={"wind": 2.0})
    assert w["distance_m"] < f["distance_m"] - 1.0


@pytest.mark.parametrize("kw, words", [
    ({"speed": float("nan")}, "speed must be a finite number"),
    ({"height": float("inf")}, "height must be a finite number"),
    ({"pitch_deg": float("nan")}, "pitch_deg must be a finite number"),
    ({"wind_m_s": float("nan")}, "wind_m_s must be a finite number"),
    ({"record_every": 0}, "record_every must be at least 1"),  # was taken as 1
    ({"t_max": float("inf")}, "t_max must be in \\(0, 600\\] s"),
])
def test_reference_simulate_refuses_a_launch_it_cannot_fly(kw, words):
    # the same launch checks as pteromys.simulate (one shared binding helper);
    # a NaN launch used to be flown into a "diverged" flight
    with pytest.raises(pteromys.InputError, match=words):
        pteromys.reference_simulate(CANARD, **kw)


# ------------------------------------------------------------ generate

@pytest.fixture(scope="module")
def generated(tmp_path_factory):
    d = tmp_path_factory.mktemp("gen")
    out = d / "ds"
    r = run(["generate", CANARD, DELTA, "-o", out, "--flights-per-glider", "4", "--seed", "11", "--quiet"])
    assert r.returncode == 0, r.stderr
    return out, r


def test_generate_writes_the_spec_dataset(generated):
    out, r = generated
    meta = json.load(open(out / "dataset.json"))
    assert meta["format"] == "pteromys-flights/1"
    assert meta["frame_rate_hz"] == 30.0 and meta["tracking_sigma_m"] == 0.05
    assert set(meta["gliders"]) == {"t17-canard", "t11-delta"}
    for rel in meta["gliders"].values():
        g = json.load(open(out / rel))
        assert g["format"] == "pteromys-glider/1"
    rows, flights = read_csv(out / meta["flights_csv"])
    assert list(rows[0].keys())[:5] == ["flight", "glider", "t_s", "x_m", "y_m"]
    assert len(flights) == 8
    for name, pts in flights.items():
        assert 15 <= len(pts) <= 20
        t = [float(p["t_s"]) for p in pts]
        assert all(b > a for a, b in zip(t, t[1:]))
        assert np.allclose(np.diff(t), 1 / 30, atol=1e-9)
        release = float(pts[0]["true_release_t_s"])
        assert 0 <= t[0] - release < 1 / 30 + 1e-9  # first frame after release
        assert 6.5 < float(pts[0]["true_speed_m_s"]) < 11.5
    gen = json.load(open(out / "generation.json"))
    assert gen["seed"] == 11 and gen["effects"].startswith("pitch_damping=1")
    assert "wrote 8 flights of 2 gliders" in r.stdout


def test_generate_is_deterministic(generated, tmp_path):
    out, _ = generated
    again = tmp_path / "again"
    r = run(["generate", CANARD, DELTA, "-o", again, "--flights-per-glider", "4", "--seed", "11", "--quiet",
             "--threads", "1"])
    assert r.returncode == 0, r.stderr
    assert open(again / "flights.csv").read() == open(out / "flights.csv").read()
    other = tmp_path / "other"
    assert run(["generate", CANARD, DELTA, "-o", other, "--flights-per-glider", "4", "--seed", "12",
                "--quiet"]).returncode == 0
    assert open(other / "flights.csv").read() != open(out / "flights.csv").read()


def test_generate_shows_progress(tmp_path):
    r = run(["generate", CANARD, "-o", tmp_path / "p", "--flights-per-glider", "3"])
    assert r.returncode == 0
    assert "generate: 3/3 flights" in r.stderr


def test_generate_from_python_refuses_a_step_the_command_refuses(tmp_path):
    # generate --dt takes [1e-05, 0.05] s; the binding took any positive step
    with pytest.raises(pteromys.InputError, match="^dt must be in \\[1e-05, 0.05\\] s, got 0.5$"):
        pteromys.generate_dataset([CANARD], str(tmp_path / "py"), flights_per_glider=2, dt=0.5)
    assert not (tmp_path / "py").exists()


def test_generate_from_python_matches_the_command(generated, tmp_path):
    out, _ = generated
    st = pteromys.generate_dataset([CANARD, DELTA], str(tmp_path / "py"), flights_per_glider=4, seed=11)
    assert st["flights"] == 8
    assert open(tmp_path / "py" / "flights.csv").read() == open(out / "flights.csv").read()


def test_a_glider_file_name_with_odd_characters_gives_the_same_safe_key_from_python_and_the_command(tmp_path):
    """The dataset's glider key comes from the file name; a comma or a space
    in it would break flights.csv, so both the command and the binding (which
    had its own copy of the rule and kept them) write it as '_'. The dataset
    then loads back and its flights name that key."""
    odd = tmp_path / "my glider, v2.glider.json"
    odd.write_text(open(CANARD).read())
    r = run(["generate", odd, "-o", tmp_path / "cli", "--flights-per-glider", "2", "--quiet"])
    assert r.returncode == 0, r.stderr
    pteromys.generate_dataset([str(odd)], str(tmp_path / "py"), flights_per_glider=2)
    for d in ("cli", "py"):
        ds = json.load(open(tmp_path / d / "dataset.json"))
        assert list(ds["gliders"]) == ["my_glider__v2"], ds["gliders"]
        rows, _ = read_csv(tmp_path / d / "flights.csv")
        assert {q["glider"] for q in rows} == {"my_glider__v2"}
    assert open(tmp_path / "py" / "flights.csv").read() == open(tmp_path / "cli" / "flights.csv").read()


def test_generated_noise_matches_sigma(tmp_path):
    """The difference between a noisy and a noise-free recording of the same
    seed is the tracking noise: standard deviation sigma (chi-square, +-10 %)."""
    a, b = tmp_path / "a", tmp_path / "b"
    for d, s in ((a, "1e-9"), (b, "0.05")):
        assert run(["generate", CANARD, DELTA, "-o", d, "--flights-per-glider", "20", "--seed", "5",
                    "--noise-m", s, "--quiet"]).returncode == 0
    ra, _ = read_csv(a / "flights.csv")
    rb, _ = read_csv(b / "flights.csv")
    assert len(ra) == len(rb) > 500
    dx = np.array([float(q["x_m"]) - float(p["x_m"]) for p, q in zip(ra, rb)])
    dy = np.array([float(q["y_m"]) - float(p["y_m"]) for p, q in zip(ra, rb)])
    assert np.sqrt(np.mean(np.r_[dx, dy] ** 2)) == pytest.approx(0.05, rel=0.1)


@pytest.mark.parametrize("args, words", [
    (["--effects", "downwash,magic"], "unknown effect 'magic'"),
    (["--strength", "wind"], "not of the form"),
    (["--points", "3-4"], "MIN >= 6"),
    (["--flights-per-glider", "0"], "--flights-per-glider"),
    (["--window", "middle"], "--window"),
    (["--noise-m", "nan"], "needs a number"),
    (["--noise-m", "0"], "must be positive"),
    (["--speed", "9:7"], "MAX is below MIN"),
    (["--speed", "7:9", "--speed-relative", "1:1.3"], "give launch speeds once"),
    (["--speed-relative", "0.1:1"], "between 0.3 and 5"),
    (["--retrim", "40"], "trim angle of attack"),
    # the command names its option and the value, as fit and diagnose do
    (["--dt", "0.1"], "--dt must be in [1e-05, 0.05] s, got 0.1"),
    (["--dt", "1e-7"], "--dt must be in [1e-05, 0.05] s, got 1e-07"),
])
def test_generate_refuses_bad_options_without_output(tmp_path, args, words):
    out = tmp_path / "ds"
    r = run(["generate", CANARD, "-o", out] + args)
    assert r.returncode == 2
    assert words in r.stderr
    assert len(r.stderr.strip().splitlines()) == 1
    assert not out.exists()
    assert os.listdir(tmp_path) == []


def test_generate_refuses_missing_inputs(tmp_path):
    r = run(["generate", tmp_path / "nope.glider.json", "-o", tmp_path / "ds"])
    assert r.returncode == 2 and "nope.glider.json" in r.stderr
    r = run(["generate", CANARD, "-o", tmp_path / "missing" / "ds"])
    assert r.returncode == 2 and "does not exist" in r.stderr
    r = run(["generate", CANARD])
    assert r.returncode == 2 and "-o" in r.stderr
    broken = os.path.join(ROOT, "tests", "data", "broken", "self_intersecting_wing.glider.json")
    r = run(["generate", broken, "-o", tmp_path / "ds"])
    assert r.returncode == 2
    assert not (tmp_path / "ds").exists()


def test_generate_warns_about_launches_it_leaves_out(tmp_path):
    """A delta with its main wing mounted at 40 deg tumbles within a few frames
    in most draws: launches without 6 tracked points are left out with a
    warning (exit 0), or refused with --strict (exit 2, no output)."""
    g = json.load(open(DELTA))
    g["wings"][0]["mount"]["angle_deg"] = 40.0
    bad = tmp_path / "bad.glider.json"
    bad.write_text(json.dumps(g))
    r = run(["generate", bad, CANARD, "-o", tmp_path / "ds", "--flights-per-glider", "3", "--seed", "7", "--quiet"])
    assert r.returncode == 0, r.stderr
    assert "left out" in r.stderr
    _, flights = read_csv(tmp_path / "ds" / "flights.csv")
    assert 3 <= len(flights) < 6
    assert json.load(open(tmp_path / "ds" / "generation.json"))["stats"]["dropped_launches"] == 6 - len(flights)
    r = run(["generate", bad, CANARD, "-o", tmp_path / "strict", "--flights-per-glider", "3", "--seed", "7",
             "--quiet", "--strict"])
    assert r.returncode == 2 and "6 tracked points" in r.stderr
    assert not (tmp_path / "strict").exists()


def test_generate_trims_gliders_for_their_reality_and_launches_at_glide_speed(tmp_path):
    """--retrim writes the trimmed gliders (what flew) into the dataset and
    says per flight how far the tail was turned; --speed-relative launches
    every glider between the given multiples of its glide speed."""
    out = tmp_path / "ds"
    r = run(["generate", CANARD, "-o", out, "--flights-per-glider", "3", "--effects", "downwash", "--retrim", "2",
             "--speed-relative", "1:1.3", "--quiet"])
    assert r.returncode == 0, r.stderr
    rows, _ = read_csv(out / "flights.csv")
    turn = {float(p["trim_turn_deg"]) for p in rows}
    glide = {float(p["glide_speed_m_s"]) for p in rows}
    assert len(turn) == 1 and len(glide) == 1
    (turn,), (glide,) = turn, glide
    assert 2.0 < glide < 12.0
    for p in rows:
        assert 0.9 * glide < float(p["true_speed_m_s"]) < 1.45 * glide
    drawn = json.load(open(CANARD))
    flown = json.load(open(out / "gliders" / (os.path.basename(CANARD))))
    assert flown["wings"][0]["name"] == "canard"
    assert flown["wings"][0]["mount"]["angle_deg"] == pytest.approx(drawn["wings"][0]["mount"]["angle_deg"] + turn,
                                                                    abs=1e-6)
    gen = json.load(open(out / "generation.json"))
    assert gen["retrim_alpha_deg"] == 2 and gen["launcher"]["speed_glide_speeds"] == [1, 1.3]
