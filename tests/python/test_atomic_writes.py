"""No lost work (issue 9): every output is written to a temporary file and
renamed into place, so a failed write or a killed process leaves the old file
or the new one, never a fragment.

Writes are made to fail for real, midway, by a file size limit
(RLIMIT_FSIZE, with SIGXFSZ ignored so that write() returns EFBIG): the
kernel stops the file at the limit, as a full disk would. Each case starts
from an old file at the target, runs the command under the limit and checks
that the command fails with a message, the old file is byte for byte intact
and no temporary file is left. Then SIGTERM and SIGKILL at random moments
of a long export: the target is always the old file or a complete new one.
"""
import json
import os
import random
import resource
import shutil
import signal
import subprocess
import sys
import time

import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", ".."))
PTEROMYS = os.environ.get("PTEROMYS_BIN") or os.path.join(ROOT, "build", "bin", "pteromys")
EX = os.path.join(ROOT, "examples", "gliders")
OLD = b"old content that must survive\n"


def limited(limit):
    def pre():
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
        resource.setrlimit(resource.RLIMIT_FSIZE, (limit, limit))
    return pre


def small_dataset(d):
    """One glider, one flight of 8 points (enough to read and fit)."""
    os.makedirs(d, exist_ok=True)
    shutil.copy(os.path.join(EX, "tapered.glider.json"), os.path.join(d, "g.glider.json"))
    with open(os.path.join(d, "dataset.json"), "w") as f:
        json.dump({"format": "pteromys-flights/1", "gliders": {"g": "g.glider.json"}, "flights_csv": "flights.csv",
                   "frame_rate_hz": 30, "tracking_sigma_m": 0.01}, f)
    with open(os.path.join(d, "flights.csv"), "w") as f:
        f.write("flight,glider,t_s,x_m,y_m\n")
        for k in range(8):
            f.write("f1,g,%.4f,%.4f,%.4f\n" % (k / 30, 0.25 * k, 1.5 - 0.002 * k * k))
    return os.path.join(d, "dataset.json")


# (name, argv with {t} = the target file, file size limit in bytes). Each
# output is larger than its limit (checked below by running without one).
CASES = [
    ("evaluate_report", ["evaluate", EX + "/tapered.glider.json", "--json", "{t}"], 2000),
    ("simulate_csv", ["simulate", EX + "/tapered.glider.json", "--csv", "{t}"], 3000),
    ("optimize_glider", ["optimize", EX + "/tapered.glider.json", "-o", "{t}"], 400),
    ("export_dxf", ["export", EX + "/tapered.glider.json", "--dxf", "{t}"], 5000),
    ("export_step", ["export", EX + "/tapered.glider.json", "--step", "{t}"], 20000),
    ("fit_model", ["fit", "{data}", "-o", "{t}", "--quiet", "--max-centres", "1"], 600),
    ("render_video", ["render-video", EX + "/tapered.glider.json", "-o", "{t}", "--quiet"], 200000),
]
SUFFIX = {"export_dxf": ".dxf", "export_step": ".step", "render_video": ".avi", "fit_model": ".model.json",
          "optimize_glider": ".glider.json", "simulate_csv": ".csv"}


def argv_of(case, target, data):
    return [PTEROMYS] + [a.format(t=target, data=data) for a in case[1]]


@pytest.mark.parametrize("case", CASES, ids=[c[0] for c in CASES])
def test_failed_write_keeps_the_old_file(case, tmp_path):
    name, _, limit = case
    data = small_dataset(str(tmp_path / "data"))
    out = tmp_path / "out"
    out.mkdir()
    target = str(out / (name + SUFFIX.get(name, ".json")))
    # Without a limit the command works and writes more than the limit.
    free = subprocess.run(argv_of(case, target, data), capture_output=True, text=True, timeout=600)
    assert free.returncode == 0, free.stderr
    assert os.path.getsize(target) > limit, (name, os.path.getsize(target))
    # With the limit: the write fails midway.
    with open(target, "wb") as f:
        f.write(OLD)
    r = subprocess.run(argv_of(case, target, data), capture_output=True, text=True, timeout=600,
                       preexec_fn=limited(limit))
    assert r.returncode == 2, (r.returncode, r.stderr)
    last = r.stderr.strip().splitlines()[-1]
    assert "cannot write" in last and os.path.basename(target) in last, last
    with open(target, "rb") as f:
        assert f.read() == OLD
    assert sorted(os.listdir(out)) == [os.path.basename(target)], os.listdir(out)


def test_python_plot_is_atomic(tmp_path):
    """The report plot of the main job (matplotlib) under the same limit."""
    rep, csv = str(tmp_path / "r.json"), str(tmp_path / "t.csv")
    subprocess.run([PTEROMYS, "evaluate", EX + "/tapered.glider.json", "--json", rep, "--csv", csv], check=True)
    out = tmp_path / "out"
    out.mkdir()
    png = str(out / "launches.png")
    with open(png, "wb") as f:
        f.write(OLD)
    env = dict(os.environ)
    r = subprocess.run(["/usr/bin/python3", "-m", "pteromys.plot", rep, csv, png], capture_output=True, text=True,
                       env=env, preexec_fn=limited(8000), timeout=300)
    assert r.returncode != 0
    with open(png, "rb") as f:
        assert f.read() == OLD
    assert os.listdir(out) == ["launches.png"]
    r = subprocess.run(["/usr/bin/python3", "-m", "pteromys.plot", rep, csv, png], capture_output=True, text=True,
                       env=env, timeout=300)
    assert r.returncode == 0, r.stderr
    with open(png, "rb") as f:
        assert f.read(8) == b"\x89PNG\r\n\x1a\n"


def complete_step(path):
    with open(path, "rb") as f:
        data = f.read()
    return data.startswith(b"ISO-10303-21;") and data.rstrip().endswith(b"END-ISO-10303-21;")


@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGKILL], ids=["SIGTERM", "SIGKILL"])
def test_killed_export_leaves_old_or_new(sig, tmp_path):
    """Kill a fused STEP export of the elliptic example (the slowest) at random
    moments: the target is the old file or a complete STEP file, every time;
    after SIGTERM no temporary file remains (after SIGKILL one may)."""
    rng = random.Random(12345)
    target = str(tmp_path / "glider.step")
    argv = [PTEROMYS, "export", EX + "/elliptic.glider.json", "--step", target, "--fused"]
    t0 = time.time()
    subprocess.run(argv, check=True, capture_output=True)
    duration = time.time() - t0
    outcomes = {"old": 0, "new": 0}
    for i in range(12):
        with open(target, "wb") as f:
            f.write(OLD)
        p = subprocess.Popen(argv, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        time.sleep(rng.uniform(0.0, duration * 1.1))
        p.send_signal(sig)
        p.wait(timeout=120)
        with open(target, "rb") as f:
            content = f.read()
        if content == OLD:
            outcomes["old"] += 1
        else:
            assert complete_step(target), "a fragment at the target after %s (run %d)" % (sig.name, i)
            outcomes["new"] += 1
        left = [n for n in os.listdir(tmp_path) if n != "glider.step"]
        if sig == signal.SIGTERM:
            assert left == [], left
        for n in left:
            os.remove(os.path.join(tmp_path, n))
    print("outcomes", sig.name, outcomes)
    assert outcomes["old"] > 0  # some kills did land during the work
