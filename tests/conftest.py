import gc
import os
import tempfile

import pytest

from app.gl.core.headless import create_context, release_context

# Keep tests away from the user's cache (shader .prs files, bench results).
os.environ["SHADELAB_CACHE_DIR"] = tempfile.mkdtemp(prefix="shadelab-test-cache-")
# Every frame's GL state read back: a renderer that leaves state or an error behind fails its test.
os.environ["SHADELAB_GL_DEBUG"] = "1"


@pytest.fixture(autouse=True)
def user_config_dir(tmp_path, monkeypatch):
    """Each test starts with an empty user config folder (history, config.cfg)."""
    path = tmp_path / "user-config"
    monkeypatch.setenv("SHADELAB_CONFIG_DIR", str(path))
    return path


def release_qt_windows() -> None:
    """Destroy every Qt window still alive and leave no Qt GL context current in this thread.

    A thread can have a current context of only one window-system API (libglvnd), so a window's GLX context
    left current would make the next EGL fixture's context fail to become current."""
    from PySide6.QtCore import QCoreApplication, QEvent
    from PySide6.QtGui import QOpenGLContext
    from PySide6.QtWidgets import QApplication

    if QApplication.instance() is None:
        return
    for widget in QApplication.topLevelWidgets():
        if _shared(widget):
            continue
        widget.close()
        widget.deleteLater()
    for _ in range(2):  # the second pass deletes what the first one's deletions posted
        QCoreApplication.sendPostedEvents(None, QEvent.Type.DeferredDelete)
        gc.collect()
    current = QOpenGLContext.currentContext()
    if current is not None:
        current.doneCurrent()


SHARED = "shadelab_shared_window"  # a Qt property: the window of `module_window`, which per-test cleanup spares


def _shared(widget) -> bool:
    """A module's shared window or one of its own (its menus, its dialogs)."""
    while widget is not None:
        if widget.property(SHARED):
            return True
        widget = widget.parentWidget()
    return False


@pytest.fixture(autouse=True)
def _qt_windows_die_with_their_test(request):
    """Tests that open windows (through qtbot) leave none behind for the next test."""
    yield
    if "qtbot" in request.fixturenames:
        left = gl_state_errors()
        release_qt_windows()
        assert not left, f"frames left GL state or errors behind: {left}"


def gl_state_errors() -> list[str]:
    """What the frames of every open window's viewport left behind (app/gl/core/gl_state.py), in GL debug mode."""
    from PySide6.QtWidgets import QApplication

    from app.views.viewport import Viewport

    if QApplication.instance() is None:
        return []
    viewports = [getattr(w, "viewport", None) for w in QApplication.topLevelWidgets()]  # the main windows'
    return [e for vp in viewports if isinstance(vp, Viewport) for e in vp.gl_state_errors]


@pytest.fixture
def volume_editor(tmp_path, monkeypatch):
    """An editor in the volume workspace (undo acts on the workspace in view), working in tmp_path."""
    from app.console.demo import VirtualClock
    from app.editor import Editor

    monkeypatch.chdir(tmp_path)
    editor = Editor(clock=VirtualClock())
    assert editor.execute("workspace volume")
    return editor


@pytest.fixture(scope="module")
def gl():
    """A headless EGL context (Mesa llvmpipe here), current, with a small framebuffer bound."""
    release_qt_windows()
    ctx = create_context()
    fbo = ctx.simple_framebuffer((8, 8))
    fbo.use()  # an EGL context has no default framebuffer
    yield ctx
    fbo.release()
    release_context(ctx)  # Qt tests later in this process need no EGL context current


def pytest_configure(config):
    # The GL surface format must be set before pytest-qt creates the QApplication.
    from app.views.application import set_surface_format

    set_surface_format()


def _never_ask(w) -> None:
    w.editor.documents.confirm = None


def _shown(bot, w):
    """`w` shown on the test's X server (pytest-xvfb), active, with a frame drawn."""
    w.show()
    bot.waitExposed(w)
    w.windowHandle().requestActivate()  # no window manager under Xvfb activates it for us
    bot.waitUntil(lambda: w.isActiveWindow(), timeout=5000)
    bot.waitUntil(lambda: w.viewport.frames > 0, timeout=10000)
    return w


@pytest.fixture
def make_window(qtbot):
    """Open a main window on its default scene, shown on the test's X server (pytest-xvfb). Unless `asks`, it
    does not ask to save unsaved changes before they go (a sample, closing): a dialog would wait for an answer
    no test gives. The tests of those questions make one that asks, and answer; none asks when the test ends."""
    from app.views.main_window import MainWindow

    def make(asks: bool = False):
        w = MainWindow()
        if not asks:
            _never_ask(w)
        qtbot.addWidget(w, before_close_func=_never_ask)
        return _shown(qtbot, w)

    return make


@pytest.fixture(scope="module")
def module_window(qapp, request, tmp_path_factory):
    """One main window for all of a module's tests, as make_window opens it (one takes seconds to open); the
    per-test cleanup spares it and it closes at the module's end. Its tests share its state: the module must put
    back what they change before each test (tests run in any order)."""
    from pytestqt.qtbot import QtBot

    from app.views.main_window import MainWindow

    with pytest.MonkeyPatch.context() as patch:  # its config folder: the tests' own come later
        patch.setenv("SHADELAB_CONFIG_DIR", str(tmp_path_factory.mktemp("user-config")))
        w = MainWindow()
        _never_ask(w)
        try:
            _shown(QtBot(request), w)
            # Spared with its parentless parts (pyqtgraph's menus), which it uses as long as it lives.
            for widget in qapp.topLevelWidgets():
                widget.setProperty(SHARED, True)
            yield w
        finally:
            for widget in qapp.topLevelWidgets():
                widget.setProperty(SHARED, False)
            # The window goes before its parentless parts, as pytest-qt closes a test's window before
            # release_qt_windows: a chart deleted after its menu crashes.
            w.close()
            w.deleteLater()
            qapp.processEvents()
            release_qt_windows()


@pytest.fixture
def window(make_window):
    return make_window()

