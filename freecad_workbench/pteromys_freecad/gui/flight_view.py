"""The flight view: the six standard hand launches, height over distance, and
the flyability summary, docked below the 3D view as in the paper's Fig. 4.

It shows the glider it follows (the one shown last, else the active
document's) and refreshes whenever that glider's results change, i.e. on
every recompute (the Glider's view provider calls :func:`glider_updated`).
Drawn with QPainter: no extra dependency, and fast enough to redraw on
every edit. :func:`grab` renders it to an image (screenshots, tests).
"""
import json
import math

import FreeCAD as App
import FreeCADGui as Gui
from PySide2 import QtCore, QtGui, QtWidgets

DOCK_NAME = "PteromysFlightView"
SPEED_COLOURS = {7.0: "#1b9e77", 9.0: "#d95f02", 11.0: "#7570b3"}


def _nice_step(span, target=6):
    if span <= 0:
        return 1.0
    raw = span / float(target)
    mag = 10 ** math.floor(math.log10(raw))
    for m in (1, 2, 2.5, 5, 10):
        if raw <= m * mag:
            return m * mag
    return 10 * mag


def _data_of(obj):
    try:
        return json.loads(obj.ResultData) if obj is not None and obj.ResultData else {}
    except (ValueError, AttributeError):
        return {}


class FlightPlot(QtWidgets.QWidget):
    """Height over distance of the six launches (equal scales on both axes when they fit)."""

    def __init__(self, parent=None):
        super().__init__(parent)
        self.data = {}
        self.banner = ""
        self.setMinimumSize(360, 160)
        self.setSizePolicy(QtWidgets.QSizePolicy.Expanding, QtWidgets.QSizePolicy.Expanding)

    def set_data(self, data, banner=""):
        self.data, self.banner = data or {}, banner or ""
        self.update()

    def paintEvent(self, event):  # noqa: N802 (Qt)
        p = QtGui.QPainter(self)
        try:
            paint_flights(p, QtCore.QRectF(self.rect()), self.data, self.banner)
        finally:
            p.end()


