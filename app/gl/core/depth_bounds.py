"""The depth bounds test (GL_EXT_depth_bounds_test), where the context has it: a fragment is dropped before the
stencil test when the depth already stored at its pixel lies outside a range, so a light's shadow volumes touch
only the pixels whose surface lies within the light's reach in depth (Everitt and Kilgard's fill cut). Mesa's
llvmpipe (22.3) has no such extension: there `depth_bounds` does nothing and says so; NVIDIA's and AMD's drivers
have it. The calls go through PyOpenGL (app/gl/core/stencil.py imports it for the context moderngl made)."""
from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager

import moderngl

from app.gl.core.stencil import GL  # first: it sets PyOpenGL's platform up
from OpenGL.GL.EXT.depth_bounds_test import GL_DEPTH_BOUNDS_EXT, GL_DEPTH_BOUNDS_TEST_EXT, glDepthBoundsEXT

EXTENSION = "GL_EXT_depth_bounds_test"


def available(ctx: moderngl.Context) -> bool:
    return EXTENSION in ctx.extensions


@contextmanager
def depth_bounds(ctx: moderngl.Context, bounds: tuple[float, float] | None) -> Iterator[bool]:
    """Inside, fragments over stored depths outside `bounds` (zmin, zmax: window depths) are dropped, where the
    context has the test and bounds are given; yields whether they are. The switch and the range are put back."""
    if bounds is None or not available(ctx):
        yield False
        return
    was_on = bool(GL.glIsEnabled(GL_DEPTH_BOUNDS_TEST_EXT))
    before = [float(v) for v in GL.glGetDoublev(GL_DEPTH_BOUNDS_EXT)]
    GL.glEnable(GL_DEPTH_BOUNDS_TEST_EXT)
    glDepthBoundsEXT(*bounds)
    try:
        yield True
    finally:
        glDepthBoundsEXT(*before)
        if not was_on:
            GL.glDisable(GL_DEPTH_BOUNDS_TEST_EXT)
