"""The view behind a modal dialog (issue 15, item 1): while a colour or file dialog's event loop runs, the screen
shows the viewport's whole picture: the 2D view its hulls, shadows and the selection's overlay, the 3D view its
scene. What is checked is what the X server shows (the picture Qt composed), not a fresh render: grabFramebuffer
draws a new frame of its own, so it could not see a picture lost on its way to the screen."""
import numpy as np
import pytest
from PySide6.QtCore import QPoint, QRect
from PySide6.QtWidgets import QColorDialog, QFileDialog

from tests.modal import while_modal
from tests.window_frames import wait_until_drawn
from tests.test_shadow_volumes_qt import rgb

MIN_VISIBLE = 0.25  # of the view left uncovered by the dialog, or the comparison would prove little
TOLERANCE = 8  # levels of 255 a pixel may move by and still count as the same
MAX_CHANGED = 0.001  # of the pixels in sight: a lost overlay (a selection's ring and line) is more


def on_screen(widget) -> np.ndarray:
    """The widget's area as the screen shows it now (RGB rows from the top): what Qt composed and sent the X
    server, which answers the grab after the drawing requests sent before it."""
    corner = widget.mapToGlobal(widget.rect().topLeft())
    image = widget.screen().grabWindow(0, corner.x(), corner.y(), widget.width(), widget.height()).toImage()
    return rgb(image)[..., :3].copy()  # a copy: a view would outlive the QImage that owns the memory


def uncovered(widget, dialog) -> np.ndarray:
    """Which of the widget's pixels the dialog's frame leaves in sight."""
    corner = widget.mapToGlobal(widget.rect().topLeft())
    box = dialog.frameGeometry().translated(-corner)
    mask = np.ones((widget.height(), widget.width()), bool)
    mask[max(box.top(), 0):max(box.bottom() + 1, 0), max(box.left(), 0):max(box.right() + 1, 0)] = False
    return mask


def aside(dialog, widget) -> None:
    """Move the dialog to the screen's corner where it hides least of the widget, as a user would to look behind."""
    screen, size = dialog.screen().availableGeometry(), dialog.frameGeometry().size()
    view = QRect(widget.mapToGlobal(widget.rect().topLeft()), widget.size())
    corners = [QPoint(x, y) for x in (screen.left(), screen.right() + 1 - size.width())
               for y in (screen.top(), screen.bottom() + 1 - size.height())]

    def hidden(corner):
        overlap = QRect(corner, size).intersected(view)
        return overlap.width() * overlap.height() if overlap.isValid() else 0
    dialog.move(min(corners, key=hidden))


def redrawn_behind(window, qtbot, dialog):
    """Ask the view for a frame while the dialog is up (as a timer, an animation or a shader reload would), let
    Qt draw and compose it inside the dialog's event loop, and read the screen: (what it shows, what is in sight)."""
    viewport = window.viewport
    aside(dialog, viewport)
    wait_until_drawn(window, qtbot)  # what the move exposed is drawn again
    frames = viewport.frames
    viewport.update()
    qtbot.waitUntil(lambda: viewport.frames > frames and viewport.settled(), timeout=10000)  # a reduced frame refined
    return on_screen(viewport), uncovered(viewport, dialog)  # read at once: more events could draw more frames


def panel(window, workspace):
    return window.workspace_panels[workspace].widget()


# Per workspace: what to select (so an overlay is drawn), and how a person opens a colour dialog there.
SELECT = {"lighting2d": lambda w: w.tools["lighting2d"].select(("light", 2)),  # the lime light
          "lights3d": lambda w: w.run("lights3d.select light 0"),
          "volume": lambda w: None}
OPEN_COLOUR = {"lighting2d": lambda w: panel(w, "lighting2d").l_color.click(),  # the selected light's swatch
               "lights3d": lambda w: panel(w, "lights3d").l_colour.click(),
               "volume": lambda w: w.run("ui.background")}  # the 3D view's background (key c)


def file_open(window):
    next(a for a in window.menus.menus["file"].actions() if a.text() == "&Open...").trigger()


@pytest.mark.parametrize("workspace", sorted(OPEN_COLOUR))
def test_the_screen_keeps_the_view_behind_modal_dialogs(window, qtbot, workspace):
    window.run(f"workspace {workspace}")
    qtbot.waitUntil(lambda: window.viewport.tool is window.tools[workspace])
    SELECT[workspace](window)
    wait_until_drawn(window, qtbot)
    before = on_screen(window.viewport)
    behind = [while_modal(qtbot, lambda: OPEN_COLOUR[workspace](window), QColorDialog,
                          lambda d: redrawn_behind(window, qtbot, d)),
              while_modal(qtbot, lambda: file_open(window), QFileDialog, lambda d: redrawn_behind(window, qtbot, d))]
    assert before.std() > 10  # a picture, not a blank view
    for image, seen in behind:
        assert seen.mean() > MIN_VISIBLE
        changed = np.abs(image.astype(int) - before.astype(int)).max(axis=-1)[seen] > TOLERANCE
        assert changed.mean() < MAX_CHANGED, f"{changed.sum()} of {seen.sum()} pixels in sight changed"
