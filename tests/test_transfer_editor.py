"""The transfer-function dock in a real window under Xvfb: the mouse on its plot becomes the transfer commands (a
point dragged: previews, then one vol.opacity and one undo step; a double click adds a point, a right click removes
one; a window handle let go: one vol.window), a preset sets the window and the curve, and the dock follows the
console and shows only in the volume workspace."""
import numpy as np
import pytest
from PySide6.QtCore import QPoint, QPointF, Qt
from PySide6.QtTest import QTest

from app.model.volume.phantom import ct_phantom
from app.model.volume.transfer_presets import PRESETS


@pytest.fixture
def editor(window, tmp_path, qtbot):
    np.save(tmp_path / "ct.npy", ct_phantom(24))
    assert window.run("workspace volume")
    assert window.run(f"load {tmp_path / 'ct.npy'}")
    window.refresh()
    dock = window.docks["transfer"]
    assert dock.isVisible()
    settle(qtbot, dock.widget())
    return dock.widget()


def settle(qtbot, editor) -> None:
    """The dock laid out (it shows with the workspace): the plot's place stays put between two looks."""
    places = []

    def still() -> bool:
        places.append(editor.view.sceneBoundingRect())
        qtbot.wait(50)
        return len(places) > 1 and places[-1] == places[-2]
    qtbot.waitUntil(still)


def transfer(window):
    return window.editor.workspaces["volume"].volume.voxels.scalars.transfer


@pytest.fixture
def sent(window) -> dict[str, list[str]]:
    """The commands run from here on: every one ("executed", a drag's quiet previews too) and those a demo records
    ("recorded")."""
    lines = {"executed": [], "recorded": []}
    window.editor.console.executed_listeners.append(lines["executed"].append)
    window.editor.console.record_listeners.append(lines["recorded"].append)
    return lines


def history(window):
    return window.editor.workspaces["volume"].volume.history


def pixel(editor, value: float, alpha: float) -> QPoint:
    """Where (value, opacity) is on the plot's viewport."""
    scene = editor.view.mapViewToScene(QPointF(value, alpha))
    return editor.plot.mapFromScene(scene)


def drag(qtbot, editor, start: QPoint, end: QPoint, steps: int = 5) -> None:
    port = editor.plot.viewport()
    QTest.mouseMove(port, start)  # hovering first: pyqtgraph gives the drag to the item the hover found
    qtbot.wait(20)
    QTest.mousePress(port, Qt.MouseButton.LeftButton, Qt.KeyboardModifier.NoModifier, start)
    for i in range(1, steps + 1):
        QTest.mouseMove(port, start + (end - start) * i / steps)
        qtbot.wait(10)
    QTest.mouseRelease(port, Qt.MouseButton.LeftButton, Qt.KeyboardModifier.NoModifier, end)
    qtbot.wait(20)


def test_dragging_a_point_previews_then_sends_one_command_and_one_undo_step(window, editor, sent, qtbot):
    assert window.run("vol.opacity -500 0 200 0.2 700 0.8")
    window.refresh()
    before, steps = transfer(window), history(window).undo_depth
    del sent["executed"][:], sent["recorded"][:]
    drag(qtbot, editor, pixel(editor, 200, 0.2), pixel(editor, 400, 0.6))
    assert len(sent["recorded"]) == 1 and sent["recorded"][0].startswith("vol.opacity -500 0 ")
    *previews, last = sent["executed"]
    assert last == sent["recorded"][0] and previews  # it showed in the 3D view while dragged
    assert all(p.startswith("vol.opacity.preview -500 0 ") for p in previews)
    (v0, a0), (v1, a1), (v2, a2) = transfer(window).points
    assert (v0, a0, v2, a2) == (-500, 0, 700, 0.8)  # the others stay
    assert abs(v1 - 400) < 40 and abs(a1 - 0.6) < 0.05 and v1 == round(v1)  # whole numbers for a CT
    assert history(window).undo_depth == steps + 1 and history(window).undo_name() == "Set Opacity"
    assert window.run("undo")
    assert transfer(window) == before
    assert window.run("redo")
    assert transfer(window).points[1] == (v1, a1)
    window.refresh()
    assert [tuple(p) for p in editor.points.data[["x", "y"]].tolist()] == list(transfer(window).points)


