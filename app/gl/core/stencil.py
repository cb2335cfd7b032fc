"""The stencil buffer, which moderngl has no API for: a target with stencil bits, stencil state that puts back
all it changed, readback and clear. The calls go through PyOpenGL to the context moderngl made current.

PyOpenGL takes its platform from PYOPENGL_PLATFORM once, at its first import (unset, on Linux: GLX).
Only core GL 3.3 entry points are used here; PyOpenGL takes those from libOpenGL/libGL, whose libglvnd
dispatch sends each call to the thread's current context whatever made it (EGL for the headless host, GLX
for Qt under xcb), so the pointers work under both. What the platform decides is PyOpenGL's own context
queries (extension checks, per-context data), none of which this module uses: on Linux EGL is chosen, for
the host the tests and `shadelab render` run on, unless the user set a platform or another library imported
PyOpenGL first (macOS and Windows keep PyOpenGL's own choice: they have no EGL). The variable is set only
around that import, so child processes never inherit it."""
from __future__ import annotations

import importlib
import os
import sys
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass

import moderngl
import numpy as np


def _import_gl():
    # moderngl leaves GL errors of its own queued (e.g. re-binding a framebuffer it released); PyOpenGL's check
    # after every call would raise them from ours. The tests read glGetError themselves after each pass.
    importlib.import_module("OpenGL").ERROR_CHECKING = False
    if not sys.platform.startswith("linux") or "OpenGL.platform" in sys.modules or "PYOPENGL_PLATFORM" in os.environ:
        return importlib.import_module("OpenGL.GL")
    os.environ["PYOPENGL_PLATFORM"] = "egl"
    try:
        return importlib.import_module("OpenGL.GL")
    finally:
        del os.environ["PYOPENGL_PLATFORM"]


GL = _import_gl()


class StencilTarget:
    """An RGBA texture (8-bit, or `dtype` "f2" for float16: sums of passes kept beyond 1 and without a rounding
    each) and a depth + 8-bit stencil renderbuffer in one single-sampled framebuffer (`fbo`).

    moderngl makes DEPTH_COMPONENT24 renderbuffers only; this one is re-specified as DEPTH24_STENCIL8 (a
    renderbuffer's storage may be) and attached to the stencil point too. Every GL object stays moderngl's,
    so `release`, and renderer_base's release walk, free them all."""

    def __init__(self, ctx: moderngl.Context, size: tuple[int, int], dtype: str = "f1") -> None:
        self.ctx, self.size = ctx, size
        self.colour = ctx.texture(size, 4, dtype=dtype)
        self.depth_stencil = ctx.depth_renderbuffer(size)
        with _bound(GL.glBindRenderbuffer, GL.GL_RENDERBUFFER, GL.GL_RENDERBUFFER_BINDING, self.depth_stencil.glo):
            GL.glRenderbufferStorage(GL.GL_RENDERBUFFER, GL.GL_DEPTH24_STENCIL8, *size)
        self.fbo = ctx.framebuffer([self.colour], self.depth_stencil)
        with _bound(GL.glBindFramebuffer, GL.GL_DRAW_FRAMEBUFFER, GL.GL_DRAW_FRAMEBUFFER_BINDING, self.fbo.glo):
            GL.glFramebufferRenderbuffer(GL.GL_DRAW_FRAMEBUFFER, GL.GL_STENCIL_ATTACHMENT, GL.GL_RENDERBUFFER,
                                         self.depth_stencil.glo)
            status = GL.glCheckFramebufferStatus(GL.GL_DRAW_FRAMEBUFFER)
        if status != GL.GL_FRAMEBUFFER_COMPLETE:
            self.release()
            raise RuntimeError(f"the depth-stencil framebuffer is incomplete (status 0x{int(status):x})")

    def clear(self, colour=(0.0, 0.0, 0.0, 0.0), depth: float = 1.0, stencil: int = 0) -> None:
        self.fbo.clear(*colour, depth=depth)  # moderngl clears colour and depth only
        clear_stencil(self.fbo, stencil)

    def read_stencil(self) -> np.ndarray:
        return read_stencil(self.fbo)

    def read_depth(self) -> np.ndarray:
        """Window depth, float32 (height, width), top row first."""
        data = np.frombuffer(self.fbo.read(components=1, attachment=-1, dtype="f4"), np.float32)
        return data.reshape(self.size[1], self.size[0])[::-1].copy()

    def release(self) -> None:
        if self.ctx.fbo is self.fbo:
            # moderngl binds the framebuffer it last used again after making another one: if that is a deleted
            # one, GL_INVALID_OPERATION waits in the queue for the next PyOpenGL call. Leave 0 bound instead.
            self.ctx.detect_framebuffer(0).use()
        for obj in (self.fbo, self.depth_stencil, self.colour):
            obj.release()


