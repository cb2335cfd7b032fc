"""The slice painter (seed 003): paint voxels on one axis-aligned slice, zoomed and panned.

A stroke shows while the mouse is down (`stroke.preview`, not recorded) and becomes one `stroke`
command on release: recorded, replayed and undone as a unit. Keys: a/d/w/s pan, h/j shrink/grow the
drawing, right-drag zooms, and the `painter:` binds of default.cfg (q/e slices, 1-4 brush size,
c colour, u/r undo/redo). Tools: brush, fill, eyedropper (or Alt+click). On a scan (a scalar volume) they paint,
fill and pick labels over it (`label.stroke`, `label.fill`), drawn over the slice with their opacity.
"""
from __future__ import annotations

import numpy as np
from PySide6.QtCore import QPointF, QRectF, Qt, Signal
from PySide6.QtGui import QBrush, QColor, QImage, QPainter, QPen, QPixmap
from PySide6.QtWidgets import (QButtonGroup, QCheckBox, QComboBox, QHBoxLayout, QLabel, QPushButton, QSpinBox,
                               QToolButton, QVBoxLayout, QWidget)

from app.commands.volume_labels import BRUSH_LABEL, OPACITY
from app.model.volume.voxels import AXES
from app.views.keys import key_name
from app.views.volume.label_row import LabelRow
from app.views.volume.scalar_mode_row import ScalarModeRow
from app.views.volume.transfer_panel import TransferPanel

NEIGHBOUR_OPACITY = 0.22  # the faint neighbouring slices under transparent voxels
PAN_STEP = 0.1            # of the canvas per key press
ZOOM_KEY = 1.25


def _over_labels(rgba: np.ndarray, labels, view, opacity: float) -> None:
    """Lay a scan's labels on its slice (v, u, 4) uint8 RGBA, each in its colour with `opacity`, over what is
    there ("over" with straight alpha: a label on clear voxels shows its colour at that opacity)."""
    plane = labels.plane(view.axis, view.index)
    where = plane != 0
    if not where.any():
        return
    under = rgba[where].astype(np.float32)
    a = under[:, 3:] / 255 * (1 - opacity)
    alpha = opacity + a
    under[:, :3] = (labels.colours[plane[where]] * opacity + under[:, :3] * a) / np.maximum(alpha, 1e-6)
    under[:, 3:] = alpha * 255
    rgba[where] = under.round()


