"""The "Diagnose flights" command (GUI part; the work is in ``diagnose.py``).

Choose a dataset.json, watch the progress (the engine runs in a worker thread
without the GIL; the dialog's Cancel stops it at the next progress report),
and the report opens in FreeCAD's web view (or the system browser). FreeCADGui
and Qt are imported inside the functions, so this module loads headless.
"""
import os
import threading
import time


class DiagnoseFlights:
    def GetResources(self):
        from .gui import icon
        return {"Pixmap": icon("PteromysFlightView"), "MenuText": "Diagnose flights...",
                "ToolTip": "Sim-to-real gap: where the model misses tracked flights and which effect explains it"}

    def IsActive(self):
        return True

    def Activated(self):
        from PySide2 import QtWidgets
        import FreeCADGui as Gui
        path, _ = QtWidgets.QFileDialog.getOpenFileName(Gui.getMainWindow(), "Flight dataset", os.path.expanduser("~"),
                                                        "Flight dataset (*.json)")
        if not path:
            return
        diagnose_dataset(path)


def diagnose_dataset(dataset, report_dir=None, **options):
    """Diagnose ``dataset`` with progress and open the report; after an
    unexplained gap, offer the second search (docs/diagnosis.md, "Second
    search") and, on Yes, run it and open its report; after a verdict that
    names an effect, offer to check that it holds at slightly changed
    simulation steps (docs/diagnosis.md, "Stability check") and, on Yes,
    make the re-runs and open the report with the check. Returns the last
    result (None when the diagnosis failed or was cancelled)."""
    result = run_with_progress(dataset, report_dir, **options)
    again = ask_second_search(result)
    if again is not None:
        second = run_with_progress(dataset, report_dir, **dict(options, **again))
        if second is None:
            return result
        result, options = second, dict(options, **again)
    check = ask_stability(result)
    if check is None:
        return result
    checked = run_with_progress(dataset, report_dir, **dict(options, **check))
    return checked if checked is not None else result


def ask_stability(result):
    """After a verdict naming an effect, ask whether to check that it holds:
    the options for the re-runs on Yes, None on No or when there is nothing
    to ask (a stability check asked for already, `none`, `unexplained`)."""
    from . import diagnose as pd
    check = pd.stability_options(result)
    return check if check is not None and _yes(pd.stability_question(result)) else None


def _yes(question):
    """Ask the command's Yes/No question (No the default): True on Yes."""
    from PySide2 import QtWidgets
    import FreeCADGui as Gui
    answer = QtWidgets.QMessageBox.question(
        Gui.getMainWindow(), "Pteromys: diagnose flights", question,
        QtWidgets.QMessageBox.Yes | QtWidgets.QMessageBox.No, QtWidgets.QMessageBox.No)
    return answer == QtWidgets.QMessageBox.Yes


def ask_second_search(result):
    """After a real gap the first search left unexplained, ask whether to
    search again from the corrections' theoretical sizes: the options for
    that search on Yes, None on No or when there is nothing to ask."""
    from . import diagnose as pd
    again = None if result is None else pd.second_search_options(result)
    return again if again is not None and _yes(pd.second_search_question(result)) else None


def run_with_progress(dataset, report_dir=None, **options):
    """Run the diagnosis of ``dataset`` under a progress dialog and open its report."""
    import FreeCAD as App
    import FreeCADGui as Gui
    from PySide2 import QtCore, QtWidgets
    from . import diagnose as pd

    dlg = QtWidgets.QProgressDialog("Starting the diagnosis...", "Cancel", 0, 100, Gui.getMainWindow())
    dlg.setWindowTitle("Pteromys: diagnose flights")
    dlg.setWindowModality(QtCore.Qt.WindowModal)
    dlg.setMinimumDuration(0)
    state = {"p": None, "cancel": False, "done": False, "result": None, "error": None}

    def progress(p):
        state["p"] = p
        App.Console.PrintLog("Pteromys diagnose: %s\n" % p["message"])
        if state["cancel"]:
            raise pd.Cancelled("cancelled")

    def work():
        try:
            state["result"] = pd.run_diagnosis(dataset, report_dir, progress=progress, **options)
        except BaseException as e:  # reported in the GUI thread
            state["error"] = e
        state["done"] = True

    th = threading.Thread(target=work, daemon=True)
    th.start()
    while not state["done"]:
        p = state["p"]
        if p:
            dlg.setMaximum(max(1, p["steps"]))
            dlg.setValue(min(p["step"], p["steps"]))
            dlg.setLabelText("%s\n(%.0f s)" % (p["message"][:160], p["elapsed_s"]))
        if dlg.wasCanceled():
            state["cancel"] = True
        QtWidgets.QApplication.processEvents()
        time.sleep(0.1)
    th.join()
    dlg.close()
    if state["error"] is not None:
        e = state["error"]
        if not state["cancel"]:
            App.Console.PrintError("Pteromys diagnose: %s\n" % e)
            QtWidgets.QMessageBox.warning(Gui.getMainWindow(), "Pteromys: diagnose flights", str(e))
        return None
    result, index = state["result"]
    App.Console.PrintMessage("Pteromys diagnose: %s (report %s)\n" % (result["verdict"], index))
    open_report(index)
    return result


def open_report(index):
    """Open the report in FreeCAD's web view, or the system browser."""
    try:
        import WebGui
        WebGui.openBrowser(index)
        return
    except Exception:
        pass
    from PySide2 import QtCore, QtGui
    QtGui.QDesktopServices.openUrl(QtCore.QUrl.fromLocalFile(index))