@contextmanager
def _bound(bind, target: int, binding: int, name: int) -> Iterator[None]:
    """`name` bound to `target` inside, the previous binding again after."""
    previous = int(GL.glGetIntegerv(binding))
    bind(target, name)
    try:
        yield
    finally:
        bind(target, previous)


def read_stencil(fbo: moderngl.Framebuffer) -> np.ndarray:
    """The stencil of a single-sampled framebuffer (GL refuses to read a multisampled one): uint8
    (height, width), top row first as images are stored."""
    width, height = fbo.size
    out = np.empty((height, width), np.uint8)
    alignment = int(GL.glGetIntegerv(GL.GL_PACK_ALIGNMENT))
    with _bound(GL.glBindFramebuffer, GL.GL_READ_FRAMEBUFFER, GL.GL_READ_FRAMEBUFFER_BINDING, fbo.glo):
        GL.glPixelStorei(GL.GL_PACK_ALIGNMENT, 1)  # rows of any width, packed
        try:
            GL.glReadPixels(0, 0, width, height, GL.GL_STENCIL_INDEX, GL.GL_UNSIGNED_BYTE, out)
        finally:
            GL.glPixelStorei(GL.GL_PACK_ALIGNMENT, alignment)
    return out[::-1].copy()


def clear_stencil(fbo: moderngl.Framebuffer, value: int = 0) -> None:
    """Set every stencil value of `fbo` to `value`: all bits (the write mask) and all pixels (no scissor),
    whatever state was set; that state is put back."""
    clear_value = int(GL.glGetIntegerv(GL.GL_STENCIL_CLEAR_VALUE))
    masks = [_uint(GL.GL_STENCIL_WRITEMASK), _uint(GL.GL_STENCIL_BACK_WRITEMASK)]
    scissor = bool(GL.glIsEnabled(GL.GL_SCISSOR_TEST))
    with _bound(GL.glBindFramebuffer, GL.GL_DRAW_FRAMEBUFFER, GL.GL_DRAW_FRAMEBUFFER_BINDING, fbo.glo):
        GL.glDisable(GL.GL_SCISSOR_TEST)
        GL.glStencilMask(0xFF)
        GL.glClearStencil(value)
        GL.glClear(GL.GL_STENCIL_BUFFER_BIT)
        GL.glClearStencil(clear_value)
        GL.glStencilMaskSeparate(GL.GL_FRONT, masks[0])
        GL.glStencilMaskSeparate(GL.GL_BACK, masks[1])
        if scissor:
            GL.glEnable(GL.GL_SCISSOR_TEST)


def _uint(name: int) -> int:
    return int(GL.glGetIntegerv(name)) & 0xFFFFFFFF  # GL answers a GLint: an all-ones mask comes back as -1


@dataclass(frozen=True)
class StencilOps:
    """What a fragment does to the stencil: the stencil test fails, it passes and the depth test fails, both
    pass (GL's sfail, dpfail, dppass)."""
    sfail: int = GL.GL_KEEP
    zfail: int = GL.GL_KEEP
    zpass: int = GL.GL_KEEP


KEEP = StencilOps()


@dataclass(frozen=True)
class StencilState:
    """The state a stencil pass draws with; `stencil_state` sets it and puts back what was there."""
    func: int = GL.GL_ALWAYS
    ref: int = 0
    read_mask: int = 0xFF
    write_mask: int = 0xFF
    front: StencilOps = KEEP
    back: StencilOps = KEEP
    depth_func: int = GL.GL_LESS
    depth_write: bool = False
    colour_write: bool = False
    cull: int | None = None  # GL_BACK or GL_FRONT; None draws both faces
    depth_clamp: bool = False  # w = 0 vertices lie beyond any far plane: clamp their depth instead of clipping


