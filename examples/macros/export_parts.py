# Pteromys macro: get the parts of a glider: laser-cut DXF, STEP, the glider
# file and a plot of its flights.
#
#   freecadcmd examples/macros/export_parts.py
#   PTEROMYS_MACRO_DOC=my.FCStd freecadcmd examples/macros/export_parts.py
#
# Uses the first glider of $PTEROMYS_MACRO_DOC, else a new template glider.
# Writes to $PTEROMYS_MACRO_OUT (default ./pteromys_macro_out):
#   <name>.dxf, <name>.step, <name>.glider.json, <name>_flights.png, <name>_results.json
import json
import os
import sys

import FreeCAD as App

try:
    import pteromys_freecad as pf
except ImportError:  # running from a source tree without installing the add-on
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "freecad_workbench"))
    import pteromys_freecad as pf

OUT = os.path.abspath(os.environ.get("PTEROMYS_MACRO_OUT") or "pteromys_macro_out")
os.makedirs(OUT, exist_ok=True)



def main():
    path = os.environ.get("PTEROMYS_MACRO_DOC")
    if path:
        doc = App.openDocument(os.path.abspath(path))
        glider = pf.gliders(doc)[0]
        doc.recompute()
    else:
        doc = App.newDocument("Parts")
        glider = pf.new_glider(doc, name="Dart")

    r = pf.results(glider)
    if r["problems"]:
        raise RuntimeError("the glider has input errors: %s" % "; ".join(r["problems"]))
    print("Status:", r["status"])
    stem = os.path.join(OUT, glider.Label.replace(" ", "_"))

    written = {}
    written["glider"] = pf.export_glider_file(glider, stem + ".glider.json")
    written["plot"] = pf.save_flight_plot(glider, stem + "_flights.png")
    summary = {}
    summary["dxf"] = pf.export_dxf(glider, stem + ".dxf")
    written["dxf"] = stem + ".dxf"
    summary["step"] = pf.export_step(glider, stem + ".step")
    written["step"] = stem + ".step"
    with open(stem + "_results.json", "w") as f:
        json.dump({"results": {k: v for k, v in r.items() if k != "report"}, "files": written,
                   "export": summary}, f, indent=1, default=str)
    for k, v in written.items():
        print("wrote %-6s %s" % (k, v))


try:
    main()
except Exception:
    if App.GuiUp:   # in the GUI, show the error and keep FreeCAD running
        raise
    import traceback
    traceback.print_exc()
    sys.exit(1)     # headless: a failing macro fails its command line (freecadcmd exits 0 otherwise)
