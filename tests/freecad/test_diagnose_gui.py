"""The "Diagnose flights" command in the real FreeCAD GUI under Xvfb (issue 7):
the diagnosis runs under its progress dialog and opens its report in
FreeCAD's web view; after a gap the first search leaves unexplained the
command asks whether to search again (a real QMessageBox, answered by
clicking its buttons), Yes giving the second search's options and No none;
after a verdict naming an effect it asks whether to check that the verdict
holds (Yes: two re-runs at changed simulation steps, and the report with
its Stability section); after `none` it asks nothing.

Set PTEROMYS_SCREENSHOTS=DIR to keep the question's screenshot.
"""
import os

import pytest

from conftest import run_gui
from test_diagnose import _dataset

GUI_SCRIPT = r'''
import json, os, time, traceback
OUT = %(out)r
DS = %(ds)r
REPORT = %(report)r
SHOTS = %(shots)r
R = {}
def pump(n=10):
    from PySide2 import QtWidgets
    for _ in range(n):
        QtWidgets.QApplication.processEvents()
try:
    import FreeCAD as App, FreeCADGui as Gui
    from PySide2 import QtWidgets, QtCore, QtGui
    mw = Gui.getMainWindow()
    mw.showMaximized()
    pump()
    Gui.activateWorkbench("PteromysWorkbench")
    R["command"] = "Pteromys_DiagnoseFlights" in Gui.listCommands()
    from pteromys_freecad import diagnose_gui as dg
    mdi = mw.findChild(QtWidgets.QMdiArea)
    windows_before = len(mdi.subWindowList())
    # the progress dialog, watched while the engine works
    seen = {"visible": 0, "labels": []}
    def watch():
        for w in mw.findChildren(QtWidgets.QProgressDialog):
            if w.isVisible():
                seen["visible"] += 1
                seen["labels"].append(w.labelText())
    timer = QtCore.QTimer()
    timer.timeout.connect(watch)
    timer.start(200)
    opts = dict(folds=3, max_centres=1, effects=["wind", "camera"], threads=2)
    asked = []
    def unexpected_question():
        # a question where none is due: recorded and answered No
        w = QtWidgets.QApplication.activeModalWidget()
        if isinstance(w, QtWidgets.QMessageBox):
            asked.append(w.text())
            w.button(QtWidgets.QMessageBox.No).click()
    guard = QtCore.QTimer()
    guard.timeout.connect(unexpected_question)
    guard.start(1000)
    result = dg.diagnose_dataset(DS, REPORT, **opts)
    timer.stop()
    pump()
    R["verdict"] = result["verdict"] if result else None
    R["progress_visible"] = seen["visible"]
    R["labels"] = seen["labels"][-3:]
    R["report"] = os.path.join(REPORT, "index.html")
    R["windows_added"] = len(mdi.subWindowList()) - windows_before
    R["window_titles"] = [w.windowTitle() for w in mdi.subWindowList()]
    R["asked_after_run"] = list(asked)
    R["ask_after_" + str(result["verdict"])] = dg.ask_second_search(result)
    R["asked_after_ask"] = list(asked)
    guard.stop()
    import pteromys_freecad.diagnose as pd
    R["stability_question_of_run"] = pd.stability_question(result) if result["verdict"] not in ("none", "unexplained") else None
    # the question after an unexplained gap, answered by clicking
    unexplained = dict(result, verdict="unexplained", escalation={"ran": False})
    def answer(button, store):
        def click():
            w = QtWidgets.QApplication.activeModalWidget()
            store["dialog"] = type(w).__name__ if w is not None else None
            if isinstance(w, QtWidgets.QMessageBox):
                store["text"] = w.text()
                store["title"] = w.windowTitle()
                store["buttons"] = sorted(b.text().replace("&", "") for b in w.buttons())
                store["default"] = w.defaultButton().text().replace("&", "") if w.defaultButton() else None
                if SHOTS:
                    QtGui.QGuiApplication.primaryScreen().grabWindow(0).save(os.path.join(SHOTS, "diagnose_second_search.png"))
                w.button(button).click()
        QtCore.QTimer.singleShot(500, click)
    yes, no = {}, {}
    answer(QtWidgets.QMessageBox.Yes, yes)
    again = dg.ask_second_search(unexplained)
    R["yes"] = dict(again, first=again["first"] is unexplained) if again else again
    R["yes_dialog"] = yes
    answer(QtWidgets.QMessageBox.No, no)
    R["no"] = dg.ask_second_search(unexplained)
    R["no_dialog"] = no
    R["question"] = pd.second_search_question(unexplained)
    # the stability question after a named verdict (the run's, or the run
    # taken as naming wind), answered by clicking; Yes makes the re-runs
    # under the progress dialog and opens the report with the check
    named = dict(result, verdict=result["verdict"] if result["verdict"] not in ("none", "unexplained") else "wind")
    named.pop("stability", None)
    syes, sno = {}, {}
    answer(QtWidgets.QMessageBox.No, sno)
    R["stability_no"] = dg.ask_stability(named)
    R["stability_no_dialog"] = sno
    answer(QtWidgets.QMessageBox.Yes, syes)
    check = dg.ask_stability(named)
    R["stability_yes_dialog"] = syes
    R["stability_yes_keys"] = sorted(check) if check else None
    R["stability_question"] = pd.stability_question(named)
    checked = dg.run_with_progress(DS, REPORT, **dict(opts, **check)) if check else None
    R["checked_stability"] = checked.get("stability") if checked else None
    R["checked_page_has_section"] = "<h2>Stability</h2>" in open(os.path.join(REPORT, "index.html")).read()
    R["finished"] = True
except Exception:
    R["error"] = traceback.format_exc()
finally:
    with open(OUT, "w") as f:
        json.dump(R, f, indent=1, default=str)
    from PySide2 import QtWidgets, QtCore
    QtCore.QTimer.singleShot(0, QtWidgets.QApplication.quit)
'''


