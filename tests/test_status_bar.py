"""The status bar of the editor window: the frame time as one measure, what lies under the cursor (a 2D world
point and the light there, a voxel and its colour), the current tool and render mode."""
import re

import numpy as np
import pytest
from PySide6.QtCore import QEvent, QPoint, QPointF, Qt
from PySide6.QtGui import QMouseEvent
from PySide6.QtWidgets import QApplication

FRAME = re.compile(r"([\d.]+) ms/frame \(([\d.]+) frames/s\), mean of the last (\d+)$")
LIGHT = re.compile(r"^x (-?[\d.]+)  y (-?[\d.]+)   light ([\d.]+) ([\d.]+) ([\d.]+)$")
VOXEL = re.compile(r"^voxel (\d+) (\d+) (\d+)   rgba (\d+) (\d+) (\d+) (\d+)$")


def hover(widget, pos: QPoint) -> None:
    """The mouse moved over the widget, no button held (delivered as it is: QTest's moves go through X)."""
    event = QMouseEvent(QEvent.Type.MouseMove, QPointF(pos), QPointF(widget.mapToGlobal(pos)), Qt.MouseButton.NoButton,
                        Qt.MouseButton.NoButton, Qt.KeyboardModifier.NoModifier)
    QApplication.sendEvent(widget, event)


def status(window) -> tuple[str, str]:
    parts = window.status_parts
    return parts.cursor_label.text(), parts.tool_label.text()


def test_the_frame_time_is_one_measure(window, qtbot):
    """Broken: "113.8 ms/frame · 29 frames/s", the last frame's time beside the mean's rate."""
    for level in (2, 5, 3, 6):  # frames of different cost
        frames = window.viewport.frames
        window.run(f"snow.level {level}")
        qtbot.waitUntil(lambda: window.viewport.frames > frames, timeout=5000)
    times = list(window.viewport.frame_ms)
    assert len(set(times)) > 1
    ms, fps, count = FRAME.search(window.status_parts.frame_label.text()).groups()
    mean = sum(times) / len(times)
    assert abs(float(ms) - mean) <= 0.05 and int(count) == len(times)
    assert abs(float(fps) - 1e3 / mean) <= 0.05  # the same measure, as a rate


def test_the_frame_time_is_the_workspace_in_view_alone(window, qtbot):
    """Broken: 238 ms shown in Snowflake after 3D lights, the mean running on over the switch."""
    frames = window.viewport.frames
    window.run("workspace lights3d")
    qtbot.waitUntil(lambda: window.viewport.frames > frames, timeout=10000)
    frames = window.viewport.frames
    window.run("workspace snowflake")
    qtbot.waitUntil(lambda: window.viewport.frames > frames, timeout=10000)
    shown = window.viewport.frames - frames
    assert len(window.viewport.frame_ms) == shown  # the 3D lights' frames are not in it
    count = FRAME.search(window.status_parts.frame_label.text()).group(3)
    assert int(count) == shown


def open_2d(window, qtbot):
    frames = window.viewport.frames
    for line in ("workspace lighting2d", "lighting.clear", "ambient 0.1 0.1 0.1", "lighting.view 0 0 400",
                 "light.add point 0 0"):
        assert window.run(line)
    qtbot.waitUntil(lambda: window.viewport.tool is window.tools["lighting2d"] and window.viewport.frames > frames)


def world_pixel(window, x, y) -> QPoint:
    cam, vp = window.editor.workspaces["lighting2d"].camera, window.viewport
    unit = cam.world_per_pixel(vp.height())
    return QPoint(round((x - cam.cx) / unit + vp.width() / 2), round(vp.height() / 2 - (y - cam.cy) / unit))


def test_the_2d_world_point_and_the_light_there_under_the_cursor(window, qtbot):
    open_2d(window, qtbot)
    unit = window.editor.workspaces["lighting2d"].camera.world_per_pixel(window.viewport.height())
    seen = {}
    for x, y in ((10.0, 0.0), (60.0, -30.0), (150.0, 150.0)):  # the last beyond the light's reach (its quad)
        hover(window.viewport, world_pixel(window, x, y))
        text, _ = status(window)
        wx, wy, *light = map(float, LIGHT.match(text).groups())
        assert abs(wx - x) <= unit and abs(wy - y) <= unit
        seen[(x, y)] = light
    assert seen[(10.0, 0.0)][0] > seen[(60.0, -30.0)][0] > 0.1  # the light falls off from its centre
    assert seen[(150.0, 150.0)] == [0.1, 0.1, 0.1]  # only the ambient
    leave = QEvent(QEvent.Type.Leave)
    QApplication.sendEvent(window.viewport, leave)
    assert status(window)[0] == ""


