# Pteromys add-on, headless part: runs in freecadcmd and in the GUI.
# Keep it light: no engine import here (it happens on first use), no GUI imports.
import FreeCAD

FreeCAD.addImportType("Pteromys glider (*.glider.json)", "pteromys_freecad.importer")
FreeCAD.addExportType("Pteromys glider (*.glider.json)", "pteromys_freecad.importer")
