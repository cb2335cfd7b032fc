"""The headless EGL context is really current, or refuses to exist (issue 12, A)."""
import pytest
from PySide6.QtGui import QOffscreenSurface, QOpenGLContext

from app.gl.core.headless import ContextError, create_context, release_context


def test_a_current_qt_context_makes_create_context_refuse_clearly(qapp):
    """libglvnd allows one window-system API's context per thread: while Qt's (GLX) context is current,
    eglMakeCurrent is refused, and glcontext used to ignore that, so GL calls went to Qt's context."""
    surface = QOffscreenSurface()
    surface.create()
    qt = QOpenGLContext()
    assert qt.create()
    assert qt.makeCurrent(surface)
    try:
        with pytest.raises(ContextError, match="could not be made current"):
            create_context()
    finally:
        qt.doneCurrent()
    ctx = create_context()  # with Qt's context done, it works
    try:
        assert ctx.info["GL_RENDERER"]
    finally:
        release_context(ctx)
