"""Frame All (`view.frame`, key F, View > Frame All): every workspace's view shows its whole scene; a loaded file
is framed where its files keep no view; the camera commands are recorded, so a demo replays the same view."""
from __future__ import annotations

import numpy as np
import pytest

from app.console.demo import VirtualClock
from app.editor import Editor
from app.model.camera2d import Camera2D


@pytest.fixture
def editor(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    return Editor(clock=VirtualClock())


def visible_2d(cam: Camera2D, aspect: float, lo, hi) -> bool:
    half_h, half_w = cam.height / 2, cam.height * aspect / 2
    return (cam.cx - half_w <= lo[0] and hi[0] <= cam.cx + half_w and cam.cy - half_h <= lo[1]
            and hi[1] <= cam.cy + half_h)


@pytest.mark.parametrize("aspect", [0.5, 1.0, 2.5])
def test_the_2d_scenes_are_framed_whole_for_any_aspect(editor, aspect):
    assert editor.execute("workspace lighting2d") and editor.execute("lighting.view 5000 5000 10")
    assert editor.execute(f"view.frame {aspect}")
    state = editor.current
    points = np.concatenate([h.world() for h in state.scene.hulls] + [np.array([light.position]) for light in
                                                                       state.scene.lights])
    assert visible_2d(state.camera, aspect, points.min(0), points.max(0))
    assert editor.execute("workspace snowflake") and editor.execute("snow.add 40 -30 2")
    assert editor.execute(f"view.frame {aspect}")
    cam = editor.current.camera
    assert visible_2d(cam, aspect, (-1.0, -1.0), (42.0, -28.0))
    assert cam.height < 1.2 * max(74.0, 43.0 / aspect)  # framed, not just zoomed far out


def test_the_3d_views_frame_their_scene(editor):
    assert editor.execute("workspace volume") and editor.execute("orbit 30 20 60")
    assert editor.execute("view.frame")
    assert editor.current.view.camera.distance < 7  # the [-1, 1] box fills most of the view again
    assert editor.execute("workspace lights3d") and editor.execute("view.orbit 10 20 1900")
    assert editor.execute("view.target 500 0 500")
    assert editor.execute("view.frame")
    cam = editor.current.camera
    assert cam.distance < 1000 and np.linalg.norm(np.array(cam.target) - (0, 10, 0)) < 100
    assert editor.execute("workspace clouds") and editor.execute("camera.look 170 -40")
    assert editor.execute("view.frame")
    assert (editor.current.view.yaw, editor.current.view.pitch) == (0.0, 12.0)


def test_an_empty_scene_says_so_and_bad_aspects_are_refused(editor):
    assert editor.execute("workspace snowflake") and editor.execute("snow.clear")
    camera = editor.current.camera.key()
    assert editor.execute("view.frame")
    assert "nothing to frame" in editor.console.log[-1].text and editor.current.camera.key() == camera
    for bad in ("0", "-1", "nan", "1e9"):
        assert not editor.execute(f"view.frame {bad}")


def test_the_framing_is_recorded_as_camera_commands_and_replays_the_same(editor, tmp_path):
    assert editor.execute("workspace lights3d") and editor.execute("record framed")
    assert editor.execute("view.orbit 80 10 1500") and editor.execute("view.frame 1.7")
    assert editor.execute("stop")
    demo = (tmp_path / "framed.demo").read_text() if (tmp_path / "framed.demo").exists() else ""
    if not demo:
        demo = next(tmp_path.rglob("framed.demo")).read_text()
    assert "view.target" in demo and "view.frame" not in demo
    framed = editor.current.camera
    other = Editor(clock=VirtualClock())
    assert other.execute("workspace lights3d") and other.execute(f"play {next(tmp_path.rglob('framed.demo'))}")
    other.demos.clock.advance(5)
    other.demos.update()
    assert other.workspaces["lights3d"].camera == framed


def test_a_loaded_volume_is_framed(editor, tmp_path):
    assert editor.execute("workspace volume") and editor.execute("new 64 16 16")
    assert editor.execute("save flat.npy") and editor.execute("orbit 0 0 40")
    assert editor.execute("load flat.npy")
    assert editor.current.view.camera.distance < 6


def test_key_f_frames_the_view_in_the_window_for_its_shape(window, qtbot):
    from PySide6.QtCore import Qt

    window.run("workspace snowflake")
    window.run("snow.view 300 300 5")
    vp = window.viewport
    vp.setFocus()
    qtbot.keyClick(vp, Qt.Key.Key_F)
    cam = window.editor.workspaces["snowflake"].camera
    aspect = vp.width() / vp.height()
    assert window.editor.workspaces.view_aspect == pytest.approx(aspect, abs=0.01)
    assert visible_2d(cam, aspect, (-1.0, -1.0), (1.0, 1.0)) and cam.height < 4


def test_a_loaded_scene_off_view_is_framed_and_one_in_view_keeps_the_view(editor, tmp_path):
    assert editor.execute("workspace snowflake") and editor.execute("snow.clear; snow.add 900 -400 3")
    assert editor.execute(f"scene.save {tmp_path / 'far.json'}") and editor.execute("snow.view 0 0 2.6")
    assert editor.execute(f"scene.load {tmp_path / 'far.json'}")
    cam = editor.current.camera
    assert visible_2d(cam, 1.0, (897, -403), (903, -397))  # framed
    assert editor.execute("snow.view 900 -400 20")
    assert editor.execute(f"scene.load {tmp_path / 'far.json'}")
    assert editor.current.camera.key() == (900.0, -400.0, 20.0)  # in view already: the view stays


def test_shadelab_render_frames_for_the_pictures_shape(tmp_path):
    """`--cmd view.frame` in a wide picture frames for its width (the headless host has no view of its own)."""
    from app import cli

    out = tmp_path / "wide.png"
    assert cli.main(["render", "snowflake", "--size", "160x40", "--cmd", "snow.clear; snow.add 10 0 1",
                     "--cmd", "snow.add -10 0 1", "--cmd", "view.frame", "--out", str(out)]) == 0
    from app.io.png import read_png

    image = read_png(out)
    lit = (image[..., :3].max(axis=-1) > 60).any(axis=0)
    assert lit[:20].any() and lit[-20:].any()  # both flakes, near either end of the wide picture
