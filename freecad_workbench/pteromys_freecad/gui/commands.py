"""Toolbar and menu commands. Each one calls a function of the macro API
(:mod:`pteromys_freecad`), which is what to use from the console or a macro;
``FreeCADGui.runCommand("Pteromys_NewGlider")`` also works.
"""
import os
import traceback

import FreeCAD as App
import FreeCADGui as Gui

from . import icon

TOOLBAR = ["Pteromys_NewGlider", "Pteromys_AddWing", "Pteromys_OptimiseNow", "Pteromys_FlightView",
           "Separator", "Pteromys_ExportDXF", "Pteromys_ExportSTEP",
           "Separator", "Pteromys_ImportGlider", "Pteromys_ExportGlider"]
MENU = ["Pteromys_NewGlider", "Pteromys_AddWing", "Pteromys_EditGlider", "Pteromys_OptimiseNow",
        "Pteromys_FlightView", "Separator", "Pteromys_ExportDXF", "Pteromys_ExportSTEP", "Separator",
        "Pteromys_ImportGlider", "Pteromys_ExportGlider", "Separator", "Pteromys_TrackVideo"]


def _pf():
    import pteromys_freecad
    return pteromys_freecad


def _main_window():
    return Gui.getMainWindow()


def _tell(title, text, error=True):
    from PySide2 import QtWidgets
    (App.Console.PrintError if error else App.Console.PrintMessage)("Pteromys: %s: %s\n" % (title, text))
    if error:
        QtWidgets.QMessageBox.warning(_main_window(), "Pteromys: " + title, text)
    else:
        QtWidgets.QMessageBox.information(_main_window(), "Pteromys: " + title, text)


def _glider_or_tell(title):
    g = _pf().active_glider()
    if g is None:
        _tell(title, "There is no glider in the active document. Create one with 'New glider' or select one.")
    return g


class _Transaction:
    """Undo step around a command; aborted (and explained) when it fails."""

    def __init__(self, doc, name):
        self.doc, self.name = doc, name

    def __enter__(self):
        self.doc.openTransaction(self.name)
        return self

    def __exit__(self, kind, err, tb):
        if kind is None:
            self.doc.commitTransaction()
            return False
        self.doc.abortTransaction()
        App.Console.PrintLog("".join(traceback.format_exception(kind, err, tb)))
        _tell(self.name, str(err))
        return True  # handled: the message says why


def _save_name(title, suggestion, pattern):
    from PySide2 import QtWidgets
    path, _ = QtWidgets.QFileDialog.getSaveFileName(_main_window(), title, suggestion, pattern)
    return path


def _suggest(g, ext):
    doc = g.Document
    folder = os.path.dirname(doc.FileName) if doc.FileName else os.path.expanduser("~")
    return os.path.join(folder, (g.Label or "glider").replace(" ", "_") + ext)


class NewGlider:
    def GetResources(self):
        return {"Pixmap": icon("PteromysNewGlider"), "MenuText": "New glider",
                "ToolTip": "Create a glider from the template: a fuselage, a main wing and a tail, ready to edit"}

    def IsActive(self):
        return True

    def Activated(self):
        doc = App.ActiveDocument or App.newDocument("Glider")
        with _Transaction(doc, "New glider"):
            g = _pf().new_glider(doc)
            Gui.Selection.clearSelection()
            Gui.Selection.addSelection(g)
            Gui.SendMsgToActiveView("ViewFit")
            from . import flight_view
            flight_view.show(g)


class AddWing:
    def GetResources(self):
        return {"Pixmap": icon("PteromysAddWing"), "MenuText": "Add wing",
                "ToolTip": "Add a wing to the selected glider: a selected sketch becomes the wing, "
                           "otherwise a small tapered wing sketch is created to edit"}

    def IsActive(self):
        return App.ActiveDocument is not None

    def Activated(self):
        g = _glider_or_tell("Add wing")
        if g is None:
            return
        sketches = [o for o in Gui.Selection.getSelection() if o.TypeId == "Sketcher::SketchObject"]
        with _Transaction(g.Document, "Add wing"):
            w = _pf().add_wing(g, sketch=sketches[0] if sketches else None)
            App.Console.PrintMessage("Pteromys: added wing '%s' to '%s'; edit its sketch and mount\n"
                                     % (w.WingName, g.Label))


class EditGlider:
    def GetResources(self):
        return {"Pixmap": icon("PteromysGlider"), "MenuText": "Edit glider...",
                "ToolTip": "Open the glider's task panel: material, ballast, optimisation, locks and flights"}

    def IsActive(self):
        return App.ActiveDocument is not None and bool(_pf().gliders())

    def Activated(self):
        g = _glider_or_tell("Edit glider")
        if g is not None:
            Gui.ActiveDocument.setEdit(g.Name)


