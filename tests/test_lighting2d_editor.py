"""The 2D lighting editor with a real window (pytest-qt on Xvfb): selecting and dragging lights, handles,
drawing hulls by clicking, vertex edits and the property panel, each landing as console commands."""
import math

import numpy as np
from PySide6.QtCore import QEvent, QPoint, QPointF, Qt
from PySide6.QtGui import QImage, QMouseEvent
from PySide6.QtWidgets import QApplication

from app.bench.lighting2d import OFFVIEW_HULLS, offview_scene
from app.model.lighting2d.scene import Hull
from app.model.lighting2d.index import SceneIndex


def panel(window):
    """The 2D panel (inside its scroll area)."""
    return window.workspace_panels["lighting2d"].widget()


def pixel(window, x, y) -> QPoint:
    cam, vp = window.editor.workspaces["lighting2d"].camera, window.viewport
    unit = cam.world_per_pixel(vp.height())
    return QPoint(round((x - cam.cx) / unit + vp.width() / 2), round(vp.height() / 2 - (y - cam.cy) / unit))


def move_to(widget, pos: QPoint) -> None:
    """A move with the left button held, delivered as it is (QTest's moves go through the X cursor)."""
    local = QPointF(pos)
    event = QMouseEvent(QEvent.Type.MouseMove, local, QPointF(widget.mapToGlobal(pos)), Qt.MouseButton.NoButton,
                        Qt.MouseButton.LeftButton, Qt.KeyboardModifier.NoModifier)
    QApplication.sendEvent(widget, event)


def drag(qtbot, widget, start: QPoint, end: QPoint, steps: int = 5) -> None:
    qtbot.mousePress(widget, Qt.MouseButton.LeftButton, pos=start)
    for k in range(1, steps + 1):
        move_to(widget, start + (end - start) * k / steps)
    qtbot.mouseRelease(widget, Qt.MouseButton.LeftButton, pos=end)


def open_2d(window, qtbot):
    window.run("workspace lighting2d")
    window.run("lighting.clear")
    window.run("lighting.view 0 0 400")
    qtbot.waitUntil(lambda: window.viewport.tool is window.tools["lighting2d"])


def test_a_light_is_selected_and_dragged_in_one_undo_step(window, qtbot):
    open_2d(window, qtbot)
    window.run("light.add point 0 0")
    before = window.editor.digest()
    vp = window.viewport
    drag(qtbot, vp, pixel(window, 0, 0), pixel(window, 60, -40))
    assert window.editor.workspaces["lighting2d"].selection == ("light", 0)
    x, y = window.editor.workspaces["lighting2d"].scene.lights[0].position
    assert math.dist((x, y), (60, -40)) < 3
    assert panel(window).light_box.isVisible() and abs(panel(window).l_place.x.value() - x) < 0.01
    window.run("undo")
    assert window.editor.digest() == before


def test_the_rotate_handle_turns_the_selection(window, qtbot):
    open_2d(window, qtbot)
    window.run("hull.add -20 -20 20 -20 20 20 -20 20")
    vp = window.viewport
    qtbot.mouseClick(vp, Qt.MouseButton.LeftButton, pos=pixel(window, 0, 0))
    assert window.editor.workspaces["lighting2d"].selection == ("hull", 0)
    unit = window.editor.workspaces["lighting2d"].camera.world_per_pixel(vp.height())
    handle = (40 * unit, 0.0)  # the round handle sits 40 px along the hull's rotation
    drag(qtbot, vp, pixel(window, *handle), pixel(window, 0, 40 * unit))
    assert abs(window.editor.workspaces["lighting2d"].scene.hulls[0].rotation - math.pi / 2) < 0.1


def test_a_hull_is_drawn_by_clicking_points(window, qtbot):
    open_2d(window, qtbot)
    vp = window.viewport
    vp.setFocus()
    qtbot.keyClick(vp, Qt.Key.Key_H)
    for x, y in ((-50, -50), (50, -50), (0, 60)):
        qtbot.mouseClick(vp, Qt.MouseButton.LeftButton, pos=pixel(window, x, y))
    qtbot.keyClick(vp, Qt.Key.Key_Return)
    hulls = window.editor.workspaces["lighting2d"].scene.hulls
    assert len(hulls) == 1 and hulls[0].valid and len(hulls[0].points) == 3
    assert window.editor.workspaces["lighting2d"].selection == ("hull", 0)


def hover(widget, pos: QPoint) -> None:
    event = QMouseEvent(QEvent.Type.MouseMove, QPointF(pos), QPointF(widget.mapToGlobal(pos)), Qt.MouseButton.NoButton,
                        Qt.MouseButton.NoButton, Qt.KeyboardModifier.NoModifier)
    QApplication.sendEvent(widget, event)


