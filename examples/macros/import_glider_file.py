# Pteromys macro: bring a glider file into FreeCAD, evaluate it as mounted,
# then let the optimiser fix its mounts, and save both versions.
#
#   PTEROMYS_MACRO_GLIDER=examples/gliders/tapered.glider.json freecadcmd examples/macros/import_glider_file.py
#
# Writes to $PTEROMYS_MACRO_OUT (default ./pteromys_macro_out):
#   imported.FCStd, imported_as_file.json, imported_optimised.glider.json, imported_compare.json
import json
import os
import sys

import FreeCAD as App

try:
    import pteromys_freecad as pf
except ImportError:  # running from a source tree without installing the add-on
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "freecad_workbench"))
    import pteromys_freecad as pf

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.abspath(os.environ.get("PTEROMYS_MACRO_OUT") or "pteromys_macro_out")
os.makedirs(OUT, exist_ok=True)
src = os.environ.get("PTEROMYS_MACRO_GLIDER") or os.path.join(HERE, "..", "gliders", "tapered.glider.json")


def main():
    doc = App.newDocument("Imported")
    glider = pf.import_glider_file(src, doc=doc)   # automatic optimisation is off: the file's mounts
    before = pf.results(glider)
    print("as in the file:  flyable %s, distances %s" % (before["flyable"], ["%.1f" % d for d in before["launch_distances_m"]]))
    with open(os.path.join(OUT, "imported_as_file.json"), "w") as f:
        json.dump({k: v for k, v in before.items() if k != "report"}, f, indent=1)

    glider.AutoOptimise = True
    doc.recompute()
    after = pf.results(glider)
    print("optimised:       flyable %s, distances %s" % (after["flyable"], ["%.1f" % d for d in after["launch_distances_m"]]))
    if not after["problems"]:
        pf.export_glider_file(glider, os.path.join(OUT, "imported_optimised.glider.json"))
    with open(os.path.join(OUT, "imported_compare.json"), "w") as f:
        json.dump({"source": os.path.abspath(src), "before": {k: v for k, v in before.items() if k != "report"},
                   "after": {k: v for k, v in after.items() if k != "report"}}, f, indent=1)
    doc.saveAs(os.path.join(OUT, "imported.FCStd"))
    print("wrote", OUT)


try:
    main()
except Exception:
    if App.GuiUp:   # in the GUI, show the error and keep FreeCAD running
        raise
    import traceback
    traceback.print_exc()
    sys.exit(1)     # headless: a failing macro fails its command line (freecadcmd exits 0 otherwise)
