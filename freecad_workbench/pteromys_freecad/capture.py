"""Flight capture in FreeCAD: track a glider in a video, look at the tracked
points frame by frame, fix frames by clicking, write the flight dataset.

This module is the headless part (usable from ``freecadcmd``, macros and the
console); the window of the ``Pteromys_TrackVideo`` command
(:mod:`pteromys_freecad.gui.capture_view`) only draws a
:class:`CaptureSession` and forwards clicks to it. The work is done by the
engine's ``pteromys.capture`` (docs/capture.md)::

    import pteromys_freecad.capture as pc
    s = pc.CaptureSession("launches.avi", "points.json", "g01.glider.json")
    s.track()                                   # automatic tracking
    s.overlay(40)                               # what the window draws on frame 40
    s.fix(40, 612.5, 301.0)                     # the glider is here in frame 40 (pixels)
    s.remove(41)                                # no glider in frame 41
    s.save_corrections("launches.corrections.json")
    s.write_dataset("data/", key="g01")         # dataset.json + flights.csv

Pixels: u to the right, v down, origin at the centre of the top-left pixel
(OpenCV's convention, as everywhere in pteromys.capture). Frames count from 0.
"""
import os

from .backend import engine


class CaptureError(ValueError):
    """Bad input for a capture session (the message is for the user)."""


def _capture():
    engine()  # finds the engine (raises EngineMissing with a reason)
    import pteromys.capture as cap
    return cap


def _input_errors():
    pt = engine()
    return (pt.InputError, ValueError, RuntimeError)


