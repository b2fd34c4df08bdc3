"""Flight capture: camera calibration, glider tracking in side-view videos,
flight datasets, synthetic test videos (docs/capture.md).

The work is done by the compiled engine (``pteromys._core``); this module
gives it keyword arguments, documentation and plots.

Frames and units: pixels with u to the right and v down (OpenCV); the flight
plane in metres with x along the flight and y up (spec/formats.md); times in
seconds, ``t = frame / fps``.

Typical use::

    import pteromys.capture as cap
    calib = cap.calibrate("points.json")            # reference points -> camera
    det = cap.detect("launches.avi")                # candidates in every frame
    res = cap.track_flights(det, calib, "g01.glider.json")
    cap.write_dataset("data/", res, det, calib, "g01.glider.json", key="g01")
"""
import json as _json
import os as _os

import numpy as _np

from . import _atomic, _core
from ._core import CameraCalibration, Detections, TrackResult, VideoFrames  # noqa: F401

__all__ = ["CameraCalibration", "Detections", "TrackResult", "VideoFrames", "calibrate", "load_calibration",
           "detect", "track_flights", "track", "write_dataset", "load_corrections", "save_corrections",
           "synthetic_camera", "synthetic_points", "render_video", "silhouette_centroid", "plot_calibration",
           "plot_tracks", "TRUTH_COLUMNS"]

#: Columns of the ``truth`` array returned by :func:`render_video`.
TRUTH_COLUMNS = ("flight", "frame", "t_s", "x_m", "y_m", "pitch_deg", "speed_m_s", "u_px", "v_px",
                 "marker_x_m", "marker_y_m", "visible")


def _points_text(points):
    if isinstance(points, dict):
        return _json.dumps(points)
    if isinstance(points, str) and points.lstrip().startswith("{"):
        return points
    with open(points, encoding="utf-8") as f:
        return f.read()


def calibrate(points, distortion=None, distance_m=None, focal_px=None):
    """Calibrate the camera from reference points.

    points: a ``pteromys-calib-points/1`` file path, dict or JSON text (at
    least 4 points with ``world_m`` [m] and ``image_px`` [px]).
    distortion: ``"auto"``, ``"none"``, ``"k1"`` or ``"k1k2"`` (overrides the file).
    distance_m / focal_px: camera distance to the flight plane [m] or focal
    length [px], for the camera pose (overrides the file).
    Returns a :class:`CameraCalibration` (``rms_px``, ``rms_m``,
    ``loo_rms_m``, ``residuals``, ``image_to_world``...). Raises
    ``pteromys.InputError`` naming the problem for bad points.
    """
    d = _json.loads(_points_text(points))
    if distortion is not None:
        d["distortion"] = distortion
    if distance_m is not None or focal_px is not None:
        cam = dict(d.get("camera") or {})
        if distance_m is not None:
            cam["distance_m"] = float(distance_m)
        if focal_px is not None:
            cam["focal_px"] = float(focal_px)
        d["camera"] = cam
    return _core.capture_calibrate(_json.dumps(d))


def load_calibration(path):
    """A calibration file (``pteromys-calibration/1``) or a reference-points file (calibrated on the fly)."""
    return _core.capture_load_calibration(str(path))


def detect(video, detector="background", frames=None, fps=None, marker_colour=None, threshold=6.0, min_area=4,
           progress=None):
    """Stage 1: candidate blobs in every frame of ``video``.

    detector: ``"background"`` (moving silhouette against a median background)
    or ``"marker"`` (a coloured disc; ``marker_colour`` as ``(r, g, b)`` 0-255
    or ``"#rrggbb"``). frames: ``"30-75,120-160"`` or a list of ``(first,
    last)`` to process only those frames. fps: overrides the file's frame rate.
    progress: called with ``(done, total)`` frames now and then.
    """
    if isinstance(frames, (list, tuple)):
        frames = ",".join("%d-%d" % (a, b) for a, b in frames)
    bgr = []
    if marker_colour is not None:
        if isinstance(marker_colour, str):
            h = marker_colour.lstrip("#")
            marker_colour = (int(h[0:2], 16), int(h[2:4], 16), int(h[4:6], 16))
        r, g, b = marker_colour
        bgr = [int(b), int(g), int(r)]
    return _core.capture_detect(str(video), detector, frames or "", float(fps or 0.0), bgr, float(threshold),
                                int(min_area), progress)