class SliceCanvas(QWidget):
    """Draws the slice; turns the mouse into brush, fill and eyedropper commands."""

    command = Signal(str)

    def __init__(self, editor, state, parent=None) -> None:
        super().__init__(parent)
        self.editor, self.state = editor, state
        self.tool = "brush"
        self.erase = False
        self.zoom = 0.0  # pixels per voxel along its shorter side; 0 = fit on first paint
        self.offset = QPointF(0, 0)  # canvas position of voxel (0, 0)
        self.points: list[tuple[int, int]] = []
        self.hover: tuple[int, int] | None = None
        self._zoom_drag: tuple[float, float] | None = None
        self._checker: QBrush | None = None
        self._image: tuple | None = None  # (what it shows, the composed slice)
        self.setMouseTracking(True)
        self.setFocusPolicy(Qt.FocusPolicy.StrongFocus)
        self.setMinimumSize(200, 200)
        self.setCursor(Qt.CursorShape.BlankCursor)  # the brush outline is the cursor

    # -- geometry ---------------------------------------------------------------------------
    def aspect(self) -> tuple[float, float]:
        """A voxel's width and height in units of its shorter side: the slice shows its physical shape (a CT's
        0.5 mm pixels and 2 mm slices make a side view's voxels four times as tall as wide)."""
        su, sv = self.state.volume.voxels.slice_spacing(self.state.view.axis)
        return su / min(su, sv), sv / min(su, sv)

    def cell(self) -> tuple[float, float]:
        """Pixels a voxel spans across and down."""
        ku, kv = self.aspect()
        zoom = self.fitted()
        return zoom * ku, zoom * kv

    def fit(self) -> None:
        u, v = self.state.volume.voxels.slice_size(self.state.view.axis)
        ku, kv = self.aspect()
        self.zoom = max(0.5, min(self.width() / (u * ku), self.height() / (v * kv)) * 0.92)
        self.offset = QPointF((self.width() - u * ku * self.zoom) / 2, (self.height() - v * kv * self.zoom) / 2)

    def fitted(self) -> float:
        """Pixels per voxel; fits the slice first when it changed shape and was not drawn since (a click can come
        before the paint)."""
        if self.zoom == 0:
            self.fit()
        return self.zoom

    def to_voxel(self, pos: QPointF) -> tuple[int, int]:
        cu, cv = self.cell()  # before reading the offset, which fitting moves
        p = pos - self.offset
        return int(np.floor(p.x() / cu)), int(np.floor(p.y() / cv))

    def zoom_about(self, factor: float, pos: QPointF) -> None:
        new = min(max(self.fitted() * factor, 0.25), 256.0)  # fitted first: the offset below is the fit's
        self.offset = pos - (pos - self.offset) * (new / self.zoom)
        self.zoom = new
        self.update()

    # -- drawing ----------------------------------------------------------------------------
    def image(self) -> np.ndarray:
        """The slice as RGBA, with the neighbouring slices faint where it is transparent and a scan's labels over
        it. Kept until the voxels, labels or the slice change: the brush cursor repaints on every mouse move."""
        vol, view = self.state.volume.voxels, self.state.view
        labels, opacity = vol.labels, self._cvar(OPACITY)
        drawn = None if labels is None else (id(labels), labels.version, labels.colour_version, opacity)
        key = (id(vol), vol.version, drawn, view.axis, view.index)
        if self._image is None or self._image[0] != key:
            rgba = self._compose(vol, view)
            if labels is not None and labels.data is not None:
                _over_labels(rgba, labels, view, opacity)
            self._image = (key, rgba)
        return self._image[1]

    def _cvar(self, name: str):
        return self.editor.console.registry.cvars[name].value

    @staticmethod
    def _compose(vol, view) -> np.ndarray:
        rgba = vol.slice(view.axis, view.index).astype(np.float32)
        around = [vol.slice(view.axis, i) for i in (view.index - 1, view.index + 1) if 0 <= i < vol.depth(view.axis)]
        if around:
            ghost = np.mean(around, axis=0)
            ghost[..., 3] *= NEIGHBOUR_OPACITY
            a = rgba[..., 3:4] / 255
            rgba[..., :3] = rgba[..., :3] * a + ghost[..., :3] * (1 - a)
            rgba[..., 3] = np.maximum(rgba[..., 3], ghost[..., 3])
        return np.ascontiguousarray(rgba.round().astype(np.uint8))

    def paintEvent(self, _event) -> None:
        cu, cv = self.cell()
        painter = QPainter(self)
        painter.fillRect(self.rect(), QColor(40, 42, 50))
        data = self.image()
        h, w = data.shape[:2]
        target = QRectF(self.offset.x(), self.offset.y(), w * cu, h * cv)
        self._checkerboard(painter, target)
        image = QImage(data.data, w, h, 4 * w, QImage.Format.Format_RGBA8888)
        painter.drawImage(target, image)
        painter.setPen(QPen(QColor(120, 125, 140), 1))
        painter.drawRect(target)
        if self.hover is not None:
            self._brush_outline(painter)
        painter.end()

    def _checkerboard(self, painter: QPainter, target: QRectF) -> None:
        """Transparency shows as a checkerboard: one tiled brush, not a fill per cell."""
        if self._checker is None:
            tile = QPixmap(16, 16)
            tile.fill(QColor(70, 72, 80))
            p = QPainter(tile)
            p.fillRect(0, 0, 8, 8, QColor(92, 94, 104))
            p.fillRect(8, 8, 8, 8, QColor(92, 94, 104))
            p.end()
            self._checker = QBrush(tile)
        painter.fillRect(target, self._checker)

    def _brush_outline(self, painter: QPainter) -> None:
        size = self.editor.console.registry.cvars["brush_size"].value if self.tool == "brush" else 1
        u, v = self.hover
        lo = u - (size - 1) // 2, v - (size - 1) // 2
        cu, cv = self.cell()
        rect = QRectF(self.offset.x() + lo[0] * cu, self.offset.y() + lo[1] * cv, size * cu, size * cv)
        painter.setPen(QPen(QColor(255, 255, 255), 1.5))
        round_brush = self.editor.console.registry.cvars["brush_round"].value and size > 2
        painter.drawEllipse(rect) if round_brush and self.tool == "brush" else painter.drawRect(rect)

    # -- input ------------------------------------------------------------------------------
    def _paint(self) -> str:
        """What the brush and fill paint, as their commands' words: a scan's label, else the colour (erase: the
        clear label, or a transparent colour)."""
        if self.state.volume.voxels.labels is not None:
            return str(0 if self.erase else self._cvar(BRUSH_LABEL))
        return " ".join(map(str, (0, 0, 0, 0) if self.erase else self.state.view.brush))

    def _stroke_line(self, verb: str) -> str:
        """A stroke command (`verb`: stroke or stroke.preview); a scan's the label.* one."""
        view = self.state.view
        size = self._cvar("brush_size")
        coords = " ".join(f"{u} {v}" for u, v in self.points)
        verb = f"label.{verb}" if self.state.volume.voxels.labels is not None else verb
        return f"{verb} {view.axis} {view.index} {size} {self._paint()} {coords}"

    def mousePressEvent(self, event) -> None:
        u, v = self.to_voxel(event.position())
        if event.button() == Qt.MouseButton.RightButton:
            self._zoom_drag = (event.position().x(), self.zoom)
            return
        if event.button() != Qt.MouseButton.LeftButton:
            return
        view = self.state.view
        tool = "pick" if event.modifiers() & Qt.KeyboardModifier.AltModifier else self.tool
        if tool == "pick":
            voxels = self.state.volume.voxels
            su, sv = voxels.slice_size(view.axis)
            if 0 <= u < su and 0 <= v < sv:
                self.command.emit(f"pick {' '.join(map(str, voxels.voxel_of(view.axis, view.index, u, v)))}")
        elif tool == "fill":
            tolerance = self._cvar("fill_tolerance")
            verb = "label.fill" if self.state.volume.voxels.labels is not None else "fill"
            line = f"{verb} {view.axis} {view.index} {u} {v} {self._paint()}"
            self.command.emit(f"{line} {tolerance}" if tolerance else line)  # 0 is the command's default
        else:
            self.points = [(u, v)]
            self.command.emit(self._stroke_line("stroke.preview"))

    def mouseMoveEvent(self, event) -> None:
        self.hover = self.to_voxel(event.position())
        if self._zoom_drag is not None:
            x0, zoom0 = self._zoom_drag
            factor = 1.01 ** (event.position().x() - x0) * zoom0 / self.zoom
            self.zoom_about(factor, QPointF(self.width() / 2, self.height() / 2))
        elif self.points and self.hover != self.points[-1]:
            self.points.append(self.hover)
            self.command.emit(self._stroke_line("stroke.preview"))
        self.update()

    def mouseReleaseEvent(self, event) -> None:
        if event.button() == Qt.MouseButton.RightButton:
            self._zoom_drag = None
        elif event.button() == Qt.MouseButton.LeftButton and self.points:
            self.command.emit(self._stroke_line("stroke"))
            self.points = []

    def leaveEvent(self, _event) -> None:
        self.hover = None
        self.update()

    def wheelEvent(self, event) -> None:
        self.zoom_about(ZOOM_KEY ** (event.angleDelta().y() / 120), event.position())

    def keyPressEvent(self, event) -> None:
        key = event.key()
        pan = {Qt.Key.Key_A: (1, 0), Qt.Key.Key_D: (-1, 0), Qt.Key.Key_W: (0, 1), Qt.Key.Key_S: (0, -1)}.get(key)
        centre = QPointF(self.width() / 2, self.height() / 2)
        if pan:
            self.offset += QPointF(pan[0] * self.width() * PAN_STEP, pan[1] * self.height() * PAN_STEP)
            self.update()
        elif key in (Qt.Key.Key_H, Qt.Key.Key_J):
            self.zoom_about(1 / ZOOM_KEY if key == Qt.Key.Key_H else ZOOM_KEY, centre)
        elif key == Qt.Key.Key_Escape and self.points:
            self.points = []
            self.command.emit("stroke.cancel")
        elif (name := key_name(key)) and (bound := self.editor.binds.lookup("painter", name)):
            self.command.emit(bound)
        else:
            super().keyPressEvent(event)