@pytest.fixture(scope="module")
def gui(fc_home, tmp_path_factory):
    tmp = tmp_path_factory.mktemp("diagnose_gui")
    ds = _dataset(tmp)
    report = tmp / "report"
    keep = os.environ.get("PTEROMYS_SCREENSHOTS", "")
    out = tmp / "gui.json"
    script = tmp / "diagnose_gui.py"
    script.write_text(GUI_SCRIPT % {"out": str(out), "ds": str(ds), "report": str(report), "shots": keep})
    if keep:
        os.makedirs(keep, exist_ok=True)
    r = run_gui(fc_home, script, out, tmp, timeout=1500)  # the diagnosis, then the stability check's two re-runs
    assert r.get("finished"), r
    return r


def test_diagnosis_runs_under_its_progress_dialog_and_opens_the_report(gui):
    assert gui["command"]
    assert gui["verdict"] in ("wind", "camera", "none", "unexplained")
    # the dialog was up while the engine worked, and showed its progress lines
    assert gui["progress_visible"] >= 3, gui
    assert any(l.strip() for l in gui["labels"]), gui["labels"]
    assert os.path.isfile(gui["report"])
    # the report opened in FreeCAD's web view, a new window of the main area
    assert gui["windows_added"] >= 1, gui["window_titles"]


def test_after_the_run_only_the_question_due_is_asked(gui):
    if gui["verdict"] == "unexplained":
        # the guard answered No to the second search's question, so it was
        # asked once (and no stability check after `unexplained`)
        assert gui["asked_after_run"] == [gui["question"]]
    elif gui["verdict"] == "none":
        assert gui["asked_after_run"] == [] and gui["asked_after_ask"] == []
        assert gui["ask_after_none"] is None
    else:
        # a named verdict: the stability question, answered No by the guard
        assert gui["asked_after_run"] == [gui["stability_question_of_run"]]
        assert gui["ask_after_" + gui["verdict"]] is None


def test_a_named_verdict_offers_the_stability_check_and_yes_makes_it(gui):
    for d in (gui["stability_yes_dialog"], gui["stability_no_dialog"]):
        assert d["dialog"] == "QMessageBox", d
        assert d["text"] == gui["stability_question"]
        assert d["buttons"] == ["No", "Yes"] and d["default"] == "No"
    assert gui["stability_no"] is None
    assert gui["stability_yes_keys"] == ["first", "stability"]
    st = gui["checked_stability"]
    # three runs in all: the result asked about (not diagnosed again) and two re-runs
    assert st is not None and st["of"] == 3 and len(st["runs"]) == 3
    assert [round(r["dt_s"], 5) for r in st["runs"]] == [0.002, 0.0019, 0.0021]
    assert st["sentence"] and gui["checked_page_has_section"]


def test_an_unexplained_gap_asks_for_the_second_search(gui):
    for d in (gui["yes_dialog"], gui["no_dialog"]):
        assert d["dialog"] == "QMessageBox", d
        assert d["text"] == gui["question"]
        assert d["title"] == "Pteromys: diagnose flights"
        assert d["buttons"] == ["No", "Yes"]
        assert d["default"] == "No"          # the slow search only when asked for
    assert gui["yes"] == {"theory_starts": True, "first": True}  # the result it follows, for the engine
    assert gui["no"] is None