def track_flights(detections, calibration, glider, corrections=None, frames=None, pitch="auto", aoa_deg=0.0,
                  marker_at=None, name="flight", gate=5.0, max_missed=3, min_points=6):
    """Stage 2: flights of the centre of gravity from the candidates.

    corrections: ``{frame: (u, v) or None}`` or a corrections file path
    (``None`` marks a frame where the glider is not visible). frames: one
    flight per range (as for :func:`detect`); default: launches found
    automatically. pitch: ``"auto"`` (the silhouette's orientation when
    silhouettes were detected, else the path), ``"silhouette"``, ``"path"`` or
    ``"none"`` (the tracked point is the CG). marker_at: the glider-frame point tracked [m] (the marker's
    centre; default the CG for the marker detector, the silhouette centroid
    otherwise). Returns a :class:`TrackResult`: ``flights`` (dicts of arrays
    ``frame, t_s, u_px, v_px, x_m, y_m, pitch_deg, confidence, manual`` ...),
    ``tracking_sigma_m``, ``sigma_components_m``, ``notes``.
    """
    if isinstance(frames, (list, tuple)):
        frames = ",".join("%d-%d" % (a, b) for a, b in frames)
    if isinstance(calibration, str):
        calibration = load_calibration(calibration)
    if corrections is not None and not isinstance(corrections, str):
        corrections = {int(k): (None if v is None else (float(v[0]), float(v[1]))) for k, v in corrections.items()}
    return _core.capture_track_flights(detections, calibration, glider, corrections, frames or "", pitch,
                                       float(aoa_deg), marker_at, name, float(gate), int(max_missed), int(min_points))


def write_dataset(out_dir, result, detections, calibration, glider, key, append=False, replace=False):
    """Write the flights as a dataset directory (dataset.json, flights.csv,
    gliders/KEY.glider.json, tracks.csv, capture.json). Returns the number of
    flights in the dataset."""
    return _core.capture_write_dataset(str(out_dir), result, detections, calibration, glider, key, append, replace)


def track(video, calibration, glider, out_dir=None, key=None, append=False, replace=False, detector="background",
          frames=None, fps=None, marker_colour=None, progress=None, **kw):
    """:func:`detect` + :func:`track_flights` (+ :func:`write_dataset` when
    ``out_dir`` is given). Returns ``(detections, result)``."""
    if isinstance(calibration, str):
        calibration = load_calibration(calibration)
    det = detect(video, detector=detector, frames=frames, fps=fps, marker_colour=marker_colour, progress=progress)
    res = track_flights(det, calibration, glider, frames=frames, **kw)
    if out_dir is not None:
        if key is None:
            key = _os.path.basename(str(glider)).split(".")[0] if isinstance(glider, str) else "glider"
        write_dataset(out_dir, res, det, calibration, glider, key, append=append, replace=replace)
    return det, res


def load_corrections(path):
    """Manual corrections ``{frame: (u, v) or None}`` from a file."""
    return dict(_core.capture_load_corrections(str(path)))


def save_corrections(corrections, path, video=""):
    """Write corrections ``{frame: (u, v) or None}`` (format ``pteromys-corrections/1``) atomically."""
    text = _core.capture_corrections_json(
        {int(k): (None if v is None else (float(v[0]), float(v[1]))) for k, v in corrections.items()}, str(video))
    tmp = "%s.tmp-%d" % (path, _os.getpid())
    with open(tmp, "w", encoding="utf-8") as f:
        f.write(text + "\n")
    _os.replace(tmp, path)


def silhouette_centroid(glider):
    """Glider-frame centroid (x, y) [m] of the side silhouette (fuselage, wings edge-on)."""
    return _core.capture_silhouette_centroid(glider)


# ----------------------------------------------------------- test videos

def synthetic_camera(distance_m=4.0, x_m=4.0, y_m=1.2, width=1280, height=720, hfov_deg=66.0, k1=-0.10, k2=0.02,
                     yaw_deg=0.0, tilt_deg=0.0, roll_deg=0.0, cx_offset_px=5.0, cy_offset_px=-3.0):
    """The true camera of a synthetic video (a :class:`CameraCalibration` with known lens and pose)."""
    return _core.capture_synthetic_camera(width, height, hfov_deg, k1, k2, [x_m, y_m, distance_m], yaw_deg,
                                          tilt_deg, roll_deg, cx_offset_px, cy_offset_px)


def synthetic_points(camera, nx=4, ny=3, click_sigma_px=0.3, seed=1, distance_m=None):
    """Reference points as a person would click them in a synthetic video (a dict,
    format ``pteromys-calib-points/1``): an nx x ny grid, world positions to the
    millimetre, image positions with Gaussian click noise."""
    return _json.loads(_core.capture_synthetic_points(camera, nx, ny, click_sigma_px, seed,
                                                      float(distance_m or 0.0)))


