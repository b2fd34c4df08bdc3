"""View provider of the Glider: tree children, colour by result, flight view refresh, task panel.

Path ``pteromys_freecad.gui.view_glider.ViewProviderGlider`` is saved in documents: never rename.
"""
import FreeCAD as App
import FreeCADGui as Gui

from . import icon

FLYABLE_COLOUR = (0.96, 0.93, 0.82)     # foam board
NOT_FLYABLE_COLOUR = (0.95, 0.55, 0.35)  # warm orange: look at the reasons
ERROR_COLOUR = (0.75, 0.75, 0.75)        # last good shape of an input error


class ViewProviderGlider:
    def __init__(self, vobj):
        vobj.Proxy = self
        self._ensure(vobj)

    def _ensure(self, vobj):
        if "ColorByResult" not in vobj.PropertiesList:
            vobj.addProperty("App::PropertyBool", "ColorByResult", "Pteromys",
                             "Colour the plates by the result: foam = flyable, orange = not flyable, grey = input error")
            vobj.ColorByResult = True

    def attach(self, vobj):
        self.ViewObject = vobj
        self.Object = vobj.Object
        self._ensure(vobj)

    def getIcon(self):
        obj = getattr(self, "Object", None)
        if obj is not None and getattr(obj, "Problems", None):
            return icon("PteromysGliderError")
        if obj is not None and hasattr(obj, "Flyable") and obj.ResultData and not obj.Flyable:
            return icon("PteromysGliderWarning")
        return icon("PteromysGlider")

    def claimChildren(self):
        obj = getattr(self, "Object", None)
        if obj is None:
            return []
        kids = [obj.Fuselage] if getattr(obj, "Fuselage", None) else []
        return kids + list(getattr(obj, "Wings", []) or [])

    def updateData(self, obj, prop):
        if prop in ("ResultData", "Status", "Problems"):
            self._colour(obj)
            try:
                from . import flight_view
                flight_view.glider_updated(obj)
            except Exception as e:  # a plot must never break a recompute
                App.Console.PrintWarning("Pteromys: flight view not refreshed: %s\n" % e)

    def _colour(self, obj):
        vobj = getattr(self, "ViewObject", None)
        if vobj is None or not getattr(vobj, "ColorByResult", False):
            return
        if obj.Problems:
            c = ERROR_COLOUR
        elif obj.Flyable:
            c = FLYABLE_COLOUR
        else:
            c = NOT_FLYABLE_COLOUR
        if tuple(round(v, 3) for v in vobj.ShapeColor[:3]) != tuple(round(v, 3) for v in c):
            vobj.ShapeColor = c

    def onChanged(self, vobj, prop):
        if prop == "ColorByResult" and getattr(vobj, "ColorByResult", False):
            self._colour(vobj.Object)

    def doubleClicked(self, vobj):
        Gui.ActiveDocument.setEdit(vobj.Object.Name)
        return True

    def setEdit(self, vobj, mode=0):
        if mode != 0:
            return None
        from . import task_panel
        self._panel = task_panel.GliderTaskPanel(vobj.Object)
        Gui.Control.showDialog(self._panel)
        return True

    def unsetEdit(self, vobj, mode=0):
        if mode != 0:
            return None
        panel, self._panel = getattr(self, "_panel", None), None
        if panel is not None and not panel.done:
            panel.abort()          # closed without OK: undo the panel's edits
        Gui.Control.closeDialog()
        return True

    def setupContextMenu(self, vobj, menu):
        from PySide2 import QtWidgets
        obj = vobj.Object
        a = QtWidgets.QAction("Edit glider...", menu)
        a.triggered.connect(lambda: Gui.ActiveDocument.setEdit(obj.Name))
        menu.addAction(a)
        b = QtWidgets.QAction("Show flight view", menu)
        b.triggered.connect(lambda: __import__("pteromys_freecad.gui.flight_view", fromlist=["x"]).show(obj))
        menu.addAction(b)

    def dumps(self):
        return None

    def loads(self, state):
        return None

    __getstate__ = dumps

    def __setstate__(self, state):
        return None