def test_a_point_stays_between_its_neighbours(window, editor, qtbot):
    assert window.run("vol.opacity -500 0 200 0.2 700 0.8")
    window.refresh()
    drag(qtbot, editor, pixel(editor, 200, 0.2), pixel(editor, 900, 1.3))  # past the next point, above 1
    (_, _), (v1, a1), (v2, _) = transfer(window).points
    assert v1 == v2 - 1 and a1 == 1.0


def test_double_click_adds_a_point_and_right_click_removes_one(window, editor, sent, qtbot):
    assert window.run("vol.opacity -500 0 700 0.8")
    window.refresh()
    del sent["executed"][:], sent["recorded"][:]
    port = editor.plot.viewport()
    where = pixel(editor, 100, 0.5)
    QTest.mouseMove(port, where)
    QTest.mouseDClick(port, Qt.MouseButton.LeftButton, Qt.KeyboardModifier.NoModifier, where)
    qtbot.waitUntil(lambda: len(transfer(window).points) == 3)
    v, a = transfer(window).points[1]
    assert abs(v - 100) < 40 and abs(a - 0.5) < 0.05
    assert sent["recorded"] == [sent["executed"][-1]] and sent["recorded"][0].startswith("vol.opacity -500 0 ")
    window.refresh()
    steps = history(window).undo_depth
    on = pixel(editor, v, a)
    QTest.mouseMove(port, on)
    qtbot.wait(20)
    QTest.mouseClick(port, Qt.MouseButton.RightButton, Qt.KeyboardModifier.NoModifier, on)
    qtbot.waitUntil(lambda: len(transfer(window).points) == 2)
    assert transfer(window).points == ((-500, 0), (700, 0.8))
    assert sent["recorded"][-1] == "vol.opacity -500 0 700 0.8" and history(window).undo_depth == steps + 1


def test_a_window_handle_let_go_sends_one_vol_window(window, editor, sent, qtbot):
    start = transfer(window)
    drag(qtbot, editor, pixel(editor, start.low, 0.5), pixel(editor, start.low + 300, 0.5))
    assert len(sent["executed"]) == 1 and sent["executed"][0].startswith("vol.window ")
    low, high = transfer(window).low, transfer(window).high
    assert abs(low - (start.low + 300)) < 40 and high == start.high
    assert transfer(window).points is None  # the ramp follows the window


def test_a_preset_sets_the_window_colours_and_curve_in_one_step(window, editor, sent, qtbot):
    steps = history(window).undo_depth
    editor.preset.setCurrentIndex(editor.preset.findData("ct_bone"))
    editor.preset.textActivated.emit(editor.preset.currentText())  # what picking it from the open list sends
    chosen = PRESETS["ct_bone"]
    assert (transfer(window).low, transfer(window).high) == chosen.window
    assert transfer(window).points == chosen.points and transfer(window).colormap == "ct_bone"
    assert sent["recorded"] == ["vol.preset ct_bone"] and history(window).undo_depth == steps + 1
    window.refresh()
    assert editor.region.getRegion() == chosen.window and editor.colormap.currentText() == "ct_bone"
    assert editor.preset.currentIndex() == 0  # a prompt again: the curve may be edited from here
    (left, right), _ = editor.view.viewRange()
    assert left <= chosen.window[0] and right >= chosen.window[1]  # both handles can be reached


def test_the_dock_follows_the_console_and_the_workspace(window, editor, qtbot):
    assert window.run("vol.colormap magma; vol.opacity.reset")
    window.refresh()
    assert editor.colormap.currentText() == "magma"
    assert len(editor.points.data) == 2  # the ramp's ends
    counts = editor.histogram.yData
    assert counts.max() == 1.0 and (counts > 0).sum() > 4  # log counts, scaled to the plot
    assert window.run("workspace lighting2d")
    assert window.docks["transfer"].isHidden()
    assert window.run("workspace volume")
    assert not window.docks["transfer"].isHidden()
    window.docks["transfer"].close()  # closed by the user: it stays closed in its workspace
    assert window.run("workspace lighting2d; workspace volume")
    assert window.docks["transfer"].isHidden()
    assert window.run("sample coords3d 8")
    window.refresh()
    assert not editor.isEnabled()
