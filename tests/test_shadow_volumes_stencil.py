"""The stencil through PyOpenGL on moderngl's EGL context: a target with 8 stencil bits, state that is put back
whatever happened inside, clear and readback; and PyOpenGL's platform choice, in fresh processes."""
import os
import subprocess
import sys
import textwrap

import numpy as np
import pytest

from app.gl.core.stencil import GL, StencilOps, StencilState, StencilTarget, clear_stencil, read_stencil, stencil_state
from tests.gl_state import differences, snapshot

SIZE = (32, 16)  # not square: a transposed readback shows
QUAD_VS = "#version 330 core\nin vec2 in_xy;\nvoid main() { gl_Position = vec4(in_xy, 0.0, 1.0); }\n"
COLOUR_FS = "#version 330 core\nuniform vec4 u_color;\nout vec4 f;\nvoid main() { f = u_color; }\n"
REPLACE = StencilOps(GL.GL_KEEP, GL.GL_KEEP, GL.GL_REPLACE)


@pytest.fixture(scope="module")
def quads(gl):
    program = gl.program(vertex_shader=QUAD_VS, fragment_shader=COLOUR_FS)
    made = []

    def quad(x0, y0, x1, y1):
        """A rectangle in normalised device coordinates, drawn where the state lets it."""
        buffer = gl.buffer(np.array([x0, y0, x1, y0, x0, y1, x1, y1], "f4"))
        vao = gl.vertex_array(program, [(buffer, "2f", "in_xy")])
        made.extend([vao, buffer])
        return vao

    yield program, quad
    for obj in [*made, program]:
        obj.release()


@pytest.fixture
def target(gl):
    target = StencilTarget(gl, SIZE)
    yield target
    target.release()
    gl.finish()
    assert GL.glGetError() == GL.GL_NO_ERROR


