"""Sim-to-real gap diagnosis from FreeCAD (issue 7; docs/diagnosis.md).

Headless part of the "Diagnose flights" command: runs the engine's
``pteromys.diagnose`` on a flight dataset (spec/formats.md, "Flight
dataset"), writes the result JSON and the readable report, and reports
progress through a callback. Usable from the console, macros and
``freecadcmd``::

    import pteromys_freecad.diagnose as pd
    result, index = pd.run_diagnosis("flights/dataset.json", "flights/diagnosis",
                                     progress=lambda p: print(p["message"]))

The GUI command (``diagnose_gui.py``) adds the file dialog, a progress dialog
with a Cancel button and opens ``index`` in FreeCAD's browser.
"""
import ctypes
import errno
import json
import os
import shutil
import tempfile

from .backend import engine


class Cancelled(Exception):
    """The diagnosis was cancelled from the progress callback."""


def default_report_dir(dataset):
    """``<dataset folder>/diagnosis``: where the command puts the report."""
    return os.path.join(os.path.dirname(os.path.abspath(dataset)), "diagnosis")


def run_diagnosis(dataset, report_dir=None, progress=None, **options):
    """Diagnose ``dataset`` (path of a dataset.json) and write the report.

    ``report_dir``: directory of ``index.html``, ``report.md``, the plots and
    ``diagnosis.json`` (default :func:`default_report_dir`); it is written
    beside and renamed into place, so a failed or cancelled run leaves an
    earlier report untouched. ``progress(dict)`` gets keys stage, step,
    steps, elapsed_s, message; raising :class:`Cancelled` in it stops the run.
    ``options`` go to ``pteromys.diagnose`` (folds, effects, max_centres, ...).
    Returns ``(result, index_path)``.
    """
    pt = engine()
    if not os.path.isfile(dataset):
        raise ValueError("no dataset file at %s" % dataset)
    report_dir = os.path.abspath(report_dir or default_report_dir(dataset))
    parent = os.path.dirname(report_dir)
    if not os.path.isdir(parent):
        raise ValueError("the report's folder %s does not exist" % parent)
    def refuse_foreign_dir():
        # The report replaces the whole directory: not one that holds
        # anything but an earlier report (the dataset, a person's files).
        why = pt.report_dir_problem(report_dir)
        if why:
            raise ValueError("cannot write the report into %s: %s" % (report_dir, why))
    refuse_foreign_dir()  # before the run
    if not os.access(parent, os.W_OK | os.X_OK):
        raise ValueError("cannot write the report into %s: its folder %s is not writable" % (report_dir, parent))
    result = pt.diagnose(dataset, progress=progress, **options)
    tmp = tempfile.mkdtemp(prefix=".diagnosis-", dir=parent)
    try:
        with open(os.path.join(tmp, "diagnosis.json"), "w") as f:
            json.dump(result, f, indent=1)
        pt.diagnosis_report(result, tmp)
        refuse_foreign_dir()  # again: it may have changed during the run
        if os.path.lexists(report_dir) and _exchange(tmp, report_dir):
            # One step: the earlier report is now at tmp, removed below.
            shutil.rmtree(tmp, ignore_errors=True)
        else:
            _replace_aside(tmp, report_dir)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    return result, os.path.join(report_dir, "index.html")


_RENAME_EXCHANGE = 2  # linux/fs.h
_AT_FDCWD = -100


def _exchange(a, b):
    """Swap directories ``a`` and ``b`` in one step (Linux ``renameat2``
    with RENAME_EXCHANGE, as the command line does). False where the C
    library or the file system cannot (the caller then moves aside);
    other errors are raised."""
    try:
        libc = ctypes.CDLL(None, use_errno=True)
        fn = libc.renameat2
    except (OSError, AttributeError):
        return False
    fn.argtypes = [ctypes.c_int, ctypes.c_char_p, ctypes.c_int, ctypes.c_char_p, ctypes.c_uint]
    fn.restype = ctypes.c_int
    if fn(_AT_FDCWD, os.fsencode(a), _AT_FDCWD, os.fsencode(b), _RENAME_EXCHANGE) == 0:
        return True
    e = ctypes.get_errno()
    # no exchange here, or the earlier report went away meanwhile: the caller
    # moves instead
    if e in (errno.EINVAL, errno.ENOSYS, errno.EOPNOTSUPP, errno.ENOTSUP, errno.ENOENT):
        return False
    raise OSError(e, "cannot put the report in place: %s" % os.strerror(e), b)


def _replace_aside(tmp, report_dir):
    """Move an earlier report aside, ``tmp`` into its place, then remove
    the earlier one; if the second move fails the earlier report is put
    back, so one of the two is always at ``report_dir``."""
    old = None
    if os.path.lexists(report_dir):
        old = report_dir + ".old-%d" % os.getpid()
        os.replace(report_dir, old)
    try:
        os.replace(tmp, report_dir)
    except BaseException:
        if old:
            os.replace(old, report_dir)
        raise
    if old:
        shutil.rmtree(old, ignore_errors=True)


