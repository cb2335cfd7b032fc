"""The renderer host draws every built workspace through the gl layer's mapping, with settings the
commands build from the cvars, and releases what each renderer made."""
import pytest

from app.editor import Editor
from app.gl.core.headless import OffscreenTarget
from app.gl.core.workspace_renderer import RENDERERS, WorkspaceRenderer
from app.model.workspace import MissingEntry, Workspace


@pytest.fixture(scope="module")
def editor():
    return Editor(configs=False)


@pytest.mark.parametrize("name", sorted(RENDERERS))
def test_each_workspace_draws_something_and_releases_what_it_made(gl, editor, name):
    host = WorkspaceRenderer(gl)
    target = OffscreenTarget(gl, (96, 64))
    assert editor.execute(f"workspace {name}")
    host.render(target.fbo, editor.current, editor.render_settings())
    image = target.read()
    assert (image != image[0, 0]).any(axis=-1).mean() > 0.02  # a scene, not a cleared background
    assert list(host.renderers) == [name]  # only the workspace shown made a renderer
    assert host.release() > 0 and not host.renderers
    gl.detect_framebuffer(0).use()  # moderngl binds its last framebuffer again later: never a deleted one
    target.release()


def test_a_workspace_without_a_renderer_is_a_clear_error_not_an_empty_background(gl):
    class Bare(Workspace):
        name = "bare"

    host = WorkspaceRenderer(gl)
    target = OffscreenTarget(gl, (16, 16))
    with pytest.raises(MissingEntry, match=r"'bare' workspace has no entry in RENDERERS"):
        host.render(target.fbo, Bare(), None)
    assert not host.renderers
    gl.detect_framebuffer(0).use()
    target.release()
