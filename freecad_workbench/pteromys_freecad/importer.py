"""FreeCAD import/export hooks for glider files (File > Open / Import / Export).

Registered in Init.py for ``*.glider.json``. FreeCAD calls ``open`` (new
document), ``insert`` (into a document) and ``export`` (selected objects).
"""
import os

import FreeCAD as App


def open(filename):  # noqa: A001  (FreeCAD's hook name)
    name = os.path.basename(filename).split(".")[0] or "Glider"
    doc = App.newDocument(name)
    insert(filename, doc.Name)
    return doc


def insert(filename, docname):
    from . import fileio
    doc = App.getDocument(docname) if docname else App.ActiveDocument
    try:
        return fileio.import_glider_file(filename, doc=doc)
    except Exception as e:  # a bad file: say why, do not crash the importer
        App.Console.PrintError("Pteromys: cannot import '%s': %s\n" % (filename, e))
        raise


def export(objects, filename):
    from . import fileio
    from . import glider as G
    gl = [o for o in objects if G.is_glider(o)]
    if len(gl) != 1:
        raise ValueError("select exactly one Pteromys glider to export (got %d)" % len(gl))
    return fileio.export_glider_file(gl[0], filename)
