"""The view behind a modal dialog (issue 15, item 1): while a colour or file dialog's event loop runs, the screen
shows the viewport's whole picture: the 2D view its hulls, shadows and the selection's overlay, the 3D view its
scene. What is checked is what the X server shows (the picture Qt composed), not a fresh render: grabFramebuffer
draws a new frame of its own, so it could not see a picture lost on its way to the screen."""
import numpy as np
import pytest
from PySide6.QtGui import QGuiApplication
from PySide6.QtWidgets import QColorDialog, QFileDialog

from tests.modal import while_modal
from tests.test_main_window import wait_until_drawn

COLOUR_BUTTON = {"lighting2d": "l_color", "lights3d": "l_colour"}  # the selected light's
MIN_VISIBLE = 0.25  # of the view left uncovered by the dialog, or the comparison would prove little


def on_screen(widget) -> np.ndarray:
    """The widget's area as the screen shows it now (RGB rows from the top)."""
    QGuiApplication.sync()  # the X server has drawn what Qt sent it
    corner = widget.mapToGlobal(widget.rect().topLeft())
    image = widget.screen().grabWindow(0, corner.x(), corner.y(), widget.width(), widget.height()).toImage()
    image = image.convertToFormat(image.Format.Format_RGB888)
    h, w = image.height(), image.width()
    return np.frombuffer(image.constBits(), np.uint8).reshape(h, image.bytesPerLine())[:, : 3 * w].reshape(h, w, 3).copy()


def uncovered(widget, dialog) -> np.ndarray:
    """Which of the widget's pixels the dialog's frame leaves in sight."""
    corner = widget.mapToGlobal(widget.rect().topLeft())
    box = dialog.frameGeometry().translated(-corner)
    mask = np.ones((widget.height(), widget.width()), bool)
    mask[max(box.top(), 0):max(box.bottom() + 1, 0), max(box.left(), 0):max(box.right() + 1, 0)] = False
    return mask


def redrawn_behind(window, qtbot, dialog):
    """Ask the view for a frame while the dialog is up (as a timer, an animation or a shader reload would), let
    Qt draw and compose it inside the dialog's event loop, and read the screen: (what it shows, what is in sight)."""
    viewport = window.viewport
    frames = viewport.frames
    viewport.update()
    qtbot.waitUntil(lambda: viewport.frames > frames, timeout=10000)
    return on_screen(viewport), uncovered(viewport, dialog)


@pytest.mark.parametrize("workspace", sorted(COLOUR_BUTTON))
def test_the_screen_keeps_the_view_behind_modal_dialogs(window, qtbot, tmp_path, workspace):
    window.run(f"workspace {workspace}")
    qtbot.waitUntil(lambda: window.viewport.tool is window.tools[workspace])
    if workspace == "lighting2d":
        window.tools[workspace].select(("light", 2))  # the lime light: its overlay is drawn
    else:
        window.run("lights3d.select light 0")
    wait_until_drawn(window, qtbot)
    before = on_screen(window.viewport)
    colour = getattr(window.workspace_panels[workspace].widget(), COLOUR_BUTTON[workspace])
    behind = [while_modal(qtbot, colour.click, QColorDialog, lambda d: redrawn_behind(window, qtbot, d)),
              while_modal(qtbot, lambda: QFileDialog.getOpenFileName(window, "Open", str(tmp_path)), QFileDialog,
                          lambda d: redrawn_behind(window, qtbot, d))]
    assert before.std() > 10  # a picture, not a blank view
    for image, seen in behind:
        assert seen.mean() > MIN_VISIBLE
        assert np.abs(image.astype(int) - before.astype(int))[seen].mean() < 1.0
