"""Determinism (issue 9): the same inputs give the same outputs, bit for bit.

Every example glider goes through evaluate (report and trajectories),
optimize and export (DXF and STEP) twice, in separate processes; the files
must be identical, with three exceptions, removed before comparing and
nothing else: the STEP header's FILE_NAME record, which holds the time of
writing (ISO 10303-21 requires it); wall-clock timings in the JSON reports
(keys "seconds", "timings", "*_ms") and the creation time of a model's
provenance ("created_utc"); and the output folder's own path where a
report names the files it wrote.
"""
import json
import glob
import hashlib
import os
import re
import subprocess

import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", ".."))
PTEROMYS = os.environ.get("PTEROMYS_BIN") or os.path.join(ROOT, "build", "bin", "pteromys")
EXAMPLES = sorted(glob.glob(os.path.join(ROOT, "examples", "gliders", "*.glider.json")))


TIMING = re.compile(r"^(seconds|timings|created_utc|.*_ms|.*_seconds)$")


def without_timings(v):
    if isinstance(v, dict):
        return {k: without_timings(x) for k, x in v.items() if not TIMING.match(k)}
    if isinstance(v, list):
        return [without_timings(x) for x in v]
    return v


def digest(path, out):
    with open(path, "rb") as f:
        data = f.read()
    if path.endswith(".json"):
        data = json.dumps(without_timings(json.loads(data.decode().replace(out, "OUT"))), sort_keys=True).encode()
    if path.endswith(".step"):
        data, n = re.subn(rb"FILE_NAME\(.*?\);", b"FILE_NAME(-);", data, count=1, flags=re.S)
        assert n == 1, "no FILE_NAME record in " + path
    return hashlib.sha256(data).hexdigest()


def run_all(glider, out):
    os.makedirs(out)
    o = lambda n: os.path.join(out, n)  # noqa: E731
    for argv in (["evaluate", glider, "--json", o("report.json"), "--csv", o("traj.csv")],
                 ["optimize", glider, "-o", o("opt.glider.json"), "--json", o("opt.json")],
                 ["export", o("opt.glider.json"), "--dxf", o("parts.dxf"), "--step", o("glider.step"),
                  "--json", o("export.json")]):
        r = subprocess.run([PTEROMYS] + argv, capture_output=True, text=True, timeout=600)
        assert r.returncode == 0, (argv, r.stderr)
    return {n: digest(o(n), out) for n in sorted(os.listdir(out))}


def test_examples_exist():
    assert len(EXAMPLES) >= 10


@pytest.mark.parametrize("glider", EXAMPLES, ids=[os.path.basename(p).split(".")[0] for p in EXAMPLES])
def test_same_input_same_output(glider, tmp_path):
    a = run_all(glider, str(tmp_path / "a"))
    b = run_all(glider, str(tmp_path / "b"))
    assert len(a) == 7
    diff = [n for n in a if a[n] != b[n]]
    assert not diff, "outputs differ between two runs: %s" % diff


def test_generate_and_fit_are_repeatable(tmp_path):
    """Synthetic flights (seeded noise) and a coefficient fit, twice each."""
    outs = []
    for run in ("a", "b"):
        d = str(tmp_path / run)
        os.makedirs(d)
        g = os.path.join(ROOT, "examples", "gliders", "tapered.glider.json")
        subprocess.run([PTEROMYS, "generate", g, os.path.join(ROOT, "examples", "gliders", "canard.glider.json"),
                        "-o", d + "/data", "--seed", "7", "--quiet"], check=True, capture_output=True)
        subprocess.run([PTEROMYS, "fit", d + "/data/dataset.json", "-o", d + "/model.json", "--json",
                        d + "/fit.json", "--max-centres", "2", "--quiet"], check=True, capture_output=True)
        files = ["data/dataset.json", "data/flights.csv", "model.json", "fit.json"]
        outs.append({f: digest(os.path.join(d, f), d) for f in files})
    diff = [f for f in outs[0] if outs[0][f] != outs[1][f]]
    assert not diff, "outputs differ between two runs: %s" % diff
