"""The headless host: an EGL context with no window, for `shadelab render`, `bench` and GL tests."""
from __future__ import annotations

import ctypes

import moderngl
import numpy as np

SAMPLES = 4  # the Qt viewport asks for the same, so both hosts give the same pixels


def create_context() -> moderngl.Context:
    return moderngl.create_standalone_context(backend="egl", require=330)


def release_context(ctx: moderngl.Context) -> None:
    """Release the context and leave none current, so Qt can make its own GLX context current later
    in this thread (Mesa refuses while an EGL context is still current; EGL only destroys a
    current context once it stops being current)."""
    ctx.release()
    egl = ctypes.CDLL("libEGL.so.1")
    egl.eglGetCurrentDisplay.restype = ctypes.c_void_p
    display = egl.eglGetCurrentDisplay()
    if display:
        egl.eglMakeCurrent.argtypes = [ctypes.c_void_p] * 4
        egl.eglMakeCurrent(display, None, None, None)


class OffscreenTarget:
    """A multisampled framebuffer to draw into and a resolved one to read back."""

    def __init__(self, ctx: moderngl.Context, size: tuple[int, int], samples: int = SAMPLES) -> None:
        self.ctx = ctx
        self.size = size
        samples = min(samples, ctx.max_samples)
        self.fbo = ctx.framebuffer(
            ctx.renderbuffer(size, samples=samples), ctx.depth_renderbuffer(size, samples=samples))
        self.resolved = ctx.simple_framebuffer(size) if samples else self.fbo

    def read(self) -> np.ndarray:
        """RGBA uint8, top row first (as images are stored), after resolving the samples."""
        if self.resolved is not self.fbo:
            self.ctx.copy_framebuffer(self.resolved, self.fbo)
        data = np.frombuffer(self.resolved.read(components=4), np.uint8)
        return data.reshape(self.size[1], self.size[0], 4)[::-1].copy()

    def release(self) -> None:
        for fbo in {self.fbo, self.resolved}:
            for attachment in (*fbo.color_attachments, fbo.depth_attachment):
                if attachment is not None:
                    attachment.release()
            fbo.release()
