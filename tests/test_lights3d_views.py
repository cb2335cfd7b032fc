"""The 3D lights editor with a real window (pytest-qt on Xvfb): the panel's list and properties, the gizmo drag,
clicking, orbiting and zooming in the viewport, each landing as console commands. One window serves the module
(opening one takes seconds): each test starts from it reset to how it opened."""
import itertools

import numpy as np
import pytest
from PySide6.QtCore import QEvent, QPoint, QPointF, Qt
from PySide6.QtGui import QMouseEvent, QWheelEvent
from PySide6.QtWidgets import QApplication, QPushButton

from app.console.text import number
from app.model.lights3d.scene import Lights3DCamera
from app.model.lights3d.gizmo import gizmo_axes, pick_light, pick_object, project


def reset(window) -> None:
    """The workspace as a fresh window shows it, by commands: every edit undone (the scene and the selection it
    opened with), then the default scene, nothing selected and the default camera, should an undo not reach."""
    window.run("workspace lights3d")
    while state(window).history.undo_name() is not None:
        assert window.run("undo")
    camera = Lights3DCamera()
    assert window.run(f"lights3d.reset; lights3d.select none; view.orbit {camera.yaw} {camera.pitch} "
                      f"{camera.distance}")


@pytest.fixture(scope="module")
def fresh_digest(module_window):
    """What every model, camera and cvar of the module's window digests to before its first test."""
    reset(module_window)
    return module_window.editor.digest()


@pytest.fixture
def lights3d(module_window, fresh_digest, qtbot):
    """The module's window (one for all its tests) on the 3D lights workspace as it opened, and the list of the
    commands it runs from here on."""
    window = module_window
    reset(window)
    assert window.editor.digest() == fresh_digest  # else an earlier test left something reset() misses
    qtbot.waitUntil(lambda: window.viewport.tool is window.tools["lights3d"])
    commands: list[str] = []
    listen = commands.append
    window.editor.console.executed_listeners.append(listen)
    yield window, commands
    window.editor.console.executed_listeners.remove(listen)


def state(window):
    return window.editor.workspaces["lights3d"]


def panel(window):
    return window.workspace_panels["lights3d"].widget()  # inside its scroll area


def size(window):
    return window.viewport.width(), window.viewport.height()


def mouse(window, kind: QEvent.Type, xy, button=Qt.MouseButton.LeftButton) -> None:
    """A mouse event delivered as it is (QTest's moves go through the X cursor)."""
    vp = window.viewport
    local = QPointF(*xy)
    held = Qt.MouseButton.NoButton if kind == QEvent.Type.MouseButtonRelease else button
    event = QMouseEvent(kind, local, QPointF(vp.mapToGlobal(local)), button if kind != QEvent.Type.MouseMove
                        else Qt.MouseButton.NoButton, held, Qt.KeyboardModifier.NoModifier)
    QApplication.sendEvent(vp, event)


def drag(window, start, end, steps: int = 6, button=Qt.MouseButton.LeftButton) -> None:
    start, end = np.asarray(start, float), np.asarray(end, float)
    mouse(window, QEvent.Type.MouseButtonPress, start, button)
    for k in range(1, steps + 1):
        mouse(window, QEvent.Type.MouseMove, start + (end - start) * k / steps, button)
    mouse(window, QEvent.Type.MouseButtonRelease, end, button)


def click(window, xy) -> None:
    mouse(window, QEvent.Type.MouseButtonPress, xy)
    mouse(window, QEvent.Type.MouseButtonRelease, xy)


