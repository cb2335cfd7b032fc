"""The central QOpenGLWidget: draws the current workspace through moderngl, on demand only."""
from __future__ import annotations

import gc
import time
from collections import deque

import moderngl
from PySide6.QtCore import Qt, QTimer, Signal
from PySide6.QtOpenGLWidgets import QOpenGLWidget

from app.gl.core.gl_state import GLStateError
from app.gl.core.workspace_renderer import EMPTY_BACKGROUND, WorkspaceRenderer
from app.views.keys import key_name
from app.views.tool import ViewportTool

SHADER_POLL_MS = 500
INTERACTIVE_GAP = 0.25  # a frame asked for this soon after the last is part of an interaction
IDLE_MS = 400           # then, once nothing moved for this long, a full-quality frame


class Viewport(QOpenGLWidget):
    """Repaints when the editor's version changes (see MainWindow), never in a spin loop."""

    frame_rendered = Signal(float)  # milliseconds, GPU work finished
    gl_error = Signal(str)
    gl_ready = Signal(str)  # the renderer's name, once the context exists
    key_command = Signal(str)  # a bound key was pressed: run this command line
    view_changed = Signal()    # view-only state of a tool (a selection) changed
    hovered = Signal(str)      # what the tool says lies under the cursor ("" once it leaves)

    def __init__(self, editor, parent=None) -> None:
        super().__init__(parent)
        self.editor = editor
        self.ctx: moderngl.Context | None = None
        self.renderer: WorkspaceRenderer | None = None
        self.frames = 0
        self.frame_ms: deque[float] = deque(maxlen=30)
        self.tool: ViewportTool | None = None  # the workspace's mouse and keys, set by MainWindow
        self.setFocusPolicy(Qt.FocusPolicy.StrongFocus)
        self.setMouseTracking(True)
        self.setMinimumSize(320, 240)
        self._shader_timer = QTimer(self, interval=SHADER_POLL_MS, timeout=self.poll_shaders)
        self._idle_timer = QTimer(self, singleShot=True, interval=IDLE_MS, timeout=self._idle)
        self._last_frame = 0.0
        self.interactive = False  # the last frame was asked for during an interaction
        self._refining = False    # the next frame is the full-quality one after an interaction
        self.preparing = False    # the window is making what a renderer needs: draw nothing yet
        self.gl_state_errors: list[str] = []  # in GL debug mode, what frames left behind (tests fail on any)
        self.paused = False       # a bench is measuring (set_paused): no frame asked for or drawn

    def initializeGL(self) -> None:
        self.ctx = moderngl.create_context()
        self.ctx.gc_mode = "context_gc"  # objects the renderer drops are freed by ctx.gc(), with the context current
        self.renderer = WorkspaceRenderer(self.ctx, on_shader_error=lambda e: self.gl_error.emit(str(e)))
        self.context().aboutToBeDestroyed.connect(self._release_gl, Qt.ConnectionType.DirectConnection)
        self._shader_timer.start()
        self.gl_ready.emit(f"{self.ctx.info['GL_RENDERER']}, OpenGL {self.ctx.version_code / 100:.1f}")

    def _release_gl(self) -> None:
        """The context is going (the window closes): free our GL objects while it can still be made current,
        and leave nothing current for the next context this thread uses."""
        self.makeCurrent()
        try:
            self._shader_timer.stop()
            self._idle_timer.stop()
            self.renderer.release()
            self.renderer = None
            gc.collect()  # the renderer's programs, buffers and textures, into the context's garbage list
            self._free_dropped()
            self.ctx.release()
            self.ctx = None
        finally:
            self.doneCurrent()

    def _free_dropped(self) -> None:
        """Free the GL objects Python dropped (moderngl's context_gc mode queues them until the context is
        current). One released already is queued too, as an InvalidObject with no release(), on which ctx.gc()
        would stop: the renderers release what they replace, so after a resize it did, and the context was
        never released."""
        queued = self.ctx.objects
        live = [obj for obj in queued if not isinstance(obj, moderngl.InvalidObject)]
        queued.clear()
        queued.extend(live)
        self.ctx.gc()

    def resizeGL(self, width: int, height: int) -> None:
        self.editor.workspaces.view_aspect = width / max(height, 1)  # what Frame All fits the scene to

    def set_paused(self, paused: bool) -> None:
        """Paused, the view keeps its last picture and draws nothing (the bench dock's measurement has the machine
        to itself); resumed, it draws what changed meanwhile."""
        self.paused = paused
        if not paused:
            self.update_full()

    def update(self, *args) -> None:
        """A frame, unless paused (then set_paused(False) asks for it)."""
        if not self.paused:
            super().update(*args)

    def paintGL(self) -> None:
        if self.paused:  # Qt asks too (the window uncovered): the last frame stays
            return
        start = time.perf_counter()
        self.interactive = start - self._last_frame < INTERACTIVE_GAP and not self._refining
        fbo = self.ctx.detect_framebuffer(self.defaultFramebufferObject())
        if self.preparing:
            fbo.clear(*EMPTY_BACKGROUND)
            return
        deferred = False
        try:
            deferred = self.renderer.render(fbo, self.editor.current, self.editor.render_settings(), self.interactive,
                                            self.editor.frame_budget_ms())
        except GLStateError as exc:  # debug mode: the frame is drawn, but left state or an error behind
            self.gl_state_errors.append(str(exc))
            self.gl_error.emit(str(exc))
        except Exception as exc:  # e.g. a shader that never compiled: say so, keep the editor alive
            fbo.clear(0.3, 0.05, 0.05, 1.0)
            self.gl_error.emit(str(exc))
        self.ctx.finish()
        self._free_dropped()
        self._last_frame = time.perf_counter()
        ms = (self._last_frame - start) * 1e3
        self.renderer.frame_took(ms)
        if deferred:
            self._idle_timer.start()
        self._refining = False
        if self.renderer.settling():  # a temporal history filling: the next frame at once (after events)
            QTimer.singleShot(0, self.update_full)
        self.frames += 1
        self.frame_ms.append(ms)
        self.frame_rendered.emit(ms)

    def value_at(self, pos):
        """What the last frame shows at a widget position (the workspace renderer's value_at), or None."""
        if self.renderer is None:
            return None
        ratio = self.devicePixelRatioF()
        size = (round(self.width() * ratio), round(self.height() * ratio))
        self.makeCurrent()
        try:
            return self.renderer.value_at(pos.x() * ratio, pos.y() * ratio, size)
        finally:
            self.doneCurrent()

    def settled(self) -> bool:
        """Whether the picture shown is final: nothing being prepared, no full frame owed after an interaction,
        no temporal history still filling."""
        busy = self.preparing or self._idle_timer.isActive()
        return not busy and (self.renderer is None or not self.renderer.settling())

    def update_full(self) -> None:
        """Ask for a frame that is not part of an interaction (time passing, a history filling): drawn at
        full quality however soon it follows the last."""
        self._refining = True
        self.update()

    def _idle(self) -> None:
        """Nothing moved for a while: catch up on deferred work and draw at full quality."""
        self.makeCurrent()
        try:
            self.renderer.idle()
        finally:
            self.doneCurrent()
        self._refining = True
        self.update()

    def forget_frame_times(self) -> None:
        """Another workspace is shown: its frames are timed from now on (an average over two workspaces says
        nothing of either)."""
        self.frame_ms.clear()

    def mean_frame_ms(self) -> float:
        """The mean time of the recent frames (Tex3Dtrace's statistic: 1000 / it is the frames per second they
        would sustain)."""
        return sum(self.frame_ms) / len(self.frame_ms) if self.frame_ms else 0.0

    def poll_shaders(self) -> None:
        """Hot reload: recompile shader files changed on disk; a broken edit keeps the old program."""
        if self.renderer is None or not self.isVisible():
            return
        self.makeCurrent()
        try:
            reloaded = self.renderer.shaders.reload_changed()
        finally:
            self.doneCurrent()
        if reloaded:
            self.update()

    def mousePressEvent(self, event) -> None:
        if self.tool:
            self.tool.press(event)

    def mouseMoveEvent(self, event) -> None:
        if self.tool:
            self.tool.move(event)
            self.hovered.emit(self.tool.hover(event))

    def leaveEvent(self, event) -> None:
        self.hovered.emit("")
        super().leaveEvent(event)

    def mouseReleaseEvent(self, event) -> None:
        if self.tool:
            self.tool.release(event)

    def wheelEvent(self, event) -> None:
        if self.tool:
            self.tool.wheel(event)

    def mouseDoubleClickEvent(self, event) -> None:
        if self.tool:
            self.tool.double_click(event)

    def selection_changed(self) -> None:
        """View-only state a tool draws (a selection, a hull being drawn) changed: redraw."""
        self.view_changed.emit()
        self.update()

    def keyPressEvent(self, event) -> None:
        """Keys run their `bind`ings (the current workspace's first, then the global ones)."""
        if self.tool and self.tool.key(event):
            return
        name = key_name(event.key())
        command = self.editor.binds.lookup(self.editor.workspace, name) if name else None
        if command and not event.modifiers() & (Qt.KeyboardModifier.ControlModifier | Qt.KeyboardModifier.AltModifier):
            self.key_command.emit(command)
        else:
            super().keyPressEvent(event)