def test_the_target_has_eight_stencil_bits_and_reads_back_top_row_first(gl, target, quads):
    _, quad = quads
    prior = GL.glGetIntegerv(GL.GL_DRAW_FRAMEBUFFER_BINDING)
    GL.glBindFramebuffer(GL.GL_DRAW_FRAMEBUFFER, target.fbo.glo)
    bits = GL.glGetFramebufferAttachmentParameteriv(GL.GL_DRAW_FRAMEBUFFER, GL.GL_STENCIL_ATTACHMENT,
                                                    GL.GL_FRAMEBUFFER_ATTACHMENT_STENCIL_SIZE)
    GL.glBindFramebuffer(GL.GL_DRAW_FRAMEBUFFER, prior)
    assert bits == 8
    target.clear(stencil=0)
    target.fbo.use()
    with stencil_state(StencilState(ref=7, front=REPLACE, back=REPLACE)):
        quad(-1, 0, 1, 1).render(5)  # GL_TRIANGLE_STRIP over the upper half
    stencil = target.read_stencil()
    assert stencil.shape == (SIZE[1], SIZE[0]) and stencil.dtype == np.uint8
    assert (stencil[: SIZE[1] // 2] == 7).all() and (stencil[SIZE[1] // 2:] == 0).all()
    assert GL.glGetError() == GL.GL_NO_ERROR


def test_the_stencil_gates_colour_and_colour_writes_stay_off_while_marking(gl, target, quads):
    program, quad = quads
    target.clear(colour=(0, 0, 0, 1), stencil=0)
    target.fbo.use()
    program["u_color"].value = (1.0, 0.0, 0.0, 1.0)
    with stencil_state(StencilState(ref=1, front=REPLACE, back=REPLACE)):  # colour writes off: only marks
        quad(-1, -1, 0, 1).render(5)
    with stencil_state(StencilState(func=GL.GL_EQUAL, ref=1, write_mask=0, colour_write=True,
                                    depth_func=GL.GL_ALWAYS)):
        quad(-1, -1, 1, 1).render(5)
    rgb = np.frombuffer(target.fbo.read(components=3), np.uint8).reshape(SIZE[1], SIZE[0], 3)
    assert (rgb[:, : SIZE[0] // 2, 0] == 255).all() and (rgb[:, SIZE[0] // 2:] == 0).all()


def set_unusual_state():
    """State no pass would set, so putting back the defaults instead would show."""
    GL.glEnable(GL.GL_CULL_FACE)
    GL.glCullFace(GL.GL_FRONT)
    GL.glStencilMaskSeparate(GL.GL_FRONT, 0x0F)
    GL.glStencilFuncSeparate(GL.GL_BACK, GL.GL_GREATER, 3, 0x7F)
    GL.glStencilOpSeparate(GL.GL_FRONT, GL.GL_ZERO, GL.GL_REPLACE, GL.GL_INVERT)
    GL.glDepthFunc(GL.GL_GEQUAL)
    GL.glColorMask(True, False, True, True)
    GL.glDepthMask(False)


def reset_state():
    GL.glDisable(GL.GL_CULL_FACE)
    GL.glCullFace(GL.GL_BACK)
    GL.glStencilMask(0xFF)
    GL.glStencilFunc(GL.GL_ALWAYS, 0, 0xFF)
    GL.glStencilOp(GL.GL_KEEP, GL.GL_KEEP, GL.GL_KEEP)
    GL.glDepthFunc(GL.GL_LESS)
    GL.glColorMask(True, True, True, True)
    GL.glDepthMask(True)


ONEPASS_LIKE = StencilState(func=GL.GL_NOTEQUAL, ref=0xFC, read_mask=0xFD, write_mask=0xFD,
                            front=StencilOps(GL.GL_KEEP, GL.GL_INVERT, GL.GL_INCR),
                            back=StencilOps(GL.GL_KEEP, GL.GL_INVERT, GL.GL_INCR), depth_clamp=True)


@pytest.mark.parametrize("prior", ["defaults", "unusual"])
def test_the_state_applies_inside_and_everything_is_put_back(gl, target, prior):
    target.fbo.use()
    try:
        if prior == "unusual":
            set_unusual_state()
        before = snapshot()
        with stencil_state(ONEPASS_LIKE):
            inside = snapshot()
        after = snapshot()
        with pytest.raises(RuntimeError, match="inside"), stencil_state(ONEPASS_LIKE):
            raise RuntimeError("a draw failed inside")
        after_error = snapshot()
    finally:
        reset_state()
    assert inside["GL_STENCIL_TEST"] and inside["GL_DEPTH_CLAMP"] and not inside["GL_CULL_FACE"]
    assert inside["GL_STENCIL_FUNC"] == GL.GL_NOTEQUAL and inside["GL_STENCIL_REF"] == 0xFC
    assert inside["GL_STENCIL_VALUE_MASK"] == inside["GL_STENCIL_WRITEMASK"] == 0xFD
    assert inside["GL_STENCIL_BACK_PASS_DEPTH_FAIL"] == GL.GL_INVERT
    assert inside["GL_COLOR_WRITEMASK"] == (False,) * 4 and not inside["GL_DEPTH_WRITEMASK"]
    assert differences(before, after) == {} and differences(before, after_error) == {}
    assert not after["GL_STENCIL_TEST"]
    assert GL.glGetError() == GL.GL_NO_ERROR


def test_clear_stencil_sets_every_bit_and_pixel_whatever_the_masks_and_scissor(gl, target):
    target.fbo.use()
    GL.glStencilMask(0x0F)
    GL.glEnable(GL.GL_SCISSOR_TEST)
    GL.glScissor(0, 0, 4, 4)
    try:
        before = snapshot()
        clear_stencil(target.fbo, 0xA5)
        after = snapshot()
    finally:
        GL.glDisable(GL.GL_SCISSOR_TEST)
        GL.glStencilMask(0xFF)
    assert (read_stencil(target.fbo) == 0xA5).all()
    assert differences(before, after) == {}


def test_release_frees_every_gl_object(gl):
    target = StencilTarget(gl, SIZE)
    renderbuffer, framebuffer = target.depth_stencil.glo, target.fbo.glo
    assert GL.glIsRenderbuffer(renderbuffer) and GL.glIsFramebuffer(framebuffer)
    target.release()
    assert not GL.glIsRenderbuffer(renderbuffer) and not GL.glIsFramebuffer(framebuffer)
    assert GL.glGetError() == GL.GL_NO_ERROR


PROBE = textwrap.dedent("""
    import os
    from app.gl.core.headless import create_context, release_context
    ctx = create_context()
    from app.gl.core.stencil import GL, StencilTarget
    import OpenGL.platform
    target = StencilTarget(ctx, (8, 4))
    target.clear(stencil=0x3C)
    print(type(OpenGL.platform.PLATFORM).__name__, os.environ.get("PYOPENGL_PLATFORM"),
          int(target.read_stencil().min()), int(target.read_stencil().max()), int(GL.glGetError()))
    target.release()
    release_context(ctx)
""")


@pytest.mark.parametrize("platform, expected", [
    (None, "EGLPlatform None"),  # chosen for the import only: a child process inherits no variable
    ("glx", "GLXPlatform glx"),  # another library imported PyOpenGL first, with GLX (a DISPLAY was set)
])
def test_pyopengl_reaches_the_headless_context_on_either_platform(platform, expected):
    env = {k: v for k, v in os.environ.items() if k != "PYOPENGL_PLATFORM"}
    if platform:
        env["PYOPENGL_PLATFORM"] = platform
    done = subprocess.run([sys.executable, "-c", PROBE], env=env, capture_output=True, text=True, timeout=60,
                          cwd=os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    assert done.returncode == 0, done.stderr
    assert done.stdout.split() == [*expected.split(), "60", "60", "0"]
