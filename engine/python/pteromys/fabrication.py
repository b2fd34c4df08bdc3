"""Pictures of fabrication results: the laser-cutting layout and the assembly.

The plates, joints and files come from the engine (:func:`pteromys.slotted_plates`,
:func:`pteromys.export`); this module only draws them with matplotlib (Agg).

Command line (Debian's interpreter, ``PYTHONPATH=build/python``)::

    python3 -m pteromys.fabrication layout PARTS.dxf OUT.png
    python3 -m pteromys.fabrication assembly GLIDER.glider.json OUT.png [--joints] [--kerf MM ...]
"""
import argparse
import math
import os
import sys

import numpy as np

from . import _atomic, _core

__all__ = ["read_dxf_layout", "plot_layout", "plot_assembly", "plot_joints"]


def read_dxf_layout(path):
    """Entities of a DXF written by ``pteromys export``, read back with ezdxf.

    Returns a dict with ``cut`` and ``sheet`` (lists of (n, 2) arrays [mm],
    closed polylines), ``lines`` ((m, 2, 2) array [mm]) and ``texts`` (list of
    (text, (x, y) [mm], height [mm], rotation [deg])) on the ENGRAVE layer,
    and ``units`` ($INSUNITS).
    """
    import ezdxf  # Debian python3-ezdxf; imported here so the package loads without it

    doc = ezdxf.readfile(path)
    msp = doc.modelspace()
    out = {"cut": [], "sheet": [], "lines": [], "texts": [], "units": doc.header.get("$INSUNITS", 0)}
    for e in msp:
        layer = e.dxf.layer
        kind = e.dxftype()
        if kind == "LWPOLYLINE":
            pts = np.array([(p[0], p[1]) for p in e.get_points("xy")], dtype=float)
            if layer == "CUT":
                out["cut"].append(pts)
            elif layer == "SHEET":
                out["sheet"].append(pts)
        elif kind == "LINE" and layer == "ENGRAVE":
            out["lines"].append(((e.dxf.start.x, e.dxf.start.y), (e.dxf.end.x, e.dxf.end.y)))
        elif kind == "TEXT" and layer == "ENGRAVE":
            p = e.dxf.align_point if e.dxf.hasattr("align_point") else e.dxf.insert
            out["texts"].append((e.dxf.text, (p.x, p.y), e.dxf.height, e.dxf.get("rotation", 0.0)))
    out["lines"] = np.array(out["lines"], dtype=float).reshape(-1, 2, 2)
    return out


def _mpl():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def plot_layout(dxf_path, png_path, title=None):
    """Draws the sheets of a DXF: cuts in red, engraving in blue, sheets in grey."""
    plt = _mpl()
    lay = read_dxf_layout(dxf_path)
    xs = np.concatenate([s[:, 0] for s in lay["sheet"]]) if lay["sheet"] else np.array([0.0, 600.0])
    ys = np.concatenate([s[:, 1] for s in lay["sheet"]]) if lay["sheet"] else np.array([0.0, 900.0])
    w, h = xs.max() - xs.min(), ys.max() - ys.min()
    fig, ax = plt.subplots(figsize=(max(4.0, 7.0 * w / max(h, 1.0)), 7.5))
    for s in lay["sheet"]:
        ax.fill(s[:, 0], s[:, 1], facecolor="#f3efe6", edgecolor="0.6", lw=0.8)
    for c in lay["cut"]:
        c2 = np.vstack([c, c[:1]])
        ax.plot(c2[:, 0], c2[:, 1], color="#c0392b", lw=0.6)
    for (a, b) in lay["lines"]:
        ax.plot([a[0], b[0]], [a[1], b[1]], color="#1f5fa8", lw=0.6)
    for text, (x, y), height, rot in lay["texts"]:
        ax.text(x, y, text, fontsize=max(3.0, height * 1.1), rotation=rot, color="#1f5fa8",
                ha="center", va="center", rotation_mode="anchor")
    ax.set_aspect("equal")
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("y [mm]")
    ax.set_title(title or os.path.basename(dxf_path) + ": red = cut, blue = engrave")
    fig.tight_layout()
    _atomic.savefig(fig, png_path, dpi=170)
    plt.close(fig)
    return png_path


