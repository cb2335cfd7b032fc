"""Each workspace's document: the file its scene came from or went to, and whether the scene changed since.

"Changed" compares the workspace's document_digest() with the one at the last save or load, so undoing back to
the saved state clears it. Before a line the user gave (typed, a menu, a panel, a key) drops unsaved changes,
`confirm` asks (the window sets it: save, discard or cancel); a headless editor never asks. Autosaves go into
a folder with a manifest (app/io/autosave.py) that says which file each scene was edited from, signed with the
editor's key: only what the editor itself autosaved is offered back. A recovered scene's first Save asks where
(Save As, offering its original file), whoever named that file."""
from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

from app.console import files
from app.console.console import Console
from app.console.quoting import join
from app.console.registry import CommandError, Reported
from app.io import autosave as autosave_file
from app.io.autosave import Autosaved
from app.io.json_file import JSONFileError, format_name
from app.model.workspace import Workspace, Workspaces
from app.resources import shipped


@dataclass(frozen=True)
class Document:
    path: str | None = None  # None: untitled
    saved: str | None = None  # the document digest when last saved or loaded; None: never (a recovered scene)
    by_script: bool = False  # a script, demo, config, bind or alias named the file: the user's Save never writes it
    recovered: bool = False  # from an autosave, not saved since: a plain Save does not write `path` unasked


