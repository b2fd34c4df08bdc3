"""Flight capture end to end through the command line (issue 8, docs/capture.md):
render-video -> calibrate -> track -> dataset -> fit, and the refusals of bad
input.

The reference is the truth written by ``render-video --truth`` (the CG of the
simulated flight the video was drawn from), not anything the tracker says.
"""
import csv
import json
import math
import os

import pytest

from conftest import ROOT, run

GLIDER = os.path.join(ROOT, "examples", "training", "t04-tapered-mild.glider.json")


def read_csv(path):
    with open(path) as f:
        return list(csv.DictReader(f))


@pytest.fixture(scope="module")
def scene(tmp_path_factory):
    """Two launches seen from 4.5 m (1280x720, 30 fps, lens distortion, noise, MJPG)."""
    d = tmp_path_factory.mktemp("capture")
    video, truth, points = d / "launches.avi", d / "truth.csv", d / "points.json"
    r = run(["render-video", GLIDER, "-o", video, "--launches", "8,4;10,0", "--distance", "4.5", "--truth", truth,
             "--points", points, "--seed", "3", "--quiet"])
    assert r.returncode == 0, r.stderr
    calib = d / "calib.json"
    r = run(["calibrate", points, "-o", calib])
    assert r.returncode == 0, r.stderr
    return {"dir": d, "video": video, "truth": truth, "points": points, "calib": calib}


@pytest.fixture(scope="module")
def dataset(scene):
    out = scene["dir"] / "data"
    r = run(["track", scene["video"], "--calib", scene["calib"], "--glider", GLIDER, "-o", out, "--glider-key", "g01",
             "--quiet"])
    assert r.returncode == 0, r.stderr
    return out


def test_calibrate_reports_residuals_in_metres(scene):
    r = run(["calibrate", scene["points"], "-o", scene["dir"] / "c2.json"])
    assert r.returncode == 0, r.stderr
    c = json.load(open(scene["calib"]))
    assert c["format"] == "pteromys-calibration/1"
    # 12 points clicked with 0.3 px noise at 4.5 m (about 4.6 mm per pixel): residuals of a few mm
    res = c["residual"]
    assert 0 < res["rms_m"] < 0.005 and 0 < res["leave_one_out_rms_m"] < 0.008, res
    assert "mm" in r.stdout


def test_track_writes_one_flight_per_launch_close_to_the_truth(scene, dataset):
    ds = json.load(open(dataset / "dataset.json"))
    assert ds["format"] == "pteromys-flights/1" and ds["frame_rate_hz"] == 30.0
    assert ds["gliders"] == {"g01": "gliders/g01.glider.json"}
    assert 0 < ds["tracking_sigma_m"] < 0.01
    rows = read_csv(dataset / ds["flights_csv"])
    assert list(rows[0].keys())[:5] == ["flight", "glider", "t_s", "x_m", "y_m"]
    flights = sorted({r["flight"] for r in rows})
    assert len(flights) == 2
    truth = {}
    for t in read_csv(scene["truth"]):
        truth[int(t["frame"])] = (float(t["x_m"]), float(t["y_m"]), int(t["flight"]))
    # tracks.csv gives each point's frame; flights.csv the CG in the plane
    tracks = read_csv(dataset / "tracks.csv")
    assert len(tracks) == len(rows)
    sq, n, by_flight = 0.0, 0, {}
    for row, tr in zip(rows, tracks):
        fr = int(tr["frame"])
        assert fr in truth, "a point in frame %d, where no glider was drawn" % fr
        x, y, k = truth[fr]
        by_flight.setdefault(row["flight"], set()).add(k)
        assert float(row["t_s"]) == pytest.approx(fr / 30.0, abs=1e-5)
        sq += (float(row["x_m"]) - x) ** 2 + (float(row["y_m"]) - y) ** 2
        n += 1
    assert n >= 20
    # each dataset flight holds the frames of one launch only
    assert sorted(len(v) for v in by_flight.values()) == [1, 1]
    assert {next(iter(v)) for v in by_flight.values()} == {0, 1}
    assert math.sqrt(sq / n) <= 0.010, math.sqrt(sq / n)


