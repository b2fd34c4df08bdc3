"""Task panel of a Glider (double-click it): flights on top, design values below.

Edits are written to the Glider's and Wings' properties and recomputed on
Apply (or OK); Cancel undoes everything done in the panel. The sketches are
edited in the sketcher as usual (double-click a wing to open its sketch).
"""
import FreeCADGui as Gui
from PySide2 import QtCore, QtWidgets

from .. import glider as G
from .. import props as P
from . import flight_view


def _spin(lo, hi, decimals, suffix, step=1.0):
    s = QtWidgets.QDoubleSpinBox()
    s.setRange(lo, hi)
    s.setDecimals(decimals)
    s.setSuffix(suffix)
    s.setSingleStep(step)
    s.setKeyboardTracking(False)
    return s


class GliderTaskPanel:
    def __init__(self, obj):
        self.obj = obj
        self.doc = obj.Document
        self.done = False
        self.doc.openTransaction("Edit glider")
        self.form = QtWidgets.QWidget()
        self.form.setWindowTitle("Pteromys glider")
        lay = QtWidgets.QVBoxLayout(self.form)
        # The plot lives in the flight view dock (wide, below the 3D view); the
        # panel shows the summary so that the effect of an edit is visible here too.
        self.summary = QtWidgets.QLabel()
        self.summary.setWordWrap(True)
        self.summary.setTextFormat(QtCore.Qt.RichText)
        lay.addWidget(self.summary)
        flight_view.show(obj)

        box = QtWidgets.QGroupBox("Material, ballast, flight")
        f = QtWidgets.QFormLayout(box)
        self.material = QtWidgets.QComboBox()
        self.material.addItems(G.MATERIAL_NAMES)
        self.thickness = _spin(0.05, 50, 2, " mm", 0.5)
        self.density = _spin(1, 5000, 1, " kg/m\u00b3", 10)
        self.ballast = _spin(0, 1000, 2, " g", 0.5)
        self.ballast_x = _spin(-5000, 5000, 1, " mm", 1)
        self.height = _spin(0.1, 10, 2, " m", 0.1)
        self.auto = QtWidgets.QCheckBox("Optimise the wing mounts on every recompute")
        self.opt_ballast = QtWidgets.QCheckBox("Let the optimiser move the ballast")
        f.addRow("Material", self.material)
        f.addRow("Thickness", self.thickness)
        f.addRow("Density", self.density)
        f.addRow("Ballast", self.ballast)
        f.addRow("Ballast x", self.ballast_x)
        f.addRow("Launch height", self.height)
        f.addRow(self.auto)
        f.addRow(self.opt_ballast)
        lay.addWidget(box)

        wbox = QtWidgets.QGroupBox("Wing mounts (design values; ticked = locked)")
        wl = QtWidgets.QVBoxLayout(wbox)
        self.table = QtWidgets.QTableWidget(0, 7)
        self.table.setHorizontalHeaderLabels(["Wing", "x [mm]", "y [mm]", "angle [\u00b0]", "lock x", "lock y",
                                              "lock angle"])
        self.table.verticalHeader().setVisible(False)
        self.table.horizontalHeader().setSectionResizeMode(QtWidgets.QHeaderView.ResizeToContents)
        wl.addWidget(self.table)
        row = QtWidgets.QHBoxLayout()
        self.optimise_btn = QtWidgets.QPushButton("Optimise now")
        self.optimise_btn.setToolTip("Optimise from the design values and store the result as the design")
        self.apply_btn = QtWidgets.QPushButton("Apply && recompute")
        row.addWidget(self.optimise_btn)
        row.addStretch(1)
        row.addWidget(self.apply_btn)
        wl.addLayout(row)
        lay.addWidget(wbox)

        self.load()
        self.refresh()
        self.material.currentTextChanged.connect(self._material_changed)
        self.optimise_btn.clicked.connect(self.optimise)
        self.apply_btn.clicked.connect(self.apply)

    # -- properties <-> widgets
    def load(self):
        o = self.obj
        self.material.setCurrentText(o.Material)
        self.thickness.setValue(P.quantity_mm(o.Thickness))
        self.density.setValue(o.Density)
        self.ballast.setValue(o.BallastGrams)
        self.ballast_x.setValue(P.quantity_mm(o.BallastX))
        self.height.setValue(P.quantity_mm(o.LaunchHeight) / 1000.0)
        self.auto.setChecked(o.AutoOptimise)
        self.opt_ballast.setChecked(o.OptimiseBallast)
        wings = G.wings_of(o)
        self.table.setRowCount(len(wings))
        self._rows = []
        for r, w in enumerate(wings):
            name = QtWidgets.QTableWidgetItem(w.WingName)
            name.setFlags(name.flags() & ~QtCore.Qt.ItemIsEditable)
            self.table.setItem(r, 0, name)
            sx, sy, sa = _spin(-5000, 5000, 2, ""), _spin(-5000, 5000, 2, ""), _spin(-45, 45, 2, "", 0.25)
            sx.setValue(P.quantity_mm(w.MountX))
            sy.setValue(P.quantity_mm(w.MountY))
            sa.setValue(P.quantity_deg(w.MountAngle))
            locks = [QtWidgets.QCheckBox() for _ in range(3)]
            for c, v in zip(locks, (w.LockX, w.LockY, w.LockAngle)):
                c.setChecked(bool(v))
            for c, wd in enumerate([sx, sy, sa] + locks, start=1):
                self.table.setCellWidget(r, c, wd)
            self._rows.append((w, sx, sy, sa, locks))

    def _material_changed(self, name):
        preset = G.MATERIALS.get(name)
        if preset:
            self.thickness.setValue(preset[0])
            self.density.setValue(preset[1])

    def store(self):
        o = self.obj
        preset = G.MATERIALS.get(self.material.currentText())
        if preset and (abs(preset[0] - self.thickness.value()) > 1e-9 or abs(preset[1] - self.density.value()) > 1e-9):
            P.set_if_changed(o, "Material", "Custom")
        else:
            P.set_if_changed(o, "Material", self.material.currentText())
        P.set_if_changed(o, "Thickness", self.thickness.value())
        P.set_if_changed(o, "Density", self.density.value())
        P.set_if_changed(o, "BallastGrams", self.ballast.value())
        P.set_if_changed(o, "BallastX", self.ballast_x.value())
        P.set_if_changed(o, "LaunchHeight", self.height.value() * 1000.0)
        P.set_if_changed(o, "AutoOptimise", self.auto.isChecked())
        P.set_if_changed(o, "OptimiseBallast", self.opt_ballast.isChecked())
        for w, sx, sy, sa, locks in self._rows:
            P.set_if_changed(w, "MountX", sx.value())
            P.set_if_changed(w, "MountY", sy.value())
            P.set_if_changed(w, "MountAngle", sa.value())
            for prop, c in zip(("LockX", "LockY", "LockAngle"), locks):
                P.set_if_changed(w, prop, c.isChecked())

    def refresh(self):
        self.summary.setText(flight_view.summary_html(self.obj, flight_view._data_of(self.obj)))

    # -- actions
    def apply(self):
        self.store()
        self.doc.recompute()
        self.refresh()

    def optimise(self):
        import pteromys_freecad as pf
        self.store()
        try:
            pf.optimise_now(self.obj)
        except Exception as e:
            QtWidgets.QMessageBox.warning(self.form, "Pteromys: Optimise now", str(e))
        self.load()
        self.refresh()

    # -- task dialog protocol
    def getStandardButtons(self):
        return int(QtWidgets.QDialogButtonBox.Ok | QtWidgets.QDialogButtonBox.Cancel)

    def accept(self):
        self.apply()
        self.doc.commitTransaction()
        self.done = True
        self._close()
        return True

    def reject(self):
        self.abort()
        self._close()
        return True

    def abort(self):
        """Undo what the panel changed (Cancel, or the dialog closed from elsewhere)."""
        if not self.done:
            self.done = True
            self.doc.abortTransaction()
            self.doc.recompute()

    def _close(self):
        Gui.Control.closeDialog()
        gd = Gui.getDocument(self.doc.Name)
        if gd is not None and gd.getInEdit() is not None:
            gd.resetEdit()