def test_the_2d_tool_and_render_mode(window, qtbot):
    open_2d(window, qtbot)
    _, tool = status(window)
    assert tool == "tool: select  ·  render: exact shadows"
    window.run("r_shadowMethod jitter")
    assert status(window)[1] == "tool: select  ·  render: jitter shadows, 16 samples"
    window.viewport.setFocus()
    qtbot.keyClick(window.viewport, Qt.Key.Key_H)
    assert status(window)[1].startswith("tool: draw hull")
    qtbot.keyClick(window.viewport, Qt.Key.Key_Escape)
    assert status(window)[1].startswith("tool: select")


@pytest.fixture
def volume_window(window, qtbot):
    for line in ("workspace volume", "sample cornell_box 32", "mode 4"):
        assert window.run(line)
    qtbot.waitUntil(lambda: window.viewport.tool is window.tools["volume"])
    return window


def test_the_voxel_and_its_colour_under_the_cursor(volume_window):
    window = volume_window
    vp = window.viewport
    hover(vp, QPoint(vp.width() // 2, vp.height() // 2))  # into the open box: its back wall
    x, y, z, *rgba = map(int, VOXEL.match(status(window)[0]).groups())
    voxels = window.editor.workspaces["volume"].volume.voxels
    assert tuple(rgba) == voxels.pick(x, y, z) and rgba[3] > 0
    hover(vp, QPoint(2, 2))  # past the box
    assert status(window)[0] == ""


def test_a_scalar_volume_shows_the_value_under_its_colour(volume_window, tmp_path):
    window = volume_window
    values = np.full((24, 24, 24), 1000, np.int16)
    values[4:20, 4:20, 4:20] = np.arange(16 ** 3, dtype=np.int16).reshape(16, 16, 16) + 2000
    np.save(tmp_path / "v.npy", values)
    assert window.run(f"load {tmp_path / 'v.npy'}") and window.run("vol.window 1500 6000")
    vp = window.viewport
    hover(vp, QPoint(vp.width() // 2, vp.height() // 2))
    match = re.match(r"^voxel (\d+) (\d+) (\d+)   rgba \d+ \d+ \d+ \d+   value (\d+)$", status(window)[0])
    x, y, z, value = map(int, match.groups())
    assert value == values[z, y, x] and value >= 2000


def test_the_volume_tool_and_render_mode(volume_window, qtbot):
    window = volume_window
    assert status(window)[1] == "tool: orbit  ·  render: mode 4: translucent"
    window.run("mode 7")
    assert status(window)[1] == "tool: orbit  ·  render: mode 7: distance-accelerated Phong + shadows"
    window.run("ui.slicepicker")
    assert status(window)[1].startswith("tool: slice picker (z)")
    window.workspace_panels["volume"].picker.reject()
    assert status(window)[1].startswith("tool: orbit")


@pytest.mark.parametrize("workspace, command, tool_words, mode_words", [
    ("snowflake", "snow.level 2.5", "add, move", "geometry shader, level 2.5"),
    ("lights3d", "r_shadowPCF 5", "select, move", "shadows: onepass (maps 1024 px, PCF 5)")])
def test_every_workspace_names_its_tool_and_render_mode(window, qtbot, workspace, command, tool_words, mode_words):
    window.run(f"workspace {workspace}")
    qtbot.waitUntil(lambda: window.viewport.tool is window.tools[workspace])
    assert window.run(command)
    tool, mode = status(window)[1].split("  ·  ")
    assert tool.startswith("tool: " + tool_words) and mode.startswith("render: ") and mode_words in mode


def test_the_clouds_tool_names_its_settings(window):
    """Without showing the clouds (their noise textures take long to make the first time)."""
    window.run("r_cloudSteps 96")
    clouds = window.tools["clouds"]
    assert clouds.tool_name().startswith("look around")
    assert clouds.render_mode() == "energy integration, 96 steps, 1/2 buffer"
