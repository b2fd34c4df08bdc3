"""Every reader and command answers bad input with its exit status and a
one-line message naming the problem, and leaves no output behind (issue 9).
The cases are tests/data/bad_inputs/cases.py; docs/reliability.md shows them
as a table (checked here)."""
import os
import shutil
import subprocess
import sys

import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "tests", "data", "bad_inputs"))
import cases as corpus  # noqa: E402

PTEROMYS = os.environ.get("PTEROMYS_BIN") or os.path.join(ROOT, "build", "bin", "pteromys")
CRASH_SIGNS = ["Traceback", "terminate called", "Assertion", "Segmentation", "AddressSanitizer", "runtime error",
               "core dumped", "what():"]


def materialise(case, tmp):
    d = os.path.join(tmp, "in")
    out = os.path.join(tmp, "out")
    os.makedirs(d)
    os.makedirs(out)
    subst = {"d": d, "ex": os.path.join(ROOT, "examples", "gliders"), "out": out, "root": ROOT}
    for name, content in case["files"].items():
        path = os.path.join(d, name)
        if isinstance(content, str) and content.startswith("@copy "):
            shutil.copyfile(content[len("@copy "):].format(**subst), path)
        elif isinstance(content, str) and content.startswith("@edit "):
            with open(path, "w") as f:
                f.write(corpus.edited_model(ROOT, content[len("@edit "):]))
        elif isinstance(content, bytes):  # a file in another encoding
            with open(path, "wb") as f:
                f.write(content)
        else:
            with open(path, "w") as f:
                f.write(content)
    return [a.format(**subst) for a in case["argv"]], d, out


def run_case(case, tmp):
    argv, d, out = materialise(case, tmp)
    before = sorted(os.listdir(d))
    r = subprocess.run([PTEROMYS] + argv, capture_output=True, text=True, timeout=600)
    return r, d, out, before


@pytest.mark.parametrize("case", corpus.CASES, ids=[c["id"] for c in corpus.CASES])
def test_bad_input_is_named(case, tmp_path):
    r, d, out, before = run_case(case, str(tmp_path))
    err = r.stderr.strip()
    assert r.returncode == case["exit"], (r.returncode, err)
    for sign in CRASH_SIGNS:
        assert sign not in err, err
    assert err, "no message on stderr"
    # The reason is one line (progress lines, if any, come before it).
    last = err.splitlines()[-1]
    for w in case["words"]:
        assert w in last, (w, last)
    # Nothing written: the output folder is still empty, the input folder unchanged.
    assert os.listdir(out) == [], os.listdir(out)
    assert sorted(os.listdir(d)) == before


def test_cases_are_distinct():
    ids = [c["id"] for c in corpus.CASES]
    assert len(ids) == len(set(ids))
    readers = {c["reader"] for c in corpus.CASES}
    assert {"flight dataset", "model file", "command line"} <= readers


def test_document_shows_the_table():
    with open(os.path.join(ROOT, "docs", "reliability.md")) as f:
        doc = f.read()
    assert corpus.table() in doc, "docs/reliability.md: regenerate the table with " \
        "`python3 tests/data/bad_inputs/cases.py --table`"
