"""What the window keeps between runs: its geometry, its docks' places and sizes, the recent files and the folder
the file dialogs start in, in an ini file in the user's config folder ($SHADELAB_CONFIG_DIR keeps tests apart
from the user's own)."""
from __future__ import annotations

from pathlib import Path

from PySide6.QtCore import QSettings, QStandardPaths

from app.console import files

RECENT_LIMIT = 10


def settings() -> QSettings:
    return QSettings(str(files.config_dir() / "window.ini"), QSettings.Format.IniFormat)


class Layout:
    """The window's geometry and dock layout: restored at start, saved on close. The layout the window was
    built with is the default that Reset Layout puts back."""

    def __init__(self, window) -> None:
        self.window = window
        self.default = window.saveState()

    def restore(self) -> bool:
        """The window's size and its docks' places as the last run left them; False: none were kept."""
        stored = settings()
        geometry, state = stored.value("window/geometry"), stored.value("window/state")
        if geometry is not None:
            self.window.restoreGeometry(geometry)
        if state is not None:
            self.window.restoreState(state)
        return state is not None

    def save(self) -> None:
        stored = settings()
        stored.setValue("window/geometry", self.window.saveGeometry())
        stored.setValue("window/state", self.window.saveState())

    def reset(self) -> None:
        self.window.restoreState(self.default)


class RecentFiles:
    """The files last opened or saved, newest first, kept in the settings."""

    KEY = "recent/files"

    def paths(self) -> list[str]:
        return settings().value(self.KEY, [], type=list)

    def add(self, path: str) -> None:
        paths = [path, *(p for p in self.paths() if p != path)]
        settings().setValue(self.KEY, paths[:RECENT_LIMIT])

    def clear(self) -> None:
        settings().setValue(self.KEY, [])


class FileFolder:
    """The folder Open and Save As start in: the last one a file was opened from or saved to, else the user's
    documents folder (their home without one). What window.ini says is input: anything but a folder that is
    there now is passed over."""

    KEY = "files/folder"

    def start(self) -> str:
        kept = settings().value(self.KEY)
        for folder in (kept, QStandardPaths.writableLocation(QStandardPaths.StandardLocation.DocumentsLocation)):
            if _is_folder(folder):
                return folder
        return str(Path.home())

    def remember(self, path: str) -> None:
        """`path`, a file just opened or saved: its folder is where the next dialog starts."""
        settings().setValue(self.KEY, str(Path(path).parent))


def _is_folder(value) -> bool:
    try:
        return isinstance(value, str) and Path(value).is_absolute() and Path(value).is_dir()
    except (OSError, ValueError):  # a name too long, a NUL in it
        return False