def test_the_list_selects_and_the_panel_shows_the_selection(lights3d):
    window, commands = lights3d
    p = panel(window)
    assert not p.light_box.isVisible() and not p.object_box.isVisible()
    p.list.setCurrentRow(len(state(window).scene.objects) + 1)  # the rows: objects, then lights
    assert commands == ["lights3d.select light 1"]
    assert state(window).selection == ("light", 1)
    light = state(window).scene.lights[1]
    assert p.light_box.isVisible() and p.light_box.title() == "Light 1"
    assert p.l_kind.currentText() == "spot" and p.l_angle.value() == light.angle
    assert [box.value() for box in p.l_position.boxes] == list(light.position)

    p.list.setCurrentRow(1)
    assert commands[-1] == "lights3d.select object 1"
    assert p.object_box.isVisible() and not p.light_box.isVisible()
    assert [box.value() for box in p.o_position.boxes] == list(state(window).scene.objects[1].position)


def test_the_shadow_combo_sets_the_selected_lights_method(lights3d):
    window, commands = lights3d
    window.run("lights3d.select light 0")
    commands.clear()
    panel(window).l_shadow.setCurrentText("zfail")
    assert commands == ["light3d.set 0 shadow zfail"]
    assert state(window).scene.lights[0].shadow == "zfail"


def test_the_cascades_combo_sets_the_cvar_and_follows_it(lights3d):
    window, commands = lights3d
    p = panel(window)
    commands.clear()
    try:
        p.cascades.setCurrentText("4")
        assert commands == ["r_shadowCascades 4"]
        assert window.editor.render_settings().cascades == 4
        window.run("r_shadowCascades 2")
        p.sync()
        assert p.cascades.currentText() == "2"
    finally:
        window.run("r_shadowCascades 3")  # the default: the next test's window digests as the first's


def test_the_direction_row_aims_a_spot_and_is_off_for_a_point_light(lights3d):
    window, commands = lights3d
    p = panel(window)
    window.run("lights3d.select light 0")  # the point light: no direction
    assert not p.l_direction.widget.isEnabled()
    window.run("lights3d.select light 1")
    assert p.l_direction.widget.isEnabled()
    assert [box.value() for box in p.l_direction.boxes] == pytest.approx(state(window).scene.lights[1].direction)
    commands.clear()
    p.l_direction.boxes[1].setValue(0.0)  # from (-0.8, -0.6, 0) to (-0.8, 0, 0): level, normalised to (-1, 0, 0)
    assert commands == ["light3d.set 1 direction -0.8 0.0 0.0"]
    assert state(window).scene.lights[1].direction == pytest.approx((-1.0, 0.0, 0.0))
    assert [box.value() for box in p.l_direction.boxes] == pytest.approx((-1.0, 0.0, 0.0))


def test_a_gizmo_drag_moves_along_one_axis_in_one_undo_step(lights3d):
    window, commands = lights3d
    window.run("lights3d.select object 1")
    before = state(window).scene.objects[1].position
    digest = window.editor.digest()
    (a, b) = gizmo_axes(state(window).camera, size(window), before)[0]  # the x handle's screen segment
    start = a + 0.7 * (b - a)
    drag(window, start, start + 1.5 * (b - a))
    moves = [c for c in commands if c.startswith("object.move 1 ")]
    assert len(moves) >= 2 and not any(c.startswith("view.orbit") for c in commands)
    assert all(word == number(float(word)) for c in moves for word in c.split()[2:])  # no 17-digit repr noise
    after = state(window).scene.objects[1].position
    assert after[0] > before[0] + 5 and after[1:] == before[1:]
    assert state(window).selection == ("object", 1)
    window.run("undo")
    assert window.editor.digest() == digest


def test_a_click_on_empty_space_deselects_and_on_a_light_selects_it(lights3d):
    window, commands = lights3d
    s = state(window)
    window.run("lights3d.select object 2")
    corner = (5, 5)  # over the ground's far edge: nothing there
    assert pick_light(s.scene, s.camera, size(window), *corner) is None
    assert pick_object(s.scene, s.camera, size(window), *corner) is None
    click(window, corner)
    assert commands[-1] == "lights3d.select none" and s.selection is None
    assert not panel(window).object_box.isVisible()

    (a, _), *_ = gizmo_axes(s.camera, size(window), s.scene.lights[0].position)  # the light's own pixel
    click(window, a)
    assert commands[-1] == "lights3d.select light 0" and s.selection == ("light", 0)


