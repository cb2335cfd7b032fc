"""The transfer-function dock: a scalar volume's histogram (log counts), the window's two handles over it, the colour
map along the bottom and the translucent mode's opacity curve as points to drag (double-click adds one, right-click
removes one), with a preset and a colour-map choice above.

Every change is one console command (`vol.window`, `vol.opacity`, `vol.colormap`, `vol.preset`,
`vol.opacity.reset`), so it is recorded, replayed and undone like any edit. A point being dragged shows in the 3D
view through `vol.opacity.preview` (neither recorded nor an undo step) and becomes one `vol.opacity` on release; a
handle of the window moves here alone until it is let go, then sends one `vol.window`.
"""
from __future__ import annotations

import math
from typing import Callable

import numpy as np
import pyqtgraph as pg
from PySide6.QtCore import QRectF, Qt
from PySide6.QtWidgets import QComboBox, QHBoxLayout, QLabel, QPushButton, QVBoxLayout, QWidget

from app.console.text import number
from app.model.volume.scalars import COLORMAPS, MAX_OPACITY_POINTS, value_histogram
from app.model.volume.transfer_presets import PRESETS

BINS = 256
BAR = (-0.11, 0.07)        # the colour map's bar below the curve: its bottom and height, in opacity units
TOP = 1.05
HISTOGRAM = (110, 110, 120)
CURVE = (255, 170, 60)
WINDOW_FILL = (80, 140, 220, 40)
PRESET_PROMPT = "preset..."
HINT = ("Drag the window's edges; drag a point of the opacity curve, double-click to add one, right-click to remove "
        "one. The curve draws in r_scalarMode translucent.")


def _points_text(points) -> str:
    return " ".join(f"{number(v)} {number(a)}" for v, a in points)


class CurvePoints(pg.ScatterPlotItem):
    """The opacity curve's points: a drag moves one (`moved` while dragging, `dropped` at the end), a right click
    removes one; both only on a point, so elsewhere the window's handles and the view take the mouse."""

    def __init__(self, moved: Callable, dropped: Callable, removed: Callable) -> None:
        super().__init__(size=11, pen=pg.mkPen(20, 20, 20), brush=pg.mkBrush(*CURVE), hoverable=False)
        self.moved, self.dropped, self.removed = moved, dropped, removed
        self.dragged: int | None = None
        self.setZValue(20)  # above the window's handles: a point on a handle is the point's

    def point_at(self, pos) -> int | None:
        hit = self.pointsAt(pos)
        return int(hit[0].index()) if len(hit) else None

    def hoverEvent(self, ev) -> None:
        if not ev.isExit() and self.point_at(ev.pos()) is not None:
            ev.acceptDrags(Qt.MouseButton.LeftButton)
            ev.acceptClicks(Qt.MouseButton.RightButton)
            ev.acceptClicks(Qt.MouseButton.LeftButton)  # a double click on a point adds none

    def mouseDragEvent(self, ev) -> None:
        if ev.button() != Qt.MouseButton.LeftButton:
            ev.ignore()
            return
        if ev.isStart():
            self.dragged = self.point_at(ev.buttonDownPos())
        if self.dragged is None:
            ev.ignore()
            return
        ev.accept()
        pos = ev.pos()
        if ev.isFinish():
            index, self.dragged = self.dragged, None
            self.dropped(index, pos.x(), pos.y())
        else:
            self.moved(self.dragged, pos.x(), pos.y())

    def mouseClickEvent(self, ev) -> None:
        index = self.point_at(ev.pos())
        if index is None:
            ev.ignore()
            return
        ev.accept()
        if ev.button() == Qt.MouseButton.RightButton:
            self.removed(index)


class TransferPlot(pg.PlotWidget):
    """Pans and zooms along the values only (the right button removes points: no menu); a double click in the plot
    adds a point of the curve there. Taken from Qt's own double-click event: pyqtgraph's click events lose a double
    click that follows a press (its issue 91), as Qt 6 delivers them."""

    def __init__(self, added: Callable) -> None:
        super().__init__(viewBox=pg.ViewBox(enableMenu=False), background=(30, 30, 34))
        self.added = added
        self.getViewBox().setMouseEnabled(x=True, y=False)
        self.hideButtons()

    def mouseDoubleClickEvent(self, ev) -> None:
        view = self.getViewBox()
        at = self.mapToScene(ev.position().toPoint())
        if ev.button() == Qt.MouseButton.LeftButton and view.sceneBoundingRect().contains(at):
            pos = view.mapSceneToView(at)
            self.added(pos.x(), pos.y())
        super().mouseDoubleClickEvent(ev)


