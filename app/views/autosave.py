"""Autosave and crash recovery. Every few minutes the scenes with unsaved changes go into this session's
folder in the cache (app/io/cache.py), which a lock file marks as in use while the session runs. A clean exit
removes the folder; a folder whose lock no running process holds is a session that crashed, and the next
start offers its scenes back (those newer than their files, from manifests the editor signed) before removing it.

The cache is input like any folder. The autosave folder must be a folder (not a file, a FIFO or a symbolic link
to one of the user's: autosave is off for the session otherwise, and said so); only its entries named as sessions
name theirs, folders and not links, are looked at; and removing one unlinks the files in it, links as links,
never following one, never going into a folder in it."""
from __future__ import annotations

import html
import os
import re
import stat
import time
from pathlib import Path

from PySide6.QtCore import QLockFile, QObject, QTimer
from PySide6.QtWidgets import QMessageBox

from app.console.quoting import quote
from app.console.registry import CommandError
from app.io.autosave import Autosaved
from app.io.cache import cache_root
from app.io.regular_file import kind
from app.model.workspaces import workspace_title

AUTOSAVE_MS = 3 * 60 * 1000
LOCK = "lock"
SESSION = re.compile(r"[0-9]+-[0-9]+")  # f"{pid}-{time_ns}": the name of a session's folder


def autosave_root() -> Path:
    return cache_root() / "autosave"


def _lock(folder: Path) -> QLockFile:
    lock = QLockFile(str(folder / LOCK))
    lock.setStaleLockTime(0)  # stale only when its process is gone, however long a session runs
    return lock


def _problem(path: Path, regular: bool = False) -> str | None:
    """Why `path` is not a folder (with `regular`, a regular file) in its own right, never a link to one: "PATH is
    a FIFO (named pipe), not a folder"; None if it is one, or nothing is there."""
    try:
        mode = os.lstat(path).st_mode
    except FileNotFoundError:
        return None
    except OSError as exc:
        return f"{path}: {exc.strerror or exc}"
    if stat.S_ISREG(mode) if regular else stat.S_ISDIR(mode):
        return None
    return f"{path} is {kind(mode)}, not {'a regular file' if regular else 'a folder'}"


def _remove(folder: Path) -> None:
    """Remove a session's folder, which must be a folder itself: the files in it go (a link as a link, never what it
    names), then the folder if that left it empty. Nothing is followed, nothing below it entered."""
    if _problem(folder):
        return
    try:
        with os.scandir(folder) as entries:
            for entry in entries:
                if not entry.is_dir(follow_symlinks=False):
                    os.unlink(entry.path)
        os.rmdir(folder)
    except OSError:  # a folder in it, a file of someone else's: left for the user
        pass


class AutosaveSession(QObject):
    def __init__(self, window) -> None:
        super().__init__(window)
        self.window = window
        self.folder: Path | None = autosave_root() / f"{os.getpid()}-{time.time_ns()}"
        self.lock = None
        problem = _problem(autosave_root())
        try:
            if problem is None:
                self.folder.mkdir(mode=0o700, parents=True)
        except OSError as exc:
            problem = f"{self.folder}: {exc.strerror or exc}"
        if problem is not None:
            self.folder = None
            window.editor.console.error(f"autosave is off this session: {problem} (remove it, or make it a folder, "
                                        "to have autosave back)")
            return
        self.lock = _lock(self.folder)
        self.lock.tryLock(0)
        self.timer = QTimer(self, interval=AUTOSAVE_MS, timeout=self.save)
        self.timer.start()

    def save(self) -> int:
        """Autosave now; how many scenes the folder holds (a failure is said in the console, nothing stops)."""
        if self.folder is None:
            return 0
        try:
            return self.window.editor.documents.autosave(self.folder)
        except (OSError, ValueError, CommandError) as exc:  # a full disk; a format that refuses the scene
            self.window.editor.console.error(f"autosave into {self.folder} failed: {exc}")
            return 0

    def end(self) -> None:
        """A clean exit: nothing to recover."""
        if self.folder is None:
            return
        self.timer.stop()
        self.lock.unlock()
        _remove(self.folder)

    def crashed(self) -> list[tuple[Path, QLockFile]]:
        """Other sessions' folders that no running process holds, each with its lock (taken now). Only folders
        named as sessions name theirs, with no lock or a regular file for one (Qt would wait on a FIFO)."""
        if self.folder is None:
            return []
        found = []
        try:
            with os.scandir(autosave_root()) as entries:
                names = sorted(e.name for e in entries if SESSION.fullmatch(e.name) and e.is_dir(follow_symlinks=False))
        except OSError:
            return []
        for name in names:
            folder = autosave_root() / name
            if folder == self.folder:
                continue
            problem = _problem(folder / LOCK, regular=True)
            if problem is not None:
                self.window.editor.console.error(f"autosave: {folder} is passed over: {problem}")
                continue
            lock = _lock(folder)
            if lock.tryLock(0):
                found.append((folder, lock))
        return found

    def offer_recovery(self) -> None:
        """Offer back the scenes of sessions that did not exit cleanly, the newest autosave of each
        workspace; their folders go whatever the answer."""
        crashed = self.crashed()
        newest: dict[str, Autosaved] = {}
        for folder, _lock_file in crashed:
            for scene in self.window.editor.documents.recoverable(folder):
                kept = newest.get(scene.workspace)
                if kept is None or kept.file.lstat().st_mtime < scene.file.lstat().st_mtime:
                    newest[scene.workspace] = scene
        if newest and self._ask(list(newest.values())):
            for scene in newest.values():
                original = f" {quote(scene.original)}" if scene.original else ""
                self.window.run(f"recover {quote(str(scene.file))}{original}")
        for folder, lock in crashed:
            lock.unlock()
            _remove(folder)

    def _ask(self, scenes: list[Autosaved]) -> bool:
        names = "".join(f"<li>{workspace_title(s.workspace)}: "
                        f"{html.escape(Path(s.original).name) if s.original else 'untitled'}</li>" for s in scenes)
        answer = QMessageBox.question(self.window, "Recover unsaved work",
                                      f"<p>Shadelab did not exit cleanly last time. Recover the scenes it "
                                      f"autosaved?</p><ul>{names}</ul><p>They open as unsaved changes; the first "
                                      "Save asks where.</p>")
        return answer == QMessageBox.StandardButton.Yes

