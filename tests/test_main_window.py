"""The editor window under Xvfb: the viewport draws on demand, and every input becomes a command."""

import numpy as np
import pytest
from PySide6.QtCore import QPoint, Qt

from app.model.workspaces import WORKSPACES
from tests.window_frames import frame_image, wait_until_drawn


def inputs(window):
    return [line.text for line in window.editor.console.log if line.level == "input"]


def centre_pixel_of_world(window, x, y):
    cam, vp = window.editor.workspaces["snowflake"].camera, window.viewport
    units = cam.world_per_pixel(vp.height())
    return QPoint(round(vp.width() / 2 + (x - cam.cx) / units), round(vp.height() / 2 - (y - cam.cy) / units))


def test_viewport_draws_the_default_scene(window):
    image = frame_image(window)
    assert image.shape[0] == window.viewport.height()
    assert (image[..., 1] > 60).sum() > 1000  # the seven flakes' outlines
    assert "ms/frame" in window.status_parts.frame_label.text()


def test_renders_on_demand_only(window, qtbot):
    wait_until_drawn(window, qtbot)
    frames = window.viewport.frames
    qtbot.wait(600)
    assert window.viewport.frames == frames  # idle: no spin loop
    window.run("snow.level 2")
    qtbot.waitUntil(lambda: window.viewport.frames == frames + 1, timeout=3000)
    window.run("snow.list")  # changes nothing drawn
    qtbot.wait(300)
    assert window.viewport.frames == frames + 1


def test_a_bound_key_runs_untrusted(window, qtbot, tmp_path):
    """Binds come from configs others may have written: a key's command writes only in the sandbox."""
    target = tmp_path / "leak.txt"
    assert window.run(f"bind k 'condump {target}'")  # typed: the user may bind what they like...
    qtbot.keyClick(window.viewport, Qt.Key.Key_K)
    assert not target.exists()  # ...but the key runs it as a bind
    assert "a key binding may write only inside the sandbox" in window.editor.console.log[-1].text
    assert window.run(f"condump {target}") and target.exists()  # typed, it may


def test_w_and_s_change_the_level(window, qtbot):
    level = window.editor.workspaces["snowflake"].scene.level
    qtbot.keyClick(window.viewport, Qt.Key.Key_W)
    qtbot.keyClick(window.viewport, Qt.Key.Key_W)
    qtbot.keyClick(window.viewport, Qt.Key.Key_S)
    assert window.editor.workspaces["snowflake"].scene.level == level + 0.25
    assert inputs(window)[-3:] == ["] snow.step 0.25", "] snow.step 0.25", "] snow.step -0.25"]
    assert window.workspace_panels["snowflake"].spin.value() == level + 0.25


def test_click_adds_drag_moves_right_click_removes(window, qtbot):
    vp = window.viewport

    def flakes():  # each edit puts a new frozen scene in place
        return window.editor.workspaces["snowflake"].scene.flakes

    n = len(flakes())
    empty = centre_pixel_of_world(window, -1.1, 0.0)
    qtbot.mouseClick(vp, Qt.MouseButton.LeftButton, pos=empty)
    assert len(flakes()) == n + 1
    added = flakes()[-1]
    cam = window.editor.workspaces["snowflake"].camera
    pixel = cam.world_per_pixel(vp.height())
    assert abs(added.x + 1.1) < 2 * pixel and abs(added.y) < 2 * pixel

    qtbot.mousePress(vp, Qt.MouseButton.LeftButton, pos=empty)
    qtbot.mouseMove(vp, centre_pixel_of_world(window, -1.1, -1.0))
    qtbot.mouseRelease(vp, Qt.MouseButton.LeftButton, pos=centre_pixel_of_world(window, -1.1, -1.0))
    assert len(flakes()) == n + 1 and abs(flakes()[-1].y + 1.0) < 0.02  # (drags run without echo)

    qtbot.mouseClick(vp, Qt.MouseButton.RightButton, pos=centre_pixel_of_world(window, -1.1, -1.0))
    assert len(flakes()) == n
    assert inputs(window)[-1] == f"] snow.remove {n}"


def test_wheel_zooms_about_the_cursor(window, qtbot):
    from PySide6.QtCore import QPointF
    from PySide6.QtGui import QWheelEvent

    vp, cam = window.viewport, window.editor.workspaces["snowflake"].camera
    pos = QPointF(vp.width() * 0.75, vp.height() * 0.25)
    before = cam.to_world(pos.x(), pos.y(), vp.width(), vp.height())
    height = cam.height
    event = QWheelEvent(pos, vp.mapToGlobal(pos), QPoint(), QPoint(0, 120), Qt.MouseButton.NoButton,
                        Qt.KeyboardModifier.NoModifier, Qt.ScrollPhase.NoScrollPhase, False)
    vp.wheelEvent(event)
    assert cam.height < height
    after = cam.to_world(pos.x(), pos.y(), vp.width(), vp.height())
    assert np.allclose(before, after, atol=1e-3)


def test_workspace_switcher(window):
    actions = window.workspace_actions
    assert [a.text() for a in actions.values()] == [w.title for w in WORKSPACES]
    assert actions["snowflake"].isChecked()
    assert all(a.isEnabled() for a in actions.values())


def test_console_widget_runs_commands_with_history(window, qtbot):
    line = window.console_widget.input
    qtbot.keyClicks(line, "snow.level 1.5")
    qtbot.keyClick(line, Qt.Key.Key_Return)
    assert window.editor.workspaces["snowflake"].scene.level == 1.5
    qtbot.keyClicks(line, "snow.level banana")
    qtbot.keyClick(line, Qt.Key.Key_Return)
    assert window.editor.workspaces["snowflake"].scene.level == 1.5
    assert "must be float" in window.console_widget.log.toPlainText()
    qtbot.keyClick(line, Qt.Key.Key_Up)
    qtbot.keyClick(line, Qt.Key.Key_Up)
    assert line.text() == "snow.level 1.5"


def test_backquote_toggles_the_console(window, qtbot):
    dock = window.docks["console"]
    assert dock.isVisible()
    qtbot.keyClick(window.viewport, Qt.Key.Key_QuoteLeft)
    assert not dock.isVisible()
    qtbot.keyClick(window.viewport, Qt.Key.Key_QuoteLeft)
    assert dock.isVisible()


def test_panel_slider_sends_a_command(window):
    window.workspace_panels["snowflake"].slider.setValue(60)  # 3.0 at 20 steps a level
    assert window.editor.workspaces["snowflake"].scene.level == 3.0
    assert inputs(window)[-1] == "] snow.level 3"


@pytest.mark.parametrize("workspace, technique", [("snowflake", "snowflake"), ("volume", "volume")])
def test_bench_dock_shows_the_workspace_technique(window, workspace, technique):
    window.run(f"workspace {workspace}")
    assert window.bench.technique == technique and window.bench.run_button.isEnabled()
