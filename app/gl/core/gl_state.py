"""One GL context, many renderers: the baseline state every frame starts from and every renderer leaves behind.

The Qt host keeps its context between frames and shares it among the workspaces, so a blend, scissor, mask or
bound object one renderer leaves set changes what the next one draws (issue: the volume drawn over the last 2D
frame). The host applies BASELINE before each renderer's frame and again after it; in debug mode (tests, or
SHADELAB_GL_DEBUG=1) it first reads the state back and names what the renderer left different, and any GL
error it left queued. The values are GL's own initial ones, so a renderer written against a fresh context is
right here too: GL's own initial values, but for what moderngl sets when it makes a context (primitive restart
at index 0xFFFFFFFF, seamless cube maps, alpha blending as the blend function).

Calls go through PyOpenGL to the current context (app/gl/core/stencil.py says why that reaches it on every host)."""
from __future__ import annotations

import os

import moderngl

from app.gl.core import texture_units
from app.gl.core.stencil import GL

ALL_ONES = 0xFFFFFFFF

# Switches GL starts with off, and those it starts with on.
OFF = ("GL_BLEND", "GL_CULL_FACE", "GL_DEPTH_TEST", "GL_STENCIL_TEST", "GL_SCISSOR_TEST", "GL_DEPTH_CLAMP",
       "GL_FRAMEBUFFER_SRGB", "GL_PROGRAM_POINT_SIZE", "GL_POLYGON_OFFSET_FILL", "GL_POLYGON_OFFSET_LINE",
       "GL_RASTERIZER_DISCARD", "GL_SAMPLE_ALPHA_TO_COVERAGE", "GL_COLOR_LOGIC_OP", "GL_LINE_SMOOTH",
       "GL_POLYGON_SMOOTH", "GL_CLIP_DISTANCE0")
ON = ("GL_MULTISAMPLE", "GL_DITHER", "GL_PRIMITIVE_RESTART", "GL_TEXTURE_CUBE_MAP_SEAMLESS")

# Integer state: query name -> the baseline value. GL answers an all-ones mask as the largest GLint, so the
# stencil masks are compared over the stencil buffer's 8 bits.
STENCIL_MASKS = ("GL_STENCIL_VALUE_MASK", "GL_STENCIL_WRITEMASK", "GL_STENCIL_BACK_VALUE_MASK",
                 "GL_STENCIL_BACK_WRITEMASK")
INTEGERS = {
    "GL_BLEND_SRC_RGB": "GL_SRC_ALPHA", "GL_BLEND_DST_RGB": "GL_ONE_MINUS_SRC_ALPHA",
    "GL_BLEND_SRC_ALPHA": "GL_SRC_ALPHA", "GL_BLEND_DST_ALPHA": "GL_ONE_MINUS_SRC_ALPHA",
    "GL_BLEND_EQUATION_RGB": "GL_FUNC_ADD", "GL_BLEND_EQUATION_ALPHA": "GL_FUNC_ADD",
    "GL_DEPTH_FUNC": "GL_LESS", "GL_CULL_FACE_MODE": "GL_BACK", "GL_FRONT_FACE": "GL_CCW",
    "GL_PROVOKING_VERTEX": "GL_LAST_VERTEX_CONVENTION",
    "GL_STENCIL_FUNC": "GL_ALWAYS", "GL_STENCIL_REF": 0, "GL_STENCIL_VALUE_MASK": 0xFF,
    "GL_STENCIL_WRITEMASK": 0xFF, "GL_STENCIL_FAIL": "GL_KEEP", "GL_STENCIL_PASS_DEPTH_FAIL": "GL_KEEP",
    "GL_STENCIL_PASS_DEPTH_PASS": "GL_KEEP", "GL_STENCIL_BACK_FUNC": "GL_ALWAYS", "GL_STENCIL_BACK_REF": 0,
    "GL_STENCIL_BACK_VALUE_MASK": 0xFF, "GL_STENCIL_BACK_WRITEMASK": 0xFF, "GL_STENCIL_BACK_FAIL": "GL_KEEP",
    "GL_STENCIL_BACK_PASS_DEPTH_FAIL": "GL_KEEP", "GL_STENCIL_BACK_PASS_DEPTH_PASS": "GL_KEEP",
    "GL_UNPACK_ROW_LENGTH": 0, "GL_UNPACK_IMAGE_HEIGHT": 0, "GL_PACK_ROW_LENGTH": 0,
    "GL_PIXEL_PACK_BUFFER_BINDING": 0, "GL_PIXEL_UNPACK_BUFFER_BINDING": 0, "GL_PRIMITIVE_RESTART_INDEX": ALL_ONES,
}
FLOATS = {
    "GL_BLEND_COLOR": (0.0, 0.0, 0.0, 0.0),
    "GL_DEPTH_RANGE": (0.0, 1.0), "GL_LINE_WIDTH": (1.0,), "GL_POINT_SIZE": (1.0,),
    "GL_POLYGON_OFFSET_FACTOR": (0.0,), "GL_POLYGON_OFFSET_UNITS": (0.0,),
}
BOOLEANS = {"GL_COLOR_WRITEMASK": (True, True, True, True), "GL_DEPTH_WRITEMASK": (True,)}
# Units whose sampler binding is checked (a sampler left bound overrides a texture's filter there): all those a
# renderer's TextureUnits hands out.
SAMPLER_UNITS = texture_units.LIMIT