def test_fit_accepts_the_tracked_dataset(dataset, tmp_path):
    rep = tmp_path / "fit.json"
    r = run(["fit", dataset / "dataset.json", "-o", tmp_path / "model.json", "--json", rep, "--max-centres", "1",
             "--threads", "2", "--quiet"])
    assert r.returncode == 0, r.stderr
    f = json.load(open(rep))
    assert f["format"] == "pteromys-fit/1" and f["flights"] == 2
    # the baseline-simulated flights, tracked to ~mm, are fitted to a few cm at most
    assert 0 < f["fit_rmse_m"] < 0.05, f["fit_rmse_m"]


def test_track_help_documents_the_command():
    h = run(["track", "--help"])
    assert h.returncode == 0
    assert "usage: pteromys track VIDEO --calib CALIB.json --glider GLIDER.glider.json -o DATASET_DIR" in h.stdout
    assert "track" in run(["--help"]).stdout


def _refused(r, words):
    assert r.returncode != 0
    assert "Traceback" not in r.stderr and "terminate" not in r.stderr
    assert words in r.stderr, r.stderr
    assert len(r.stderr.strip().splitlines()) == 1, r.stderr


@pytest.mark.parametrize("case", ["missing video", "unreadable video", "glider not found", "calibration not found",
                                  "comma in --name", "line end in --name"])
def test_track_refuses_bad_input_and_writes_nothing(scene, tmp_path, case):
    out = tmp_path / "data"
    video, glider, calib = scene["video"], GLIDER, scene["calib"]
    if case == "missing video":
        video, words = tmp_path / "nope.avi", "no such file"
    elif case == "unreadable video":
        video = tmp_path / "text.avi"
        video.write_text("not a video\n" * 100)
        words = "cannot read video"
    elif case == "glider not found":
        glider, words = tmp_path / "nope.glider.json", "nope.glider.json"
    elif case == "calibration not found":
        calib, words = tmp_path / "nope.json", "nope.json"
    # --name names the flights in flights.csv: a comma, quote or line end in
    # it wrote a dataset that fit could not read back (exit 0 before)
    name = {"comma in --name": 'a,"b', "line end in --name": "a\nb"}.get(case)
    if name:
        words = "--name must be 1-100 letters, digits"
    r = run(["track", video, "--calib", calib, "--glider", glider, "-o", out, "--quiet"] +
            (["--name", name] if name else []))
    _refused(r, words)
    assert not out.exists() or not os.listdir(out)


def _points(scene, edit):
    p = json.load(open(scene["points"]))
    edit(p["points"])
    return p


@pytest.mark.parametrize("case", ["three points", "collinear points"])
def test_calibrate_refuses_too_few_or_collinear_points(scene, tmp_path, case):
    def three(pts):
        del pts[3:]

    def collinear(pts):
        # five points measured along one rod: every world point on one line
        del pts[5:]
        for i, q in enumerate(pts):
            q["world_m"] = [0.5 * i, 1.0 + 0.25 * i]
    p = _points(scene, three if case == "three points" else collinear)
    path = tmp_path / "points.json"
    path.write_text(json.dumps(p))
    out = tmp_path / "calib.json"
    r = run(["calibrate", path, "-o", out])
    _refused(r, "at least 4" if case == "three points" else "line")
    assert not out.exists()
    # the same points given straight to track are refused the same way, with no dataset
    r = run(["track", scene["video"], "--calib", path, "--glider", GLIDER, "-o", tmp_path / "data", "--quiet"])
    _refused(r, "at least 4" if case == "three points" else "line")
    assert not (tmp_path / "data").exists()


def test_existing_dataset_is_kept_unless_asked(scene, dataset):
    before = (dataset / "flights.csv").read_text()
    r = run(["track", scene["video"], "--calib", scene["calib"], "--glider", GLIDER, "-o", dataset, "--quiet"])
    _refused(r, "already holds a dataset")
    assert (dataset / "flights.csv").read_text() == before