def paint_flights(p, rect, data, banner=""):
    p.setRenderHint(QtGui.QPainter.Antialiasing, True)
    p.fillRect(rect, QtGui.QColor("white"))
    fm = p.fontMetrics()
    rep = data.get("report") or {}
    flights = data.get("flights") or []
    launches = rep.get("launches") or []
    if not launches:
        p.setPen(QtGui.QColor("#666"))
        p.drawText(rect, QtCore.Qt.AlignCenter, banner or "No flights yet: create a glider (Pteromys > New glider) and recompute.")
        return
    left, bottom, top, right = 46.0, 34.0, 10.0 + (22 if banner else 0), 14.0
    plot = QtCore.QRectF(rect.left() + left, rect.top() + top, rect.width() - left - right,
                         rect.height() - top - bottom)
    if plot.width() < 40 or plot.height() < 30:
        return
    xs = [x for f in flights for x, _ in f] + [0.0]
    ys = [y for f in flights for _, y in f] + [0.0]
    h0 = launches[0].get("height_m", 1.5)
    x1 = max(max(xs), 1.0) * 1.04
    y1 = max(max(ys), h0 + 0.3) * 1.08
    x0 = min(min(xs), 0.0)
    y0 = min(min(ys), 0.0)
    # equal scales (metres look like metres) when that wastes little room
    sx, sy = plot.width() / (x1 - x0), plot.height() / (y1 - y0)
    if 0.6 < sx / sy < 1.7:
        s = min(sx, sy)
        x1 = x0 + plot.width() / s
        y1 = y0 + plot.height() / s
        sx = sy = s

    def P(x, y):
        return QtCore.QPointF(plot.left() + (x - x0) * sx, plot.bottom() - (y - y0) * sy)

    # grid and axes
    grid = QtGui.QPen(QtGui.QColor("#e4e4e4"))
    axis = QtGui.QPen(QtGui.QColor("#555"))
    p.setPen(grid)
    step_x, step_y = _nice_step(x1 - x0, max(3, int(plot.width() / 70))), _nice_step(y1 - y0, max(2, int(plot.height() / 40)))
    k = math.ceil(x0 / step_x)
    while k * step_x <= x1 + 1e-9:
        x = k * step_x
        p.setPen(grid)
        p.drawLine(P(x, y0), P(x, y1))
        p.setPen(axis)
        t = "%g" % round(x, 6)
        p.drawText(QtCore.QPointF(P(x, y0).x() - fm.horizontalAdvance(t) / 2, plot.bottom() + fm.ascent() + 3), t)
        k += 1
    k = math.ceil(y0 / step_y)
    while k * step_y <= y1 + 1e-9:
        y = k * step_y
        p.setPen(grid)
        p.drawLine(P(x0, y), P(x1, y))
        p.setPen(axis)
        t = "%g" % round(y, 6)
        p.drawText(QtCore.QPointF(plot.left() - fm.horizontalAdvance(t) - 5, P(x0, y).y() + fm.ascent() / 2 - 1), t)
        k += 1
    p.setPen(axis)
    p.drawRect(plot)
    p.drawText(QtCore.QRectF(plot.left(), rect.bottom() - fm.height() - 1, plot.width(), fm.height()),
               QtCore.Qt.AlignCenter, "distance [m]")
    p.save()
    p.translate(rect.left() + fm.height() * 0.2, plot.center().y())
    p.rotate(-90)
    p.drawText(QtCore.QRectF(-60, 0, 120, fm.height()), QtCore.Qt.AlignCenter, "height [m]")
    p.restore()
    # ground
    p.setPen(QtGui.QPen(QtGui.QColor("#7a5c3a"), 2))
    p.drawLine(P(x0, 0), P(x1, 0))
    # launcher
    p.setPen(QtGui.QPen(QtGui.QColor("#444"), 1.5))
    p.drawLine(P(0, 0), P(0, h0))
    p.setClipRect(plot.adjusted(-2, -2, 2, 2))
    for i, l in enumerate(launches):
        if i >= len(flights) or len(flights[i]) < 2:
            continue
        col = QtGui.QColor(SPEED_COLOURS.get(float(l.get("speed_m_s", 0)), "#333"))
        pen = QtGui.QPen(col, 2.0)
        if float(l.get("angle_deg", 0)) != 0:
            pen.setStyle(QtCore.Qt.DashLine)
        p.setPen(pen)
        path = QtGui.QPainterPath(P(*flights[i][0]))
        for x, y in flights[i][1:]:
            path.lineTo(P(x, y))
        p.drawPath(path)
        end = P(*flights[i][-1])
        if l.get("stable", True):
            p.setBrush(col)
            p.drawEllipse(end, 3, 3)
            p.setBrush(QtCore.Qt.NoBrush)
        else:
            p.setPen(QtGui.QPen(QtGui.QColor("#c0392b"), 2.2))
            p.drawLine(end + QtCore.QPointF(-5, -5), end + QtCore.QPointF(5, 5))
            p.drawLine(end + QtCore.QPointF(-5, 5), end + QtCore.QPointF(5, -5))
    p.setClipping(False)
    # legend
    lines = []
    for i, l in enumerate(launches):
        txt = "%g m/s, %g\u00b0 up: %.1f m%s" % (l.get("speed_m_s", 0), l.get("angle_deg", 0), l.get("distance_m", 0),
                                                "" if l.get("stable", True) else " (unstable)")
        lines.append((l, txt))
    wmax = max(fm.horizontalAdvance(t) for _, t in lines) + 36
    lh = fm.height() + 1
    box = QtCore.QRectF(plot.right() - wmax - 6, plot.top() + 6, wmax, lh * len(lines) + 6)
    p.setPen(QtGui.QPen(QtGui.QColor("#bbb")))
    p.setBrush(QtGui.QColor(255, 255, 255, 225))
    p.drawRect(box)
    p.setBrush(QtCore.Qt.NoBrush)
    for k, (l, txt) in enumerate(lines):
        y = box.top() + 4 + lh * k + lh / 2
        col = QtGui.QColor(SPEED_COLOURS.get(float(l.get("speed_m_s", 0)), "#333"))
        pen = QtGui.QPen(col, 2.0)
        if float(l.get("angle_deg", 0)) != 0:
            pen.setStyle(QtCore.Qt.DashLine)
        p.setPen(pen)
        p.drawLine(QtCore.QPointF(box.left() + 6, y), QtCore.QPointF(box.left() + 28, y))
        p.setPen(QtGui.QColor("#222") if l.get("stable", True) else QtGui.QColor("#c0392b"))
        p.drawText(QtCore.QPointF(box.left() + 32, y + fm.ascent() / 2 - 1), txt)
    if banner:
        r = QtCore.QRectF(rect.left() + 4, rect.top() + 3, rect.width() - 8, 20)
        p.fillRect(r, QtGui.QColor("#fbe3e0"))
        p.setPen(QtGui.QColor("#a02818"))
        p.drawText(r.adjusted(6, 0, -6, 0), QtCore.Qt.AlignVCenter | QtCore.Qt.AlignLeft,
                   fm.elidedText(banner, QtCore.Qt.ElideRight, int(r.width() - 12)))


