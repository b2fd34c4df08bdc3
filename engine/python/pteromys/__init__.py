"""Pteromys: design, optimise and build hand-launched gliders made of flat plates.

The compiled engine lives in ``pteromys._core``; this package adds a few
conveniences. Gliders are accepted as :class:`Glider` objects, as dicts in the
glider-file format of ``spec/formats.md`` or as paths to ``.glider.json`` files.

Units are SI (metres, kilograms, seconds); angles in degrees where the name
ends in ``_deg``.
"""
import json as _json

from . import _core
from ._core import (  # noqa: F401  (re-exported API)
    Glider,
    InputError,
    Model,
    MountedGlider,
    default_model,
    default_model_path,
    flat_plate_model,
    load_glider,
    load_model,
    mass_properties,
    model_from_json,
    mount,
    save_glider,
    slice_wing,
    validation_problems,
)

__version__ = _core.__version__

#: Column names of a trajectory array returned by :func:`simulate` and :func:`evaluate`.
TRAJECTORY_COLUMNS = ("t_s", "x_m", "y_m", "pitch_deg", "speed_m_s", "alpha_deg",
                      "pitch_rate_deg_s", "vx_m_s", "vy_m_s")


def glider(data):
    """A :class:`Glider` from a dict (glider-file format), JSON text or a path."""
    if isinstance(data, Glider):
        return data
    if isinstance(data, dict):
        return Glider.from_json(_json.dumps(data))
    if isinstance(data, str) and data.lstrip().startswith("{"):
        return Glider.from_json(data)
    return load_glider(str(data))


def glider_dict(g):
    """The glider-file dict of a glider (any accepted form)."""
    return _json.loads(glider(g).to_json())


def evaluate(g, model=None, height=1.5, dz=0.005, dt=0.002, integrator="verlet", record_every=5):
    """Flyability report of a glider as it is mounted.

    Returns ``(report, trajectories)``: the report as a dict in the format
    ``pteromys-report/1`` and a list with one ``(n, 9)`` array per standard
    launch (columns :data:`TRAJECTORY_COLUMNS`).
    """
    text, flights = _core.evaluate(g if not isinstance(g, dict) else glider(g), model, height, dz, dt,
                                   integrator, record_every)
    return _json.loads(text), list(flights)


def simulate(g, speed=7.0, climb_deg=0.0, height=1.5, pitch_deg=None, pitch_rate_deg_s=0.0, model=None,
             dz=0.005, dt=0.002, t_max=20.0, integrator="verlet", record_every=1, ballistic=False):
    """Simulate one hand launch; see ``pteromys._core.simulate``."""
    return _core.simulate(g if not isinstance(g, dict) else glider(g), speed, climb_deg, height, pitch_deg,
                          pitch_rate_deg_s, model, dz, dt, t_max, integrator, record_every, ballistic)
from ._core import optimize, design_cost, OptimizeState  # noqa: E402,F401  (issue 3)
from ._core import export, fabrication_plan, slotted_plates  # noqa: F401,E402  (fabrication, docs/fabrication.md)
from .fit import fit, fit_launch, predict_flights, simulate_track, synthetic_dataset  # noqa: E402,F401  (issue 6)
from .reference import *  # noqa: E402,F401,F403  (issue 6: reference simulator)
from . import capture  # noqa: E402,F401  (issue 8: flight capture, docs/capture.md)
from .diagnose import diagnose, diagnosis_report, effect_library, report_dir_problem  # noqa: E402,F401  (issue 7: sim-to-real diagnosis)
