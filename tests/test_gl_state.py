"""The baseline GL state the host restores around every workspace's frame (app/gl/core/gl_state.py), and its debug mode,
which names what a renderer left behind and any GL error it left queued."""
from __future__ import annotations

import moderngl
import pytest

from app.gl.core import gl_state
from app.gl.core.gl_state import GLStateError
from app.gl.core.headless import OffscreenTarget
from app.gl.core.renderer_base import WorkspaceRendererBase
from app.gl.core.stencil import GL
from app.gl.core.workspace_renderer import RENDERERS, WorkspaceRenderer
from app.model.workspace import Workspace


HOSTS = {"GL_DRAW_FRAMEBUFFER_BINDING", "GL_READ_FRAMEBUFFER_BINDING", "GL_VIEWPORT"}  # the caller's, put back


def left_behind(target) -> dict:
    """What differs from the baseline once the host gave the caller its framebuffer (and viewport) back."""
    return {k: v for k, v in gl_state.differences(target.fbo).items() if k not in HOSTS}


class Leaky(Workspace):
    name = "leaky"


class LeakyRenderer(WorkspaceRendererBase):
    """Draws nothing, and leaves what `leave` sets."""
    leave = staticmethod(lambda ctx: None)

    def render(self, fbo, state, settings, interactive=False) -> bool:
        fbo.use()
        fbo.clear(0.2, 0.3, 0.4, 1.0)
        self.leave(self.ctx)
        return False


@pytest.fixture
def leaky(monkeypatch):
    monkeypatch.setitem(RENDERERS, "leaky", LeakyRenderer)
    return Leaky()


def test_a_fresh_context_is_the_baseline_and_applying_it_is_idempotent(gl):
    target = OffscreenTarget(gl, (16, 16))
    try:
        gl_state.apply_baseline(gl, target.fbo)
        assert gl_state.problems(target.fbo) == []
        gl_state.apply_baseline(gl, target.fbo)
        assert gl_state.differences(target.fbo) == {}
    finally:
        target.release()


@pytest.mark.parametrize("leave, named", [
    (lambda ctx: ctx.enable(moderngl.BLEND), "GL_BLEND"),
    (lambda ctx: setattr(ctx, "blend_func", (moderngl.ONE, moderngl.ONE)), "GL_BLEND_SRC_RGB"),
    (lambda ctx: setattr(ctx, "depth_func", "=="), "GL_DEPTH_FUNC"),
    (lambda ctx: GL.glEnable(GL.GL_SCISSOR_TEST), "GL_SCISSOR_TEST"),
    (lambda ctx: GL.glColorMask(False, False, False, True), "GL_COLOR_WRITEMASK"),
    (lambda ctx: GL.glStencilMask(0x0F), "GL_STENCIL_WRITEMASK"),
    (lambda ctx: ctx.sampler().use(3), "GL_SAMPLER_BINDING"),
    (lambda ctx: GL.glViewport(0, 0, 4, 4), "GL_VIEWPORT"),
    (lambda ctx: GL.glBindFramebuffer(GL.GL_FRAMEBUFFER, 0), "GL_DRAW_FRAMEBUFFER_BINDING"),
    (lambda ctx: GL.glBindTexture(GL.GL_TEXTURE_2D, 987654), "GL error 0x502"),
])
def test_debug_mode_names_what_a_frame_left_and_the_host_puts_it_back(gl, leaky, monkeypatch, leave, named):
    monkeypatch.setattr(LeakyRenderer, "leave", staticmethod(leave))
    host = WorkspaceRenderer(gl, debug=True)
    target = OffscreenTarget(gl, (16, 16))
    try:
        bound = gl_state.bound_framebuffer()
        with pytest.raises(GLStateError, match=f"the leaky frame left .*{named}"):
            host.render(target.fbo, leaky, None)
        assert left_behind(target) == {} and gl_state.gl_errors() == []  # the baseline, whatever was left
        assert gl_state.bound_framebuffer() == bound  # the caller's framebuffer bound again
    finally:
        host.release()
        target.release()


def test_without_debug_mode_the_host_still_restores_the_baseline(gl, leaky, monkeypatch):
    monkeypatch.setattr(LeakyRenderer, "leave", staticmethod(lambda ctx: GL.glEnable(GL.GL_SCISSOR_TEST)))
    host = WorkspaceRenderer(gl, debug=False)
    target = OffscreenTarget(gl, (16, 16))
    try:
        assert host.render(target.fbo, leaky, None) is False
        assert left_behind(target) == {}
    finally:
        host.release()
        target.release()