class TransferEditor(QWidget):
    def __init__(self, state, run) -> None:
        super().__init__()
        self.state, self.run = state, run
        self.preset = QComboBox(toolTip="Set the window, colour map and opacity curve at once (vol.preset), as 3D "
                                        "Slicer's volume-rendering presets")
        self.preset.addItem(PRESET_PROMPT)
        for name, chosen in PRESETS.items():
            self.preset.addItem(chosen.title, name)
        self.colormap = QComboBox(toolTip="The colour map across the window (vol.colormap)")
        self.colormap.addItems(COLORMAPS)
        self.reset = QPushButton("reset curve", toolTip="The opacity curve back to a ramp over the window, 0 at "
                                                        "low to 1 at high (vol.opacity.reset)")
        self.info = QLabel(HINT, wordWrap=True)
        self.plot = TransferPlot(self._add)
        self.view = self.plot.getViewBox()
        self.plot.setLabel("left", "opacity")
        self.plot.setMinimumHeight(120)
        self.view.setYRange(BAR[0] - 0.01, TOP, padding=0)
        self.histogram = pg.PlotDataItem(stepMode="center", fillLevel=0, pen=pg.mkPen(*HISTOGRAM),
                                         brush=pg.mkBrush(*HISTOGRAM, 110))
        self.bar = pg.ImageItem()
        self.region = pg.LinearRegionItem(brush=pg.mkBrush(*WINDOW_FILL), pen=pg.mkPen(120, 180, 255, width=2))
        self.region.setMovable(False)  # the body passes the mouse on (to the view, to the points)...
        for line in self.region.lines:  # ...its two edges are the handles
            line.setMovable(True)
        self.region.lines[0].setToolTip("Window low: values here and below take the colour map's first colour")
        self.region.lines[1].setToolTip("Window high: values here and above take the colour map's last colour")
        self.line = pg.PlotDataItem(pen=pg.mkPen(*CURVE, width=2))  # the curve, out to the view's edges
        self.points = CurvePoints(self._move, self._drop, self._remove)
        for item in (self.histogram, self.bar, self.region, self.line, self.points):
            self.view.addItem(item)
        top = QHBoxLayout()
        for widget in (QLabel("preset"), self.preset, QLabel("colour map"), self.colormap, self.reset):
            top.addWidget(widget)
        top.addStretch(1)
        layout = QVBoxLayout(self)
        layout.setContentsMargins(2, 2, 2, 2)
        layout.addLayout(top)
        layout.addWidget(self.plot, 1)
        layout.addWidget(self.info)
        self.preset.textActivated.connect(self._preset)
        self.colormap.textActivated.connect(lambda name: self.run(f"vol.colormap {name}"))
        self.reset.clicked.connect(lambda: self.run("vol.opacity.reset"))
        self.region.sigRegionChangeFinished.connect(self._window_moved)
        self.view.sigXRangeChanged.connect(lambda *_: self._draw_curve(self._curve))
        self._values = None  # the values the histogram is of
        self._shown = False  # the transfer function the items show; False: none yet
        self._curve: list[tuple[float, float]] = []  # the points drawn (while dragging, ahead of the model)
        self._span = (0.0, 1.0)  # the values' finite range
        self.sync()

    # --- the model into the items -------------------------------------------------------------------------------

    def sync(self) -> None:
        scalars = self.state.volume.voxels.scalars
        transfer = scalars.transfer if scalars is not None else None
        if transfer == self._shown and (scalars is None or scalars.values is self._values):
            return  # the camera moved, a slice changed...: nothing here
        self._shown = transfer
        self.setEnabled(scalars is not None)
        if scalars is None:
            self._values = None
            self.histogram.setData([], [])
            self.points.setData([], [])
            self.line.setData([], [])
            self.bar.clear()
            return
        if scalars.values is not self._values:
            self._values = scalars.values
            self._show_histogram(scalars.values)
        self.region.blockSignals(True)
        self.region.setRegion((transfer.low, transfer.high))
        self.region.blockSignals(False)
        (left, right), _ = self.view.viewRange()
        if transfer.low < left or transfer.high > right:  # both handles in view, to be dragged
            self.view.setXRange(min(left, transfer.low), max(right, transfer.high), padding=0.02)
        self.colormap.setCurrentText(transfer.colormap)
        self.preset.setCurrentIndex(0)
        self._draw_curve(list(transfer.opacity()))
        self._draw_bar()

    def _show_histogram(self, values: np.ndarray) -> None:
        edges, counts = value_histogram(values, BINS)
        heights = np.log1p(counts)  # log counts: a scan's air or background would flatten the rest
        if heights.max() > 0:
            heights /= heights.max()
        self.histogram.setData(edges, heights)
        self._span = (float(edges[0]), float(edges[-1]))
        self.view.setXRange(*self._span, padding=0.02)

    def _draw_curve(self, points: list[tuple[float, float]]) -> None:
        """The points, joined and held level beyond the ends to the edges of what the view shows."""
        self._curve = points
        if not points:
            return
        (left, right), _ = self.view.viewRange()
        xs = [min(left, points[0][0]), *(v for v, _ in points), max(right, points[-1][0])]
        ys = [points[0][1], *(a for _, a in points), points[-1][1]]
        self.line.setData(xs, ys)
        self.points.setData([v for v, _ in points], [a for _, a in points])

    def _draw_bar(self) -> None:
        """The colour map's colour at each value across the histogram, clamped beyond the window as it is drawn."""
        transfer = self._shown
        low, high = self._span
        values = np.linspace(low, high, 512)
        t = np.clip((values - transfer.low) / (transfer.high - transfer.low), 0.0, 1.0)
        colours = transfer.table()[np.rint(t * 255).astype(int), :3]
        self.bar.setImage(colours[:, None, :], levels=(0, 255))
        self.bar.setRect(QRectF(low, BAR[0], max(high - low, 1e-9), BAR[1]))

    # --- the mouse into commands ----------------------------------------------------------------------------

    def _round(self, value: float) -> float:
        """A value to the places the data's span needs (whole numbers for a CT's thousands of units)."""
        low, high = self._span
        return round(value, max(0, 3 - math.floor(math.log10(max(high - low, 1e-12)))))

    def _step(self) -> float:
        low, high = self._span
        return 10.0 ** -max(0, 3 - math.floor(math.log10(max(high - low, 1e-12))))

    def _placed(self, index: int, x: float, y: float) -> list[tuple[float, float]]:
        """The curve with point `index` at (x, y): its value kept between its neighbours', its opacity in 0..1."""
        points = list(self._shown.opacity())
        step = self._step()
        value = self._round(x)
        if index > 0:
            value = max(value, points[index - 1][0] + step)
        if index < len(points) - 1:
            value = min(value, points[index + 1][0] - step)
        points[index] = (value, round(min(max(y, 0.0), 1.0), 3))
        return points

    def _move(self, index: int, x: float, y: float) -> None:
        points = self._placed(index, x, y)
        self._draw_curve(points)
        self.run(f"vol.opacity.preview {_points_text(points)}")

    def _drop(self, index: int, x: float, y: float) -> None:
        self._send(f"vol.opacity {_points_text(self._placed(index, x, y))}")

    def _remove(self, index: int) -> None:
        points = list(self._shown.opacity())
        if len(points) > 1:
            del points[index]
            self._send(f"vol.opacity {_points_text(points)}")

    def _add(self, x: float, y: float) -> None:
        points = list(self._shown.opacity()) if self._shown else []
        value = self._round(x)
        if not points or len(points) >= MAX_OPACITY_POINTS or any(abs(v - value) < self._step() for v, _ in points):
            return
        points = sorted([*points, (value, round(min(max(y, 0.0), 1.0), 3))])
        self._send(f"vol.opacity {_points_text(points)}")

    def _window_moved(self) -> None:
        low, high = (self._round(v) for v in self.region.getRegion())
        if (low, high) != (self._shown.low, self._shown.high):
            self._send(f"vol.window {number(low)} {number(high)}")

    def _preset(self, _title: str) -> None:
        name = self.preset.currentData()
        if name is not None:
            self._send(f"vol.preset {name}")

    def _send(self, line: str) -> None:
        if not self.run(line):
            self._shown = False
            self.sync()  # refused (a window of no width): show the model's transfer function again