class OptimiseNow:
    def GetResources(self):
        return {"Pixmap": icon("PteromysOptimise"), "MenuText": "Optimise now",
                "ToolTip": "Optimise the unlocked wing mounts from the design values and store the result "
                           "in the design (works also with automatic optimisation off)"}

    def IsActive(self):
        return App.ActiveDocument is not None and bool(_pf().gliders())

    def Activated(self):
        g = _glider_or_tell("Optimise now")
        if g is None:
            return
        with _Transaction(g.Document, "Optimise now"):
            r = _pf().optimise_now(g)
            App.Console.PrintMessage("Pteromys: optimised '%s': %s\n" % (g.Label, r["status"]))


class FlightView:
    def GetResources(self):
        return {"Pixmap": icon("PteromysFlightView"), "MenuText": "Flight view",
                "ToolTip": "Show the six standard hand launches (height over distance) and the flyability summary"}

    def IsActive(self):
        return True

    def Activated(self):
        from . import flight_view
        flight_view.show(_pf().active_glider())


class _Export:
    title = ext = pattern = ""

    def IsActive(self):
        return App.ActiveDocument is not None and bool(_pf().gliders())

    def Activated(self):
        g = _glider_or_tell(self.title)
        if g is None:
            return
        path = _save_name(self.title, _suggest(g, self.ext), self.pattern)
        if not path:
            return
        if not path.lower().endswith(self.accept):
            path += self.ext
        try:
            self.run(g, path)
            App.Console.PrintMessage("Pteromys: wrote %s\n" % path)
        except Exception as e:
            _tell(self.title, str(e))


class ExportDXF(_Export):
    title, ext, accept, pattern = "Export DXF", ".dxf", (".dxf",), "DXF for laser cutting (*.dxf)"

    def GetResources(self):
        return {"Pixmap": icon("PteromysExportDXF"), "MenuText": "Export DXF...",
                "ToolTip": "Write the slotted plates, laid out flat on sheets, as a DXF for laser cutting (mm)"}

    def run(self, g, path):
        _pf().export_dxf(g, path)


class ExportSTEP(_Export):
    title, ext, accept, pattern = "Export STEP", ".step", (".step", ".stp"), "STEP (*.step *.stp)"

    def GetResources(self):
        return {"Pixmap": icon("PteromysExportSTEP"), "MenuText": "Export STEP...",
                "ToolTip": "Write the slotted plates, assembled, as STEP (3D printing, other CAD)"}

    def run(self, g, path):
        _pf().export_step(g, path)


class ExportGlider(_Export):
    title, ext, accept, pattern = "Export glider file", ".glider.json", (".json",), "Pteromys glider (*.glider.json)"

    def GetResources(self):
        return {"Pixmap": icon("PteromysExportGlider"), "MenuText": "Export glider file...",
                "ToolTip": "Write the glider (outlines and the mounts in use) as a .glider.json file"}

    def run(self, g, path):
        _pf().export_glider_file(g, path)


class ImportGlider:
    def GetResources(self):
        return {"Pixmap": icon("PteromysImportGlider"), "MenuText": "Import glider file...",
                "ToolTip": "Create sketches, wings and a glider from a .glider.json file"}

    def IsActive(self):
        return True

    def Activated(self):
        from PySide2 import QtWidgets
        path, _ = QtWidgets.QFileDialog.getOpenFileName(_main_window(), "Import glider file", os.path.expanduser("~"),
                                                        "Pteromys glider (*.glider.json *.json)")
        if not path:
            return
        doc = App.ActiveDocument or App.newDocument(os.path.basename(path).split(".")[0] or "Glider")
        with _Transaction(doc, "Import glider file"):
            g = _pf().import_glider_file(path, doc=doc)
            Gui.SendMsgToActiveView("ViewFit")
            from . import flight_view
            flight_view.show(g)


COMMANDS = {
    "Pteromys_NewGlider": NewGlider, "Pteromys_AddWing": AddWing, "Pteromys_EditGlider": EditGlider,
    "Pteromys_OptimiseNow": OptimiseNow, "Pteromys_FlightView": FlightView,
    "Pteromys_ExportDXF": ExportDXF, "Pteromys_ExportSTEP": ExportSTEP,
    "Pteromys_ImportGlider": ImportGlider, "Pteromys_ExportGlider": ExportGlider,
}
from .capture_view import TrackVideo  # noqa: E402 (flight capture, docs/capture.md)
COMMANDS["Pteromys_TrackVideo"] = TrackVideo

from ..diagnose_gui import DiagnoseFlights  # noqa: E402  (issue 7: sim-to-real diagnosis)
COMMANDS["Pteromys_DiagnoseFlights"] = DiagnoseFlights
MENU += ["Separator", "Pteromys_DiagnoseFlights"]

_registered = False


def register():
    global _registered
    if _registered:
        return
    for name, cls in COMMANDS.items():
        Gui.addCommand(name, cls())
    _registered = True
