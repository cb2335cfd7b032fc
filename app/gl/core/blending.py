"""Blending that puts back what it changed, for passes that add light, draw translucent lines or must draw opaque
whatever the host left on (moderngl's enable flags are set through GL directly, so raw GL is what has to be put
back)."""
from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager

from app.gl.core.stencil import GL

_QUERIES = (GL.GL_BLEND_SRC_RGB, GL.GL_BLEND_DST_RGB, GL.GL_BLEND_SRC_ALPHA, GL.GL_BLEND_DST_ALPHA,
            GL.GL_BLEND_EQUATION_RGB, GL.GL_BLEND_EQUATION_ALPHA)
ADDITIVE = (GL.GL_ONE, GL.GL_ONE)
ALPHA = (GL.GL_SRC_ALPHA, GL.GL_ONE_MINUS_SRC_ALPHA)


@contextmanager
def blended(func: tuple[int, int] | None) -> Iterator[None]:
    """Inside: colour blended by `func` (source and destination factors, equation add), or blending off for
    None; on exit as before."""
    was_on = bool(GL.glIsEnabled(GL.GL_BLEND))
    src_rgb, dst_rgb, src_alpha, dst_alpha, eq_rgb, eq_alpha = (int(GL.glGetIntegerv(q)) for q in _QUERIES)
    try:
        if func is not None:
            GL.glEnable(GL.GL_BLEND)
            GL.glBlendEquation(GL.GL_FUNC_ADD)
            GL.glBlendFunc(*func)
        else:
            GL.glDisable(GL.GL_BLEND)
        yield
    finally:
        GL.glBlendEquationSeparate(eq_rgb, eq_alpha)
        GL.glBlendFuncSeparate(src_rgb, dst_rgb, src_alpha, dst_alpha)
        (GL.glEnable if was_on else GL.glDisable)(GL.GL_BLEND)


def blending(additive: bool):
    """Inside: colour added (ONE, ONE) with `additive`, else blending off; on exit as before."""
    return blended(ADDITIVE if additive else None)