def test_a_drag_on_empty_space_orbits(lights3d):
    window, commands = lights3d
    yaw = state(window).camera.yaw
    drag(window, (5, 5), (45, 5))
    assert commands and all(c.startswith("view.orbit") for c in commands)
    assert state(window).camera.yaw == pytest.approx((yaw - 40 * 0.4) % 360, abs=1e-3)
    assert state(window).selection is None


def test_the_wheel_zooms(lights3d):
    window, commands = lights3d
    distance = state(window).camera.distance
    vp = window.viewport
    centre = QPointF(vp.width() / 2, vp.height() / 2)
    event = QWheelEvent(centre, QPointF(vp.mapToGlobal(centre)), QPoint(), QPoint(0, 120), Qt.MouseButton.NoButton,
                        Qt.KeyboardModifier.NoModifier, Qt.ScrollPhase.NoScrollPhase, False)
    QApplication.sendEvent(vp, event)
    assert state(window).camera.distance == pytest.approx(distance / 1.15, abs=1e-3)
    assert commands[-1].startswith("view.orbit")


def test_delete_removes_the_selection(lights3d, qtbot):
    window, commands = lights3d
    window.run("lights3d.select light 1")
    qtbot.keyClick(window.viewport, Qt.Key.Key_Delete)
    assert commands[-1] == "light3d.remove 1"
    assert len(state(window).scene.lights) == 1 and state(window).selection is None


def test_sync_sends_no_commands(lights3d):
    window, commands = lights3d
    log = len(window.editor.console.log)
    for selection in ("object 4", "light 1", "none", "object 0"):
        window.editor.console.execute(f"lights3d.select {selection}", echo=False)
        panel(window).sync()
    assert commands == [f"lights3d.select {s}" for s in ("object 4", "light 1", "none", "object 0")]
    assert len(window.editor.console.log) == log


def test_add_menus_add_and_select_and_sizes_follow_the_kind(lights3d):
    window, commands = lights3d
    p = panel(window)
    add_light = next(b for b in p.findChildren(QPushButton) if b.text() == "+ Light").menu()
    next(a for a in add_light.actions() if a.text() == "point").trigger()
    assert commands == ["light3d.add point", "lights3d.select light 2"]
    assert p.light_box.title() == "Light 2"

    window.run("lights3d.select object 4")  # an L-prism: four numbers
    p.o_size[3].setValue(10)
    assert commands[-1] == "object.set 4 size 40.0 40.0 16.0 10.0"
    window.run("lights3d.select object 0")  # the ground plane: one
    form = p.object_box.layout()
    assert [form.isRowVisible(box) for box in p.o_size] == [True, False, False, False]
    assert form.labelForField(p.o_size[0]).text() == "size"


def test_add_object_places_it_in_view_clear_of_the_others_and_selects_it(lights3d):
    window, commands = lights3d
    add_object = next(b for b in panel(window).findChildren(QPushButton) if b.text() == "+ Object").menu()
    next(a for a in add_object.actions() if a.text() == "box").trigger()
    objects = state(window).scene.objects
    box = objects[5]
    assert commands == [f"object.add box {' '.join(map(number, box.position))}", "lights3d.select object 5"]
    assert panel(window).object_box.title() == "Object 5 · box"
    (lo, hi) = box.bounds
    assert lo[1] == 0.0 and not any((lo < other_hi).all() and (other_lo < hi).all()
                                    for other_lo, other_hi in (o.bounds for o in objects[:5]))
    pixels, depth = project(state(window).camera, size(window), list(itertools.product(*zip(lo, hi))))
    assert (depth > 0).all() and (pixels >= 0).all() and (pixels <= size(window)).all()
