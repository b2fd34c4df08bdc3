"""View provider of a Wing: icon and its sketch as tree child.

Path ``pteromys_freecad.gui.view_wing.ViewProviderWing`` is saved in documents: never rename.
"""
from . import icon


class ViewProviderWing:
    def __init__(self, vobj):
        vobj.Proxy = self

    def attach(self, vobj):
        self.ViewObject = vobj
        self.Object = vobj.Object

    def getIcon(self):
        return icon("PteromysWing")

    def claimChildren(self):
        obj = getattr(self, "Object", None)
        s = getattr(obj, "Sketch", None) if obj is not None else None
        return [s] if s is not None else []

    def doubleClicked(self, vobj):
        s = getattr(vobj.Object, "Sketch", None)
        if s is not None:
            import FreeCADGui as Gui
            Gui.ActiveDocument.setEdit(s.Name)
            return True
        return False

    def dumps(self):
        return None

    def loads(self, state):
        return None

    __getstate__ = dumps

    def __setstate__(self, state):
        return None
