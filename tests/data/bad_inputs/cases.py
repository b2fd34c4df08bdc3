"""The bad-input corpus of the command line (issue 9; docs/reliability.md).

Each case is one bad input to one reader or command: the files it writes into
a fresh folder, the command line, and what a user must get back: the exit
status of the spec (2 = bad input, docs/formats.md) and the words of the
one-line message that name the problem. tests/python/test_bad_inputs.py runs
every case; `python3 cases.py --table` prints the table of docs/reliability.md
(a test checks that the document shows this table).

Placeholders in argv: {d} the case's folder, {ex} examples/gliders, {out} a
path in a fresh output folder that must still be empty afterwards.
"""
import json

GLIDER_OK = "{ex}/tapered.glider.json"
DATASET = {"format": "pteromys-flights/1", "gliders": {"g": "g.glider.json"}, "flights_csv": "flights.csv",
           "frame_rate_hz": 30, "tracking_sigma_m": 0.01}
HEADER = "flight,glider,t_s,x_m,y_m"
ROWS = ["f1,g,%.3f,%.3f,%.3f" % (k / 30.0, 0.2 * k, 1.5 - 0.001 * k * k) for k in range(8)]


def csv(rows=None, header=HEADER):
    return "\n".join([header] + (ROWS if rows is None else rows)) + "\n"


def dataset(csv_text=None, **changes):
    """Files of a dataset with dataset.json changed by `changes` (None deletes a key)."""
    d = dict(DATASET)
    for k, v in changes.items():
        if v is None:
            d.pop(k, None)
        else:
            d[k] = v
    files = {"dataset.json": json.dumps(d), "flights.csv": csv() if csv_text is None else csv_text,
             "g.glider.json": "@copy {ex}/tapered.glider.json"}
    return files


def fit(files, name, what, exit, words):
    return {"id": name, "reader": "flight dataset", "what": what, "files": files,
            "argv": ["fit", "{d}/dataset.json", "-o", "{out}/model.json", "--quiet"], "exit": exit, "words": words}


MODEL_OK = "@copy {root}/engine/models/fitted.model.json"


def model(name, what, text, words):
    return {"id": name, "reader": "model file", "what": what, "files": {"m.model.json": text},
            "argv": ["evaluate", GLIDER_OK, "--model", "{d}/m.model.json", "--json", "{out}/report.json"],
            "exit": 2, "words": words}


def cmd(name, what, argv, words, files=None, exit=2):
    return {"id": name, "reader": "command line", "what": what, "files": files or {}, "argv": argv,
            "exit": exit, "words": words}