class Documents:
    def __init__(self, console: Console, workspaces: Workspaces) -> None:
        self.console, self.workspaces = console, workspaces
        self._documents = {state.name: Document() for state in workspaces}
        # workspace -> its autosave: the document digest, the file and the file's SHA-256
        self._autosaved: dict[str, tuple[str, Path, str]] = {}
        # (workspace, the line that would drop its changes) -> go on; the window's save/discard/cancel dialog
        self.confirm: Callable[[Workspace, str], bool] | None = None
        self.path_listeners: list[Callable[[str], None]] = []  # every file a scene is opened from or saved to
        self.changes = 0  # counts renamings: a window retitles when it moves
        self._digests: dict[str, tuple[object, object, str]] = {}  # workspace -> (model, its version, digest)

    def digest(self, state: Workspace) -> str:
        """The workspace's document digest, kept while its document model stands unchanged."""
        model = state.document_model()
        if model is None:
            return state.document_digest()
        cached = self._digests.get(state.name)
        if cached is None or cached[0] is not model[0] or cached[1] != model[1]:
            cached = self._digests[state.name] = (*model, state.document_digest())
        return cached[2]

    def path(self, state: Workspace) -> str | None:
        return self._documents[state.name].path

    def save_path(self, state: Workspace) -> str | None:
        """Where a plain Save writes: the scene's file, unless it is untitled or one of the shipped resources
        (a sample opened and edited is saved as a new file, never over the sample), or of a format the workspace
        reads but does not write (a DICOM folder, a NIfTI file: Save asks where), or the scene was recovered
        from an autosave and not saved since (the file an autosave names is asked about, never written unasked), or
        a script named it (then Save asks where, as Save As does: state a script set is never used with the user's
        trust unasked)."""
        path = self.path(state)
        return None if path is None or shipped(path) or self.recovered(state) or self.named_by_script(state) or (
            state.files is not None and not state.files.writes(path)) else path

    def named_by_script(self, state: Workspace) -> bool:
        return self._documents[state.name].by_script

    def recovered(self, state: Workspace) -> bool:
        """Whether the scene was recovered from an autosave and not saved since."""
        return self._documents[state.name].recovered

    def suggested_path(self, state: Workspace) -> str | None:
        """The file Save As offers first: where a plain Save writes, else a recovered scene's original file."""
        path = self.path(state)
        return self.save_path(state) or (path if self.recovered(state) and not shipped(path) else None)

    def modified(self, state: Workspace) -> bool:
        return state.files is not None and self._documents[state.name].saved != self.digest(state)

    def named(self, state: Workspace, path: str | None, recovered: bool = False) -> None:
        """The scene is now the file `path` (None: untitled), as saved, unless it was `recovered` from an autosave."""
        path = None if path is None else os.path.abspath(path)
        self._documents[state.name] = Document(path, None if recovered else self.digest(state),
                                               by_script=path is not None and not self.console.trusted,
                                               recovered=recovered)
        self.changes += 1
        for listener in self.path_listeners if path is not None else ():
            listener(path)

    def forget_changes(self) -> None:
        """Every scene as it stands counts as saved (the start-up scenes; a window closed by its owner)."""
        for state in self.workspaces:
            self._documents[state.name] = Document(self.path(state), self.digest(state),
                                                   self._documents[state.name].recovered)
        self.changes += 1

    def may_replace(self, state: Workspace, line: str) -> None:
        """Before `line` puts another scene in `state`: if the user gave it and the scene has unsaved changes,
        ask; a cancel stops the command (Reported). Scripts, demos and configs are never asked."""
        users = all(origin.kind == "bind" for origin in self.console.origins)
        if self.confirm is None or not users or not self.modified(state):
            return
        if not self.confirm(state, line):
            self.console.print(f"{line}: cancelled; the unsaved changes are kept")
            raise Reported(line)

    def frame(self, state: Workspace, aspect: float | None = None) -> bool:
        """Frame All in `state` (the current workspace), for a view `aspect` wide per unit of height (None: the
        host's view). False: nothing to frame."""
        return self._run_camera(state.frame_commands(self.workspaces.view_aspect if aspect is None else aspect))

    def frame_loaded(self, state: Workspace) -> None:
        """A file just loaded is framed where it is not in view already (and its files keep no view of their own:
        Workspace.load_frame_commands)."""
        self._run_camera(state.load_frame_commands(self.workspaces.view_aspect))

    def _run_camera(self, lines: list[str]) -> bool:
        """The camera commands run as if typed, so a demo records them and replays the same camera whatever the
        size of the window it plays in."""
        for line in lines:
            if not self.console.execute(line, echo=False):
                raise Reported(line)
        return bool(lines)

    def owner(self, path: str) -> Workspace:
        """The workspace whose files `path` is: by its suffix, and for a suffix several share (.json) by the
        "format" the file names; else CommandError."""
        suffix = Path(path).suffix.lower()
        states = [s for s in self.workspaces if s.files is not None and s.files.suffix(path) is not None]
        if not states:  # a folder, or a file of no listed suffix, that a workspace knows as its own
            states = [s for s in self.workspaces if s.files is not None and s.files.claims and s.files.claims(path)]
        if len(states) > 1:
            try:
                name = format_name(path)
            except JSONFileError as exc:
                raise CommandError(str(exc)) from None
            states = [s for s in states if s.files.format is not None and s.files.format == name]
            if not states:
                raise CommandError(f"{path} is no scene file of any workspace (its format is {name!r})")
        if not states:
            raise CommandError(f"no workspace opens {suffix or 'files without a suffix'} "
                               f"(they open {', '.join(self.suffixes())})")
        return states[0]

    def suffixes(self) -> tuple[str, ...]:
        """Every suffix some workspace's files have."""
        return tuple(sorted({x for state in self.workspaces if state.files is not None for x in state.files.suffixes}))

    def written_suffixes(self) -> tuple[str, ...]:
        """The suffixes some workspace writes (those of `suffixes` not only read, and those of the files it writes
        beside them): what a snapshot, or a file beside it, may end in."""
        return tuple(sorted({x for state in self.workspaces if state.files is not None
                             for x in (*state.files.suffixes, *state.files.beside) if x not in state.files.read_only}))

    def track(self) -> None:
        """Each workspace's own verbs that replace its scene (SceneFiles.replacing) ask first and leave it
        untitled; its own load and save verbs (SceneFiles.verbs) name the file they return, the one they read
        or wrote, as scene.load and scene.save do. Their handlers are wrapped here, once every workspace has
        registered them."""
        for state in self.workspaces:
            if state.files is None:
                continue
            for verb in state.files.replacing:
                self._wrap(state, verb, ask=True, titled=False)
            if state.files.verbs is not None:
                load, save = state.files.verbs
                self._wrap(state, load, ask=True, titled=True)
                self._wrap(state, save, ask=False, titled=True)

    def _wrap(self, state: Workspace, verb: str, ask: bool, titled: bool) -> None:
        command = self.console.registry.resolve(f"{state.name}:{verb}", None)
        handler = command.handler

        def tracked(*args) -> None:
            if ask:  # a variadic argument is a list of words
                self.may_replace(state, join([verb, *(str(w) for a in args for w in (a if isinstance(a, list) else
                                                                                     [a]))]))
            path = handler(*args)
            self.named(state, path if titled else None)
            if ask and titled:  # a load verb
                self.frame_loaded(state)

        command.handler = tracked

    # ---- autosave -----------------------------------------------------------------------------------

    def autosave(self, folder: Path) -> int:
        """Save each scene with unsaved changes into `folder` (those unchanged since the last autosave stay as
        they are) and list them in its manifest, signed; a scene saved since loses its autosave. Returns how many
        scenes the folder holds."""
        key = self._autosave_key()
        folder.mkdir(mode=0o700, parents=True, exist_ok=True)
        kept = []
        for state in self.workspaces:
            if state.files is None:
                continue
            held = self._autosaved.pop(state.name, None)
            file = None
            if self.modified(state):
                file, digest = folder / f"{state.name}{state.files.keeping_suffix()}", self.digest(state)
                saved = held
                if held is None or held[:2] != (digest, file) or not file.is_file():
                    state.files.save(str(file))
                    saved = (digest, file, autosave_file.file_digest(file))
                self._autosaved[state.name] = saved
                kept.append(Autosaved(state.name, file, self.path(state), saved[2]))
            if held is not None and held[1] != file:  # saved since, or another format keeps the scene now
                held[1].unlink(missing_ok=True)
        autosave_file.write(folder, kept, key)
        return len(kept)

    def recoverable(self, folder: Path) -> list[Autosaved]:
        """The scenes an autosave folder holds that are newer than the files they were edited from (all the
        untitled ones), for workspaces this editor has. A folder whose manifest this editor did not write (no
        signature or a wrong one, a scene file changed since) gives none, and one console message."""
        try:
            scenes = autosave_file.read(folder, self._autosave_key())
        except autosave_file.AutosaveError as exc:
            self.console.error(f"autosave: {folder} is passed over: {exc}")
            return []
        found = []
        for scene in scenes:
            if scene.workspace not in self.workspaces:
                continue
            original = Path(scene.original) if scene.original else None
            if original is not None and original.is_file() and original.stat().st_mtime >= scene.file.lstat().st_mtime:
                continue
            found.append(scene)
        return found

    @staticmethod
    def _autosave_key() -> bytes:
        """Read each time: another session may have made it again (autosave_file.signing_key)."""
        return autosave_file.signing_key(files.config_dir() / autosave_file.KEY_FILE)