def _plate_faces(p):
    """Corners of the plate's outline on both faces in the glider frame [mm]."""
    M = np.asarray(p["transform"])
    t = p["thickness_m"]
    out = []
    for w in (-t / 2, t / 2):
        uv = np.asarray(p["outline"])
        P = np.c_[uv, np.full(len(uv), w), np.ones(len(uv))] @ M.T
        out.append(P[:, :3] * 1000)
    return out


def plot_assembly(glider, png_path, **options):
    """Side view, top view and 3D view of the assembled plates (slots visible).

    ``options`` go to :func:`pteromys.slotted_plates` (kerf_mm, clearance_mm, ...).
    """
    plt = _mpl()
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: F401  (registers 3d)

    plates = _core.slotted_plates(glider, **options)
    colours = {"fuselage": "#8c6d46", "wing": "#3b7dbd"}
    fig = plt.figure(figsize=(13, 8))
    ax3 = fig.add_subplot(2, 2, (1, 3), projection="3d")
    side = fig.add_subplot(2, 2, 2)
    top = fig.add_subplot(2, 2, 4)
    for p in plates:
        col = colours[p["kind"]]
        a, b = _plate_faces(p)
        ax3.add_collection3d(Poly3DCollection([a[:, [0, 2, 1]]], facecolor=col, alpha=0.55, edgecolor="k", lw=0.3))
        for h in p["holes"]:
            M = np.asarray(p["transform"])
            H = (np.c_[np.asarray(h), np.zeros(len(h)), np.ones(len(h))] @ M.T)[:, :3] * 1000
            ax3.plot(H[:, 0], H[:, 2], H[:, 1], color="k", lw=0.6)
        # side view (x, y) and top view (x, z): both faces
        for face in (a, b):
            f = np.vstack([face, face[:1]])
            side.plot(f[:, 0], f[:, 1], color=col, lw=0.7)
            top.plot(f[:, 0], f[:, 2], color=col, lw=0.7)
    fus = next(p for p in plates if p["kind"] == "fuselage")
    for m in fus["marks"]:
        if m["kind"] == "cross" and "gravity" in m["text"]:
            c = m["points"][0] * 1000
            side.plot(c[0], c[1], "k+", ms=10)
            side.annotate("CG", c, textcoords="offset points", xytext=(4, -12))
    allp = np.vstack([np.vstack(_plate_faces(p)) for p in plates])
    lo, hi = allp.min(axis=0), allp.max(axis=0)
    span = (hi - lo).max() / 2
    mid = (hi + lo) / 2
    ext = np.maximum(hi - lo, 1.0)
    ax3.set_xlim(lo[0], hi[0])
    ax3.set_ylim(lo[2], hi[2])
    ax3.set_zlim(mid[1] - 0.15 * span, mid[1] + 0.15 * span)
    ax3.set_box_aspect((ext[0], ext[2], 0.3 * span))
    ax3.set_xlabel("x [mm]")
    ax3.set_ylabel("z [mm]")
    ax3.set_zlabel("y [mm]")
    ax3.view_init(elev=28, azim=-130)
    side.set_aspect("equal")
    side.set_title("side view (x, y): tilted slots hold the mounting angles")
    side.set_xlabel("x [mm]")
    side.set_ylabel("y [mm]")
    top.set_aspect("equal")
    top.set_title("top view (x, z)")
    top.set_xlabel("x [mm]")
    top.set_ylabel("z [mm]")
    joints = sorted({j["wing"] + ": " + j["type"] for p in plates for j in p["joints"]})
    fig.suptitle("assembled plates; joints " + ", ".join(joints))
    fig.tight_layout()
    _atomic.savefig(fig, png_path, dpi=140)
    plt.close(fig)
    return png_path


def _closed(p):
    p = np.asarray(p) * 1000
    return np.vstack([p, p[:1]])


