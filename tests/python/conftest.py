"""Shared fixtures: the built command and module, example gliders, broken corpus.

Run through ctest (which sets PYTHONPATH and PTEROMYS_BIN) or with
``PYTHONPATH=build/python /usr/bin/python3 -m pytest tests/python``.
"""
import glob
import importlib.util
import json
import os
import subprocess

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BUILD = os.environ.get("PTEROMYS_BUILD_DIR", os.path.join(ROOT, "build"))
BIN = os.environ.get("PTEROMYS_BIN", os.path.join(BUILD, "bin", "pteromys"))
EXAMPLES = sorted(glob.glob(os.path.join(ROOT, "examples", "gliders", "*.glider.json")))
BROKEN_DIR = os.path.join(ROOT, "tests", "data", "broken")


def pytest_configure(config):
    # A missing build is an error with a reason, never a silent skip.
    if not os.path.exists(BIN):
        raise pytest.UsageError(f"pteromys command not built at {BIN}; run scripts/test_all.sh")


@pytest.fixture(scope="session")
def bin_path():
    return BIN


@pytest.fixture(scope="session")
def examples():
    assert len(EXAMPLES) >= 10, "expected at least 10 example gliders"
    return EXAMPLES


def run(args, timeout=600, **kw):
    """Runs the pteromys command; returns CompletedProcess (text). The
    timeout is a guard against a hung run, not a speed test (bench/ measures
    speed): a call that runs several diagnoses in one process gives more."""
    return subprocess.run([BIN] + [str(a) for a in args], capture_output=True, text=True, timeout=timeout, **kw)


def load(path):
    with open(path) as f:
        return json.load(f)


def bench_module(name):
    """A fresh import of bench/diagnosis/NAME.py (the bench scripts are not a
    package)."""
    spec = importlib.util.spec_from_file_location(name, os.path.join(ROOT, "bench", "diagnosis", name + ".py"))
    m = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(m)
    return m


def broken_cases():
    return sorted(load(os.path.join(BROKEN_DIR, "expected.json")).items())
