"""The window's side of documents (app/commands/documents.py): the title names the current workspace's file
and marks unsaved changes; File > Open and Save As choose files in dialogs filtered by the workspaces'
formats, and start in the folder of the file last opened or saved (app/views/layout_settings.py); before a line
drops unsaved changes (a sample, Open, New) a dialog asks to save, discard or cancel, and before the window closes
one dialog asks it for every changed scene. What a dialog chooses runs as a console command, as the user's own
line."""
from __future__ import annotations

from pathlib import Path

from PySide6.QtCore import QObject
from PySide6.QtWidgets import QFileDialog, QMessageBox

from app.console.quoting import quote
from app.console.registry import CommandError
from app.model.workspace import Workspace
from app.model.workspaces import workspace_title
from app.resources import shipped
from app.views.layout_settings import FileFolder, RecentFiles
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
        self.documents.path_listeners += [RecentFiles().add, weak_callback(self, "_remember_folder")]
        self._titled = None
        reg = self.editor.console.registry
        reg.command("ui.open", "", "Choose a file to open in its workspace (File > Open)", recorded=False)(
            weak_callback(self, "open_dialog"))
        reg.command("ui.openfolder", "", "Choose a folder to open: a DICOM series (File > Open Folder)",
                    recorded=False)(weak_callback(self, "open_folder_dialog"))
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
        return self._ask([state], doing)

    def may_close(self) -> bool:
        """Before the window closes: one question for all the scenes with unsaved changes."""
        changed = [state for state in self.editor.workspaces if self.documents.modified(state)]
        return not self.asking or not changed or self._ask(changed, "closing Shadelab")

    def _ask(self, states: list[Workspace], doing: str) -> bool:
        """One dialog before `doing`: save the unsaved changes of every scene in `states`, discard them or cancel;
        True: go on. Several are listed by workspace and file, with Save All and Discard All."""
        if len(states) == 1:
            text = f"The {workspace_title(states[0].name)} scene {self.file_name(states[0])} has unsaved changes."
            info, save = f"Save them before {doing}?", Button.Save
        else:
            text = f"{len(states)} scenes have unsaved changes:"
            listed = "\n".join(f"• {workspace_title(state.name)}: {self.file_name(state)}" for state in states)
            info, save = f"{listed}\n\nSave them before {doing}?", Button.SaveAll
        box = QMessageBox(QMessageBox.Icon.Warning, "Unsaved changes", text, save | Button.Discard | Button.Cancel,
                          self.window)
        box.setInformativeText(info)
        box.setDefaultButton(save)
        if save == Button.SaveAll:
            box.button(Button.Discard).setText("Discard All")
        answer = box.exec()
        if answer == Button.Discard:
            return True
        if answer == save:
            with self.editor.console.as_user():  # the user chose to save, whichever key asked
                return all(self._save_scene(state) for state in states)  # a Save As cancelled stops here
        return False

    def _save_scene(self, state: Workspace) -> bool:
        """Save `state`'s scene, shown first: an untitled one or a shipped sample asks where in Save As."""
        if state.name != self.editor.workspace and not self.window.run(f"workspace {state.name}"):
            return False
        return self.save()

    # ---- files --------------------------------------------------------------------------------------

    def open_dialog(self) -> bool:
        """Choose a file: the current workspace's formats first, then every workspace's."""
        current = self.editor.current
        with_files = [s for s in self.editor.workspaces if s.files is not None]
        filters = [name_filter(f"{workspace_title(s.name)} files", s.files.suffixes)
                   for s in sorted(with_files, key=lambda s: s is not current)]
        every = name_filter("Every Shadelab file", self.documents.suffixes())
        filters.insert(1 if current.files is not None else 0, every)
        path, _ = QFileDialog.getOpenFileName(self.window, "Open", FileFolder().start(),
                                              ";;".join([*filters, "All files (*)"]))
        return bool(path) and self._run_chosen(f"open {quote(path)}")

    def open_folder_dialog(self) -> bool:
        """Choose a folder: what a workspace reads as one file (a DICOM series, its slices a file each)."""
        path = QFileDialog.getExistingDirectory(self.window, "Open Folder (a DICOM series)", FileFolder().start())
        return bool(path) and self._run_chosen(f"open {quote(path)}")

    def save(self) -> bool:
        """File > Save: to the scene's file, or to one chosen in a dialog if it is untitled (or recovered and not
        saved since). True: saved."""
        if self.documents.save_path(self.editor.current) is None:
            return self.save_as()
        return self.window.run("scene.save")

    def save_as(self) -> bool:
        state = self.editor.current
        if state.files is None:
            raise CommandError(f"the {state.name} workspace has no scene files")
        title = workspace_title(state.name)
        shown = self.documents.path(state)  # a sample's name is offered in the user's folder, never its own
        start = (self.documents.suggested_path(state)  # a recovered scene's original: the user says if it goes there
                 or str(Path(FileFolder().start(), Path(shown).name if shown else "")))
        path, _ = QFileDialog.getSaveFileName(self.window, f"Save As — {title} scene", start,
                                              name_filter(f"{title} files", state.files.suffixes))
        if not path:
            return False
        if not Path(path).suffix:
            path += state.files.keeping_suffix()  # a scalar volume: .nrrd, which keeps its window
        return self._run_chosen(f"scene.save {quote(path)}")

    def _remember_folder(self, path: str) -> None:
        """The folder of a file the user opened or saved is where the next dialog starts (not a script's, nor
        the shipped samples' folder)."""
        if self.editor.console.trusted and not shipped(path):
            FileFolder().remember(path)

    def _run_chosen(self, line: str) -> bool:
        with self.editor.console.as_user():  # what the user chose in a dialog, whichever key opened it
            return self.window.run(line)