def summary_html(obj, data):
    """The flyability summary beside the plot (plain HTML)."""
    if obj is None:
        return "<i>No glider.</i>"
    esc = lambda s: (str(s).replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;"))  # noqa: E731
    out = ["<b>%s</b><br/>" % esc(obj.Label)]
    if obj.Problems:
        out.append("<span style='color:#a02818'><b>Input error</b></span><ul style='margin:2px'>%s</ul>"
                   % "".join("<li>%s</li>" % esc(p) for p in obj.Problems))
        if data:
            out.append("<i>Showing the last good design.</i><br/>")
    if data:
        rep = data.get("report") or {}
        if rep.get("flyable"):
            out.append("<span style='color:#1e7b34;font-size:large'><b>\u2714 Flyable</b></span><br/>")
        else:
            out.append("<span style='color:#c0392b;font-size:large'><b>\u2718 Not flyable</b></span>"
                       "<ul style='margin:2px'>%s</ul>" % "".join("<li>%s</li>" % esc(r) for r in rep.get("reasons", [])))
        g = rep.get("glide") or {}
        rows = []
        if g:
            rows += [("Trim speed", "%.2f m/s" % g["speed_m_s"]), ("Glide ratio", "%.2f" % g["glide_ratio"]),
                     ("Sink rate", "%.2f m/s" % g["sink_rate_m_s"])]
        if rep.get("static_margin") is not None:
            rows.append(("Static margin", "%.1f %% of chord" % (100.0 * rep["static_margin"])))
        rows += [("Mass", "%.2f g" % (rep.get("mass_kg", 0) * 1e3)),
                 ("CG x", "%.1f mm" % (rep.get("cg_m", [0, 0])[0] * 1e3))]
        for m in rep.get("mounts", []):
            rows.append(("%s" % esc(m["wing"]), "x %.1f, y %.1f mm, %.2f\u00b0" % (m["x_m"] * 1e3, m["y_m"] * 1e3,
                                                                               m["angle_deg"])))
        rows.append(("Optimised", "yes (%d evaluations)" % obj.OptimisationEvaluations if data.get("optimised") else "no"))
        rows.append(("Recompute", "%.0f ms" % obj.RecomputeMilliseconds))
        out.append("<table cellspacing='0' cellpadding='1'>%s</table>"
                   % "".join("<tr><td>%s:&nbsp;</td><td>%s</td></tr>" % (a, b) for a, b in rows))
        fab = list(getattr(obj, "FabricationProblems", []) or [])
        if fab:
            out.append("<div style='color:#a02818'><b>Plates without slots:</b> %s</div>" % esc(fab[0]))
        steps = list(getattr(obj, "Assembly", []) or [])
        if steps:
            out.append("<div><b>Assembly</b><br/>%s</div>" % "<br/>".join(esc(s) for s in steps))
        notes = (rep.get("warnings") or []) + (data.get("notes") or [])
        if notes:
            out.append("<div style='color:#8a6d00'>%s</div>" % "<br/>".join("\u26a0 " + esc(n) for n in notes))
    elif not obj.Problems:
        out.append("<i>%s</i>" % esc(obj.Status or "Not computed yet: recompute the document."))
    return "".join(out)


class FlightView(QtWidgets.QWidget):
    """Plot and summary for one glider."""

    def __init__(self, parent=None):
        super().__init__(parent)
        self.glider_ref = None  # (document name, object name): no dangling C++ objects
        lay = QtWidgets.QHBoxLayout(self)
        lay.setContentsMargins(4, 4, 4, 4)
        self.plot = FlightPlot(self)
        self.summary = QtWidgets.QLabel(self)
        self.summary.setTextFormat(QtCore.Qt.RichText)
        self.summary.setAlignment(QtCore.Qt.AlignTop | QtCore.Qt.AlignLeft)
        self.summary.setWordWrap(True)
        self.summary.setTextInteractionFlags(QtCore.Qt.TextSelectableByMouse)
        scroll = QtWidgets.QScrollArea(self)
        scroll.setWidget(self.summary)
        scroll.setWidgetResizable(True)
        scroll.setMinimumWidth(260)
        scroll.setMaximumWidth(380)
        lay.addWidget(self.plot, 1)
        lay.addWidget(scroll, 0)

    def glider(self):
        if self.glider_ref:
            try:
                doc = App.getDocument(self.glider_ref[0])
                o = doc.getObject(self.glider_ref[1])
                if o is not None:
                    return o
            except Exception:
                pass
        import pteromys_freecad
        return pteromys_freecad.active_glider()

    def follow(self, obj):
        self.glider_ref = (obj.Document.Name, obj.Name) if obj is not None else None
        self.refresh()

    def refresh(self):
        obj = self.glider()
        data = _data_of(obj)
        banner = ""
        if obj is not None and obj.Problems:
            banner = "Input error: %s" % obj.Problems[0] + (" (last good flights shown)" if data else "")
        self.plot.set_data(data, banner)
        self.summary.setText(summary_html(obj, data))


def _dock(create=True):
    mw = Gui.getMainWindow()
    dock = mw.findChild(QtWidgets.QDockWidget, DOCK_NAME)
    if dock is None and create:
        dock = QtWidgets.QDockWidget("Pteromys flight view", mw)
        dock.setObjectName(DOCK_NAME)
        dock.setWidget(FlightView(dock))
        mw.addDockWidget(QtCore.Qt.BottomDockWidgetArea, dock)
        dock.setMinimumHeight(220)
    return dock


def show(obj=None):
    """Show the flight view (docked below the 3D view), following `obj`."""
    dock = _dock()
    dock.show()
    dock.raise_()
    dock.widget().follow(obj)
    return dock


def glider_updated(obj):
    """Called on every change of a Glider's results: refresh if it is shown."""
    dock = _dock(create=False)
    if dock is None or not dock.isVisible():
        return
    view = dock.widget()
    shown = view.glider()
    if shown is None:
        view.follow(obj)
    elif (shown.Document.Name, shown.Name) == (obj.Document.Name, obj.Name):
        view.refresh()


def grab(path, width=None, height=None):
    """Save the flight view (plot and summary) as an image; returns the path."""
    dock = _dock(create=False)
    if dock is None:
        raise RuntimeError("the flight view is not open")
    w = dock.widget()
    if width and height:
        w.resize(width, height)
    QtWidgets.QApplication.processEvents()
    pix = w.grab()
    if not pix.save(str(path)):
        raise RuntimeError("could not write %s" % path)
    return str(path)


def render(obj, path, width=1000, height=320):
    """Render the plot of a glider to an image without showing any window."""
    img = QtGui.QImage(width, height, QtGui.QImage.Format_ARGB32)
    img.fill(QtGui.QColor("white"))
    p = QtGui.QPainter(img)
    try:
        banner = ("Input error: %s" % obj.Problems[0]) if obj.Problems else ""
        paint_flights(p, QtCore.QRectF(0, 0, width, height), _data_of(obj), banner)
    finally:
        p.end()
    if not img.save(str(path)):
        raise RuntimeError("could not write %s" % path)
    return str(path)