def overlay(window):
    return window.viewport.renderer.renderers["lighting2d"].overlay


def test_a_hull_being_drawn_shows_its_rubber_band_to_the_cursor(window, qtbot):
    """Broken: the points clicked showed, but nothing joined the last one to the cursor."""
    open_2d(window, qtbot)
    vp = window.viewport
    vp.setFocus()
    qtbot.keyClick(vp, Qt.Key.Key_H)
    for x, y in ((-50, -50), (50, -50)):
        qtbot.mouseClick(vp, Qt.MouseButton.LeftButton, pos=pixel(window, x, y))
    frames = vp.frames
    hover(vp, pixel(window, 0, 60))
    qtbot.waitUntil(lambda: vp.frames > frames)
    vp.makeCurrent()  # a buffer is read in its own context: Qt leaves another current at times
    try:
        segments = overlay(window)._selection_layer.lines.uploaded()
    finally:
        vp.doneCurrent()
    state = window.editor.workspaces["lighting2d"]
    first, last, cursor = (np.array(p) for p in (state.pending[0], state.pending[-1], state.pending_cursor))
    assert np.linalg.norm(cursor - (0, 60)) < 3

    def drawn(a, b) -> bool:
        return bool((np.abs(segments - np.array([a, b], "f4")).max(axis=(1, 2)) < 1e-3).any())

    assert drawn(last, cursor) and drawn(cursor, first)  # the band, and where the hull would close
    qtbot.keyClick(vp, Qt.Key.Key_Escape)
    assert window.editor.workspaces["lighting2d"].pending_cursor is None


def test_every_hull_shows_its_outline_without_the_wireframe(window, qtbot):
    """Broken: sample g's hulls were invisible unless r_debug2d drew the wireframe."""
    open_2d(window, qtbot)
    window.run("hull.add -20 -20 20 -20 20 20 -20 20")
    frames = window.viewport.frames
    qtbot.waitUntil(lambda: window.viewport.frames > frames)
    layer = overlay(window)._scene_layer
    outline = [count for colour, _first, count in layer.spans if colour[:3] == (0.85, 0.85, 0.9)]
    assert outline == [4]


def test_vertices_are_dragged_inserted_and_deleted(window, qtbot):
    open_2d(window, qtbot)
    window.run("hull.add -40 -40 40 -40 40 40 -40 40")
    vp = window.viewport
    qtbot.mouseClick(vp, Qt.MouseButton.LeftButton, pos=pixel(window, 0, 0))
    drag(qtbot, vp, pixel(window, 40, 40), pixel(window, 70, 60))
    state = window.editor.workspaces["lighting2d"]
    assert math.dist(tuple(state.scene.hulls[0].points[2]), (70, 60)) < 3
    qtbot.mouseDClick(vp, Qt.MouseButton.LeftButton, pos=pixel(window, 0, -40))  # on the bottom edge
    assert len(state.scene.hulls[0].points) == 5
    qtbot.mouseClick(vp, Qt.MouseButton.RightButton, pos=pixel(window, 70, 60))
    assert len(state.scene.hulls[0].points) == 4


def test_an_invalid_hull_shows_its_reason_in_the_panel(window, qtbot):
    open_2d(window, qtbot)
    window.run("hull.add -40 -40 40 40 40 -40 -40 40")  # a bow tie
    window.editor.workspaces["lighting2d"].selection = ("hull", 0)
    panel(window).sync()
    assert "cross" in panel(window).h_state.text()


def test_panel_edits_are_commands(window, qtbot):
    open_2d(window, qtbot)
    window.run("light.add point 0 0")
    window.editor.workspaces["lighting2d"].selection = ("light", 0)
    panel(window).sync()
    panel(window).l_radius.setValue(33)
    assert window.editor.workspaces["lighting2d"].scene.lights[0].radius == 33
    panel(window).method.setCurrentText("penumbra")
    assert window.editor.console.registry.cvars["r_shadowMethod"].value == "penumbra"
    window.run("undo")
    assert window.editor.workspaces["lighting2d"].scene.lights[0].radius == 20


def frame_pixels(window):
    image = window.viewport.grabFramebuffer().convertToFormat(QImage.Format.Format_RGBA8888)
    h, w = image.height(), image.width()
    return np.frombuffer(image.constBits(), np.uint8).reshape(h, image.bytesPerLine())[:, : 4 * w].reshape(h, w, 4)


