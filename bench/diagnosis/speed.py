#!/usr/bin/env python3
"""Speed of `pteromys diagnose` on the issue's reference size (issue 7, "Speed"):
a 20-glider dataset of 110-120 flights, every diagnosis default, with the
readable report. Prints wall clock, CPU time, peak memory and the phase
timings the diagnosis stores (docs/diagnosis.md, "Speed").

    /usr/bin/python3 bench/diagnosis/speed.py --build build [--out out/diag-speed] [--polish N]

The dataset is what `pteromys generate` makes of the 20 training gliders with
the six aerodynamic effects on (`--effects physics`), 6 launches each at the
paper's tracking (30 fps, 15-20 points, 5 cm noise): 120 flights, 2104
points with the default seed (launches that leave fewer than 6 tracked points
would be left out by the generator).
"""
import argparse
import glob
import json
import os
import resource
import shlex
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", ".."))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "diag-speed"))
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--noise-m", type=float, default=None,
                    help="tracking noise of the generated dataset [m] (default: generate's, 5 cm)")
    ap.add_argument("--effects", default="physics",
                    help="effects of the generated dataset (default physics: the six aerodynamic ones); with one "
                         "the diagnosis finds (e.g. wind), the second round runs too, the slowest case")
    ap.add_argument("--polish", type=int, default=0, help="passed to diagnose (default 0, its default)")
    ap.add_argument("--generate-args", default="",
                    help='further options for `pteromys generate`, e.g. the blind benchmark\'s recording protocol '
                         '"--frame-rate 30 --points 30-45 --retrim 2 --speed-relative 1:1.3" (longer tracked '
                         'windows: docs/diagnosis.md, "Speed")')
    ap.add_argument("--diagnose-args", default="",
                    help='further options for the diagnosis, e.g. "--step-alpha 1" (for experiments)')
    ap.add_argument("--no-report", action="store_true", help="time the diagnosis without the HTML report")
    ap.add_argument("--profile", action="store_true",
                    help="pass --profile (profiled starts, the default since 2026-11-26; for binaries of earlier commits)")
    ap.add_argument("--no-profile", action="store_true", help="pass --no-profile (fixed coefficients only) to diagnose")
    args = ap.parse_args()
    pt = os.path.join(args.build, "bin", "pteromys")
    if not os.access(pt, os.X_OK):
        sys.exit("speed.py: %s is not built (run ./scripts/setup.sh)" % pt)
    os.makedirs(args.out, exist_ok=True)
    data = os.path.join(args.out, "data")
    gliders = sorted(glob.glob(os.path.join(ROOT, "examples", "training", "*.glider.json")))
    if not os.path.isfile(os.path.join(data, "dataset.json")):
        t = time.time()
        subprocess.run([pt, "generate"] + gliders + ["-o", data, "--effects", args.effects, "--seed", str(args.seed)] +
                       (["--noise-m", str(args.noise_m)] if args.noise_m is not None else []) + [
                                                      "--quiet"] + shlex.split(args.generate_args), check=True)
        print("dataset generated in %.1f s" % (time.time() - t))
    with open(os.path.join(data, "dataset.json")) as f:
        ds = json.load(f)
    n_gliders = len(ds["gliders"])
    import csv
    with open(os.path.join(data, ds.get("flights_csv", "flights.csv"))) as f:
        rows = list(csv.DictReader(f))
    n_flights = len({r["flight"] for r in rows})
    print("dataset: %d gliders, %d flights, %d tracked points" % (n_gliders, n_flights, len(rows)))

    res = os.path.join(args.out, "diagnosis.json")
    cmd = [pt, "diagnose", os.path.join(data, "dataset.json"), "--json", res]
    if not args.no_report:
        cmd += ["--report", os.path.join(args.out, "report")]
    if args.polish:
        cmd += ["--polish", str(args.polish)]
    if args.profile:
        cmd += ["--profile"]
    if args.no_profile:
        cmd += ["--no-profile"]
    cmd += shlex.split(args.diagnose_args)
    print("$ " + " ".join(cmd), flush=True)
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    t = time.time()
    with open(os.path.join(args.out, "log.txt"), "w") as log:
        p = subprocess.run(cmd, stderr=log)
    wall = time.time() - t
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    if p.returncode != 0:
        sys.exit("diagnose failed (%d); see %s" % (p.returncode, os.path.join(args.out, "log.txt")))
    with open(res) as f:
        d = json.load(f)
    try:
        load = os.getloadavg()[0]
    except OSError:
        load = float("nan")
    print("wall clock            %6.0f s  (%d min %02d s; target <= 600 s)" % (wall, wall // 60, wall % 60))
    print("CPU time (user+sys)   %6.0f s  on %d cores" %
          (r1.ru_utime - r0.ru_utime + r1.ru_stime - r0.ru_stime, os.cpu_count()))
    print("peak memory           %6.0f MB" % (r1.ru_maxrss / 1024.0))
    print("load average (1 min)  %6.1f  at the end (other work on the machine slows the run)" % load)
    for k, v in sorted(d.get("timings", {}).items()):
        if isinstance(v, (int, float)):
            print("  timings.%-24s %8.1f s" % (k, v))
    print("verdict: %s" % d["verdict"])


if __name__ == "__main__":
    main()
