#!/usr/bin/env python3
"""Writes the seed inputs of the fuzz targets whose input is not a project
file: corpus/geometry (the byte encoding of fuzz_geometry.cpp) and
corpus/dataset (a selector byte, then a flights.csv or dataset.json).
Run from anywhere; rewrites the seeds in place."""
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))


def i8(v):
    return struct.pack("b", v)


def geometry(fuselage, wings, ballast=None, thickness=2, density=1):
    b = bytes([thickness, density, len(fuselage) - 3])
    for x, y in fuselage:
        b += i8(x) + i8(y)
    b += bytes([len(wings) - 1])
    for w in wings:
        b += bytes([len(w["half"]) - 1]) + i8(w["x0"]) + i8(w["x1"])
        for x, z in w["half"]:
            b += i8(x) + i8(z)
        b += i8(w["mx"]) + i8(w["my"]) + i8(w["angle"])
    if ballast:
        b += bytes([1, ballast[0]]) + i8(ballast[1]) + i8(ballast[2])
    else:
        b += bytes([0])
    return b


# Coordinates in 5 mm units (mount y in mm, angle in 0.2 deg).
FUS = [(0, 0), (-60, 2), (-60, 8), (-56, 8), (-50, 3), (0, 3)]
MAIN = {"x0": -8, "x1": -24, "half": [(-10, 40), (-24, 40)], "mx": 0, "my": 12, "angle": 10}
TAIL = {"x0": -50, "x1": -57, "half": [(-52, 12), (-57, 12)], "mx": 0, "my": 25, "angle": 0}
SWEPT = {"x0": -6, "x1": -20, "half": [(-16, 36), (-22, 36)], "mx": 0, "my": 12, "angle": 10}
DELTA = {"x0": -4, "x1": -30, "half": [(-30, 30)], "mx": 0, "my": 12, "angle": 10}
CRESCENT = {"x0": -8, "x1": -22, "half": [(-10, 20), (-20, 40), (-26, 42), (-22, 20)], "mx": 0, "my": 12, "angle": 5}
OFF = dict(MAIN, my=100)  # a wing that misses the fuselage

SEEDS = {
    "two_wings": geometry(FUS, [MAIN, TAIL], ballast=(4, -2, 3)),
    "swept": geometry(FUS, [SWEPT, TAIL]),
    "delta": geometry(FUS, [DELTA]),
    "crescent": geometry(FUS, [CRESCENT, TAIL], ballast=(6, 0, 2)),
    "wing_off_fuselage": geometry(FUS, [OFF, TAIL]),
    "bowtie_fuselage": geometry([(0, 0), (-60, 8), (-60, 0), (0, 8)], [MAIN]),
}

CSV = ("flight,glider,t_s,x_m,y_m\n" + "".join(
    "f1,g,%.3f,%.3f,%.3f\n" % (k / 30.0, 0.2 * k, 1.5 + 0.02 * k - 0.01 * k * k / 3) for k in range(8)))
DATASET = ('{"format": "pteromys-flights/1", "gliders": {"g": "g.glider.json"}, '
           '"flights_csv": "flights.csv", "frame_rate_hz": 30, "tracking_sigma_m": 0.01}')
DATA_SEEDS = {
    "csv_valid": b"\x00" + CSV.encode(),
    "csv_extra_column": b"\x00" + "\n".join(
        [CSV.splitlines()[0] + ",launcher_speed_m_s"] + [r + ",7" for r in CSV.splitlines()[1:]]).encode() + b"\n",
    "csv_nan": b"\x00" + CSV.replace("0.200,", "nan,", 1).encode(),
    "json_valid": b"\x01" + DATASET.encode(),
    "json_unknown_glider": b"\x01" + DATASET.replace('"g":', '"h":').encode(),
}

for sub, seeds in (("geometry", SEEDS), ("dataset", DATA_SEEDS)):
    d = os.path.join(HERE, "corpus", sub)
    os.makedirs(d, exist_ok=True)
    for name, data in seeds.items():
        with open(os.path.join(d, name), "wb") as f:
            f.write(data)
print("seeds written")