def test_a_light_shows_an_icon_at_its_centre_that_a_click_selects(window, qtbot):
    """Broken: a light far smaller than a pixel or two could only be found with the wireframe."""
    open_2d(window, qtbot)
    window.run("lighting.view 0 0 4000")  # the light's disc (20 units) is 3 pixels across
    window.run("light.add point 0 0")
    qtbot.waitUntil(lambda: window.viewport.settled())
    centre = pixel(window, 0, 0)
    image = frame_pixels(window)
    on_ray = image[centre.y() - 1:centre.y() + 2, centre.x() + 8].astype(int)  # the right ray: 6.5 .. 10 px out
    # the icon's orange, not the white light: its 1-pixel ray on one row, or half on two (the view's height even)
    assert sum(max(r - b, 0) for r, _g, b, _a in on_ray) > 150, on_ray
    qtbot.mouseClick(window.viewport, Qt.MouseButton.LeftButton, pos=centre + QPoint(9, 0))  # at its rays' tips
    assert window.editor.workspaces["lighting2d"].selection == ("light", 0)


def test_a_drawn_hull_turns_and_scales_about_its_centroid(window, qtbot):
    """Broken: a drawn hull's origin stayed at the world's (0, 0), its handles far from it."""
    open_2d(window, qtbot)
    window.run("lighting.view 100 50 400")
    vp = window.viewport
    vp.setFocus()
    qtbot.keyClick(vp, Qt.Key.Key_H)
    for x, y in ((60, 20), (140, 20), (140, 60), (60, 60)):
        qtbot.mouseClick(vp, Qt.MouseButton.LeftButton, pos=pixel(window, x, y))
    qtbot.keyClick(vp, Qt.Key.Key_Return)
    state = window.editor.workspaces["lighting2d"]
    hull = state.scene.hulls[0]
    unit = state.camera.world_per_pixel(vp.height())
    assert math.dist(hull.position, (100, 40)) < unit and hull.origin == hull.position
    assert np.allclose(hull.world(), hull.points)  # the outline where it was drawn
    assert any(line.text.startswith("] hull.draw ") for line in window.editor.console.log if line.level == "input")
    handle = (hull.position[0] + 40 * unit, hull.position[1])  # the round handle, 40 px from the centre
    drag(qtbot, vp, pixel(window, *handle), pixel(window, hull.position[0], hull.position[1] + 40 * unit))
    turned = state.scene.hulls[0]
    assert abs(turned.rotation - math.pi / 2) < 0.1
    assert np.allclose(turned.world().mean(axis=0), turned.points.mean(axis=0), atol=unit)  # it turned in place


def test_a_click_tests_only_the_hulls_under_it(window, qtbot, monkeypatch):
    """A click used to test every hull of the scene (about a second with 10,000); the index answers which."""
    open_2d(window, qtbot)
    state = window.editor.workspaces["lighting2d"]
    state.scene = offview_scene(OFFVIEW_HULLS)  # scene j and 10,000 hulls far outside the view
    tested = []
    contains = Hull.contains
    monkeypatch.setattr(Hull, "contains", lambda hull, x, y: tested.append(hull) or contains(hull, x, y))
    target = state.scene.hulls[0]
    x, y = target.world()[0] + (20, 20)  # scene j's first hull is an L: just inside its corner
    assert target.contains(x, y)
    tested.clear()
    window.run(f"lighting.view {x} {y} 400")
    qtbot.mouseClick(window.viewport, Qt.MouseButton.LeftButton, pos=pixel(window, x, y))
    assert state.selection == ("hull", 0)
    assert 1 <= len(tested) <= 3  # scene j has three hulls, none of the far ones was looked at


def test_after_an_edit_one_index_build_serves_the_frame_and_a_click(window, qtbot, monkeypatch):
    """Broken: the tool built its own index of the scene after each edit (32 ms with 10,000 hulls) beside the
    renderer's for the same version; now both ask the workspace's."""
    open_2d(window, qtbot)
    state = window.editor.workspaces["lighting2d"]
    window.run("hull.add -20 -20 20 -20 20 20 -20 20")
    built = []
    init = SceneIndex.__init__
    monkeypatch.setattr(SceneIndex, "__init__", lambda index, scene: built.append(scene) or init(index, scene))
    vp = window.viewport
    frames = vp.frames
    window.run("hull.move 0 60 10")
    qtbot.waitUntil(lambda: vp.frames > frames)
    assert len(built) == 1 and built[0] is state.scene  # the frame's
    qtbot.mouseClick(vp, Qt.MouseButton.LeftButton, pos=pixel(window, 65, 15))
    assert state.selection == ("hull", 0)
    qtbot.waitUntil(lambda: vp.settled())
    assert len(built) == 1 and built[0] is state.scene  # the click asked the same index
