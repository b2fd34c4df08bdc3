"""The capture window (command ``Pteromys_TrackVideo``): open a video, its
calibration and the glider, track automatically, step through the frames with
the tracked points drawn over them, and fix a frame by clicking where the
tracked point (the marker, or the middle of the silhouette) really is.

All logic lives in :class:`pteromys_freecad.capture.CaptureSession`; this
module draws it (QPainter) and turns clicks into ``fix``/``remove`` calls.
Mouse: left click = the point of this frame is here; right click = no glider
in this frame. Keys: Left/Right step, PageUp/PageDown jump 10 frames,
Delete = no glider, Backspace = undo the fix of this frame.
"""
import os
import traceback

import FreeCAD as App
import FreeCADGui as Gui
from PySide2 import QtCore, QtGui, QtWidgets

from .. import capture as pc
from . import icon

WINDOW_NAME = "PteromysCaptureWindow"
PATH_COLOUR = "#00c8ff"
MANUAL_COLOUR = "#ff9f1c"
CG_COLOUR = "#ff2d2d"


def _qimage(rgb):
    h, w = rgb.shape[:2]
    return QtGui.QImage(rgb.tobytes(), w, h, 3 * w, QtGui.QImage.Format_RGB888).copy()


class FrameView(QtWidgets.QWidget):
    """One frame scaled to fit, with the tracked points over it. Emits
    clicked(u, v, button) in image pixels."""

    clicked = QtCore.Signal(float, float, int)

    def __init__(self, parent=None):
        super().__init__(parent)
        self.image = None      # QImage
        self.img_size = (1280, 720)
        self.overlay = None
        self.message = "Open a video, its calibration and the glider, then Track."
        self.setMinimumSize(480, 270)
        self.setSizePolicy(QtWidgets.QSizePolicy.Expanding, QtWidgets.QSizePolicy.Expanding)
        self.setCursor(QtCore.Qt.CrossCursor)

    def set_frame(self, qimage, overlay, img_size):
        self.image, self.overlay, self.img_size = qimage, overlay, img_size
        self.update()

    def _to_view(self, u, v):
        x, y = pc.image_to_view(u, v, self.width(), self.height(), *self.img_size)
        return QtCore.QPointF(x, y)

    def mousePressEvent(self, ev):  # noqa: N802 (Qt)
        if self.image is None:
            return
        p = pc.view_to_image(ev.pos().x(), ev.pos().y(), self.width(), self.height(), *self.img_size)
        if p is not None:
            self.clicked.emit(p[0], p[1], 2 if ev.button() == QtCore.Qt.RightButton else 1)

    def paintEvent(self, event):  # noqa: N802 (Qt)
        p = QtGui.QPainter(self)
        try:
            p.fillRect(self.rect(), QtGui.QColor("#202020"))
            if self.image is None:
                p.setPen(QtGui.QColor("#ddd"))
                p.drawText(self.rect(), QtCore.Qt.AlignCenter, self.message)
                return
            a = self._to_view(-0.5, -0.5)
            b = self._to_view(self.img_size[0] - 0.5, self.img_size[1] - 0.5)
            p.setRenderHint(QtGui.QPainter.SmoothPixmapTransform, True)
            p.drawImage(QtCore.QRectF(a, b), self.image)
            p.setRenderHint(QtGui.QPainter.Antialiasing, True)
            ov = self.overlay or {}
            path = ov.get("path") or []
            if len(path) > 1:
                p.setPen(QtGui.QPen(QtGui.QColor(PATH_COLOUR), 1.2))
                p.drawPolyline(QtGui.QPolygonF([self._to_view(u, v) for u, v, _ in path]))
            for u, v, manual in path:
                c = QtGui.QColor(MANUAL_COLOUR if manual else PATH_COLOUR)
                p.setPen(QtGui.QPen(c, 1.5))
                p.setBrush(QtCore.Qt.NoBrush)
                p.drawEllipse(self._to_view(u, v), 3.0, 3.0)
            pt = ov.get("point")
            if pt:
                c = self._to_view(pt["u_px"], pt["v_px"])
                p.setPen(QtGui.QPen(QtGui.QColor(MANUAL_COLOUR if pt["manual"] else "#ffffff"), 2))
                p.drawLine(c + QtCore.QPointF(-12, 0), c + QtCore.QPointF(12, 0))
                p.drawLine(c + QtCore.QPointF(0, -12), c + QtCore.QPointF(0, 12))
                g = self._to_view(pt["cg_u_px"], pt["cg_v_px"])
                p.setPen(QtGui.QPen(QtGui.QColor(CG_COLOUR), 2))
                p.drawLine(g + QtCore.QPointF(-6, -6), g + QtCore.QPointF(6, 6))
                p.drawLine(g + QtCore.QPointF(-6, 6), g + QtCore.QPointF(6, -6))
            if ov.get("corrected") is None:
                p.setPen(QtGui.QPen(QtGui.QColor(CG_COLOUR), 3))
                p.drawText(QtCore.QRectF(a, b), QtCore.Qt.AlignTop | QtCore.Qt.AlignRight, "marked: no glider  ")
        finally:
            p.end()


