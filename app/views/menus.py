"""The menu bar: File, Edit, View and Help. Every action runs a console command, as everything else does,
so a menu does nothing a typed line, a script or a demo could not; the dialogs are `ui.*` commands."""
from __future__ import annotations

import html
from importlib import metadata
from pathlib import Path

from PySide6 import __version__ as PYSIDE_VERSION
from PySide6.QtCore import QObject, Qt
from PySide6.QtGui import QAction, QKeySequence
from PySide6.QtWidgets import QDialog, QLabel, QMessageBox, QScrollArea, QVBoxLayout

from app.console.quoting import quote
from app.console.registry import SCRIPTS, CommandError
from app.model.workspaces import workspace_title
from app.views.docs_viewer import DocsViewer
from app.views.edit_keys import EditKeys
from app.views.layout_settings import RecentFiles
from app.views.weak_callback import weak_callback

DOCS = Path(__file__).resolve().parents[2] / "docs"  # beside the package in a source checkout
EDITOR_KEYS = (("`", "show or hide the console"), ("Ctrl+Z", "undo"), ("Ctrl+Shift+Z, Ctrl+Y", "redo"),
               ("Ctrl+N / Ctrl+O / Ctrl+S / Ctrl+Shift+S", "new, open, save, save as"), ("Ctrl+Q", "quit"),
               ("F", "frame the whole scene (View > Frame All; in the volume F is the wireframe, as in the seed)"))


def _table(rows, code: bool) -> str:
    cell = "<code>{}</code>" if code else "{}"
    return "<table>" + "".join(f"<tr><td><b>{html.escape(key)}</b>&nbsp;&nbsp;</td><td>"
                               f"{cell.format(html.escape(text))}</td></tr>" for key, text in rows) + "</table>"


def _version() -> str:
    try:
        return metadata.version("shadelab")
    except metadata.PackageNotFoundError:  # run from a checkout that was never installed
        return "(not installed)"


