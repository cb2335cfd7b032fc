"""The slice painter on a scan, under Xvfb: the mouse paints, fills, erases and picks labels as recorded
label.* commands, the slice shows them over the scan, and the label row takes the colour button's place."""
import numpy as np
import pytest
from PySide6.QtCore import QTimer, Qt
from PySide6.QtGui import QColor
from PySide6.QtWidgets import QApplication, QColorDialog

from app.model.volume.labels import DEFAULT_COLOURS
from painter_canvas import at, open_painter


@pytest.fixture
def scan_painter(window, qtbot, tmp_path):
    values = np.full((3, 12, 16), -1000, np.int16)
    values[:, :, :8] = 600  # bright on the left, air on the right
    np.save(tmp_path / "ct.npy", values)
    return open_painter(window, qtbot, ("workspace volume", f"load {tmp_path / 'ct.npy'}", "vol.window -1000 600",
                                        "slice z 1", "brush_size 1", "brush_round 1", "brush_label 3"), refresh=True)


def demo_lines(path) -> list[str]:
    return [line.split(" ", 1)[1] for line in path.read_text().splitlines()[2:]]


def commands(window) -> list[str]:
    return [line.text for line in window.editor.console.log if line.level == "input"]


def volume(window):
    return window.editor.workspaces["volume"].volume


def test_a_drag_on_a_scan_paints_the_brush_label_as_one_recorded_command(window, scan_painter, qtbot, tmp_path):
    vol = volume(window)
    values, colours = vol.voxels.scalars.values.copy(), vol.voxels.rgba()
    window.run(f"record {tmp_path / 'labels'}")
    qtbot.mousePress(scan_painter, Qt.MouseButton.LeftButton, pos=at(scan_painter, 2, 3))
    qtbot.mouseMove(scan_painter, at(scan_painter, 9, 3))
    assert vol.voxels.label_at(5, 3, 1) == 3  # the preview shows while the mouse is down
    qtbot.mouseRelease(scan_painter, Qt.MouseButton.LeftButton, pos=at(scan_painter, 9, 3))
    window.run("stop")
    assert [line for line in demo_lines(tmp_path / "labels.demo") if "stroke" in line] == \
        ["label.stroke z 1 1 3 2 3 9 3"]
    z, y, x = np.nonzero(vol.voxels.labels.data)
    assert set(zip(x.tolist(), y.tolist(), z.tolist())) == {(u, 3, 1) for u in range(2, 10)}
    np.testing.assert_array_equal(vol.voxels.scalars.values, values)
    np.testing.assert_array_equal(vol.voxels.rgba(), colours)
    # the slice shows the label over the scan: half its colour over the grey, half its colour on the clear air
    image = scan_painter.image()
    red = DEFAULT_COLOURS[3].astype(float)
    assert np.abs(image[3, 2, :3] - (0.5 * red + 0.5 * 255)).max() <= 1 and image[3, 2, 3] == 255
    assert np.abs(image[3, 9, :3] - red).max() <= 1 and image[3, 9, 3] == 128
    assert (image[4, 2] == colours[1, 4, 2]).all()  # unlabelled: the scan alone
    window.run("r_labelOpacity 1")
    assert (scan_painter.image()[3, 2, :3] == DEFAULT_COLOURS[3]).all()
    window.run("undo")
    assert vol.voxels.labels.data is None and (scan_painter.image()[3, 2] == colours[1, 3, 2]).all()


def test_fill_erase_and_eyedropper_on_a_scan(window, scan_painter, qtbot):
    vol = volume(window)
    panel = window.workspace_panels["volume"]
    scan_painter.tool = "fill"
    qtbot.mouseClick(scan_painter, Qt.MouseButton.LeftButton, pos=at(scan_painter, 2, 2))  # the bright left half
    assert (vol.voxels.labels.data[1, :, :8] == 3).all() and not vol.voxels.labels.data[1, :, 8:].any()
    assert commands(window)[-1] == "] label.fill z 1 2 2 3"
    panel.erase.setChecked(True)
    scan_painter.tool = "brush"
    qtbot.mouseClick(scan_painter, Qt.MouseButton.LeftButton, pos=at(scan_painter, 4, 5))
    assert vol.voxels.label_at(4, 5, 1) == 0 and vol.voxels.label_at(4, 4, 1) == 3
    panel.erase.setChecked(False)
    window.run("brush_label 7")
    qtbot.mouseClick(scan_painter, Qt.MouseButton.LeftButton, stateKey=Qt.KeyboardModifier.AltModifier,
                     pos=at(scan_painter, 1, 1))
    assert window.editor.console.registry.cvars["brush_label"].value == 3  # the eyedropper took the label there
    window.refresh()
    assert panel.labels.number.value() == 3 and panel.labels.button.text() == "label 3"


def test_the_label_row_takes_the_colour_buttons_place_and_sends_commands(window, scan_painter, qtbot):
    panel = window.workspace_panels["volume"]
    row, cvars = panel.labels, window.editor.console.registry.cvars
    assert row.isVisible() and not panel.colour.isVisible()
    row.number.setValue(12)
    assert cvars["brush_label"].value == 12
    row.opacity.setValue(0.8)
    assert cvars["r_labelOpacity"].value == 0.8
    window.run("label.voxel 1 1 1 40")
    window.run("ui.brushcolor")  # key c on a scan: the label menu, not the colour dialog
    qtbot.waitUntil(row.menu.isVisible)
    texts = [action.text() for action in row.menu.actions()]
    assert texts[:2] == ["label 1", "label 2"] and "label 40  (1 voxels)" in texts and "eraser (label 0)" in texts
    [twelve] = [a for a in row.menu.actions() if a.text() == "label 12"]
    assert twelve.isChecked()
    [five] = [a for a in row.menu.actions() if a.text() == "label 5"]
    five.trigger()
    row.menu.hide()
    assert cvars["brush_label"].value == 5

    def choose() -> None:
        dialog = QApplication.activeModalWidget()
        if not isinstance(dialog, QColorDialog):
            QTimer.singleShot(20, choose)
            return
        dialog.setCurrentColor(QColor(10, 200, 30))
        dialog.accept()

    QTimer.singleShot(0, choose)
    window.run("ui.labelcolor")
    assert tuple(volume(window).voxels.labels.colours[5]) == (10, 200, 30)
    window.refresh()
    assert row.button.text() == "label 5" and "rgb(10,200,30)" in row.button.styleSheet()
    window.run("new 8 8 8")  # an RGBA volume: its colour button again
    window.refresh()
    assert panel.colour.isVisible() and not row.isVisible()
