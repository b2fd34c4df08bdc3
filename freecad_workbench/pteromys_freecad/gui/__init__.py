"""GUI parts of the workbench (view providers, commands, flight view, task panel).

Imported only when FreeCAD's GUI is up; nothing outside this package imports
FreeCADGui or Qt at module level, so the add-on loads in freecadcmd.
"""
import os

ICONS = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))), "Resources", "icons")


def icon(name):
    """Path of an icon in Resources/icons."""
    return os.path.join(ICONS, name + ".svg")
