"""Autosave and crash recovery. Every few minutes the scenes with unsaved changes go into this session's
folder in the cache (app/io/cache.py), which a lock file marks as in use while the session runs. A clean exit
removes the folder; a folder whose lock no running process holds is a session that crashed, and the next
start offers its scenes back (those newer than their files) before removing it."""
from __future__ import annotations

import os
import shlex
import shutil
import time
from pathlib import Path

from PySide6.QtCore import QLockFile, QObject, QTimer
from PySide6.QtWidgets import QMessageBox

from app.console.registry import CommandError
from app.io.autosave import Autosaved
from app.io.cache import cache_root
from app.model.workspaces import workspace_title

AUTOSAVE_MS = 3 * 60 * 1000
LOCK = "lock"


def autosave_root() -> Path:
    return cache_root() / "autosave"


def _lock(folder: Path) -> QLockFile:
    lock = QLockFile(str(folder / LOCK))
    lock.setStaleLockTime(0)  # stale only when its process is gone, however long a session runs
    return lock


class AutosaveSession(QObject):
    def __init__(self, window) -> None:
        super().__init__(window)
        self.window = window
        self.folder = autosave_root() / f"{os.getpid()}-{time.time_ns()}"
        self.folder.mkdir(parents=True, exist_ok=True)
        self.lock = _lock(self.folder)
        self.lock.tryLock(0)
        self.timer = QTimer(self, interval=AUTOSAVE_MS, timeout=self.save)
        self.timer.start()

    def save(self) -> int:
        """Autosave now; how many scenes the folder holds (a failure is said in the console, nothing stops)."""
        try:
            return self.window.editor.documents.autosave(self.folder)
        except (OSError, ValueError, CommandError) as exc:  # a full disk; a format that refuses the scene
            self.window.editor.console.error(f"autosave into {self.folder} failed: {exc}")
            return 0

    def end(self) -> None:
        """A clean exit: nothing to recover."""
        self.timer.stop()
        self.lock.unlock()
        shutil.rmtree(self.folder, ignore_errors=True)

    def crashed(self) -> list[tuple[Path, QLockFile]]:
        """Other sessions' folders that no running process holds, each with its lock (taken now)."""
        found = []
        root = autosave_root()
        for folder in sorted(root.iterdir()) if root.is_dir() else ():
            if folder != self.folder and folder.is_dir():
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
                if kept is None or kept.file.stat().st_mtime < scene.file.stat().st_mtime:
                    newest[scene.workspace] = scene
        if newest and self._ask(list(newest.values())):
            for scene in newest.values():
                original = f" {shlex.quote(scene.original)}" if scene.original else ""
                self.window.run(f"recover {shlex.quote(str(scene.file))}{original}")
        for folder, lock in crashed:
            lock.unlock()
            shutil.rmtree(folder, ignore_errors=True)

    def _ask(self, scenes: list[Autosaved]) -> bool:
        names = "".join(f"<li>{workspace_title(s.workspace)}: {Path(s.original).name if s.original else 'untitled'}"
                        "</li>" for s in scenes)
        answer = QMessageBox.question(self.window, "Recover unsaved work",
                                      f"<p>Shadelab did not exit cleanly last time. Recover the scenes it "
                                      f"autosaved?</p><ul>{names}</ul><p>They open as unsaved changes.</p>")
        return answer == QMessageBox.StandardButton.Yes
