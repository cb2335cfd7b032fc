"""The stencil in a Qt QOpenGLWidget under Xvfb (Qt's GLX context, multisampled default framebuffer): PyOpenGL's
core entry points reach Qt's context as they reach the headless EGL one, and the state is put back."""
import ctypes

import moderngl
import numpy as np
from PySide6.QtCore import Qt
from PySide6.QtGui import QImage, QSurfaceFormat
from PySide6.QtOpenGLWidgets import QOpenGLWidget

from app.gl.core.headless import SAMPLES
from app.gl.core.stencil import GL, StencilOps, StencilState, clear_stencil, stencil_state
from tests.gl_state import differences, snapshot

QUAD_VS = "#version 330 core\nin vec2 in_xy;\nvoid main() { gl_Position = vec4(in_xy, 0.0, 1.0); }\n"
COLOUR_FS = "#version 330 core\nuniform vec4 u_color;\nout vec4 f;\nvoid main() { f = u_color; }\n"
RECTANGLES = {"left": (-1, -1, 0, 1), "all": (-1, -1, 1, 1), "top": (-1, 0.75, 1, 1)}  # normalised device coords
MARK = StencilState(ref=1, front=StencilOps(GL.GL_KEEP, GL.GL_KEEP, GL.GL_REPLACE),
                    back=StencilOps(GL.GL_KEEP, GL.GL_KEEP, GL.GL_REPLACE))
WHERE_MARKED = StencilState(func=GL.GL_EQUAL, ref=1, write_mask=0, colour_write=True, depth_func=GL.GL_ALWAYS)


class StencilWidget(QOpenGLWidget):
    """Marks the left half in the stencil and fills red where marked; then plain moderngl draws a green strip
    along the top, which a stencil test left on would keep off the right half."""

    def __init__(self) -> None:
        super().__init__()
        fmt = QSurfaceFormat.defaultFormat()
        fmt.setStencilBufferSize(8)
        self.setFormat(fmt)
        self.ctx: moderngl.Context | None = None
        self.seen: dict = {}

    def initializeGL(self) -> None:
        self.ctx = moderngl.create_context()
        self.program = self.ctx.program(vertex_shader=QUAD_VS, fragment_shader=COLOUR_FS)
        self.buffers = {name: self.ctx.buffer(np.array([x0, y0, x1, y0, x0, y1, x1, y1], "f4"))
                        for name, (x0, y0, x1, y1) in RECTANGLES.items()}
        self.vaos = {name: self.ctx.vertex_array(self.program, [(buffer, "2f", "in_xy")])
                     for name, buffer in self.buffers.items()}
        self.context().aboutToBeDestroyed.connect(self._release, Qt.ConnectionType.DirectConnection)

    def _release(self) -> None:
        self.makeCurrent()
        try:
            for obj in [*self.vaos.values(), *self.buffers.values(), self.program]:
                obj.release()
            self.ctx.release()
        finally:
            self.doneCurrent()

    def paintGL(self) -> None:
        fbo = self.ctx.detect_framebuffer(self.defaultFramebufferObject())
        fbo.use()
        fbo.clear(0.0, 0.0, 0.0, 1.0)
        clear_stencil(fbo)
        before = snapshot()
        with stencil_state(MARK):
            self.vaos["left"].render(moderngl.TRIANGLE_STRIP)
        self.program["u_color"].value = (1.0, 0.0, 0.0, 1.0)
        with stencil_state(WHERE_MARKED):
            self.vaos["all"].render(moderngl.TRIANGLE_STRIP)
        after = snapshot()
        self.program["u_color"].value = (0.0, 1.0, 0.0, 1.0)
        self.vaos["top"].render(moderngl.TRIANGLE_STRIP)
        egl = ctypes.CDLL("libEGL.so.1")
        egl.eglGetCurrentContext.restype = ctypes.c_void_p
        self.seen = {"changed": differences(before, after), "stencil test after": after["GL_STENCIL_TEST"],
                     "stencil bits": int(GL.glGetFramebufferAttachmentParameteriv(
                         GL.GL_DRAW_FRAMEBUFFER, GL.GL_STENCIL_ATTACHMENT, GL.GL_FRAMEBUFFER_ATTACHMENT_STENCIL_SIZE)),
                     "samples": int(GL.glGetIntegerv(GL.GL_SAMPLES)), "egl context": egl.eglGetCurrentContext(),
                     "error": int(GL.glGetError())}


def rgb(image: QImage) -> np.ndarray:
    image = image.convertToFormat(QImage.Format.Format_RGBA8888)
    h, w = image.height(), image.width()
    return np.frombuffer(image.constBits(), np.uint8).reshape(h, image.bytesPerLine())[:, : 4 * w].reshape(h, w, 4)


def test_the_stencil_works_in_a_qt_gl_widget_and_leaves_no_state(qtbot):
    widget = StencilWidget()
    qtbot.addWidget(widget)
    widget.resize(64, 64)
    widget.show()
    qtbot.waitExposed(widget)
    image = rgb(widget.grabFramebuffer())  # draws a frame and reads it back, resolved
    seen = widget.seen
    print(f"\nQt, seen in paintGL: {seen}")
    assert seen["stencil bits"] == 8 and seen["samples"] == SAMPLES  # the app's format: stencil on a multisampled FBO
    assert seen["egl context"] is None  # Qt's context is GLX: PyOpenGL (EGL platform or not) still reached it
    assert seen["changed"] == {} and not seen["stencil test after"]
    assert seen["error"] == GL.GL_NO_ERROR
    h, w = image.shape[:2]
    strip, half = h // 8, w // 2
    assert (image[2: strip - 2, 2:-2, :3] == (0, 255, 0)).all()  # the strip: both halves
    assert (image[strip + 2:-2, 2: half - 2, :3] == (255, 0, 0)).all()  # red where the stencil was marked
    assert (image[strip + 2:-2, half + 2:-2, :3] == 0).all()  # nothing where it was not