def plot_joints(glider, png_path, **options):
    """One column per wing: the fuselage around the joint (top) and the wing's
    root (bottom), finished parts in plate coordinates [mm], slots as the
    engine reports them, cut paths dashed.
    """
    plt = _mpl()
    plates = _core.slotted_plates(glider, **options)
    fus = plates[0]
    joints = fus["joints"]
    fig, axes = plt.subplots(2, len(joints), figsize=(4.6 * len(joints), 6.4), squeeze=False)
    for k, j in enumerate(joints):
        top, bot = axes[0][k], axes[1][k]
        lo, hi = np.array(j["engaged_m"]) * 1000
        pad = max(12.0, 0.35 * (hi - lo))
        # fuselage, around the slot(s) of this wing
        fs = [s for s in j["slots"] if s["plate"] == "fuselage"]
        wp = next(p for p in plates if p["wing"] == j["wing"])
        centre = (wp["transform"] @ np.array([(lo + hi) / 2000, 0.0, 0.0, 1.0]))[:2] * 1000
        for poly, style in [(fus["outline"], "-"), *[(h, "-") for h in fus["holes"]]]:
            c = _closed(poly)
            top.plot(c[:, 0], c[:, 1], "k" + style, lw=1.0)
        for poly in [fus["cut_outline"], *fus["cut_holes"]]:
            c = _closed(poly)
            top.plot(c[:, 0], c[:, 1], color="#c0392b", ls="--", lw=0.6)
        for s in fs:
            c = _closed(s["rect"])
            top.fill(c[:, 0], c[:, 1], color="#3b7dbd", alpha=0.25)
        for m in fus["marks"]:
            if m["kind"] == "line":
                q = m["points"] * 1000
                top.plot(q[:, 0], q[:, 1], color="#1f5fa8", lw=0.8)
        span_x = (hi - lo) / 2 + pad
        top.set_xlim(centre[0] - span_x, centre[0] + span_x)
        top.set_ylim(centre[1] - 0.45 * span_x, centre[1] + 0.45 * span_x)
        top.set_aspect("equal")
        top.set_title(f"fuselage at wing '{j['wing']}': {j['type']}", fontsize=9)
        top.set_xlabel("x [mm]")
        top.set_ylabel("y [mm]")
        # the wing plate(s) near the root
        for p in plates[1:]:
            if p["wing"] != j["wing"]:
                continue
            col = {"right": "#2e86c1", "left": "#e67e22"}.get(p["half"], "#2e86c1")
            c = _closed(p["outline"])
            bot.fill(c[:, 0], c[:, 1], color=col, alpha=0.3, label=p["name"])
            bot.plot(c[:, 0], c[:, 1], color=col, lw=1.0)
            for s in j["slots"]:
                if s["plate"] == p["name"]:
                    r = _closed(s["rect"])
                    bot.plot(r[:, 0], r[:, 1], color="k", lw=0.6, ls=":")
        bot.axhline(0, color="0.5", lw=0.5)
        bot.set_xlim(lo - pad, hi + pad)
        bot.set_ylim(-0.45 * ((hi - lo) / 2 + pad), 0.45 * ((hi - lo) / 2 + pad))
        bot.set_aspect("equal")
        bot.set_title(f"wing '{j['wing']}' at its root (x, z)", fontsize=9)
        bot.set_xlabel("x [mm]")
        bot.set_ylabel("z [mm]")
        bot.legend(fontsize=7, loc="lower left")
    fig.tight_layout()
    _atomic.savefig(fig, png_path, dpi=150)
    plt.close(fig)
    return png_path


def main(argv=None):
    ap = argparse.ArgumentParser(prog="python3 -m pteromys.fabrication", description=__doc__.split("\n\n")[0])
    sub = ap.add_subparsers(dest="what", required=True)
    a = sub.add_parser("layout", help="draw the sheets of a DXF written by pteromys export")
    a.add_argument("dxf")
    a.add_argument("png")
    b = sub.add_parser("assembly", help="draw the assembled plates of a glider")
    b.add_argument("glider")
    b.add_argument("--joints", action="store_true", help="draw the joints close up instead")
    b.add_argument("png")
    b.add_argument("--kerf", type=float, default=None, help="kerf [mm]")
    b.add_argument("--clearance", type=float, default=None, help="slot clearance [mm]")
    b.add_argument("--min-web", type=float, default=None, help="minimum web [mm]")
    b.add_argument("--joint", default=None, help="joint type for every wing")
    args = ap.parse_args(argv)
    try:
        if args.what == "layout":
            print("wrote", plot_layout(args.dxf, args.png))
        else:
            opts = {k: v for k, v in (("kerf_mm", args.kerf), ("clearance_mm", args.clearance),
                                      ("min_web_mm", args.min_web), ("joint", args.joint)) if v is not None}
            draw = plot_joints if args.joints else plot_assembly
            print("wrote", draw(args.glider, args.png, **opts))
    except (_core.InputError, OSError) as e:
        print("pteromys.fabrication: error:", e, file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