def render_video(path, camera, glider, flights, fps=30.0, exposure_s=1.0 / 250, blur_samples=5, noise_sigma=2.0,
                 quality=90, seed=1, marker=True, marker_at=None, marker_radius_m=0.012, lead_frames=12,
                 gap_frames=24, tail_frames=12, progress=None, wing_shade=0.82):
    """Render flights as a side-view video (MJPG .avi). flights: list of
    ``(n, 4)`` arrays of ``t_s, x_m, y_m, pitch_deg`` (CG, world frame).
    Returns a dict with ``truth`` (an array, columns :data:`TRUTH_COLUMNS`),
    ``frames`` and ``flight_frames``. wing_shade: the wings' grey level as a
    fraction of the plates' (wings seen at a slant look darker)."""
    fl = [_np.ascontiguousarray(_np.asarray(f, dtype=float)[:, :4]) for f in flights]
    return _core.capture_render_video(str(path), camera, glider, fl, float(fps), float(exposure_s), int(blur_samples),
                                      float(noise_sigma), int(quality), int(seed), bool(marker), marker_at,
                                      float(marker_radius_m), int(lead_frames), int(gap_frames), int(tail_frames),
                                      progress, float(wing_shade))


# ----------------------------------------------------------------- plots

def _plt():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def plot_calibration(calibration, path, image=None, title=None):
    """Reference points and their residuals (arrows x 50) over the image (an
    RGB array, e.g. ``VideoFrames(video)[0]``), and the residual per point in
    millimetres. Writes a PNG."""
    plt = _plt()
    fig, (a, b) = plt.subplots(1, 2, figsize=(13, 4.2), gridspec_kw={"width_ratios": [1.6, 1]})
    if image is not None:
        a.imshow(image)
    pts = calibration.points
    res = calibration.residuals
    scale = 50.0
    for (name, w, im), r in zip(pts, res):
        a.plot(im[0], im[1], "+", color="yellow", ms=10, mew=2)
        a.annotate("", xy=(im[0] - scale * r["du_px"], im[1] - scale * r["dv_px"]), xytext=(im[0], im[1]),
                   arrowprops=dict(arrowstyle="->", color="red", lw=1.5))
        a.text(im[0] + 6, im[1] - 6, name, color="white", fontsize=7)
    a.set_xlim(0, calibration.width)
    a.set_ylim(calibration.height, 0)
    a.set_title(title or "reference points, residual arrows x %g" % scale)
    names = [r["name"] for r in res]
    fit = [1000 * _np.hypot(r["dx_m"], r["dy_m"]) for r in res]
    loo = [1000 * r["loo_m"] if r["loo_m"] is not None else _np.nan for r in res]
    x = _np.arange(len(names))
    b.bar(x - 0.2, fit, 0.4, label="fit residual")
    b.bar(x + 0.2, loo, 0.4, label="left out of the fit")
    b.set_xticks(x)
    b.set_xticklabels(names, rotation=90, fontsize=7)
    b.set_ylabel("error in the flight plane [mm]")
    b.set_title("rms %.2f px = %.1f mm; leave-one-out %.1f mm" % (
        calibration.rms_px, 1000 * calibration.rms_m,
        1000 * calibration.loo_rms_m if calibration.loo_rms_m >= 0 else float("nan")))
    b.legend(fontsize=8)
    fig.tight_layout()
    _atomic.savefig(fig, path, dpi=110)
    plt.close(fig)


def plot_tracks(result, path, image=None, calibration=None, truth=None, title=None):
    """Tracked CG trajectories in the flight plane (and, with ``image`` and
    ``calibration``, the tracked points over a frame). ``truth``: optional
    ``(n, >=5)`` array with columns like :data:`TRUTH_COLUMNS` to compare."""
    plt = _plt()
    n = 2 if image is not None else 1
    fig, axes = plt.subplots(1, n, figsize=(7 * n, 4.2))
    axes = _np.atleast_1d(axes)
    ax = axes[0]
    for f in result.flights:
        ax.plot(f["x_m"], f["y_m"], ".-", ms=4, label=f["name"])
        m = f["manual"]
        if m.any():
            ax.plot(f["x_m"][m], f["y_m"][m], "o", mfc="none", mec="k", ms=8)
    if truth is not None:
        t = _np.asarray(truth)
        for k, fl in enumerate(_np.unique(t[:, 0])):  # one line per rendered flight
            s = t[t[:, 0] == fl]
            ax.plot(s[:, 3], s[:, 4], "k-", lw=0.7, alpha=0.6, label="truth" if k == 0 else None)
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_aspect("equal", adjustable="datalim")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    ax.set_title(title or "tracked centre of gravity (sigma %.1f mm)" % (1000 * result.tracking_sigma_m))
    if image is not None:
        b = axes[1]
        b.imshow(image)
        for f in result.flights:
            b.plot(f["u_px"], f["v_px"], ".-", ms=3)
        b.set_title("tracked points over a frame")
        b.axis("off")
    fig.tight_layout()
    _atomic.savefig(fig, path, dpi=110)
    plt.close(fig)
