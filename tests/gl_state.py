"""The GL state a stencil pass may touch, read back through PyOpenGL, for tests that it was put back."""
from app.gl.core.stencil import GL

SWITCHES = ("GL_STENCIL_TEST", "GL_DEPTH_TEST", "GL_CULL_FACE", "GL_DEPTH_CLAMP", "GL_SCISSOR_TEST", "GL_BLEND")
INTEGERS = ("GL_STENCIL_FUNC", "GL_STENCIL_REF", "GL_STENCIL_VALUE_MASK", "GL_STENCIL_WRITEMASK", "GL_STENCIL_FAIL",
            "GL_STENCIL_PASS_DEPTH_FAIL", "GL_STENCIL_PASS_DEPTH_PASS", "GL_STENCIL_BACK_FUNC", "GL_STENCIL_BACK_REF",
            "GL_STENCIL_BACK_VALUE_MASK", "GL_STENCIL_BACK_WRITEMASK", "GL_STENCIL_BACK_FAIL",
            "GL_STENCIL_BACK_PASS_DEPTH_FAIL", "GL_STENCIL_BACK_PASS_DEPTH_PASS", "GL_STENCIL_CLEAR_VALUE",
            "GL_DEPTH_FUNC", "GL_CULL_FACE_MODE", "GL_PACK_ALIGNMENT", "GL_DRAW_FRAMEBUFFER_BINDING",
            "GL_READ_FRAMEBUFFER_BINDING", "GL_RENDERBUFFER_BINDING")


def snapshot() -> dict:
    state = {name: bool(GL.glIsEnabled(getattr(GL, name))) for name in SWITCHES}
    state.update({name: int(GL.glGetIntegerv(getattr(GL, name))) for name in INTEGERS})
    state["GL_COLOR_WRITEMASK"] = tuple(bool(c) for c in GL.glGetBooleanv(GL.GL_COLOR_WRITEMASK))
    state["GL_DEPTH_WRITEMASK"] = bool(GL.glGetBooleanv(GL.GL_DEPTH_WRITEMASK))
    return state


def differences(before: dict, after: dict) -> dict:
    return {k: (before[k], after[k]) for k in before if before[k] != after[k]}
