"""Finding and importing the Pteromys engine (the ``pteromys`` Python module).

The workbench keeps no physics of its own: everything is computed by the
compiled engine through the ``pteromys`` package. It is found, in order:

1. already importable (installed into ``/usr/local/lib/python3/dist-packages``
   by ``cmake --install``, or on ``PYTHONPATH``);
2. the directories in the environment variable ``PTEROMYS_PYTHONPATH``
   (``:``-separated; a build directory's ``python`` folder);
3. the ``python_path`` entry of ``pteromys.cfg`` next to the installed add-on
   (written by ``freecad_workbench/install.sh``);
4. ``<repository>/build/python`` when the add-on runs from a source tree.

Parts of the engine land at different times (optimisation, fabrication).
:func:`feature_missing` names what a build lacks, in words for the user,
instead of pretending that a missing function worked.
"""
import json
import os
import sys

ADDON_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CONFIG_FILE = os.path.join(ADDON_DIR, "pteromys.cfg")

_engine = None
_error = None


def candidate_paths():
    """Directories searched for the ``pteromys`` package, in order."""
    paths = []
    env = os.environ.get("PTEROMYS_PYTHONPATH", "")
    paths += [p for p in env.split(os.pathsep) if p]
    try:
        with open(CONFIG_FILE, encoding="utf-8") as f:
            cfg = json.load(f)
        p = cfg.get("python_path")
        if p:
            paths.append(p)
    except (OSError, ValueError):
        pass
    paths.append(os.path.join(os.path.dirname(ADDON_DIR), "build", "python"))
    return paths


def _try_import():
    import importlib
    return importlib.import_module("pteromys")


def engine():
    """The ``pteromys`` module; raises ``EngineMissing`` with a plain reason."""
    global _engine, _error
    if _engine is not None:
        return _engine
    try:
        _engine = _try_import()
        return _engine
    except ImportError as e:
        first = e
    for p in candidate_paths():
        if os.path.isfile(os.path.join(p, "pteromys", "__init__.py")) and p not in sys.path:
            sys.path.insert(0, p)
            try:
                _engine = _try_import()
                return _engine
            except ImportError as e:  # a broken build: say which one
                sys.path.remove(p)
                first = e
    _error = ("the Pteromys engine (Python module 'pteromys') was not found: build it "
              "(cmake --build build) and install the add-on with freecad_workbench/install.sh, "
              "or set PTEROMYS_PYTHONPATH to <build>/python (%s)" % first)
    raise EngineMissing(_error)


class EngineMissing(RuntimeError):
    """The engine module cannot be imported."""


#: Engine functions the workbench uses beyond the core, with the user's words
#: for what is lost when the build lacks them.
FEATURES = {
    "optimize": "optimisation is not available in this build (pteromys.optimize is missing)",
    "slotted_plates": "slotted plates are not available in this build (pteromys.slotted_plates is missing)",
    "export": "DXF/STEP export is not available in this build (pteromys.export is missing)",
}


def feature_missing(name):
    """None when the engine has function `name`, else a sentence saying it is missing."""
    try:
        pt = engine()
    except EngineMissing as e:
        return str(e)
    return None if hasattr(pt, name) else FEATURES.get(name, "pteromys.%s is missing" % name)


def input_error_types():
    """Exception types that mean bad input (their message is for the user)."""
    pt = engine()
    return (pt.InputError, ValueError)