class SlicePainter(QWidget):
    """The dock: slice and brush controls above the canvas."""

    def __init__(self, editor, state, run, parent=None) -> None:
        super().__init__(parent)
        self.editor, self.state = editor, state
        self.run = run
        self.picker = None  # the slice picker dialog while it is open
        self.canvas = SliceCanvas(editor, state)
        self.canvas.command.connect(run)
        self.axis = QComboBox()
        self.axis.addItems(AXES)
        self.index = QSpinBox()
        self.size = QSpinBox(minimum=1, maximum=64)
        self.round = QCheckBox("round")
        self.colour = QPushButton()
        self.colour.setToolTip("Brush colour (c)")
        self.colour.clicked.connect(lambda: run("ui.brushcolor"))
        self.labels = LabelRow(editor, state, run)  # on a scan, in the colour button's place
        self.erase = QCheckBox("erase")
        self.erase.toggled.connect(lambda on: setattr(self.canvas, "erase", on))
        tools = QButtonGroup(self)
        tool_row = QHBoxLayout()
        tips = (("brush", "Paint"), ("fill", "Flood fill within the slice"), ("pick", "Eyedropper (Alt+click)"))
        for name, tip in tips:
            button = QToolButton(text=name, checkable=True, checked=name == "brush", toolTip=tip)
            button.toggled.connect(lambda on, n=name: on and setattr(self.canvas, "tool", n))
            tools.addButton(button)
            tool_row.addWidget(button)
        self.tolerance = QSpinBox(minimum=0, maximum=255, toolTip="Fill: take in the voxels whose every channel "
                                  "(r, g, b, a) is within this of the clicked one's; 0: one exact colour")
        tool_row.addWidget(QLabel("tolerance"))
        tool_row.addWidget(self.tolerance)
        tool_row.addWidget(self.erase)
        tool_row.addStretch(1)
        top = QHBoxLayout()
        for label, widget in (("slice", self.axis), ("", self.index), ("brush", self.size), ("", self.round),
                              ("", self.colour), ("", self.labels)):
            if label:
                top.addWidget(QLabel(label))
            top.addWidget(widget)
        top.addStretch(1)
        layout = QVBoxLayout(self)
        layout.setContentsMargins(2, 2, 2, 2)
        layout.addLayout(top)
        layout.addLayout(tool_row)
        layout.addWidget(self.canvas, 1)
        self.transfer = TransferPanel(state, run)  # a scalar volume's window and colour map
        self.modes = ScalarModeRow(state, self.editor.console.registry.cvars, run)  # and how it is drawn
        self.transfer.layout().addWidget(self.modes)
        layout.addWidget(self.transfer)
        self.axis.currentTextChanged.connect(lambda a: self._set_slice(a, self.state.view.index))
        self.index.valueChanged.connect(lambda i: self._set_slice(self.axis.currentText(), i))
        self.size.valueChanged.connect(lambda s: run(f"brush_size {s}"))
        self.round.toggled.connect(lambda on: run(f"brush_round {int(on)}"))
        self.tolerance.valueChanged.connect(lambda t: run(f"fill_tolerance {t}"))
        self.sync()

    def _set_slice(self, axis: str, index: int) -> None:
        view = self.state.view
        index = min(index, self.state.volume.voxels.depth(axis) - 1)
        if (axis, index) != (view.axis, view.index):
            self.run(f"slice {axis} {index}")

    def sync(self) -> None:
        """Show the model's values without sending them back as commands."""
        self.transfer.sync()
        self.labels.sync()
        self.modes.sync()
        view, vol = self.state.view, self.state.volume.voxels
        self.colour.setVisible(vol.labels is None)
        cvars = self.editor.console.registry.cvars
        for widget, setter, value in ((self.axis, "setCurrentText", view.axis),
                                      (self.index, "setMaximum", vol.depth(view.axis) - 1),
                                      (self.index, "setValue", view.index),
                                      (self.size, "setValue", cvars["brush_size"].value),
                                      (self.round, "setChecked", cvars["brush_round"].value),
                                      (self.tolerance, "setValue", cvars["fill_tolerance"].value)):
            widget.blockSignals(True)
            getattr(widget, setter)(value)
            widget.blockSignals(False)
        shape = (view.axis, vol.slice_size(view.axis), vol.slice_spacing(view.axis))
        if shape != getattr(self, "_shape", None):
            self.canvas.zoom = 0  # refit: another axis, a new or rotated volume, another spacing
            self._shape = shape
            self.canvas.update()
        labels = None if vol.labels is None else (id(vol.labels), vol.labels.version, vol.labels.colour_version,
                                                  cvars[OPACITY].value)
        shown = (vol.version, labels, view.axis, view.index, view.brush, cvars["brush_size"].value,
                 cvars["brush_round"].value)
        if shown == getattr(self, "_shown", None):
            return  # an orbit or another view change: nothing here to redraw
        self._shown = shown
        r, g, b, a = view.brush
        self.colour.setText(f"#{r:02x}{g:02x}{b:02x} α{a}")
        text = "black" if r + g + b > 380 else "white"
        self.colour.setStyleSheet(f"background: rgba({r},{g},{b},{a}); color: {text}")
        self.canvas.update()
