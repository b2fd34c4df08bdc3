#!/usr/bin/env python3
"""Writes the corpus of broken glider files and expected.json (file -> message fragment).

Each file breaks one rule of spec/formats.md or of physical sense; the engine
must reject it with a message containing the fragment, never crash.
"""
import copy
import json
import os

HERE = os.path.dirname(os.path.abspath(__file__))
BASE = {
    "format": "pteromys-glider/1",
    "name": "base",
    "material": {"thickness_m": 0.001, "density_kg_m3": 180.0},
    "fuselage": {"outline_m": [[0.0, 0.0], [-0.05, 0.012], [-0.30, 0.008], [-0.30, -0.004], [-0.05, -0.010]]},
    "wings": [
        {"name": "main",
         "outline_m": [[0.0, 0.0], [-0.005, 0.20], [-0.055, 0.20], [-0.07, 0.0], [-0.055, -0.20], [-0.005, -0.20]],
         "mount": {"x_m": -0.06, "y_m": 0.004, "angle_deg": 3.0}},
        {"name": "tail",
         "outline_m": [[0.0, 0.0], [-0.01, 0.07], [-0.04, 0.07], [-0.045, 0.0], [-0.04, -0.07], [-0.01, -0.07]],
         "mount": {"x_m": -0.255, "y_m": 0.006, "angle_deg": 0.0}}],
    "ballast": [{"name": "paperclip", "mass_kg": 0.0012, "x_m": -0.012, "y_m": 0.0}],
}

cases = {}


def case(name, fragment, mutate=None, text=None):
    if text is None:
        g = copy.deepcopy(BASE)
        mutate(g)
        text = json.dumps(g, indent=1)
    with open(os.path.join(HERE, name + ".glider.json"), "w") as f:
        f.write(text)
    cases[name + ".glider.json"] = fragment


def delete(path):
    def m(g):
        d = g
        for k in path[:-1]:
            d = d[k]
        del d[path[-1]]
    return m


def setv(path, value):
    def m(g):
        d = g
        for k in path[:-1]:
            d = d[k]
        d[path[-1]] = value
    return m


case("not_json", "not valid JSON", text="{ this is not json ]")
case("empty", "not valid JSON", text="")
case("nan_thickness", "NaN or Infinity",
     text=json.dumps(BASE, indent=1).replace('"thickness_m": 0.001', '"thickness_m": NaN'))
case("infinite_mount", "NaN or Infinity",
     text=json.dumps(BASE, indent=1).replace('"x_m": -0.06', '"x_m": -Infinity'))
case("overflowing_number", "not a finite number",
     text=json.dumps(BASE, indent=1).replace('"density_kg_m3": 180.0', '"density_kg_m3": 1e999'))
case("unknown_format", "unknown format", setv(["format"], "pteromys-glider/9"))
case("missing_format", "missing key 'format'", delete(["format"]))
case("missing_material", "missing key 'material'", delete(["material"]))
case("missing_thickness", "missing key 'material.thickness_m'", delete(["material", "thickness_m"]))
case("missing_mount", "missing key 'wings[1].mount'", delete(["wings", 1, "mount"]))
case("string_number", "material.thickness_m must be a number", setv(["material", "thickness_m"], "1mm"))
case("null_number", "is null", setv(["wings", 0, "mount", "angle_deg"], None))
case("zero_thickness", "thickness must be a positive", setv(["material", "thickness_m"], 0.0))
case("negative_density", "density must be a positive", setv(["material", "density_kg_m3"], -5.0))
case("self_intersecting_fuselage", "fuselage outline crosses itself",
     setv(["fuselage", "outline_m"], [[0.0, 0.0], [-0.3, 0.01], [-0.3, -0.01], [-0.1, 0.02]]))
case("self_intersecting_wing", "wing 'main' outline crosses itself",
     setv(["wings", 0, "outline_m"], [[0.0, -0.2], [-0.06, 0.2], [-0.06, -0.2], [0.0, 0.2]]))
case("degenerate_wing", "degenerate", setv(["wings", 1, "outline_m"], [[0.0, -0.07], [0.0, 0.0], [0.0, 0.07]]))
case("two_points", "needs at least 3", setv(["wings", 0, "outline_m"], [[0.0, -0.2], [0.0, 0.2]]))
case("duplicate_point", "repeats the point",
     setv(["fuselage", "outline_m"], [[0.0, 0.0], [-0.05, 0.012], [-0.05, 0.012], [-0.30, 0.008], [-0.30, -0.004]]))
case("asymmetric_wing", "not mirror-symmetric",
     setv(["wings", 0, "outline_m"], [[0.0, 0.0], [-0.005, 0.20], [-0.055, 0.20], [-0.07, 0.0], [-0.055, -0.15], [-0.005, -0.15]]))
case("wing_off_fuselage", "wing 'tail' does not touch the fuselage", setv(["wings", 1, "mount", "y_m"], 0.2))
case("wing_ahead_of_nose", "wing 'main' does not touch the fuselage", setv(["wings", 0, "mount", "x_m"], 0.2))
case("no_wings", "has no wing", setv(["wings"], []))
case("millimetres", "millimetres", setv(["fuselage", "outline_m"],
                                       [[0.0, 0.0], [-50, 12], [-300, 8], [-300, -4], [-50, -10]]))
case("outline_not_list", "must be a list of [x, y] pairs", setv(["wings", 0, "outline_m"], "rectangle"))
case("point_not_pair", "must be a pair of numbers", setv(["wings", 0, "outline_m", 2], [1.0, 2.0, 3.0]))
case("duplicate_wing_names", "two wings are named 'main'", setv(["wings", 1, "name"], "main"))
case("negative_ballast", "negative mass", setv(["ballast", 0, "mass_kg"], -0.001))
case("wings_not_list", "wings must be a list", setv(["wings"], {"main": 1}))
case("top_level_array", "must hold a JSON object", text="[1, 2, 3]")

with open(os.path.join(HERE, "expected.json"), "w") as f:
    json.dump(cases, f, indent=1, sort_keys=True)
    f.write("\n")
print(len(cases), "broken files")