class CaptureWindow(QtWidgets.QWidget):
    """The capture window; `session` is the CaptureSession shown (None until files are chosen)."""

    def __init__(self, parent=None):
        super().__init__(parent, QtCore.Qt.Window)
        self.setObjectName(WINDOW_NAME)
        self.setWindowTitle("Pteromys: track a flight video")
        self.session = None
        self.files = {"video": "", "calibration": "", "glider": ""}
        self.frame = 0
        lay = QtWidgets.QVBoxLayout(self)
        top = QtWidgets.QHBoxLayout()
        self.buttons = {}
        for key, text in (("video", "Video..."), ("calibration", "Calibration..."), ("glider", "Glider...")):
            b = QtWidgets.QPushButton(text)
            b.clicked.connect(lambda _=False, k=key: self.choose(k))
            top.addWidget(b)
            self.buttons[key] = b
        self.detector = QtWidgets.QComboBox()
        self.detector.addItems(["background", "marker"])
        self.detector.setToolTip("background: the moving silhouette; marker: a red disc on the glider")
        top.addWidget(self.detector)
        self.track_button = QtWidgets.QPushButton("Track")
        self.track_button.clicked.connect(self.track)
        top.addWidget(self.track_button)
        top.addStretch(1)
        lay.addLayout(top)
        self.files_label = QtWidgets.QLabel()
        self.files_label.setWordWrap(True)
        lay.addWidget(self.files_label)
        self.view = FrameView()
        self.view.clicked.connect(self.on_click)
        lay.addWidget(self.view, 1)
        nav = QtWidgets.QHBoxLayout()
        self.slider = QtWidgets.QSlider(QtCore.Qt.Horizontal)
        self.slider.valueChanged.connect(self.show_frame)
        self.spin = QtWidgets.QSpinBox()
        self.spin.valueChanged.connect(self.show_frame)
        nav.addWidget(self.slider, 1)
        nav.addWidget(self.spin)
        for text, slot, tip in (("Next doubtful", self.next_doubtful, "next frame with a weak or missing point"),
                                ("No glider here", self.remove_point, "this frame has no usable glider (Delete)"),
                                ("Undo fix", self.undo_fix, "back to the automatic point in this frame (Backspace)")):
            b = QtWidgets.QPushButton(text)
            b.setToolTip(tip)
            b.clicked.connect(slot)
            nav.addWidget(b)
        lay.addLayout(nav)
        self.info = QtWidgets.QLabel()
        self.info.setWordWrap(True)
        self.info.setTextInteractionFlags(QtCore.Qt.TextSelectableByMouse)
        lay.addWidget(self.info)
        out = QtWidgets.QHBoxLayout()
        for text, slot in (("Save corrections...", self.save_corrections), ("Write dataset...", self.write_dataset)):
            b = QtWidgets.QPushButton(text)
            b.clicked.connect(slot)
            out.addWidget(b)
        out.addStretch(1)
        lay.addLayout(out)
        self.resize(1100, 760)
        self._refresh_files()

    # ------------------------------------------------------------ files
    def choose(self, key):
        pattern = {"video": "Videos (*.avi *.mp4 *.mov *.mkv *.mts);;All files (*)",
                   "calibration": "Calibration or reference points (*.json)",
                   "glider": "Pteromys glider (*.glider.json *.json)"}[key]
        path, _ = QtWidgets.QFileDialog.getOpenFileName(self, "Choose the " + key, self.files[key]
                                                        or os.path.expanduser("~"), pattern)
        if path:
            self.set_files(**{key: path})

    def set_files(self, video=None, calibration=None, glider=None):
        """Set any of the three files; opens the session when all three are known (shows frame 0)."""
        for k, v in (("video", video), ("calibration", calibration), ("glider", glider)):
            if v:
                self.files[k] = str(v)
        self.session = None
        self._refresh_files()
        if all(self.files.values()):
            try:
                self.session = pc.CaptureSession(self.files["video"], self.files["calibration"],
                                                 self.files["glider"], detector=self.detector.currentText())
            except Exception as e:  # noqa: BLE001 (the message is shown, FreeCAD stays up)
                self._error("Open video", e)
                return False
            n = self.session.frame_count
            for w in (self.slider, self.spin):
                w.blockSignals(True)
                w.setRange(0, max(n - 1, 0))
                w.blockSignals(False)
            self.show_frame(0)
        return self.session is not None

    def _refresh_files(self):
        self.files_label.setText("  ".join("<b>%s</b>: %s" % (k, os.path.basename(v) if v else "<i>not chosen</i>")
                                           for k, v in self.files.items()))

    # ------------------------------------------------------------ actions
    def track(self):
        if self.session is None:
            self.info.setText("Choose the video, the calibration and the glider first.")
            return False
        self.session.detector = self.detector.currentText()
        self.session.detections = None
        QtWidgets.QApplication.setOverrideCursor(QtCore.Qt.WaitCursor)
        try:
            self.session.track()
        except Exception as e:  # noqa: BLE001
            self._error("Track", e)
            return False
        finally:
            QtWidgets.QApplication.restoreOverrideCursor()
        fl = self.session.result.flights
        if fl:
            self.show_frame(int(fl[0]["first_frame"]))
        else:
            self.show_frame(self.frame)
        return True

    def on_click(self, u, v, button):
        if self.session is None:
            return
        try:
            if button == 2:
                self.session.remove(self.frame)
            else:
                self.session.fix(self.frame, u, v)
        except Exception as e:  # noqa: BLE001
            self._error("Fix frame", e)
        self.show_frame(self.frame)

    def remove_point(self):
        self.on_click(0, 0, 2)

    def undo_fix(self):
        if self.session is not None:
            self.session.undo(self.frame)
            self.show_frame(self.frame)

    def next_doubtful(self):
        if self.session is not None:
            f = self.session.next_doubtful(self.frame)
            if f is not None:
                self.show_frame(f)

    def save_corrections(self):
        if self.session is None:
            return
        base = os.path.splitext(self.files["video"])[0] + ".corrections.json"
        path, _ = QtWidgets.QFileDialog.getSaveFileName(self, "Save corrections", base, "Corrections (*.json)")
        if path:
            try:
                self.session.save_corrections(path)
                App.Console.PrintMessage("Pteromys: wrote %s\n" % path)
            except Exception as e:  # noqa: BLE001
                self._error("Save corrections", e)

    def write_dataset(self):
        if self.session is None:
            return
        folder = QtWidgets.QFileDialog.getExistingDirectory(self, "Dataset folder",
                                                            os.path.dirname(self.files["video"]))
        if not folder:
            return
        append = os.path.isfile(os.path.join(folder, "dataset.json"))
        try:
            n = self.session.write_dataset(folder, append=append)
            App.Console.PrintMessage("Pteromys: dataset %s now holds %d flights\n" % (folder, n))
            self.info.setText("Dataset %s now holds %d flights." % (folder, n))
        except Exception as e:  # noqa: BLE001
            self._error("Write dataset", e)

    # ------------------------------------------------------------ drawing
    def show_frame(self, frame):
        if self.session is None:
            return
        frame = max(0, min(int(frame), self.session.frame_count - 1))
        self.frame = frame
        for w in (self.slider, self.spin):
            if w.value() != frame:
                w.blockSignals(True)
                w.setValue(frame)
                w.blockSignals(False)
        ov = self.session.overlay(frame)
        self.view.set_frame(_qimage(self.session.image(frame)), ov, self.session.size)
        pt = ov["point"]
        head = "frame %d (t = %.3f s)" % (frame, frame / self.session.fps)
        if pt:
            head += ": %s, CG x = %.3f m, y = %.3f m, pitch %.1f deg, confidence %.2f%s" % (
                pt["flight"], pt["x_m"], pt["y_m"], pt["pitch_deg"], pt["confidence"],
                " (fixed by hand)" if pt["manual"] else "")
        elif ov["corrected"] is None:
            head += ": marked as no glider"
        else:
            head += ": no tracked point"
        self.info.setText(head + "\n" + self.session.summary())

    def keyPressEvent(self, ev):  # noqa: N802 (Qt)
        k = ev.key()
        step = {QtCore.Qt.Key_Right: 1, QtCore.Qt.Key_Left: -1, QtCore.Qt.Key_PageDown: 10,
                QtCore.Qt.Key_PageUp: -10}.get(k)
        if step is not None:
            self.show_frame(self.frame + step)
        elif k == QtCore.Qt.Key_Delete:
            self.remove_point()
        elif k == QtCore.Qt.Key_Backspace:
            self.undo_fix()
        else:
            super().keyPressEvent(ev)

    def _error(self, title, err):
        App.Console.PrintLog(traceback.format_exc())
        App.Console.PrintError("Pteromys: %s: %s\n" % (title, err))
        self.info.setText("%s: %s" % (title, err))
        if not os.environ.get("PTEROMYS_NO_DIALOGS"):
            QtWidgets.QMessageBox.warning(self, "Pteromys: " + title, str(err))


_window = None


def show(video=None, calibration=None, glider=None, track=False):
    """Open (or raise) the capture window; optional files are set; `track` runs the tracking."""
    global _window
    if _window is None:
        _window = CaptureWindow(Gui.getMainWindow())
    _window.show()
    _window.raise_()
    if video or calibration or glider:
        _window.set_files(video, calibration, glider)
    if track:
        _window.track()
    return _window


class TrackVideo:
    """FreeCAD command: open the capture window."""

    def GetResources(self):  # noqa: N802 (FreeCAD)
        return {"Pixmap": icon("PteromysFlightView"), "MenuText": "Track flight video...",
                "ToolTip": "Track a glider in a side-view video, fix frames by clicking, "
                           "write a flight dataset for fitting (docs/capture.md)"}

    def IsActive(self):  # noqa: N802 (FreeCAD)
        return True

    def Activated(self):  # noqa: N802 (FreeCAD)
        show()
