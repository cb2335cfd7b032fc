"""The view behind a modal dialog (issue 15, item 1): while a colour or file dialog's event loop runs, the
viewport repaints the same whole picture: the 2D view its hulls, shadows and the selection's overlay, the 3D
view its scene."""
import numpy as np
import pytest
from PySide6.QtWidgets import QColorDialog, QFileDialog

from tests.modal import while_modal
from tests.test_main_window import frame_image, wait_until_drawn

COLOUR_BUTTON = {"lighting2d": "l_color", "lights3d": "l_colour"}  # the selected light's


@pytest.mark.parametrize("workspace", sorted(COLOUR_BUTTON))
def test_the_view_keeps_its_picture_behind_modal_dialogs(window, qtbot, tmp_path, workspace):
    window.run(f"workspace {workspace}")
    qtbot.waitUntil(lambda: window.viewport.tool is window.tools[workspace])
    if workspace == "lighting2d":
        window.tools[workspace].select(("light", 2))  # the lime light: its overlay is drawn
    else:
        window.run("lights3d.select light 0")
    wait_until_drawn(window, qtbot)
    before = frame_image(window)
    colour = getattr(window.workspace_panels[workspace].widget(), COLOUR_BUTTON[workspace])
    frames = window.viewport.frames
    behind = [while_modal(qtbot, colour.click, QColorDialog, lambda _d: frame_image(window)),
              while_modal(qtbot, lambda: QFileDialog.getOpenFileName(window, "Open", str(tmp_path)), QFileDialog,
                          lambda _d: frame_image(window))]
    assert window.viewport.frames >= frames + 2  # each grab drew a frame inside the dialog's event loop
    for image in behind:
        assert image.shape == before.shape and np.abs(image.astype(int) - before.astype(int)).mean() < 1.0
