"""`shadelab render` draws the scene, not the editor: the volume's slice plane, the 2D light icons and hull outlines,
the 3D lights' markers and gizmo only with --overlays, which the host passes (the editor's viewport always does)."""
import subprocess
import sys
from dataclasses import replace

import numpy as np
import pytest
from PIL import Image

from app.editor import Editor
from app.gl.core.headless import OffscreenTarget
from app.gl.core.workspace_renderer import WorkspaceRenderer

SIZE = (96, 72)


def frame(host, editor, overlays: bool) -> np.ndarray:
    target = OffscreenTarget(host.ctx, SIZE)
    host.render(target.fbo, editor.current, editor.render_settings(), overlays=overlays)
    return read_and_release(host.ctx, target)


def read_and_release(ctx, target: OffscreenTarget) -> np.ndarray:
    """The picture; then the target deleted while not bound (GL reports a deleted bound framebuffer at the next
    one made, which moderngl takes for a failure to create it)."""
    image = target.read()
    ctx.detect_framebuffer(0).use()
    target.release()
    return image


def scene_alone(host, editor) -> np.ndarray:
    """What each workspace's own renderer draws with its marks turned off by hand."""
    state, settings, renderer = editor.current, editor.render_settings(), host.renderers[editor.workspace]
    target = OffscreenTarget(host.ctx, SIZE)
    if editor.workspace == "volume":
        renderer.tracer.render(target.fbo, state.volume.voxels, state.view, replace(settings, slice_planes=False))
    elif editor.workspace == "lighting2d":
        renderer.lighting.render(target.fbo, state.scene, state.camera, settings, index=state.index())
        renderer.overlay.draw(target.fbo, state.scene, state.index(), state.camera, settings.flip_y, settings.debug,
                              marks=False)
    else:
        renderer.lights.render(target.fbo, state.scene, state.camera, settings, state.selection, marks=False)
    return read_and_release(host.ctx, target)


def select_2d_light(editor) -> bool:
    editor.current.selection = ("light", 0)  # the 2D tool's click: view state no command records
    return True


@pytest.mark.parametrize("workspace, marks", [
    ("volume", lambda editor: editor.execute("slice y 3; slice.highlight x 9")),
    ("lighting2d", select_2d_light),
    ("lights3d", lambda editor: editor.execute("lights3d.select light 0")),
])
def test_the_scene_alone_unless_the_host_asks_for_overlays(gl, workspace, marks):
    editor = Editor(configs=False)
    assert editor.execute(f"workspace {workspace}")
    host = WorkspaceRenderer(gl)
    try:
        plain = frame(host, editor, overlays=False)
        assert np.array_equal(plain, scene_alone(host, editor))
        assert not np.array_equal(plain, frame(host, editor, overlays=True))  # the default scene has marks
        assert marks(editor)  # what only the editor shows changes nothing in a render
        assert np.array_equal(frame(host, editor, overlays=False), plain)
        assert not np.array_equal(frame(host, editor, overlays=True), plain)
    finally:
        host.release()


def test_the_2d_debug_wireframe_is_a_setting_not_an_overlay(gl):
    editor = Editor(configs=False)
    assert editor.execute("workspace lighting2d")
    host = WorkspaceRenderer(gl)
    try:
        plain = frame(host, editor, overlays=False)
        assert editor.execute("r_debug2d 1")
        assert not np.array_equal(frame(host, editor, overlays=False), plain)
    finally:
        host.release()


def test_shadelab_render_takes_overlays(tmp_path):
    def render(*args) -> np.ndarray:
        out = tmp_path / f"{len(list(tmp_path.iterdir()))}.png"
        # its own process: `render` makes and releases a headless context, which would leave this module's
        # context no longer current for the tests after it
        done = subprocess.run([sys.executable, "-m", "app", "render", "volume", "--size", "64x48", "--out", str(out),
                               *args], capture_output=True, text=True, timeout=120)
        assert done.returncode == 0, done.stderr
        return np.asarray(Image.open(out))

    plain = render()
    assert np.array_equal(render("--cmd", "slice x 40"), plain)  # the painter's slice is not in the picture
    assert not np.array_equal(render("--overlays"), plain)
    assert not np.array_equal(render("--overlays", "--cmd", "slice x 40"), render("--overlays"))
