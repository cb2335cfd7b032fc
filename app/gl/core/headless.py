"""The headless host: an EGL context with no window, for `shadelab render`, `bench` and GL tests."""
from __future__ import annotations

import ctypes

import moderngl
import numpy as np

SAMPLES = 4  # the Qt viewport asks for the same, so both hosts give the same pixels


class ContextError(RuntimeError):
    """The headless context exists but is not the one GL calls would reach."""


def _egl() -> ctypes.CDLL:
    egl = ctypes.CDLL("libEGL.so.1")
    egl.eglGetCurrentDisplay.restype = egl.eglGetCurrentContext.restype = ctypes.c_void_p
    egl.eglMakeCurrent.argtypes = [ctypes.c_void_p] * 4
    return egl


def create_context() -> moderngl.Context:
    """A headless EGL context, current in this thread, or ContextError.

    libglvnd lets a thread have a current context of one window-system API only: while a Qt window's GLX
    context is current, eglMakeCurrent is refused. glcontext ignores that refusal, and every GL call would
    then go to Qt's context (until the window dies and nothing is current), so check."""
    ctx = moderngl.create_standalone_context(backend="egl", require=330)
    if not _egl().eglGetCurrentContext():
        ctx.release()
        raise ContextError("the headless EGL context could not be made current: another API's context (a Qt "
                           "window's GLX context?) is current in this thread; release that one first")
    return ctx


def release_context(ctx: moderngl.Context) -> None:
    """Release the context and leave none current, so Qt can make its own GLX context current later
    in this thread (Mesa refuses while an EGL context is still current; EGL only destroys a
    current context once it stops being current)."""
    ctx.release()
    egl = _egl()
    display = egl.eglGetCurrentDisplay()
    if display:
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
        if self.ctx.fbo in (self.fbo, self.resolved):
            # moderngl binds its last bound framebuffer again after making one: never let that be a deleted one
            self.ctx.detect_framebuffer(0).use()
        for fbo in {self.fbo, self.resolved}:
            for attachment in (*fbo.color_attachments, fbo.depth_attachment):
                if attachment is not None:
                    attachment.release()
            fbo.release()
