"""The panels' shared widgets under Xvfb: the colour button's dialog."""
import pytest
from PySide6.QtCore import QTimer
from PySide6.QtGui import QColor, QPalette
from PySide6.QtWidgets import QApplication, QColorDialog, QVBoxLayout, QWidget

from app.views.form_widgets import ColorButton


def open_dialog_of(button, qtbot, inspect):
    """Click the button; `inspect(dialog)` runs while its modal dialog is open, which is then cancelled."""
    seen = []

    def look():
        dialog = QApplication.activeModalWidget()
        if not isinstance(dialog, QColorDialog):
            QTimer.singleShot(20, look)
            return
        qtbot.waitExposed(dialog)
        seen.append(inspect(dialog))
        dialog.reject()
    QTimer.singleShot(0, look)
    button.click()  # returns once the dialog is closed
    assert seen, "no colour dialog opened"
    return seen[0]


@pytest.mark.parametrize("colour", [(0.0, 1.0, 0.0), (0.07, 0.07, 0.09)])  # a lime light, a near-black ambient
def test_the_colour_dialog_opens_on_the_colour_with_the_normal_style(qtbot, colour):
    holder = QWidget()
    QVBoxLayout(holder).addWidget(button := ColorButton("Light colour", lambda c: None))
    qtbot.addWidget(holder)
    holder.show()
    button.show_color(colour)

    def inspect(dialog):
        corner = dialog.grab().toImage().pixelColor(3, 3)  # the dialog's own background, in its margin
        return dialog.currentColor(), corner

    current, corner = open_dialog_of(button, qtbot, inspect)
    assert current.name() == QColor.fromRgbF(*colour).name()  # the dialog keeps 8 bits a channel
    assert corner == QApplication.palette().color(QPalette.ColorRole.Window)  # as any dialog, not the swatch's colour
