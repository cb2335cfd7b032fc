"""The window's side of documents (app/commands/documents.py): the title names the current workspace's file
and marks unsaved changes; File > Open and Save As choose files in dialogs filtered by the workspaces'
formats; and before a line drops unsaved changes (a sample, Open, New) or the window closes, a dialog asks
to save, discard or cancel. What a dialog chooses runs as a console command, as the user's own line."""
from __future__ import annotations

import shlex
from pathlib import Path

from PySide6.QtCore import QObject
from PySide6.QtWidgets import QFileDialog, QMessageBox

from app.console.registry import CommandError
from app.model.workspace import Workspace
from app.model.workspaces import workspace_title
from app.views.layout_settings import RecentFiles
from app.views.weak_callback import weak_callback

APP = "Shadelab"
Button = QMessageBox.StandardButton


def name_filter(title: str, suffixes) -> str:
    return f"{title} ({' '.join('*' + s for s in suffixes)})"


class DocumentsUI(QObject):
    def __init__(self, window) -> None:
        super().__init__(window)
        self.window = window
        self.editor = window.editor
        self.documents = window.editor.documents
        self.documents.confirm = weak_callback(self, "confirm", gone=True)  # no window left to ask: go on
        self.documents.path_listeners.append(RecentFiles().add)
        self._titled = None
        reg = self.editor.console.registry
        reg.command("ui.open", "", "Choose a file to open in its workspace (File > Open)", recorded=False)(
            weak_callback(self, "open_dialog"))
        reg.command("ui.save", "", "Save the scene to its file, or choose one if it is untitled (File > Save)",
                    recorded=False)(weak_callback(self, "save"))
        reg.command("ui.saveas", "", "Choose a file to save the scene to (File > Save As)", recorded=False)(
            weak_callback(self, "save_as"))

    @property
    def asking(self) -> bool:
        """Whether this window asks before unsaved changes go (an embedding host or a test may turn it off by
        setting documents.confirm to None)."""
        return self.documents.confirm is not None

    def sync(self) -> None:
        """Title the window "file.json* — 2D lighting — Shadelab" (the star while there are unsaved changes)."""
        state = self.editor.current
        key = (self.editor.version(), self.documents.changes)
        if key == self._titled:
            return
        self._titled = key
        title = workspace_title(state.name)
        if state.files is None:
            self.window.setWindowTitle(f"{title} — {APP}")
            self.window.setWindowModified(False)
            return
        self.window.setWindowTitle(f"{self.file_name(state)}[*] — {title} — {APP}")
        self.window.setWindowModified(self.documents.modified(state))

    def file_name(self, state: Workspace) -> str:
        path = self.documents.path(state)
        return Path(path).name if path else "untitled"

    # ---- asking -------------------------------------------------------------------------------------

    def confirm(self, state: Workspace, doing: str) -> bool:
        """Save, discard or cancel the unsaved changes of `state`'s scene before `doing`; True: go on. The
        workspace is shown first, so the question is about what the user sees."""
        if state.name != self.editor.workspace:
            self.window.run(f"workspace {state.name}")
        box = QMessageBox(QMessageBox.Icon.Warning, "Unsaved changes",
                          f"The {workspace_title(state.name)} scene {self.file_name(state)} has unsaved changes.",
                          Button.Save | Button.Discard | Button.Cancel, self.window)
        box.setInformativeText(f"Save them before {doing}?")
        box.setDefaultButton(Button.Save)
        answer = box.exec()
        if answer == Button.Discard:
            return True
        if answer == Button.Save:
            with self.editor.console.as_user():  # the user chose to save, whichever key asked
                return self.save()
        return False

    def may_close(self) -> bool:
        """Before the window closes: save, discard or cancel for each scene with unsaved changes."""
        return not self.asking or all(self.confirm(state, "closing Shadelab") for state in self.editor.workspaces
                                      if self.documents.modified(state))

    # ---- files --------------------------------------------------------------------------------------

    def open_dialog(self) -> bool:
        """Choose a file: the current workspace's formats first, then every workspace's."""
        current = self.editor.current
        with_files = [s for s in self.editor.workspaces if s.files is not None]
        filters = [name_filter(f"{workspace_title(s.name)} files", s.files.suffixes)
                   for s in sorted(with_files, key=lambda s: s is not current)]
        every = name_filter("Every Shadelab file", self.documents.suffixes())
        filters.insert(1 if current.files is not None else 0, every)
        recent = RecentFiles().paths()
        folder = str(Path(recent[0]).parent) if recent else ""  # beside the newest recent file
        path, _ = QFileDialog.getOpenFileName(self.window, "Open", folder, ";;".join([*filters, "All files (*)"]))
        return bool(path) and self._run_chosen(f"open {shlex.quote(path)}")

    def save(self) -> bool:
        """File > Save: to the scene's file, or to one chosen in a dialog if it is untitled. True: saved."""
        if self.documents.save_path(self.editor.current) is None:
            return self.save_as()
        return self.window.run("scene.save")

    def save_as(self) -> bool:
        state = self.editor.current
        if state.files is None:
            raise CommandError(f"the {state.name} workspace has no scene files")
        title = f"{workspace_title(state.name)} files"
        path, _ = QFileDialog.getSaveFileName(self.window, "Save As", self.documents.path(state) or "",
                                              name_filter(title, state.files.suffixes))
        if not path:
            return False
        if not Path(path).suffix:
            path += state.files.keeping_suffix()  # a scalar volume: .nrrd, which keeps its window
        return self._run_chosen(f"scene.save {shlex.quote(path)}")

    def _run_chosen(self, line: str) -> bool:
        with self.editor.console.as_user():  # what the user chose in a dialog, whichever key opened it
            return self.window.run(line)