CASES = [
    # ------------------------------------------------------------ datasets
    fit({"dataset.json": "{\"format\": \"pteromys-flights/1\",", "flights.csv": csv()},
        "dataset_not_json", "dataset.json is cut off", 2, ["dataset.json", "not valid JSON"]),
    fit({"dataset.json": "[1, 2]"}, "dataset_top_level_array", "a JSON array instead of an object", 2,
        ["dataset.json", "JSON object"]),
    fit(dataset(format="pteromys-flights/9"), "dataset_unknown_format", "format pteromys-flights/9", 2,
        ["unknown format", "pteromys-flights/9"]),
    fit(dataset(gliders=None), "dataset_missing_gliders", "no 'gliders' key", 2, ["missing key 'gliders'"]),
    fit(dataset(gliders={"g": "nowhere.glider.json"}), "dataset_glider_file_missing",
        "a glider file that does not exist", 2, ["nowhere.glider.json"]),
    fit(dict(dataset(), **{"g.glider.json": "@copy {root}/tests/data/broken/self_intersecting_wing.glider.json"}),
        "dataset_glider_invalid", "a glider whose wing crosses itself", 2, ["g.glider.json", "crosses itself"]),
    fit(dataset(flights_csv=None), "dataset_missing_flights_csv", "no 'flights_csv' key", 2,
        ["missing key 'flights_csv'"]),
    fit(dataset(flights_csv="gone.csv"), "dataset_csv_missing", "the flights CSV does not exist", 2,
        ["gone.csv"]),
    fit(dataset(frame_rate_hz=-30), "dataset_negative_frame_rate", "frame_rate_hz -30", 2,
        ["frame_rate_hz", "positive"]),
    fit(dataset(tracking_sigma_m="1 cm"), "dataset_sigma_string", "tracking_sigma_m as a string", 2,
        ["tracking_sigma_m", "number"]),
    fit(dataset(csv_text=""), "csv_empty", "an empty flights.csv", 2, ["flights.csv"]),
    fit(dataset(csv_text=csv(header="flight,glider,time,x,y")), "csv_wrong_header", "wrong column names", 2,
        ["header must start with flight,glider,t_s,x_m,y_m"]),
    fit(dataset(csv_text=csv(ROWS[:3] + ["f1,g,0.100,nan,1.49"] + ROWS[4:])), "csv_nan", "x_m is nan", 2,
        ["flights.csv", "line 5"]),
    fit(dataset(csv_text=csv(ROWS[:3] + ["f1,g,0.100,abc,1.49"] + ROWS[4:])), "csv_not_a_number",
        "x_m is 'abc'", 2, ["flights.csv", "line 5"]),
    fit(dataset(csv_text=csv(ROWS[:3] + ["f1,g,0.100,0x1A,1.49"] + ROWS[4:])), "csv_hexadecimal",
        "x_m written 0x1A (hexadecimal)", 2, ["flights.csv line 5 x_m", "'0x1A' is not a decimal number"]),
    fit(dataset(csv_text=csv(ROWS[:3] + ["f1,g,0.100," + "9" * 5000 + ",1.49"] + ROWS[4:])), "csv_huge_number",
        "x_m of 5000 digits", 2, ["flights.csv line 5 x_m", "'" + "9" * 37 + "...' is beyond the range"]),
    fit(dataset(csv_text=csv(ROWS[:3] + ["f1,g,0.100," + "\u00e9" * 30 + ",1.49"] + ROWS[4:])), "csv_long_text_cell",
        "x_m of 30 accented letters (60 bytes)", 2, ["x_m: '" + "\u00e9" * 18 + "...' is not a number"]),
    fit(dataset(csv_text=csv(ROWS[:3] + [ROWS[2]] + ROWS[4:])), "csv_time_not_increasing",
        "a repeated time", 2, ["flights.csv", "line 5", "time does not increase"]),
    fit(dataset(csv_text=csv(ROWS[:4])), "csv_too_few_points", "a flight of 4 points", 2,
        ["'f1' has 4 points", "at least 6"]),
    fit(dataset(csv_text=csv([r.replace(",g,", ",h,") for r in ROWS])), "csv_unknown_glider",
        "rows name glider 'h', which dataset.json does not list", 2, ["unknown glider", "h"]),
    fit(dataset(csv_text=csv(ROWS[:3] + [r.replace("f1,", "f2,") for r in ROWS] + ROWS[3:])),
        "csv_rows_not_contiguous", "flight f1's rows interrupted by f2", 2, ["flights.csv", "rows of flight 'f1' are not together"]),
    fit(dataset(csv_text=csv([r + ",1" for r in ROWS])), "csv_extra_cells", "more cells than the header", 2,
        ["flights.csv", "line 2"]),
    fit(dict(dataset(), **{"flights.csv": csv(ROWS[:2] + [ROWS[2].replace("f1,", "f\xe9,")]).encode("latin-1")}),
        "csv_not_utf8", "a flight name saved as Latin-1 (byte 0xE9)", 2,
        ["flights.csv line 4", "0xE9 is not UTF-8"]),
    fit(dataset(gravity_m_s2=981), "dataset_gravity_in_cm", "gravity_m_s2 981 (cm/s^2)", 2,
        ["gravity_m_s2 is 981", "1 to 30"]),
    fit(dataset(air={"density_kg_m3": 100}), "dataset_air_density", "air density 100 kg/m^3", 2,
        ["air.density_kg_m3 is 100"]),
    fit(dataset(tracking_sigma_m=1e-300), "dataset_sigma_underflows", "tracking_sigma_m 1e-300", 2,
        ["tracking_sigma_m", "at least 1e-09"]),
    fit(dataset(flights_csv="/dev/zero"), "dataset_csv_endless", "flights_csv /dev/zero (endless)", 2,
        ["/dev/zero", "larger than 256 MB"]),
    # ------------------------------------------------------------ model files
    model("model_not_json", "a model file cut off", "{\"format\": \"pteromys-model/1\",", ["not valid JSON"]),
    model("model_unknown_format", "format pteromys-model/7", json.dumps({"format": "pteromys-model/7"}),
          ["unknown model format", "pteromys-model/7"]),
    model("model_unknown_type", "type 'neural'", json.dumps({"format": "pteromys-model/1", "type": "neural"}),
          ["neural"]),
    model("model_rbf_no_centres", "an RBF model without centres",
          json.dumps({"format": "pteromys-model/1", "type": "rbf"}), ["missing key 'scales'"]),
    model("model_centres_not_list", "centres is a string", "@edit centres='many'", ["centres must be a non-empty list"]),
    model("model_centre_missing_cl", "a centre without its lift coefficient", "@edit centres[0].cl=None",
          ["centres[0]", "cl"]),
    model("model_overflowing_number", "a scale of 1e999", "@edit scales.alpha_deg=1e999", ["not a finite number"]),
    model("model_coefficient_huge", "a centre's cl of 1e308", "@edit centres[0].cl=1e308",
          ["centres[0].cl is 1e+308", "between -10 and 10"]),
    model("model_negative_scale", "a negative RBF scale", "@edit scales.alpha_deg=-3",
          ["scales must be positive"]),
    model("model_limit_string", "alpha_limit_deg as a string", "@edit alpha_limit_deg='40'",
          ["alpha_limit_deg must be a number"]),
    # ------------------------------------------------------------ commands
    cmd("no_command", "pteromys with no command", [], ["no command given"]),
    cmd("unknown_command", "pteromys fly", ["fly"], ["unknown command", "fly"]),
    cmd("evaluate_no_glider", "evaluate without a file", ["evaluate"], ["GLIDER"]),
    cmd("evaluate_missing_file", "a glider file that does not exist", ["evaluate", "{d}/none.glider.json"],
        ["none.glider.json"]),
    cmd("evaluate_unknown_option", "--colour red", ["evaluate", GLIDER_OK, "--colour", "red"],
        ["unknown option", "--colour"]),
    cmd("evaluate_height_not_number", "--height abc", ["evaluate", GLIDER_OK, "--height", "abc"],
        ["--height", "abc"]),
    cmd("evaluate_negative_dz", "--dz -1", ["evaluate", GLIDER_OK, "--dz", "-1"], ["--dz"]),
    cmd("evaluate_zero_dt", "--dt 0", ["evaluate", GLIDER_OK, "--dt", "0"], ["--dt"]),
    cmd("evaluate_model_missing", "--model of a file that does not exist",
        ["evaluate", GLIDER_OK, "--model", "{d}/none.model.json"], ["none.model.json"]),
    cmd("evaluate_output_dir_missing", "--json into a folder that does not exist",
        ["evaluate", GLIDER_OK, "--json", "{d}/no/such/dir/r.json"], ["no/such/dir"]),
    cmd("simulate_no_csv", "simulate without --csv", ["simulate", GLIDER_OK], ["--csv"]),
    cmd("optimize_no_output", "optimize without -o", ["optimize", GLIDER_OK], ["-o"]),
    cmd("optimize_unknown_lock", "--lock of a wing that does not exist",
        ["optimize", GLIDER_OK, "-o", "{out}/o.glider.json", "--lock", "rudder.angle"], ["rudder"]),
    cmd("export_nothing_to_write", "export without an output", ["export", GLIDER_OK], ["--dxf"]),
    cmd("export_negative_kerf", "--kerf -0.1", ["export", GLIDER_OK, "--dxf", "{out}/p.dxf", "--kerf", "-0.1"],
        ["kerf"]),
    cmd("export_huge_clearance", "a slot clearance larger than the plate",
        ["export", GLIDER_OK, "--dxf", "{out}/p.dxf", "--clearance", "50"], ["clearance"]),
    cmd("fit_no_output", "fit without -o", ["fit", "{d}/dataset.json"], ["-o"], files=dataset()),
    cmd("fit_output_is_the_dataset", "fit -o the dataset's own dataset.json",
        ["fit", "{d}/dataset.json", "-o", "{d}/dataset.json", "--quiet"], ["is an input of the dataset"],
        files=dataset()),
    cmd("fit_output_is_the_csv", "fit --json the dataset's flights.csv",
        ["fit", "{d}/dataset.json", "-o", "{out}/m.json", "--json", "{d}/flights.csv", "--quiet"],
        ["flights.csv", "is an input of the dataset"], files=dataset()),
    cmd("fit_outputs_collide", "fit -o X --json X",
        ["fit", "{d}/dataset.json", "-o", "{out}/x.json", "--json", "{out}/x.json", "--quiet"],
        ["same file as the model"], files=dataset()),
    cmd("fit_report_on_a_full_disk", "fit --json /dev/full: the model is not written either",
        ["fit", "{d}/dataset.json", "-o", "{out}/m.json", "--json", "/dev/full", "--quiet", "--max-centres", "1"],
        ["/dev/full", "no output was changed"], files=dataset()),
    cmd("fit_tiny_step", "fit --dt 1e-7 (would run for hours)",
        ["fit", "{d}/dataset.json", "-o", "{out}/m.json", "--dt", "1e-7"], ["--dt", "1e-05"], files=dataset()),
    cmd("evaluate_outputs_collide", "evaluate --json X --csv X",
        ["evaluate", GLIDER_OK, "--json", "{out}/x", "--csv", "{out}/x"], ["same file as the report"]),
    cmd("optimize_over_its_glider", "optimize -o its own glider file",
        ["optimize", "{d}/g.glider.json", "-o", "{d}/g.glider.json"], ["is the glider"],
        files={"g.glider.json": "@copy {ex}/tapered.glider.json"}),
    cmd("generate_unknown_effect", "--effects of an unknown effect",
        ["generate", GLIDER_OK, "-o", "{out}/data", "--effects", "gravity_waves"], ["gravity_waves"]),
    cmd("generate_mirroring_camera", "--camera-scale-error -2 with the camera effect on (mirrors the flights)",
        ["generate", GLIDER_OK, "-o", "{out}/data", "--effects", "camera", "--camera-scale-error", "-2"],
        ["camera scale with its scale error", "got -1"]),
    cmd("diagnose_unknown_effect", "--effects of an unknown effect",
        ["diagnose", "{d}/dataset.json", "--json", "{out}/d.json", "--effects", "gremlins"], ["gremlins"],
        files=dataset()),
    cmd("diagnose_tiny_step", "diagnose --dt 1e-9 (would run for days)",
        ["diagnose", "{d}/dataset.json", "--json", "{out}/d.json", "--dt", "1e-9"], ["--dt", "1e-05"],
        files=dataset()),
    cmd("diagnose_json_is_the_report", "diagnose --json X --report X",
        ["diagnose", "{d}/dataset.json", "--json", "{out}/x", "--report", "{out}/x", "--quiet"],
        ["same file as the diagnosis"], files=dataset()),
    cmd("diagnose_too_few_gliders", "a dataset of one glider (cross-validation needs several)",
        ["diagnose", "{d}/dataset.json", "--json", "{out}/d.json", "--quiet"], ["glider"], files=dataset()),
    cmd("calibrate_not_json", "a points file that is not JSON",
        ["calibrate", "{d}/points.json", "-o", "{out}/calib.json"], ["points.json"],
        files={"points.json": "x"}),
    cmd("track_video_missing", "a video that does not exist",
        ["track", "{d}/none.avi", "--calib", "{d}/c.json", "--glider", GLIDER_OK, "-o", "{out}/data"],
        ["none.avi"]),
    cmd("render_trajectory_hexadecimal", "render-video --trajectory with x_m written 0x1A",
        ["render-video", GLIDER_OK, "-o", "{out}/v.avi", "--trajectory", "{d}/t.csv", "--quiet"],
        ["t.csv' line 3", "'0x1A' is not a decimal number"],
        files={"t.csv": "t_s,x_m,y_m\n0,0,1.5\n0.1,0x1A,1.5\n0.2,2,1.4\n"}),
]


