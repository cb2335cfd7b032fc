"""The panels' shared widgets under Xvfb: the colour button's dialog."""
import pytest
from PySide6.QtGui import QColor, QPalette
from PySide6.QtWidgets import QApplication, QColorDialog, QVBoxLayout, QWidget

from app.views.form_widgets import ColorButton
from tests.modal import while_modal


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

    current, corner = while_modal(qtbot, button.click, QColorDialog, inspect)
    assert current.name() == QColor.fromRgbF(*colour).name()  # the dialog keeps 8 bits a channel
    assert corner == QApplication.palette().color(QPalette.ColorRole.Window)  # as any dialog, not the swatch's colour