def debug_enabled() -> bool:
    """Tests set SHADELAB_GL_DEBUG=1 (tests/conftest.py); a user may too, to find a renderer's leak."""
    return os.environ.get("SHADELAB_GL_DEBUG", "") not in ("", "0")


class GLStateError(RuntimeError):
    """A renderer left GL state other than the baseline, or a GL error queued."""


def _value(v):
    return getattr(GL, v) if isinstance(v, str) else v


def _baseline(fbo: moderngl.Framebuffer) -> dict:
    """What the state must read after a frame drawn into `fbo`."""
    state = {name: False for name in OFF} | {name: True for name in ON}
    state |= {name: _value(v) for name, v in INTEGERS.items()}
    state |= FLOATS | BOOLEANS
    state["GL_POLYGON_MODE"] = GL.GL_FILL
    state["GL_DRAW_FRAMEBUFFER_BINDING"] = state["GL_READ_FRAMEBUFFER_BINDING"] = fbo.glo
    state["GL_VIEWPORT"] = (0, 0, *fbo.size)
    state["GL_SAMPLER_BINDING"] = (0,) * SAMPLER_UNITS
    return state


def snapshot() -> dict:
    """The state BASELINE covers, read back from the current context."""
    state = {name: bool(GL.glIsEnabled(getattr(GL, name))) for name in OFF + ON}
    state |= {name: int(GL.glGetIntegerv(getattr(GL, name))) for name in INTEGERS}
    state["GL_PRIMITIVE_RESTART_INDEX"] &= ALL_ONES  # read back as a GLint: -1
    state |= {name: state[name] & 0xFF for name in STENCIL_MASKS}
    state |= {name: tuple(round(float(x), 6) for x in GL.glGetFloatv(getattr(GL, name)).ravel()[:len(v)])
              for name, v in FLOATS.items()}
    state |= {name: tuple(bool(x) for x in GL.glGetBooleanv(getattr(GL, name)).ravel()[:len(v)])
              for name, v in BOOLEANS.items()}
    state["GL_POLYGON_MODE"] = int(GL.glGetIntegerv(GL.GL_POLYGON_MODE).ravel()[0])
    for name in ("GL_DRAW_FRAMEBUFFER_BINDING", "GL_READ_FRAMEBUFFER_BINDING"):
        state[name] = int(GL.glGetIntegerv(getattr(GL, name)))
    state["GL_VIEWPORT"] = tuple(int(x) for x in GL.glGetIntegerv(GL.GL_VIEWPORT))
    active = int(GL.glGetIntegerv(GL.GL_ACTIVE_TEXTURE))
    units = []
    for unit in range(SAMPLER_UNITS):
        GL.glActiveTexture(GL.GL_TEXTURE0 + unit)
        units.append(int(GL.glGetIntegerv(GL.GL_SAMPLER_BINDING)))
    GL.glActiveTexture(active)
    state["GL_SAMPLER_BINDING"] = tuple(units)
    return state


def differences(fbo: moderngl.Framebuffer, state: dict | None = None) -> dict:
    """Each state that differs from the baseline for `fbo`: name -> (baseline, found)."""
    state = snapshot() if state is None else state
    return {name: (want, state[name]) for name, want in _baseline(fbo).items() if state[name] != want}