def edited_model(root, edit):
    """The shipped fitted model with one edit 'path=python-literal' (None deletes;
    1e999 is written as the JSON number 1e999, which overflows a double)."""
    import ast
    import re
    with open(root + "/engine/models/fitted.model.json") as f:
        m = json.load(f)
    path, value = edit.split("=", 1)
    keys = [int(k) if k.isdigit() else k for k in re.findall(r"[^.\[\]]+", path)]
    obj = m
    for k in keys[:-1]:
        obj = obj[k]
    v = ast.literal_eval(value)
    if v is None:
        del obj[keys[-1]]
    else:
        obj[keys[-1]] = "@@OVERFLOW@@" if value == "1e999" else v
    return json.dumps(m, indent=1).replace('"@@OVERFLOW@@"', "1e999")


def glider_cases(root):
    """The broken glider files of tests/data/broken and the words each message must hold."""
    with open(root + "/tests/data/broken/expected.json") as f:
        exp = json.load(f)
    return sorted(exp.items())


def table(root=None):
    import os
    root = root or os.path.abspath(os.path.join(os.path.dirname(__file__), "..", "..", ".."))
    lines = ["| input | reader / command | exit | message names |", "|---|---|---|---|"]
    for name, words in glider_cases(root):
        lines.append("| tests/data/broken/%s | glider file (every command) | 2 | \u201c%s\u201d |" % (name, words))
    for c in CASES:
        lines.append("| %s (`%s`) | %s | %d | %s |" % (c["what"], c["id"], c["reader"], c["exit"],
                                                     ", ".join("\u201c%s\u201d" % w for w in c["words"])))
    return "\n".join(lines) + "\n"


if __name__ == "__main__":
    import sys
    if "--table" in sys.argv:
        sys.stdout.write(table())
