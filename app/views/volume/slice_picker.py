"""The slice picker (seed key v): choose an axis, hover the 3D view to highlight a slice, click to
edit it; or type the index. It opens beside the 3D view, not over it."""
from __future__ import annotations

from PySide6.QtCore import QPoint, QRect
from PySide6.QtWidgets import QComboBox, QDialog, QDialogButtonBox, QFormLayout, QLabel, QSpinBox

from app.model.volume.voxels import AXES


GAP_PX = 8


def beside(size, view: QRect, screen: QRect) -> QPoint:
    """Where a window of `size` covers least of `view`, on the screen: left of it, right, above or below."""
    w, h = size.width(), size.height()
    places = [QPoint(view.left() - w - GAP_PX, view.top()), QPoint(view.right() + GAP_PX, view.top()),
              QPoint(view.left(), view.top() - h - GAP_PX), QPoint(view.left(), view.bottom() + GAP_PX)]

    def on_screen(p: QPoint) -> QPoint:
        return QPoint(max(screen.left(), min(p.x(), screen.right() - w)),
                      max(screen.top(), min(p.y(), screen.bottom() - h)))

    def covered(p: QPoint) -> int:
        overlap = QRect(p, size).intersected(view)
        return overlap.width() * overlap.height() if overlap.isValid() else 0

    return min((on_screen(p) for p in places), key=covered)


class SlicePicker(QDialog):
    def __init__(self, state, tool, run, parent=None) -> None:
        super().__init__(parent)
        self.setWindowTitle("Slice picker")
        self.state, self.tool, self.run = state, tool, run
        self.axis = QComboBox()
        self.axis.addItems(AXES)
        self.axis.setCurrentText(state.view.axis)
        self.index = QSpinBox()
        buttons = QDialogButtonBox(QDialogButtonBox.StandardButton.Ok | QDialogButtonBox.StandardButton.Cancel)
        buttons.accepted.connect(lambda: self.pick(self.axis.currentText(), self.index.value()))
        buttons.rejected.connect(self.reject)
        form = QFormLayout(self)
        form.addRow(QLabel("Hover the 3D view to highlight a slice; click it to edit it."))
        form.addRow("axis", self.axis)
        form.addRow("slice", self.index)
        form.addRow(buttons)
        self.axis.currentTextChanged.connect(self._axis_changed)
        self.index.valueChanged.connect(lambda i: self.run(f"slice.highlight {self.axis.currentText()} {i}"))
        self.tool.on_pick = self.pick
        self.finished.connect(self._closed)
        self._axis_changed(self.axis.currentText())

    def showEvent(self, event) -> None:
        super().showEvent(event)
        view = self.tool.viewport
        self.move(beside(self.frameGeometry().size(), QRect(view.mapToGlobal(QPoint(0, 0)), view.size()),
                         view.screen().availableGeometry()))

    def _axis_changed(self, axis: str) -> None:
        self.tool.picker_axis = axis
        self.index.setMaximum(self.state.volume.voxels.depth(axis) - 1)
        self.index.blockSignals(True)
        self.index.setValue(min(self.state.view.index, self.index.maximum()))
        self.index.blockSignals(False)
        self.run(f"slice.highlight {axis} {self.index.value()}")

    def pick(self, axis: str, index: int) -> None:
        self.run(f"slice {axis} {index}")
        self.accept()

    def _closed(self) -> None:
        self.tool.picker_axis = None
        self.run("slice.highlight")