class Menus(QObject):
    def __init__(self, window) -> None:
        super().__init__(window)
        self.window = window
        self.recent = RecentFiles()
        self.keys_dialog: QDialog | None = None
        self.docs_viewer: DocsViewer | None = None
        bar = window.menuBar()

        file = bar.addMenu("&File")
        self.new = self._action(file, "&New", "scene.new", "Ctrl+N")
        self._action(file, "&Open...", "ui.open", "Ctrl+O")
        self._action(file, "Open &Folder...", "ui.openfolder")
        self.recent_menu = file.addMenu("Open &Recent")
        self.recent_menu.aboutToShow.connect(self._fill_recent)
        self.save = self._action(file, "&Save", "ui.save", "Ctrl+S")
        self.save_as = self._action(file, "Save &As...", "ui.saveas", "Ctrl+Shift+S")
        file.addSeparator()
        self._action(file, "&Quit", "quit", "Ctrl+Q")

        edit = bar.addMenu("&Edit")
        self.undo = self._action(edit, "&Undo", "undo", "Ctrl+Z")
        self.redo = self._action(edit, "&Redo", "redo", "Ctrl+Shift+Z", "Ctrl+Y")
        self.edit_keys = EditKeys(window, self.undo, self.redo)  # also from a text field with nothing to undo

        view = bar.addMenu("&View")
        view.aboutToShow.connect(self._check_docks)
        self.dock_actions = {}
        for key, dock in window.docks.items():
            action = view.addAction(dock.windowTitle())
            action.setCheckable(True)
            action.triggered.connect(lambda _checked=False, k=key: window.run(f"ui.dock {k}"))
            self.dock_actions[key] = action
        view.addSeparator()
        self._action(view, "&Frame All", "view.frame")  # key F: a global bind (default.cfg), as binds are keys
        self._action(view, "Reset &Layout", "ui.resetlayout")

        help_ = bar.addMenu("&Help")
        self._action(help_, "&Keys", "ui.keys")  # not F1: the volume binds F1-F11
        self._action(help_, "&Documentation", "ui.docs")
        self._action(help_, "&About Shadelab", "ui.about")
        self.menus = {"file": file, "edit": edit, "view": view, "help": help_}
        self._register()

    def _action(self, menu, text: str, line: str, *keys: str) -> QAction:
        action = menu.addAction(text)
        action.setShortcuts([QKeySequence(key) for key in keys])
        action.triggered.connect(lambda _checked=False: self.window.run(line))
        return action

    def _register(self) -> None:
        reg = self.window.editor.console.registry
        reg.command("ui.dock", "name [shown:int]", "Show (1) or hide (0) a dock, or toggle it: "
                    + ", ".join(self.window.docks), recorded=False, allow=SCRIPTS,
                    completer=lambda p: [k for k in self.window.docks if k.startswith(p)])(
            weak_callback(self, "show_dock"))
        reg.command("ui.resetlayout", "", "Put the docks and toolbars back where they start (View > Reset Layout)",
                    recorded=False, allow=SCRIPTS)(weak_callback(self.window, "reset_layout"))
        reg.command("ui.keys", "", "Show the keys and mouse of the current workspace (Help > Keys)",
                    recorded=False, allow=SCRIPTS)(weak_callback(self, "show_keys"))
        reg.command("ui.docs", "", "Open the current workspace's documentation (Help > Documentation)",
                    recorded=False, allow=SCRIPTS)(weak_callback(self, "open_docs"))
        reg.command("ui.about", "", "Say which Shadelab, Qt and OpenGL this is (Help > About)",
                    recorded=False, allow=SCRIPTS)(weak_callback(self, "about"))

    def sync(self) -> None:
        """Name the steps undo and redo would take, and offer file actions only where there are scene files."""
        editor = self.window.editor
        history = editor.current.history
        for action, verb, name in ((self.undo, "Undo", history.undo_name()), (self.redo, "Redo", history.redo_name())):
            action.setText(f"&{verb} {name}" if name else f"&{verb}")
            action.setEnabled(name is not None)
        has_files = editor.current.files is not None
        for action in (self.save, self.save_as):
            action.setEnabled(has_files)
        self.new.setEnabled(has_files and editor.current.files.new is not None)

    def _check_docks(self) -> None:
        """Tick the docks shown (closed by their own button, a layout restored or reset, a command)."""
        for key, action in self.dock_actions.items():
            action.setChecked(not self.window.docks[key].isHidden())

    def _fill_recent(self) -> None:
        self.recent_menu.clear()
        paths = self.recent.paths()  # window.ini, read once
        for path in paths:
            action = self.recent_menu.addAction(path)
            action.triggered.connect(lambda _checked=False, p=path: self.window.run(f"open {quote(p)}"))
        self.recent_menu.addSeparator()
        clear = self.recent_menu.addAction("Clear Menu", self.recent.clear)
        clear.setEnabled(bool(paths))

    # ---- the ui.* commands --------------------------------------------------------------------------

    def show_dock(self, name: str, shown: int | None = None) -> None:
        dock = self.window.docks.get(name)
        if dock is None:
            raise CommandError(f"no dock {name!r}; the docks are {', '.join(self.window.docks)}")
        dock.setVisible(dock.isHidden() if shown is None else bool(shown))
        if not dock.isHidden():
            dock.raise_()

    def show_keys(self) -> None:
        """A window beside the editor listing the view's mouse and keys, the bound keys and the editor's own."""
        editor = self.window.editor
        tool = self.window.tools.get(editor.workspace)
        binds = sorted((key, line) for (scope, key), line in editor.binds.table.items()
                       if scope in ("", editor.workspace))
        rows = [f"<h3>{html.escape(workspace_title(editor.workspace))}</h3>"]
        if tool is not None and tool.KEYS:
            rows.append(f"<p>{html.escape(tool.KEYS)}</p>")
        rows.append("<h4>Bound keys</h4>" + (_table(binds, code=True) if binds else
                                              "<p>No keys are bound here (<code>bind</code> binds one).</p>"))
        rows.append("<h4>Editor</h4>" + _table(EDITOR_KEYS, code=False))
        if self.keys_dialog is None:
            self.keys_dialog = QDialog(self.window, windowTitle="Keys")
            self.keys_label = QLabel(wordWrap=True, textFormat=Qt.TextFormat.RichText)
            self.keys_label.setAlignment(Qt.AlignmentFlag.AlignTop)
            scroll = QScrollArea(widgetResizable=True)
            scroll.setWidget(self.keys_label)
            QVBoxLayout(self.keys_dialog).addWidget(scroll)
            self.keys_dialog.resize(520, 560)
        self.keys_label.setText("".join(rows))
        self.keys_dialog.show()
        self.keys_dialog.raise_()

    def open_docs(self) -> None:
        page = DOCS / f"{self.window.editor.workspace}.md"
        if not page.is_file():
            page = DOCS.parent / "README.md"
        if not page.is_file():
            raise CommandError(f"the documentation is not installed with this copy (looked in {DOCS})")
        if self.docs_viewer is None:
            self.docs_viewer = DocsViewer(self.window, DOCS)
        self.docs_viewer.show_page(page)
        self.window.editor.console.print(f"showing {page.name}")

    def about(self) -> None:
        vp = self.window.viewport
        gl = vp.ctx.info["GL_RENDERER"] if vp.renderer is not None else "not started yet"
        QMessageBox.about(self.window, "About Shadelab",
                          f"<h3>Shadelab {_version()}</h3><p>A workbench for real-time lighting and volume "
                          f"techniques.</p><p>Qt {PYSIDE_VERSION} (PySide6)<br>OpenGL: {gl}</p>")
