"""The main window: the viewport in the middle, docks around it, a workspace switcher, menus, frame stats.
It knows no workspace by name: their tools and panels come from app/views/workspace_views.py, their files
from the workspace unit (app/views/documents.py)."""
from __future__ import annotations

from PySide6.QtCore import Qt, QTimer
from PySide6.QtGui import QAction, QActionGroup, QKeySequence
from PySide6.QtWidgets import QDockWidget, QLabel, QMainWindow, QProgressDialog, QStackedWidget

from app.console import files
from app.editor import Editor
from app.gl.core.workspace_renderer import RENDERERS
from app.model.workspaces import WORKSPACES
from app.views.autosave import AutosaveSession
from app.views.bench_dock import BenchDock
from app.views.console_widget import ConsoleWidget
from app.views.documents import DocumentsUI
from app.views.layout_settings import Layout
from app.views.menus import Menus
from app.views.status_bar import StatusParts
from app.views.viewport import Viewport
from app.views.weak_callback import weak_callback
from app.views.workspace_views import VIEWS


class MainWindow(QMainWindow):
    def __init__(self, editor: Editor | None = None) -> None:
        super().__init__()
        self.editor = editor or Editor()
        self.setWindowTitle("Shadelab")
        self.resize(1400, 860)
        self._drawn_version = None

        self.viewport = Viewport(self.editor)
        self.setCentralWidget(self.viewport)
        self.panels = QStackedWidget()
        self.placeholder = QLabel(alignment=Qt.AlignmentFlag.AlignCenter, wordWrap=True)
        self.panels.addWidget(self.placeholder)
        self.tools, self.workspace_panels = {}, {}
        for state in self.editor.workspaces:
            views = VIEWS[state.name]
            self.tools[state.name] = tool = views.tool(self.viewport, state, self.run) if views.tool else None
            if views.panel:
                self.workspace_panels[state.name] = panel = views.panel(self, state, tool)
                self.panels.addWidget(panel)
        self.console_widget = ConsoleWidget(self.editor.console, files.history_file())
        self.bench = BenchDock()
        self.bench.measuring.connect(self.viewport.set_paused)  # its measurement has the machine to itself
        self.docks = {
            "editor": self._dock("Editor", self.panels, Qt.DockWidgetArea.LeftDockWidgetArea),
            "console": self._dock("Console", self.console_widget, Qt.DockWidgetArea.BottomDockWidgetArea),
            "bench": self._dock("Speed vs accuracy", self.bench, Qt.DockWidgetArea.RightDockWidgetArea),
        }
        self.workspace_docks: dict[str, list[str]] = {}  # a workspace's name -> the keys of its own docks
        self._docks_kept: dict[str, bool] = {}  # a workspace dock's key -> shown when its workspace was left
        for state in self.editor.workspaces:
            for spec in VIEWS[state.name].docks:
                self.docks[spec.key] = dock = self._dock(spec.title, spec.make(self, state),
                                                         Qt.DockWidgetArea.RightDockWidgetArea)
                self.splitDockWidget(self.docks["bench"], dock, Qt.Orientation.Vertical)
                self.workspace_docks.setdefault(state.name, []).append(spec.key)
        self.resizeDocks([self.docks["bench"]], [420], Qt.Orientation.Horizontal)
        self.resizeDocks([self.docks["console"]], [170], Qt.Orientation.Vertical)

        self.workspace_actions = self._workspace_bar()
        toggle = QAction("Console", self, shortcut=QKeySequence("`"), triggered=self.toggle_console)
        self.addAction(toggle)
        self.console_widget.input.closed.connect(self.toggle_console)
        self.viewport.key_command.connect(self.run_bind)
        self.documents_ui = DocumentsUI(self)
        self.menus = Menus(self)
        self.autosave = AutosaveSession(self)

        # Demo playback and `wait` advance on a timer that runs only while they have work.
        self.ticker = QTimer(self, interval=10, timeout=self._tick)
        # The editor may outlive this window (tests, embedding): its listeners must not keep it alive.
        self.editor.demos.frame = weak_callback(self.viewport, "repaint")  # timedemo draws each frame now
        self.editor.console.quit_listeners.append(weak_callback(self, "close"))

        self.viewport.gl_ready.connect(self._gl_ready)
        self.viewport.gl_error.connect(self.editor.console.error)
        self.editor.console.executed_listeners.append(weak_callback(self, "refresh", drop_args=True))
        # after refresh among the listeners: a command's new workspace has its tool in the viewport by then
        self.status_parts = StatusParts(self.statusBar(), self.viewport, self.editor.console)
        self.refresh()
        self.status_parts.sync()
        self.layout_settings = Layout(self)  # the layout built above is the default Reset Layout puts back
        self._fit_on_show = not self.layout_settings.restore()
        self._show_workspace_docks(self.editor.workspace, leaving=self.editor.workspace)  # as restored, if current
        QTimer.singleShot(0, weak_callback(self.autosave, "offer_recovery"))  # once the window is up

    def _tick(self) -> None:
        self.editor.demos.update()  # a slice of the commands due: the window stays responsive through a demo
        self.editor.console.frame()
        self.refresh()
        player = self.editor.demos.player
        if player is not None:
            self.statusBar().showMessage(f"playing a demo: {player.index} of {len(player.events)} commands "
                                         "(Esc stops)")
        elif self.statusBar().currentMessage().startswith("playing a demo"):
            self.statusBar().clearMessage()
        if not (self.editor.demos.playing or self.editor.console.waiting):
            self.ticker.stop()

    def showEvent(self, event) -> None:
        """A hidden window ignores resizeDocks: fit the editor dock to the workspace once the window shows, so a
        window started on a workspace has the view every other way of showing it has."""
        super().showEvent(event)
        if self._fit_on_show:
            self._fit_on_show = False
            QTimer.singleShot(0, weak_callback(self, "_fit_current_dock"))

    def _fit_current_dock(self) -> None:
        self._fit_editor_dock(self.editor.workspace)

    def keyPressEvent(self, event) -> None:
        """Esc stops a demo playing (keys the viewport and the panels did not take come here)."""
        if event.key() == Qt.Key.Key_Escape and self.editor.demos.playing:
            self.run("stop")
        else:
            super().keyPressEvent(event)

    def closeEvent(self, event) -> None:
        """Unsaved scenes are saved or discarded first (or the window stays); the layout is kept, and Quake
        writes config.cfg on the way out: archived cvars, binds and aliases survive."""
        if not self.documents_ui.may_close():
            event.ignore()
            return
        self.layout_settings.save()
        self.autosave.end()
        self.editor.documents.confirm = None  # the editor may outlive the window: no one left to ask
        self.editor.demos.stop_all()
        self.editor.console.execute("writeconfig", echo=False)
        super().closeEvent(event)

    def _dock(self, title: str, widget, area) -> QDockWidget:
        dock = QDockWidget(title, self)
        dock.setObjectName(title)
        dock.setWidget(widget)
        self.addDockWidget(area, dock)
        return dock

    def _workspace_bar(self) -> dict[str, QAction]:
        bar = self.addToolBar("Workspaces")
        bar.setObjectName("Workspaces")
        group = QActionGroup(self)
        actions = {}
        for info in WORKSPACES:
            action = QAction(info.title, self, checkable=True)
            action.triggered.connect(lambda _=False, n=info.name: self.run(f"workspace {n}"))
            group.addAction(action)
            bar.addAction(action)
            actions[info.name] = action
        return actions

    def run(self, line: str) -> bool:
        """Every edit from a widget, the mouse or a key passes through the console (drags unechoed)."""
        return self.editor.console.execute(line, echo=None)

    def run_bind(self, line: str) -> bool:
        """A bound key's command: binds come from configs others may have written (docs/architecture.md rule 6)."""
        with self.editor.console.untrusted("bind"):
            return self.run(line)

    def toggle_console(self) -> None:
        dock = self.docks["console"]
        dock.setVisible(not dock.isVisible())
        if dock.isVisible():
            self.console_widget.input.setFocus()
        else:
            self.viewport.setFocus()

    def refresh(self) -> None:
        """Bring widgets in line with the model and redraw only if something drawn changed."""
        self.console_widget.sync()
        self.documents_ui.sync()
        self.menus.sync()
        if (self.editor.demos.playing or self.editor.console.waiting) and not self.ticker.isActive():
            self.ticker.start()
        version = self.editor.version()
        if version == self._drawn_version:
            return
        workspace = self.editor.workspace
        if self._drawn_version is None or workspace != self._drawn_version[0]:
            self._show_workspace(workspace)
        self._drawn_version = version
        panel = self.workspace_panels.get(workspace)
        if panel is not None:  # only the workspace in view: the others sync when shown
            panel.sync()
        for key in self.workspace_docks.get(workspace, ()):
            self.docks[key].widget().sync()
        self.viewport.update()

    def _show_workspace(self, name: str) -> None:
        self._show_workspace_docks(name, leaving=self._drawn_version[0] if self._drawn_version else None)
        self._prepare(name)
        self.workspace_actions[name].setChecked(True)
        self.viewport.forget_frame_times()
        self.viewport.tool = self.tools.get(name)
        self.panels.setCurrentWidget(self.workspace_panels.get(name, self.placeholder))
        self._fit_editor_dock(name)
        self.bench.show_workspace(name)

    def _show_workspace_docks(self, name: str, leaving: str | None) -> None:
        """A workspace's own docks show while it is current, as the user last left them there; the others' hide."""
        for key in self.workspace_docks.get(leaving, ()):
            self._docks_kept[key] = not self.docks[key].isHidden()
        for owner, keys in self.workspace_docks.items():
            for key in keys:
                self.docks[key].setVisible(owner == name and self._docks_kept.get(key, True))

    def _fit_editor_dock(self, name: str) -> None:
        self.resizeDocks([self.docks["editor"]], [VIEWS[name].dock_width], Qt.Orientation.Horizontal)

    def reset_layout(self) -> None:
        """View > Reset Layout: the docks and toolbar where the window first put them, every one shown."""
        self.layout_settings.reset()
        self._docks_kept.clear()
        self._show_workspace_docks(self.editor.workspace, leaving=None)
        self._fit_editor_dock(self.editor.workspace)

    def _prepare(self, name: str) -> None:
        """What the workspace's renderer makes once (noise textures), with a progress bar while something is
        made (the dialog exists only then: loading from the cache reports only finished parts)."""
        dialogs: list[QProgressDialog] = []

        def progress(what: str, fraction: float) -> None:
            if not dialogs and fraction < 1.0:
                dialogs.append(QProgressDialog("", "", 0, 1000, self, minimumDuration=300))
                dialogs[0].setCancelButton(None)
                dialogs[0].setWindowModality(Qt.WindowModality.WindowModal)
            if dialogs:
                dialogs[0].setLabelText(f"Making the {what} texture (once: it is cached)")
                dialogs[0].setValue(int(fraction * 999))  # a modal dialog processes events here
        self.viewport.preparing = True  # events are processed: no frame of a workspace half made
        try:
            RENDERERS[name].prepare(progress, self.editor.console.error)
        finally:
            self.viewport.preparing = False
            for dialog in dialogs:
                dialog.reset()
                dialog.deleteLater()

    def _gl_ready(self, renderer: str) -> None:
        self.editor.console.print(f"Shadelab on {renderer}. Type help for commands; ` toggles the console.")