class CaptureSession:
    """A video, its calibration and the glider flown, the automatic track and
    the person's corrections.

    video: a video file (any format OpenCV reads). calibration: a calibration
    file (``pteromys calibrate``) or a reference-points file. glider: a
    ``.glider.json`` path (or a dict in that format). detector: ``"background"``
    or ``"marker"``; marker_at: glider-frame point (x, y) [m] of the tracked
    marker. corrections: ``{frame: (u, v) or None}`` or a corrections file.
    Bad input raises :class:`CaptureError` (or the engine's ``InputError``)
    with a message naming the problem; nothing is half-done.
    """

    def __init__(self, video, calibration, glider, detector="background", marker_at=None, corrections=None):
        cap = _capture()
        if not video or not os.path.isfile(str(video)):
            raise CaptureError("video '%s': no such file" % video)
        if isinstance(glider, str) and not os.path.isfile(glider):
            raise CaptureError("glider file '%s': no such file" % glider)
        if isinstance(calibration, str) and not os.path.isfile(calibration):
            raise CaptureError("calibration file '%s': no such file" % calibration)
        self.video = str(video)
        self.glider = glider
        self.detector = detector
        self.marker_at = marker_at
        try:
            self.calibration = (cap.load_calibration(calibration) if isinstance(calibration, str)
                                else calibration)
            self.frames = cap.VideoFrames(self.video)
        except _input_errors() as e:
            raise CaptureError(str(e)) from e
        if (self.frames.width, self.frames.height) != (self.calibration.width, self.calibration.height):
            raise CaptureError("the calibration was made for %dx%d images, the video is %dx%d"
                               % (self.calibration.width, self.calibration.height, self.frames.width,
                                  self.frames.height))
        self.corrections = {}
        if corrections is not None:
            self.corrections = (cap.load_corrections(corrections) if isinstance(corrections, str)
                                else {int(k): v for k, v in corrections.items()})
        self.detections = None
        self.result = None

    # ------------------------------------------------------------ video
    @property
    def frame_count(self):
        return len(self.frames)

    @property
    def fps(self):
        return self.frames.fps

    @property
    def size(self):
        """(width, height) of the frames [px]."""
        return self.frames.width, self.frames.height

    def image(self, frame):
        """Frame `frame` as an RGB array (height, width, 3) of uint8."""
        if not 0 <= int(frame) < self.frame_count:
            raise CaptureError("frame %d is outside the video (0 to %d)" % (frame, self.frame_count - 1))
        return self.frames[int(frame)]

    # ------------------------------------------------------------ tracking
    def track(self, progress=None):
        """Detect the glider in every frame and track it (with the corrections). Returns the flights."""
        cap = _capture()
        try:
            if self.detections is None:
                self.detections = cap.detect(self.video, detector=self.detector, progress=progress)
            self._retrack()
        except _input_errors() as e:
            raise CaptureError(str(e)) from e
        return self.result.flights

    def _retrack(self):
        cap = _capture()
        self.result = cap.track_flights(self.detections, self.calibration, self.glider,
                                        corrections=dict(self.corrections), marker_at=self.marker_at)

    def _need_track(self):
        if self.detections is None:
            self.track()

    def fix(self, frame, u, v):
        """The person says: in `frame` the tracked point is at pixel (u, v). Re-tracks."""
        self._check_frame(frame)
        w, h = self.size
        if not (-0.5 <= u <= w - 0.5 and -0.5 <= v <= h - 0.5):
            raise CaptureError("pixel (%.1f, %.1f) is outside the image (%dx%d)" % (u, v, w, h))
        return self._correct(int(frame), (float(u), float(v)))

    def remove(self, frame):
        """The person says: the glider is not (usefully) visible in `frame`. Re-tracks."""
        self._check_frame(frame)
        return self._correct(int(frame), None)

    def undo(self, frame):
        """Forget the correction of `frame` (back to the automatic track). Re-tracks."""
        old = self.corrections.pop(int(frame), "none")
        if old != "none" and self.detections is not None:
            self._retrack()
        return old != "none"

    def _correct(self, frame, value):
        self._need_track()
        had = frame in self.corrections
        old = self.corrections.get(frame)
        self.corrections[frame] = value
        try:
            self._retrack()
        except _input_errors() as e:  # refused: the session stays as it was
            if had:
                self.corrections[frame] = old
            else:
                del self.corrections[frame]
            raise CaptureError(str(e)) from e
        return self.point(frame)

    def _check_frame(self, frame):
        if not 0 <= int(frame) < self.frame_count:
            raise CaptureError("frame %d is outside the video (0 to %d)" % (frame, self.frame_count - 1))

    # ------------------------------------------------------------ reading
    def point(self, frame):
        """The tracked point of `frame` as a dict (flight, u_px, v_px, cg_u_px, cg_v_px, x_m, y_m,
        pitch_deg, confidence, manual), or None when no flight has a point there."""
        if self.result is None:
            return None
        for k, f in enumerate(self.result.flights):
            if f["first_frame"] <= frame <= f["last_frame"]:
                idx = [i for i, fr in enumerate(f["frame"]) if int(fr) == int(frame)]
                if not idx:
                    return None
                i = idx[0]
                cg = self.calibration.world_to_image([[float(f["x_m"][i]), float(f["y_m"][i])]])[0]
                return {"flight": f["name"], "index": k, "u_px": float(f["u_px"][i]), "v_px": float(f["v_px"][i]),
                        "cg_u_px": float(cg[0]), "cg_v_px": float(cg[1]), "x_m": float(f["x_m"][i]),
                        "y_m": float(f["y_m"][i]), "pitch_deg": float(f["pitch_deg"][i]),
                        "confidence": float(f["confidence"][i]), "manual": bool(f["manual"][i])}
        return None

    def overlay(self, frame, tail=None):
        """What the window draws over `frame`: ``{"point": point(frame) or None,
        "path": [(u, v, manual), ...] the tracked points of the flight holding
        the frame (all of them, or the last `tail` up to the frame),
        "corrected": the frame's correction ((u, v), None for 'no glider') or
        "none", "flights": [(name, first, last)]}``."""
        out = {"point": self.point(frame), "path": [], "corrected": self.corrections.get(int(frame), "none"),
               "flights": []}
        if self.result is None:
            return out
        for f in self.result.flights:
            out["flights"].append((f["name"], int(f["first_frame"]), int(f["last_frame"])))
            if f["first_frame"] <= frame <= f["last_frame"]:
                pts = [(float(u), float(v), bool(m), int(fr))
                       for u, v, m, fr in zip(f["u_px"], f["v_px"], f["manual"], f["frame"])]
                if tail is not None:
                    pts = [p for p in pts if frame - tail <= p[3] <= frame]
                out["path"] = [p[:3] for p in pts]
        return out

    def next_doubtful(self, frame, threshold=0.5):
        """The first frame after `frame` whose point has a confidence below
        `threshold` or that lies inside a flight without a point; None if none."""
        if self.result is None:
            return None
        best = None
        for f in self.result.flights:
            have = {int(fr): float(c) for fr, c in zip(f["frame"], f["confidence"])}
            for fr in range(max(int(f["first_frame"]), int(frame) + 1), int(f["last_frame"]) + 1):
                marked_empty = fr in self.corrections and self.corrections[fr] is None
                if not marked_empty and (fr not in have or have[fr] < threshold):
                    best = fr if best is None else min(best, fr)
                    break
        return best

    def summary(self):
        """One line per flight, in words."""
        if self.result is None:
            return "not tracked yet"
        lines = []
        for f in self.result.flights:
            n = len(f["frame"])
            lines.append("%s: frames %d-%d, %d points (%d fixed by hand), ends: %s"
                         % (f["name"], f["first_frame"], f["last_frame"], n, int(sum(f["manual"])), f["end"]))
        lines.append("tracking sigma %.1f mm, pitch from %s" % (1000 * self.result.tracking_sigma_m,
                                                               self.result.pitch_source))
        return "\n".join(lines) if self.result.flights else "no flight found"

    # ------------------------------------------------------------ files
    def save_corrections(self, path):
        """Write the corrections (format pteromys-corrections/1) atomically; `pteromys track --corrections` reads them."""
        _capture().save_corrections(self.corrections, str(path), video=self.video)

    def write_dataset(self, out_dir, key=None, append=False, replace=False):
        """Write the flights as a dataset directory (dataset.json, flights.csv, ...); returns the flights in it."""
        self._need_track()
        if key is None:
            key = (os.path.basename(self.glider).split(".")[0] if isinstance(self.glider, str) else "glider")
        try:
            return _capture().write_dataset(str(out_dir), self.result, self.detections, self.calibration,
                                            self.glider, key, append=append, replace=replace)
        except _input_errors() as e:
            raise CaptureError(str(e)) from e


def view_to_image(x, y, view_w, view_h, img_w, img_h):
    """Pixel (u, v) of the image under widget point (x, y) when the image is
    drawn scaled to fit a view_w x view_h widget, centred, aspect kept; None
    outside the image. Inverse of :func:`image_to_view`."""
    s, ox, oy = _fit(view_w, view_h, img_w, img_h)
    u = (x - ox) / s - 0.5
    v = (y - oy) / s - 0.5
    if not (-0.5 <= u <= img_w - 0.5 and -0.5 <= v <= img_h - 0.5):
        return None
    return u, v


def image_to_view(u, v, view_w, view_h, img_w, img_h):
    """Widget point (x, y) where image pixel (u, v) is drawn (see :func:`view_to_image`)."""
    s, ox, oy = _fit(view_w, view_h, img_w, img_h)
    return ox + (u + 0.5) * s, oy + (v + 0.5) * s


def _fit(view_w, view_h, img_w, img_h):
    s = min(view_w / float(img_w), view_h / float(img_h))
    return s, 0.5 * (view_w - s * img_w), 0.5 * (view_h - s * img_h)
