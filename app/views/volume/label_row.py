"""The slice painter's brush row on a scan: which label the brush paints (a menu of swatches on the label button,
key c, and a spin box for any of the 255), a label's colour, and how opaque the labels are over the scan. On an
RGBA volume the painter shows its colour button instead. Every choice goes out as a command."""
from __future__ import annotations

from PySide6.QtGui import QColor, QIcon, QPixmap
from PySide6.QtWidgets import QHBoxLayout, QLabel, QMenu, QPushButton, QSpinBox, QWidget

from app.commands.volume_labels import BRUSH_LABEL, OPACITY
from app.model.volume.labels import LABELS
from app.views.form_widgets import spin

MENU_LABELS = 12  # the labels the menu always offers; those painted beyond them are added


def swatch(rgb) -> QIcon:
    pixmap = QPixmap(14, 14)
    pixmap.fill(QColor(*(int(c) for c in rgb)))
    return QIcon(pixmap)


class LabelRow(QWidget):
    def __init__(self, editor, state, run) -> None:
        super().__init__()
        self.editor, self.state, self.run = editor, state, run
        self.button = QPushButton(toolTip="The label the brush paints over the scan (c): pick one, or its colour")
        self.menu = QMenu(self)
        self.button.clicked.connect(self.open_menu)
        self.number = QSpinBox(minimum=0, maximum=LABELS, toolTip="Any label 1..255; 0 erases")
        self.number.setKeyboardTracking(False)
        self.number.valueChanged.connect(lambda n: run(f"{BRUSH_LABEL} {n}"))
        self.opacity = spin(0.0, 1.0, 0.1)
        self.opacity.setToolTip("How opaque the labels are over the scan, here and in the 3D view")
        self.opacity.valueChanged.connect(lambda a: run(f"{OPACITY} {a:g}"))
        row = QHBoxLayout(self)
        row.setContentsMargins(0, 0, 0, 0)
        for widget in (self.button, self.number, QLabel("opacity"), self.opacity):
            row.addWidget(widget)
        self._shown = None

    def _label(self) -> int:
        return self.editor.console.registry.cvars[BRUSH_LABEL].value

    def open_menu(self) -> None:
        """The labels to pick from (their swatches; the painted ones marked), the eraser, and the colour dialog."""
        labels, current = self.state.volume.voxels.labels, self._label()
        counts = labels.counts()
        painted = [int(n) for n in counts[1:].nonzero()[0] + 1]
        self.menu.clear()
        for n in sorted(set(range(1, MENU_LABELS + 1)) | set(painted)):
            text = f"label {n}" + (f"  ({counts[n]} voxels)" if counts[n] else "")
            action = self.menu.addAction(swatch(labels.colours[n]), text, lambda n=n: self.run(f"{BRUSH_LABEL} {n}"))
            action.setCheckable(True)
            action.setChecked(n == current)
        self.menu.addAction("eraser (label 0)", lambda: self.run(f"{BRUSH_LABEL} 0"))
        self.menu.addSeparator()
        colour = self.menu.addAction(f"colour of label {current}...", lambda: self.run("ui.labelcolor"))
        colour.setEnabled(current > 0)
        self.menu.popup(self.button.mapToGlobal(self.button.rect().bottomLeft()))

    def sync(self) -> None:
        labels = self.state.volume.voxels.labels
        self.setVisible(labels is not None)
        if labels is None:
            return
        cvars = self.editor.console.registry.cvars
        label, opacity = self._label(), cvars[OPACITY].value
        shown = (label, opacity, id(labels), labels.colour_version)
        if shown == self._shown:
            return
        self._shown = shown
        for widget, value in ((self.number, label), (self.opacity, opacity)):
            widget.blockSignals(True)
            widget.setValue(value)
            widget.blockSignals(False)
        if label:
            r, g, b = (int(c) for c in labels.colours[label])
            self.button.setText(f"label {label}")
            text = "black" if r + g + b > 380 else "white"
            self.button.setStyleSheet(f"background: rgb({r},{g},{b}); color: {text}")
        else:
            self.button.setText("eraser")
            self.button.setStyleSheet("")
