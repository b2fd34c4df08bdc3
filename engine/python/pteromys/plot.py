"""Plots of flights: height over distance for the standard launches (paper Fig. 4).

Command line: ``python3 -m pteromys.plot REPORT.json TRAJECTORIES.csv OUT.png``.
"""
from pteromys import _atomic
import csv
import json
import sys


def _pyplot():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def read_trajectories(path):
    """{launch index: (x list, y list)} from a `pteromys simulate` CSV."""
    out = {}
    with open(path) as f:
        for row in csv.DictReader(f):
            k = int(row["launch"])
            xs, ys = out.setdefault(k, ([], []))
            xs.append(float(row["x_m"]))
            ys.append(float(row["y_m"]))
    return out


def plot_launches(report, trajectories, path, title=None):
    """Height over distance of the six launches with the flyability summary.

    `report`: report dict; `trajectories`: {index: (xs, ys)} or a list of
    (n, >=3) arrays (t, x, y, ...).
    """
    plt = _pyplot()
    if not isinstance(trajectories, dict):
        trajectories = {i: (a[:, 1], a[:, 2]) for i, a in enumerate(trajectories)}
    fig, ax = plt.subplots(figsize=(8, 3.6), dpi=110)
    colours = {7.0: "#1b9e77", 9.0: "#d95f02", 11.0: "#7570b3"}
    for i, l in enumerate(report["launches"]):
        if i not in trajectories:
            continue
        xs, ys = trajectories[i]
        style = "-" if l["angle_deg"] == 0 else "--"
        label = f'{l["speed_m_s"]:g} m/s, {l["angle_deg"]:g}° up: {l["distance_m"]:.1f} m'
        if not l["stable"]:
            label += " (unstable)"
        ax.plot(xs, ys, style, color=colours.get(float(l["speed_m_s"]), "k"), label=label)
    ax.axhline(0, color="0.5", lw=0.8)
    ax.set_xlabel("distance [m]")
    ax.set_ylabel("height [m]")
    ax.set_aspect("equal", adjustable="datalim")
    ax.grid(alpha=0.3)
    ok = "flyable" if report["flyable"] else "NOT flyable"
    g = report.get("glide") or {}
    extra = f', glide {g["speed_m_s"]:.1f} m/s, L/D {g["glide_ratio"]:.1f}' if g else ""
    ax.set_title(title or f'{report.get("glider", "")}: {ok}{extra}', fontsize=10)
    ax.legend(fontsize=7, loc="upper right")
    fig.tight_layout()
    _atomic.savefig(fig, path)
    plt.close(fig)


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    if len(argv) != 3:
        print("usage: python3 -m pteromys.plot REPORT.json TRAJECTORIES.csv OUT.png", file=sys.stderr)
        return 2
    with open(argv[0]) as f:
        report = json.load(f)
    plot_launches(report, read_trajectories(argv[1]), argv[2])
    return 0


if __name__ == "__main__":
    sys.exit(main())