def problems(fbo: moderngl.Framebuffer, state: bool = True) -> list[str]:
    """The GL errors queued (drained) and, with `state`, each state other than the baseline, in words."""
    said = [f"GL error 0x{e:x}" for e in gl_errors()]
    if state:
        said += [f"{name} is {_name(found)}, not {_name(want)}" for name, (want, found) in differences(fbo).items()]
    return said


def _name(value):
    """A GL enum by its name where the baseline names it (GL_ONE rather than 1)."""
    return _ENUM_NAMES.get(value, value) if isinstance(value, int) and not isinstance(value, bool) else value


_ENUM_NAMES = {int(getattr(GL, v)): v for v in INTEGERS.values() if isinstance(v, str)}


def bound_framebuffer() -> int:
    """The framebuffer GL draws into now (moderngl's ctx.fbo is only what moderngl last bound)."""
    return int(GL.glGetIntegerv(GL.GL_DRAW_FRAMEBUFFER_BINDING))


def gl_errors() -> list[int]:
    """Drain the error queue (GL keeps one flag per kind of error, so this ends)."""
    errors = []
    while (error := GL.glGetError()) != GL.GL_NO_ERROR and len(errors) < 16:
        errors.append(int(error))
    return errors


def _reset_set_at_use() -> None:
    """State moderngl sets itself before every use (the program and vertex array at each draw, the alignment at
    each read and write, the clear values at each clear, the texture unit at each bind): reset for the host's
    sake, but not checked, since a renderer has no moderngl call to put it back."""
    GL.glClearColor(0.0, 0.0, 0.0, 0.0)
    GL.glClearDepth(1.0)
    GL.glClearStencil(0)
    GL.glPixelStorei(GL.GL_PACK_ALIGNMENT, 4)
    GL.glPixelStorei(GL.GL_UNPACK_ALIGNMENT, 4)
    GL.glActiveTexture(GL.GL_TEXTURE0)
    GL.glUseProgram(0)
    GL.glBindVertexArray(0)
    GL.glBindRenderbuffer(GL.GL_RENDERBUFFER, 0)


def apply_baseline(ctx: moderngl.Context, fbo: moderngl.Framebuffer) -> None:
    """Set every state BASELINE covers, `fbo` bound (through moderngl, so its own idea of the bound framebuffer
    and of its switches agrees) with its whole area as the viewport and no scissor."""
    ctx.enable_only(moderngl.NOTHING)  # moderngl's switches, its cache of them too
    for name in OFF:
        GL.glDisable(getattr(GL, name))
    for name in ON:
        GL.glEnable(getattr(GL, name))
    GL.glBlendEquation(GL.GL_FUNC_ADD)
    GL.glBlendFunc(GL.GL_SRC_ALPHA, GL.GL_ONE_MINUS_SRC_ALPHA)
    GL.glPrimitiveRestartIndex(ALL_ONES)
    GL.glBlendColor(0.0, 0.0, 0.0, 0.0)
    GL.glDepthFunc(GL.GL_LESS)
    GL.glDepthRange(0.0, 1.0)
    GL.glCullFace(GL.GL_BACK)
    GL.glFrontFace(GL.GL_CCW)
    GL.glProvokingVertex(GL.GL_LAST_VERTEX_CONVENTION)
    GL.glPolygonMode(GL.GL_FRONT_AND_BACK, GL.GL_FILL)
    GL.glPolygonOffset(0.0, 0.0)
    GL.glLineWidth(1.0)
    GL.glPointSize(1.0)
    GL.glStencilFunc(GL.GL_ALWAYS, 0, ALL_ONES)
    GL.glStencilOp(GL.GL_KEEP, GL.GL_KEEP, GL.GL_KEEP)
    GL.glStencilMask(ALL_ONES)
    for name in ("GL_UNPACK_ROW_LENGTH", "GL_UNPACK_IMAGE_HEIGHT", "GL_PACK_ROW_LENGTH"):
        GL.glPixelStorei(getattr(GL, name), 0)
    GL.glBindBuffer(GL.GL_PIXEL_PACK_BUFFER, 0)
    GL.glBindBuffer(GL.GL_PIXEL_UNPACK_BUFFER, 0)
    for unit in range(SAMPLER_UNITS):
        GL.glBindSampler(unit, 0)
    _reset_set_at_use()
    fbo.scissor = None
    fbo.color_mask = (True, True, True, True)
    fbo.depth_mask = True
    fbo.viewport = (0, 0, *fbo.size)
    fbo.use()  # binds it for drawing and reading, sets its viewport, scissor off, its masks
