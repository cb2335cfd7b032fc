"""Widgets the workspace panels share: number spin boxes that report only finished edits, a colour button
that opens QColorDialog, and a row of widgets kept to the left."""
from __future__ import annotations

from PySide6.QtGui import QColor
from PySide6.QtWidgets import QColorDialog, QDoubleSpinBox, QHBoxLayout, QPushButton, QWidget


def spin(lo: float, hi: float, step: float, decimals: int = 2) -> QDoubleSpinBox:
    box = QDoubleSpinBox(minimum=lo, maximum=hi, singleStep=step, decimals=decimals)
    box.setKeyboardTracking(False)  # one command per finished edit, not per digit typed
    return box


def left_row(*widgets: QWidget) -> QHBoxLayout:
    """The widgets side by side at their own widths, the spare room after them."""
    row = QHBoxLayout()
    for widget in widgets:
        row.addWidget(widget)
    row.addStretch(1)
    return row


def rgb_words(color) -> str:
    """A colour as a command's three numbers."""
    return " ".join(f"{c:.4f}" for c in color)


class ColorButton(QPushButton):
    """Shows a colour; clicking opens QColorDialog and reports the choice as (r, g, b) in 0..1."""

    def __init__(self, title: str, chosen) -> None:
        super().__init__()
        self.title = title
        self.chosen = chosen
        self.color = (1.0, 1.0, 1.0)
        self.clicked.connect(self._pick)

    def show_color(self, color) -> None:
        # Over-bright colours (a 3D light's go to 16) show, and start the dialog, at their 0..1 clamp.
        self.color = tuple(min(max(c, 0.0), 1.0) for c in color)
        q = QColor.fromRgbF(*self.color)
        self.setText(q.name())
        self.setStyleSheet(f"background-color: {q.name()}; color: {'black' if q.lightnessF() > 0.5 else 'white'}")

    def _pick(self) -> None:
        # The window is the dialog's parent, not this button: a child would inherit the button's style sheet and
        # be painted all over in the swatch's colour.
        picked = QColorDialog.getColor(QColor.fromRgbF(*self.color), self.window(), self.title)
        if picked.isValid():
            self.chosen((picked.redF(), picked.greenF(), picked.blueF()))