_SWITCHES = (GL.GL_STENCIL_TEST, GL.GL_DEPTH_TEST, GL.GL_CULL_FACE, GL.GL_DEPTH_CLAMP)
_FACES = {  # face: its func, ref, read mask, write mask, sfail, zfail, zpass queries
    GL.GL_FRONT: (GL.GL_STENCIL_FUNC, GL.GL_STENCIL_REF, GL.GL_STENCIL_VALUE_MASK, GL.GL_STENCIL_WRITEMASK,
                  GL.GL_STENCIL_FAIL, GL.GL_STENCIL_PASS_DEPTH_FAIL, GL.GL_STENCIL_PASS_DEPTH_PASS),
    GL.GL_BACK: (GL.GL_STENCIL_BACK_FUNC, GL.GL_STENCIL_BACK_REF, GL.GL_STENCIL_BACK_VALUE_MASK,
                 GL.GL_STENCIL_BACK_WRITEMASK, GL.GL_STENCIL_BACK_FAIL, GL.GL_STENCIL_BACK_PASS_DEPTH_FAIL,
                 GL.GL_STENCIL_BACK_PASS_DEPTH_PASS),
}


@contextmanager
def stencil_state(state: StencilState) -> Iterator[None]:
    """Draw inside with `state`; on exit every switch, mask, op and function it touched is as before (stencil
    test off, for a caller that had it off), so no other workspace ever finds a stencil test left on.

    Bind the framebuffer (`fbo.use()`) before entering: moderngl's use() re-applies the framebuffer's own
    colour and depth masks."""
    saved = _save()
    try:
        _apply(state)
        yield
    finally:
        _restore(saved)


def _save() -> dict:
    return {
        "switches": {s: bool(GL.glIsEnabled(s)) for s in _SWITCHES},
        "faces": {face: [_uint(q) for q in queries] for face, queries in _FACES.items()},
        "colour": [bool(c) for c in GL.glGetBooleanv(GL.GL_COLOR_WRITEMASK)],
        "depth_write": bool(GL.glGetBooleanv(GL.GL_DEPTH_WRITEMASK)),
        "depth_func": int(GL.glGetIntegerv(GL.GL_DEPTH_FUNC)),
        "cull_face": int(GL.glGetIntegerv(GL.GL_CULL_FACE_MODE)),
    }


def _switch(name: int, on: bool) -> None:
    (GL.glEnable if on else GL.glDisable)(name)


def _apply(state: StencilState) -> None:
    _switch(GL.GL_STENCIL_TEST, True)
    _switch(GL.GL_DEPTH_TEST, True)
    _switch(GL.GL_CULL_FACE, state.cull is not None)
    if state.cull is not None:
        GL.glCullFace(state.cull)
    _switch(GL.GL_DEPTH_CLAMP, state.depth_clamp)
    GL.glStencilFunc(state.func, state.ref, state.read_mask)
    GL.glStencilMask(state.write_mask)
    for face, ops in ((GL.GL_FRONT, state.front), (GL.GL_BACK, state.back)):
        GL.glStencilOpSeparate(face, ops.sfail, ops.zfail, ops.zpass)
    GL.glColorMask(*[state.colour_write] * 4)
    GL.glDepthMask(state.depth_write)
    GL.glDepthFunc(state.depth_func)


def _restore(saved: dict) -> None:
    for face, (func, ref, read_mask, write_mask, sfail, zfail, zpass) in saved["faces"].items():
        GL.glStencilFuncSeparate(face, func, ref, read_mask)
        GL.glStencilMaskSeparate(face, write_mask)
        GL.glStencilOpSeparate(face, sfail, zfail, zpass)
    GL.glColorMask(*saved["colour"])
    GL.glDepthMask(saved["depth_write"])
    GL.glDepthFunc(saved["depth_func"])
    GL.glCullFace(saved["cull_face"])
    for name, on in saved["switches"].items():
        _switch(name, on)
