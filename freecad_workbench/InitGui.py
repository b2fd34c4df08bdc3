# Pteromys add-on, GUI part: registers the workbench (runs only with the GUI).
import FreeCADGui


class PteromysWorkbench(FreeCADGui.Workbench):
    """Design hand-launched flat-plate gliders: sketches in, flight and laser-cut parts out."""

    MenuText = "Pteromys"
    ToolTip = "Design, optimise and build hand-launched gliders made of flat plates"

    def __init__(self):
        import os
        import pteromys_freecad.gui as g
        self.__class__.Icon = os.path.join(g.ICONS, "PteromysWorkbench.svg")

    def Initialize(self):
        from pteromys_freecad.gui import commands
        commands.register()
        self.appendToolbar("Pteromys", commands.TOOLBAR)
        self.appendMenu("&Pteromys", commands.MENU)

    def Activated(self):
        pass

    def Deactivated(self):
        pass

    def GetClassName(self):
        return "Gui::PythonWorkbench"


FreeCADGui.addWorkbench(PteromysWorkbench())