def second_search_options(result):
    """Options for a second search, or None: when ``result`` (a diagnosis
    that did not already search twice) leaves a real gap unexplained, the
    diagnosis can be made again with every aerodynamic correction also
    started at its theoretical size (``theory_starts``; the engine's
    ``escalate`` does the same after its first search; docs/diagnosis.md,
    "Second search"). Only with profiled starts, which those starts need;
    not after a withheld verdict (result key ``withheld``: a candidate closes
    the gap, and the launches are in question, not the starts). The
    options carry ``result`` as ``first``: the engine then concludes the
    second search as its ``escalate`` does, keeping an effect only if it
    also predicts the held-out gliders better than ``result``'s baseline by
    the margin (else ``result`` stands, its summary saying what the second
    search found), and records the first search in ``escalation``."""
    opts = result.get("options", {})
    if result.get("verdict") != "unexplained" or result.get("escalation", {}).get("ran"):
        return None
    if result.get("withheld"):  # a candidate closes the gap; the launches, not the starts, are in question
        return None
    if opts.get("theory_starts") or not opts.get("profile", True):
        return None
    return {"theory_starts": True, "first": result}


SECOND_SEARCH_QUESTION = (
    "No candidate effect closes the gap between the model and the flights.\n\n"
    "Search again with every aerodynamic correction also started at its theoretical size? "
    "It can find an effect the first search misses, but takes several times as long.")

# How much longer the second search took than the first on the blind
# benchmark: the smallest and largest ratio over the archived second
# searches (bench/diagnosis/runs-escalate; docs/diagnosis.md, "Second
# search": 1.4-7.3 times, median 2.7; tests/python/test_blind_bench.py
# recounts them).
SECOND_SEARCH_FACTOR = (1.4, 7.3)


def duration_text(seconds):
    """A duration as a person reads it: "under a minute", "about 7 min",
    "about 2 h 26 min"."""
    if not (seconds >= 0) or seconds == float("inf"):
        raise ValueError("a duration is a finite number of seconds, not %r" % (seconds,))
    minutes = int(round(seconds / 60.0))
    if minutes < 1:
        return "under a minute"
    if minutes < 60:
        return "about %d min" % minutes
    return "about %d h %02d min" % divmod(minutes, 60)


def _seconds_taken(result):
    """The diagnosis's own time (timings.total_s), or None when it has none."""
    t = (result.get("timings") or {}).get("total_s")
    return float(t) if isinstance(t, (int, float)) and not isinstance(t, bool) and t > 0 else None


def second_search_question(result):
    """The question the command asks after an `unexplained` first search:
    SECOND_SEARCH_QUESTION, with what the second search should take when
    the first search's time is known (SECOND_SEARCH_FACTOR times it), so a
    person can decide whether to wait."""
    s = _seconds_taken(result)
    if s is None:
        return SECOND_SEARCH_QUESTION
    lo, hi = (duration_text(f * s) for f in SECOND_SEARCH_FACTOR)
    if lo == hi:
        span = lo
    elif lo.startswith("about ") and hi.startswith("about "):  # "about 23 min to 56 min"
        span = "%s to %s" % (lo, hi[len("about "):])
    else:
        span = "%s to %s" % (lo, hi)
    return SECOND_SEARCH_QUESTION + " This search took %s; expect the second to take %s." % (duration_text(s), span)


def stability_options(result):
    """Options for checking a named verdict afterwards, or None: when
    ``result`` names an effect and has no stability check yet, the
    diagnosis can be made twice more with the simulation step changed
    slightly (1.9 and 2.1 ms for 2 ms), ``result`` standing for the first
    run (``first``), to see whether the verdict holds or turns on the
    search's path (docs/diagnosis.md, "Stability check"). Not for `none`
    or `unexplained`, whose re-runs would say nothing a person acts on."""
    if result is None or result.get("stability") or result.get("verdict") in (None, "none", "unexplained"):
        return None
    return {"stability": 3, "first": result}


def stability_question(result):
    """The question the command asks after a named verdict. After a second
    search each re-run makes both searches again (the engine's
    stability_rerun_options), which the question says."""
    both = (result.get("escalation") or {}).get("ran") is True
    s = _seconds_taken(result)
    # each re-run is one diagnosis like the first; after a second search a
    # re-run whose first search names the effect makes no second, so "up to"
    up_to = "up to " if both else ""
    took = "" if s is None else " (this diagnosis took %s, so %s%s more)" % (duration_text(s), up_to,
                                                                            duration_text(2 * s))
    return ("The verdict names %s.\n\n"
            "Check that it holds? The diagnosis is made twice more with the simulation step changed slightly "
            "(1.9 and 2.1 ms for 2 ms)%s; a verdict that changes turns on the search's path rather than on the "
            "data and is marked tentative in the report. It takes %sabout twice as long again%s."
            % (result["verdict"], ", each time with both searches, as the verdict was found" if both else "",
               up_to, took))


def summary_text(result):
    """A few lines for a message box: verdict, summary and the best effects."""
    lines = ["Verdict: %s" % result["verdict"], "", result.get("summary", ""), ""]
    if result.get("also"):
        lines[1:1] = ["Also significant beside it (a lead to test, not shown): %s" % ", ".join(result["also"])]
    if result.get("alternatives"):
        lines[1:1] = ["Cannot be told apart from it: %s" % ", ".join(result["alternatives"])]
    if result.get("withheld"):
        lines[1:1] = ["Withheld (launch rotation fits too; check the launches): %s" % result["withheld"]["effect"]]
    if result.get("passed_over"):
        lines[1:1] = ["Passed over (re-tuned coefficients can imitate it): %s" % result["passed_over"]["effect"]]
    for e in result["effects"][:3]:
        lines.append("%s: held-out %.1f cm, shrink %.0f %%%s" % (
            e["name"], 100 * e["holdout_rmse_m"], 100 * e["shrink"], ", significant" if e["significant"] else ""))
    return "\n".join(lines)