def test_static_clutter_after_the_flight_is_not_a_second_flight(tmp_path):
    """Regression (found by bench/capture/accuracy_study.py): with the marker
    detector at 5 m, a red poster edge whose centroid flickered between two
    spots 11 px apart looked like a slow launch after the glider had left the
    image and became a second 'flight' 7 m away from the glider."""
    import numpy as np
    import pteromys
    import pteromys.capture as cap
    f = pteromys.reference_simulate(GLIDER, speed=9.0, climb_deg=4.0, t_max=2.5)["samples"][:, :4]
    width = 2 * 5.0 * math.tan(math.radians(33.0))
    sel = f[:, 1] < f[0, 1] + 0.8 * width
    cam = cap.synthetic_camera(distance_m=5.0, x_m=f[0, 1] + 0.42 * width, y_m=float(f[sel, 2].mean()), hfov_deg=66.0,
                               tilt_deg=1.5, roll_deg=-0.8)
    video = str(tmp_path / "marker.avi")
    nose = (-0.03, 0.001)
    r = cap.render_video(video, cam, GLIDER, [f], seed=11, marker=True, marker_at=nose, marker_radius_m=0.008)
    calib = cap.calibrate(cap.synthetic_points(cam, 4, 3, click_sigma_px=0.3, seed=11, distance_m=5.0))
    res = cap.track_flights(cap.detect(video, detector="marker"), calib, GLIDER, marker_at=nose)
    truth = {int(row[1]): row for row in r["truth"]}
    assert len(res.flights) == 1, [(x["first_frame"], x["last_frame"]) for x in res.flights]
    fl = res.flights[0]
    err = np.array([math.hypot(fl["x_m"][i] - truth[int(fr)][3], fl["y_m"][i] - truth[int(fr)][4])
                    for i, fr in enumerate(fl["frame"])])
    assert len(err) >= 20 and err.max() < 0.05 and math.sqrt((err ** 2).mean()) <= 0.010, err


def test_three_gliders_tracked_into_one_dataset_are_diagnosed(tmp_path):
    """Videos of three training gliders (three launches each) tracked with
    --append into one dataset, which `pteromys diagnose` reads. The videos are
    drawn from flights of the baseline model itself, so the diagnosis must
    find no gap beyond the tracking noise (verdict 'none')."""
    data = tmp_path / "data"
    keys = []
    for i, stem in enumerate(["t01-rectangular", "t04-tapered-mild", "t07-swept-30"]):
        g = os.path.join(ROOT, "examples", "training", stem + ".glider.json")
        key = stem.split("-")[0]
        keys.append(key)
        video, points = tmp_path / (key + ".avi"), tmp_path / (key + ".points.json")
        r = run(["render-video", g, "-o", video, "--launches", "7,6;9,3;11,0", "--distance", "4.5", "--points", points,
                 "--seed", i + 1, "--quiet"])
        assert r.returncode == 0, r.stderr
        r = run(["track", video, "--calib", points, "--glider", g, "-o", data, "--glider-key", key, "--quiet"]
                + (["--append"] if i else []))
        assert r.returncode == 0, r.stderr
    ds = json.load(open(data / "dataset.json"))
    assert sorted(ds["gliders"]) == keys
    assert len({r["flight"] for r in read_csv(data / "flights.csv")}) == 9   # one flight per launch
    out = tmp_path / "diag.json"
    r = run(["diagnose", data / "dataset.json", "--json", out, "--quiet"])
    assert r.returncode == 0, r.stderr
    d = json.load(open(out))
    assert d["format"] == "pteromys-diagnosis/1"
    assert d["baseline"]["holdout_rmse_m"] < 0.01
    assert d["verdict"] == "none", (d["verdict"], d["baseline"])


def test_a_long_video_name_makes_a_shortened_default_flight_name(scene, tmp_path):
    """Without --name the flights are named KEY-VIDEONAME-NN; a video with a
    long name was refused as if --name had been given (the 100-character
    check); the default is now cut to 100 characters and the dataset reads
    back."""
    long_video = tmp_path / ("b" * 120 + ".avi")
    os.symlink(scene["video"], long_video)
    out = tmp_path / "data"
    r = run(["track", long_video, "--calib", scene["calib"], "--glider", GLIDER, "-o", out, "--glider-key", "g01",
             "--quiet"])
    assert r.returncode == 0, r.stderr
    names = {q["flight"] for q in read_csv(out / "flights.csv")}
    assert names and all(n.startswith("g01-bbbb") and len(n) == 103 for n in names), names  # 100 + "-NN"
    assert run(["fit", out / "dataset.json", "-o", tmp_path / "m.json", "--quiet", "--max-centres", "1"]).returncode == 0
