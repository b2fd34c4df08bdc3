"""Where `pteromys diagnose` may write, and the datasets it reads in the
wrong units (docs/reliability.md, "No lost work"; docs/formats.md, "Flight
dataset"): found by a review of bad input on 2026-12-06, where --report
deleted whatever its directory held (the dataset itself, when pointed at
its folder), --json replaced devices, pipes and symbolic links with regular
files, --json '' computed everything and wrote nothing, a report that failed
left the result file behind, times in milliseconds made a diagnosis run for
hours, and Python's Ctrl-C waited for the whole diagnosis.

Every expectation here is what the file system shows afterwards (the files
that exist, their bytes, their type), not what the command says it did.
"""
import json
import os
import signal
import stat
import subprocess
import sys
import textwrap
import threading

import pytest

from conftest import BUILD, ROOT, load, run

GLIDERS = ["t01-rectangular", "t04-tapered-mild", "t06-swept-15"]
# A diagnosis of a few seconds: two candidates, fixed coefficients, 3 folds.
QUICK = ["--folds", "3", "--effects", "wind,camera", "--iterations", "2", "--max-centres", "2", "--no-full-fit",
         "--threads", "1", "--no-profile", "--quiet"]


@pytest.fixture(scope="module")
def dataset(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("outpaths")
    gl = tmp / "gliders"
    gl.mkdir()
    for g in GLIDERS:
        (gl / (g + ".glider.json")).write_text(open(os.path.join(ROOT, "examples", "training", g + ".glider.json")).read())
    r = run(["generate", gl, "-o", tmp / "data", "--flights-per-glider", "2", "--seed", "5", "--quiet"])
    assert r.returncode == 0, r.stderr
    return tmp / "data"


def _snapshot(d):
    """Every file under d with its bytes."""
    out = {}
    for root, _, files in os.walk(d):
        for f in files:
            p = os.path.join(root, f)
            out[os.path.relpath(p, d)] = open(p, "rb").read()
    return out


def test_a_report_is_not_written_over_the_dataset_or_a_persons_files(tmp_path, dataset):
    import shutil
    ds = tmp_path / "ds"
    shutil.copytree(dataset, ds)
    before = _snapshot(ds)
    out = tmp_path / "o.json"
    r = run(["diagnose", ds / "dataset.json", "--json", out, "--report", ds] + QUICK)
    assert r.returncode == 2 and "flights.csv" in r.stderr or "dataset.json" in r.stderr, r.stderr
    assert "replaces the whole directory" in r.stderr
    assert _snapshot(ds) == before and not out.exists()
    notes = tmp_path / "mine"
    notes.mkdir()
    (notes / "notes.txt").write_text("keep me")
    r = run(["diagnose", ds / "dataset.json", "--json", out, "--report", notes] + QUICK)
    assert r.returncode == 2 and "notes.txt" in r.stderr, r.stderr
    assert (notes / "notes.txt").read_text() == "keep me" and os.listdir(notes) == ["notes.txt"]
    # pictures alone are not an earlier report either (no index.html)
    pics = tmp_path / "pics"
    pics.mkdir()
    (pics / "holiday.png").write_bytes(b"\x89PNG")
    r = run(["diagnose", ds / "dataset.json", "--json", out, "--report", pics] + QUICK)
    assert r.returncode == 2 and "index.html" in r.stderr and os.listdir(pics) == ["holiday.png"]
    assert not out.exists()


def test_an_earlier_report_or_an_empty_directory_is_replaced(tmp_path, dataset):
    rep = tmp_path / "rep"
    rep.mkdir()  # empty
    out = tmp_path / "o.json"
    r = run(["diagnose", dataset / "dataset.json", "--json", out, "--report", rep] + QUICK)
    assert r.returncode == 0, r.stderr
    first = sorted(os.listdir(rep))
    assert "index.html" in first and "report.md" in first
    (rep / "stale.png").write_bytes(b"old plot")  # a plot an earlier report had, gone from the new one
    r = run(["diagnose", dataset / "dataset.json", "--json", out, "--report", rep] + QUICK)
    assert r.returncode == 0, r.stderr
    assert sorted(os.listdir(rep)) == first
    assert [f for f in os.listdir(tmp_path) if ".tmp" in f or ".old" in f] == []


def test_a_report_that_cannot_be_rendered_is_refused_before_the_work(tmp_path, dataset):
    """The report is rendered by Debian's python3 with matplotlib; a
    PYTHONHOME where no Python lives makes that interpreter fail to start
    (the command itself is C++ and does not care): refused before the
    diagnosis runs, rather than after a run of hours."""
    env = dict(os.environ, PYTHONHOME=str(tmp_path / "no-python-here"))
    out = tmp_path / "o.json"
    r = run(["diagnose", dataset / "dataset.json", "--json", out, "--report", tmp_path / "rep"] + QUICK[:-1], env=env)
    assert r.returncode == 2 and "cannot import matplotlib" in r.stderr, r.stderr
    assert "flights of" not in r.stderr  # before the dataset was read
    assert os.listdir(tmp_path) == []


def test_a_report_directory_given_with_a_trailing_slash_is_that_directory(tmp_path, dataset):
    rep = tmp_path / "rep"
    rep.mkdir()
    r = run(["diagnose", dataset / "dataset.json", "--json", tmp_path / "o.json", "--report", str(rep) + "/"] + QUICK)
    assert r.returncode == 0, r.stderr
    assert "index.html" in os.listdir(rep) and not [f for f in os.listdir(rep) if "tmp" in f]
    assert sorted(os.listdir(tmp_path)) == ["o.json", "rep"]


def test_an_empty_or_impossible_json_path_is_refused_before_the_work(tmp_path, dataset):
    for bad, words in [("", "no file name"), (str(tmp_path / "afile" / "o.json"), "is not a directory"),
                       (str(tmp_path), "is a directory")]:
        (tmp_path / "afile").write_text("x")
        r = run(["diagnose", dataset / "dataset.json", "--json", bad] + QUICK[:-1])
        assert r.returncode == 2 and words in r.stderr, (bad, r.stderr)
        # refused before the dataset was read: no progress line
        assert "flights of" not in r.stderr


def test_an_unwritable_directory_is_refused_before_the_work(dataset):
    """Root writes anywhere, so as root the command runs as the user nobody
    (runuser); everything it needs is made in /tmp, where nobody can reach it."""
    import shutil
    import tempfile
    top = tempfile.mkdtemp(prefix="pteromys-ro-")
    try:
        shutil.copytree(dataset, os.path.join(top, "data"))
        for root, dirs, files in os.walk(top):
            for x in dirs:
                os.chmod(os.path.join(root, x), 0o755)
            for x in files:
                os.chmod(os.path.join(root, x), 0o644)
        os.chmod(top, 0o777)  # the result may go here; the report may not go into ro
        ro = os.path.join(top, "ro")
        os.mkdir(ro)
        os.chmod(ro, 0o555)
        # a copy of the command where nobody can run it (the build tree may be
        # in a directory only root can enter)
        exe = os.path.join(top, "pteromys")
        shutil.copy(os.path.join(BUILD, "bin", "pteromys"), exe)
        os.chmod(exe, 0o755)
        cmd = [exe, "diagnose", os.path.join(top, "data", "dataset.json")]
        if os.geteuid() == 0:
            cmd = ["runuser", "-u", "nobody", "--"] + cmd
        for out in (["--json", os.path.join(ro, "o.json")], ["--json", os.path.join(top, "o.json"), "--report",
                                                             os.path.join(ro, "rep")]):
            r = subprocess.run(cmd + out + QUICK[:-1], capture_output=True, text=True, timeout=300)
            assert r.returncode == 2 and "'%s' is not writable" % ro in r.stderr, r.stderr
            assert "flights of" not in r.stderr  # before the dataset was read
        assert os.listdir(ro) == [] and not os.path.exists(os.path.join(top, "o.json"))
    finally:
        shutil.rmtree(top, ignore_errors=True)


def test_a_symbolic_link_is_written_through(tmp_path, dataset):
    (tmp_path / "target").mkdir()
    link = tmp_path / "link.json"
    os.symlink("target/real.json", link)
    r = run(["diagnose", dataset / "dataset.json", "--json", link] + QUICK)
    assert r.returncode == 0, r.stderr
    assert os.path.islink(link) and os.readlink(link) == "target/real.json"
    assert load(tmp_path / "target" / "real.json")["format"] == "pteromys-diagnosis/1"


def test_a_link_into_a_missing_directory_names_where_it_points(tmp_path, dataset):
    os.symlink("nodir/real.json", tmp_path / "dangling.json")
    r = run(["diagnose", dataset / "dataset.json", "--json", tmp_path / "dangling.json"] + QUICK)
    assert r.returncode == 2, r.stderr
    assert "does not exist (where the symbolic link points: '%s')" % (tmp_path / "nodir" / "real.json") in r.stderr
    assert os.path.islink(tmp_path / "dangling.json") and sorted(os.listdir(tmp_path)) == ["dangling.json"]


def test_a_pipe_is_written_into_not_replaced(tmp_path, dataset):
    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    got = {}

    def reader():
        with open(fifo, "rb") as f:
            got["bytes"] = f.read()
    t = threading.Thread(target=reader, daemon=True)
    t.start()
    r = run(["diagnose", dataset / "dataset.json", "--json", fifo] + QUICK)
    t.join(60)
    assert r.returncode == 0, r.stderr
    assert stat.S_ISFIFO(os.stat(fifo).st_mode)
    assert json.loads(got["bytes"])["format"] == "pteromys-diagnosis/1"


def test_standard_output_can_take_the_result(dataset, tmp_path):
    r = run(["diagnose", dataset / "dataset.json", "--json", "/dev/stdout"] + QUICK)
    assert r.returncode == 0, r.stderr
    assert json.loads(r.stdout)["format"] == "pteromys-diagnosis/1"
    # standard output redirected to a file (>> log): the result is appended
    # to it, as a shell redirection would, not renamed over it
    log = tmp_path / "log.txt"
    log.write_text("PRIOR\n")
    with open(log, "a") as f:
        p = subprocess.run([os.path.join(BUILD, "bin", "pteromys"), "diagnose", str(dataset / "dataset.json"),
                            "--json", "/dev/stdout"] + QUICK, stdout=f, stderr=subprocess.PIPE, text=True, timeout=300)
    assert p.returncode == 0, p.stderr
    text = log.read_text()
    assert text.startswith("PRIOR\n") and json.loads(text[len("PRIOR\n"):])["format"] == "pteromys-diagnosis/1"
    # and /dev/null stays the device it was
    r = run(["diagnose", dataset / "dataset.json", "--json", "/dev/null"] + QUICK)
    assert r.returncode == 0 and stat.S_ISCHR(os.stat("/dev/null").st_mode), r.stderr


def test_an_export_to_a_device_is_refused_by_name(tmp_path):
    """DXF and STEP are written by libraries into a new file that is renamed
    into place, which would replace a device: refused, at once (it hung)."""
    glider = os.path.join(ROOT, "examples", "training", "t01-rectangular.glider.json")
    for opt in ("--dxf", "--step"):
        r = subprocess.run([os.path.join(BUILD, "bin", "pteromys"), "export", glider, opt, "/dev/null", "--quiet"],
                           capture_output=True, text=True, timeout=60)
        assert r.returncode == 2 and "not a regular file" in r.stderr, (opt, r.stderr)
    assert stat.S_ISCHR(os.stat("/dev/null").st_mode)


def _rewrite(src, dst, change_csv=None, change_json=None):
    import shutil
    shutil.copytree(src, dst)
    if change_csv:
        lines = (dst / "flights.csv").read_text().splitlines()
        (dst / "flights.csv").write_text("\n".join(change_csv(lines)) + "\n")
    if change_json:
        j = json.loads((dst / "dataset.json").read_text())
        change_json(j)
        (dst / "dataset.json").write_text(json.dumps(j))
    return dst / "dataset.json"


def _cells(line):
    return line.split(",")


def _scale_column(lines, col, k):
    out = [lines[0]]
    for line in lines[1:]:
        c = _cells(line)
        c[col] = repr(float(c[col]) * k)
        out.append(",".join(c))
    return out


def _stray_point(lines):
    """The first flight's last point moved 10 s later."""
    first = _cells(lines[1])[0]
    last = max(i for i, line in enumerate(lines) if i > 0 and _cells(line)[0] == first)
    c = _cells(lines[last])
    c[2] = repr(float(c[2]) + 10.0)
    return lines[:last] + [",".join(c)] + lines[last + 1:]


@pytest.mark.parametrize("name, csv_change, json_change, words", [
    ("milliseconds", lambda ls: _scale_column(ls, 2, 1000.0), None, "times are in seconds"),
    ("stray point", _stray_point, None, "stray point"),
    ("millimetres", lambda ls: _scale_column(ls, 3, 1.0e6), None, "positions are in metres"),
    ("noise in millimetres", None, lambda j: j.update(tracking_sigma_m=20.0), "tracking_sigma_m is 20 m"),
])
def test_a_dataset_in_the_wrong_units_is_refused_at_once(tmp_path, dataset, name, csv_change, json_change, words):
    ds = _rewrite(dataset, tmp_path / "d", csv_change, json_change)
    out = tmp_path / "o.json"
    r = run(["diagnose", ds, "--json", out] + QUICK)
    assert r.returncode == 2 and words in r.stderr, r.stderr
    assert len(r.stderr.strip().splitlines()) == 1 and not out.exists()


def test_a_byte_order_mark_is_read_and_a_missing_noise_is_said(tmp_path, dataset):
    def bom(lines):
        return ["\ufeff" + lines[0]] + lines[1:]
    ds = _rewrite(dataset, tmp_path / "d", bom, lambda j: j.pop("tracking_sigma_m"))
    assert (tmp_path / "d" / "flights.csv").read_bytes().startswith(b"\xef\xbb\xbf")
    # said even with --quiet (QUICK's last), which stops progress, not warnings
    assert QUICK[-1] == "--quiet"
    r = run(["diagnose", ds, "--json", tmp_path / "o.json"] + QUICK)
    assert r.returncode == 0, r.stderr
    assert "gives no tracking_sigma_m; 0.05 m is assumed" in r.stderr
    # the same as with 0.05 m given (and without the mark)
    given = _rewrite(dataset, tmp_path / "g", None, lambda j: j.update(tracking_sigma_m=0.05))
    r = run(["diagnose", given, "--json", tmp_path / "g.json"] + QUICK[:-1])
    assert r.returncode == 0 and "assumed" not in r.stderr, r.stderr
    assert load(tmp_path / "o.json")["baseline"]["noise_rmse_m"] == load(tmp_path / "g.json")["baseline"]["noise_rmse_m"]


def test_more_folds_than_gliders_are_said_as_run(dataset, tmp_path):
    r = run(["diagnose", dataset / "dataset.json", "--json", tmp_path / "o.json"] + QUICK[:-1] + ["--folds", "100"])
    assert r.returncode == 0, r.stderr
    assert "3 folds (at most one per glider; 100 asked)" in r.stderr
    assert load(tmp_path / "o.json")["cross_validation"]["folds"] == 3


def test_python_call_takes_an_effect_string_and_refuses_text_for_a_number(dataset):
    import pteromys
    r = pteromys.diagnose(str(dataset / "dataset.json"), folds=3, effects="wind, camera", max_centres=2,
                          full_fit=False, profile=False, iterations=2, threads=1)
    assert sorted(e["name"] for e in r["effects"]) == ["camera", "wind"]
    with pytest.raises(Exception) as e:
        pteromys.diagnose(str(dataset / "dataset.json"), folds="3")
    assert "folds must be a number" in str(e.value) and "'3'" in str(e.value)
    assert pteromys.report_dir_problem(str(dataset)) != ""
    assert pteromys.report_dir_problem(str(dataset / "no-such-dir")) == ""


@pytest.mark.parametrize("call", [
    "pteromys.diagnose(sys.argv[1], folds=3, max_centres=3, threads=1, progress=progress)",
    "pteromys.fit(sys.argv[1], max_centres=6, threads=1, progress=progress)",
], ids=["diagnose", "fit"])
def test_ctrl_c_stops_a_python_run_at_the_next_progress_report(dataset, tmp_path, call):
    """SIGINT once the engine has reported progress: KeyboardInterrupt comes
    from inside the engine (the run never reports "done"), not after the
    whole run as before."""
    script = tmp_path / "run.py"
    script.write_text(textwrap.dedent("""
        import sys, pteromys
        stages = []
        def progress(p):
            if not stages:
                print("STARTED", flush=True)
            stages.append(p["stage"])
        try:
            %s
            print("FINISHED", stages[-1])
        except KeyboardInterrupt:
            print("INTERRUPTED", "done" in stages, len(stages))
    """) % call)
    env = dict(os.environ, PYTHONPATH=os.path.join(BUILD, "python"))
    p = subprocess.Popen(["/usr/bin/python3", str(script), str(dataset / "dataset.json")], stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, text=True, env=env)
    first = p.stdout.readline()  # the engine has started: its first progress report
    assert first.strip() == "STARTED", (first, p.stderr.read() if p.poll() is not None else "")
    p.send_signal(signal.SIGINT)
    out, err = p.communicate(timeout=300)
    assert out.startswith("INTERRUPTED False"), (out, err)


@pytest.mark.parametrize("how", ["SIGTERM to the command", "Ctrl-C to its process group", "SIGHUP to its group"])
def test_a_signal_while_the_report_is_rendered_leaves_the_earlier_report(tmp_path, dataset, how):
    """The report is rendered into REP.tmp-PID by a Python child process; a
    signal then (a kill, a terminal's Ctrl-C or hang-up) used to leave that
    directory and the renderer behind. Now the command stops the renderer,
    removes the directory, keeps the earlier report as it was and ends by the
    signal; the result file, written before the report, is complete."""
    rep = tmp_path / "rep"
    out = tmp_path / "o.json"
    r = run(["diagnose", dataset / "dataset.json", "--json", out, "--report", rep] + QUICK)
    assert r.returncode == 0, r.stderr
    before = _snapshot(rep)
    out.unlink()
    sig = {"SIGTERM": signal.SIGTERM, "Ctrl-C": signal.SIGINT, "SIGHUP": signal.SIGHUP}[how.split()[0]]
    p = subprocess.Popen([os.path.join(BUILD, "bin", "pteromys"), "diagnose", str(dataset / "dataset.json"), "--json",
                          str(out), "--report", str(rep)] + QUICK, start_new_session=True,
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    tmp = tmp_path / ("rep.tmp-%d" % p.pid)
    try:
        # wait until the renderer has written its first file into REP.tmp-PID
        import time
        deadline = time.time() + 120
        while not (tmp.is_dir() and os.listdir(tmp)):
            assert p.poll() is None, "the command ended before its report was being rendered"
            assert time.time() < deadline, "no report was rendered within 2 minutes"
            time.sleep(0.002)
        if "group" in how:
            os.killpg(p.pid, sig)
        else:
            p.send_signal(sig)
        p.communicate(timeout=60)
        assert p.returncode == -sig, p.returncode
        assert sorted(f.name for f in tmp_path.iterdir()) == ["o.json", "rep"]
        assert _snapshot(rep) == before
        assert json.load(open(out))["format"] == "pteromys-diagnosis/1"
        # no renderer left writing into the removed directory
        assert _processes_naming(tmp) == [], "renderer processes left"
    finally:
        _stop_session(p)
        for pid in _processes_naming(tmp):
            os.kill(int(pid), signal.SIGKILL)


def _stop_session(p):
    """A failed test leaves nothing running: the command started with
    start_new_session and its renderer (one session, one process group)."""
    try:
        os.killpg(p.pid, signal.SIGKILL)
    except ProcessLookupError:
        pass
    p.wait()


def _processes_naming(path):
    """The pids whose command line names `path`."""
    left = []
    for pid in os.listdir("/proc"):
        if pid.isdigit():
            try:
                if str(path).encode() in open("/proc/%s/cmdline" % pid, "rb").read():
                    left.append(pid)
            except OSError:
                pass
    return left


_NO_EXCHANGE_SHIM = r"""
#define _GNU_SOURCE
#include <dlfcn.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
/* a file system that cannot exchange two directories */
int renameat2(int olddirfd, const char* o, int newdirfd, const char* n, unsigned int flags) {
  (void)olddirfd; (void)o; (void)newdirfd; (void)n; (void)flags;
  errno = EINVAL;
  return -1;
}
/* a slow rename from a path holding SHIM_SLOW_FROM, announced on stderr */
int rename(const char* o, const char* n) {
  static int (*real)(const char*, const char*);
  if (!real) real = (int (*)(const char*, const char*))dlsym(RTLD_NEXT, "rename");
  const char* mark = getenv("SHIM_SLOW_FROM");
  if (mark && *mark && strstr(o, mark)) {
    fprintf(stderr, "SHIM: renaming slowly\n");
    fflush(stderr);
    sleep(2);
  }
  return real(o, n);
}
"""


@pytest.mark.parametrize("signalled", [False, True], ids=["replaced", "SIGTERM between the renames"])
def test_an_earlier_report_is_replaced_where_directories_cannot_be_exchanged(tmp_path, dataset, signalled):
    """Where the file system cannot exchange two directories (renameat2 with
    RENAME_EXCHANGE fails: an LD_PRELOAD shim, compiled here, makes it so),
    the earlier report is moved aside and the new one renamed in. A signal
    between the two renames (the shim makes the second one slow) once left
    no report at all (review of 2026-12-06): it is held until both are done,
    so the new report is in place and nothing else is left."""
    import shutil
    cc = shutil.which("cc") or shutil.which("gcc")
    assert cc, "no C compiler (cc or gcc) to build the shim this test needs; scripts/setup.sh installs build-essential"
    shim = tmp_path / "shim" / "noexchange.so"
    shim.parent.mkdir()
    (shim.parent / "shim.c").write_text(_NO_EXCHANGE_SHIM)
    b = subprocess.run([cc, "-shared", "-fPIC", "-o", str(shim), str(shim.parent / "shim.c"), "-ldl"],
                       capture_output=True, text=True)
    assert b.returncode == 0, b.stderr
    work = tmp_path / "work"
    work.mkdir()
    rep = work / "rep"
    out = work / "o.json"
    r = run(["diagnose", dataset / "dataset.json", "--json", out, "--report", rep] + QUICK)
    assert r.returncode == 0, r.stderr
    names = sorted(os.listdir(rep))
    (rep / "stale.png").write_bytes(b"a plot only the earlier report has")
    env = dict(os.environ, LD_PRELOAD=str(shim), SHIM_SLOW_FROM="rep.tmp-" if signalled else "")
    p = subprocess.Popen([os.path.join(BUILD, "bin", "pteromys"), "diagnose", str(dataset / "dataset.json"), "--json",
                          str(out), "--report", str(rep)] + QUICK, start_new_session=True, env=env,
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        if signalled:
            seen = []
            for line in p.stderr:
                seen.append(line)
                if "SHIM: renaming slowly" in line:
                    break
            assert seen and "SHIM" in seen[-1], "the report was never renamed into place: %s" % "".join(seen)
            p.send_signal(signal.SIGTERM)
        _, err = p.communicate(timeout=120)
        assert p.returncode == (-signal.SIGTERM if signalled else 0), (p.returncode, err)
    finally:
        _stop_session(p)
    # the new report, whole, and nothing beside it
    assert sorted(os.listdir(rep)) == names
    assert sorted(os.listdir(work)) == ["o.json", "rep"]


def test_a_report_that_fails_while_rendered_leaves_the_result_and_the_earlier_report(tmp_path, dataset):
    """The renderer starts (checked before the run) but fails midway: here a
    file size limit (RLIMIT_FSIZE, SIGXFSZ ignored, as a full disk would)
    above the result file's size and below the largest plot's. The command
    exits 2 saying where the result is; the result file is complete, the
    earlier report is as it was and no temporary directory is left."""
    import resource
    rep = tmp_path / "rep"
    out = tmp_path / "o.json"
    r = run(["diagnose", dataset / "dataset.json", "--json", out, "--report", rep] + QUICK)
    assert r.returncode == 0, r.stderr
    before = _snapshot(rep)
    result_size = out.stat().st_size
    largest_plot = max(len(v) for k, v in before.items() if k.endswith(".png"))
    assert result_size < largest_plot, (result_size, largest_plot)  # else this limit cannot separate them
    limit = (result_size + largest_plot) // 2
    out.unlink()

    def limited():
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
        resource.setrlimit(resource.RLIMIT_FSIZE, (limit, limit))

    p = subprocess.run([os.path.join(BUILD, "bin", "pteromys"), "diagnose", str(dataset / "dataset.json"), "--json",
                        str(out), "--report", str(rep)] + QUICK, capture_output=True, text=True, preexec_fn=limited,
                       timeout=600)
    assert p.returncode == 2, (p.returncode, p.stderr)
    assert "report could not be rendered" in p.stderr and "the diagnosis result is in '%s'" % out in p.stderr, p.stderr
    # the renderer's own one-line reason, not a traceback
    assert "cannot write" in p.stderr and "File too large" in p.stderr and "Traceback" not in p.stderr, p.stderr
    assert json.load(open(out))["format"] == "pteromys-diagnosis/1"
    assert _snapshot(rep) == before
    assert sorted(f.name for f in tmp_path.iterdir()) == ["o.json", "rep"]


def test_outputs_to_a_redirected_standard_output_are_not_the_same_file(tmp_path):
    """Two outputs to /dev/stdout redirected into a file are written one after
    the other into it (the outputs check compared that file with itself and
    refused); a device that fails after one of them says what was written."""
    glider = os.path.join(ROOT, "examples", "gliders", "canard.glider.json")
    out = tmp_path / "both.txt"
    with open(out, "w") as f:
        p = subprocess.run([os.path.join(BUILD, "bin", "pteromys"), "evaluate", glider, "--json", "/dev/stdout",
                            "--csv", "/dev/stdout", "--quiet"], stdout=f, stderr=subprocess.PIPE, text=True, timeout=300)
    assert p.returncode == 0, p.stderr
    text = out.read_text()
    report_end = text.index("\n}\n") + 3
    assert json.loads(text[:report_end])["format"] == "pteromys-report/1"
    assert text[report_end:].startswith("launch,t_s,x_m,y_m,pitch_deg,speed_m_s")
    r = run(["evaluate", glider, "--json", "/dev/stdout", "--csv", "/dev/full"])
    assert r.returncode == 2 and "only '/dev/stdout' was written, no file was replaced" in r.stderr, r.stderr
    assert json.loads(r.stdout)["format"] == "pteromys-report/1"


def test_a_result_inside_the_report_directory_is_refused_before_the_work(tmp_path, dataset):
    """The report replaces its directory as a whole: a --json inside it went
    with the earlier report (exit 0, the result gone), or was refused after
    the whole run as a file that is not a report's."""
    rep = tmp_path / "R"
    r = run(["diagnose", dataset / "dataset.json", "--json", tmp_path / "o.json", "--report", rep] + QUICK)
    assert r.returncode == 0, r.stderr
    before = _snapshot(rep)
    for j in (rep / "diagnosis.json", tmp_path / "R" / ".." / "R" / "x.json"):
        r = run(["diagnose", dataset / "dataset.json", "--json", j, "--report", str(rep) + "/"] + QUICK)
        assert r.returncode == 2 and "inside the report's directory" in r.stderr, r.stderr
        assert "held-out" not in r.stderr  # refused before the work
        assert _snapshot(rep) == before
    # a name that only starts like the report's is beside it, not inside
    r = run(["diagnose", dataset / "dataset.json", "--json", tmp_path / "R.json", "--report", rep] + QUICK)
    assert r.returncode == 0, r.stderr
