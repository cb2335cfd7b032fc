"""What the window keeps between runs: its geometry, its docks' places and sizes, the recent files and the folder
the file dialogs start in, in an ini file in the user's config folder ($SHADELAB_CONFIG_DIR keeps tests apart
from the user's own). window.ini is input like any file: Qt's reader would wait for ever on a FIFO in its place,
so one that is not a regular file of at most MAX_BYTES is left alone and nothing is kept this session; and each
value it gives is checked for its type and sense before it is used."""
from __future__ import annotations

import re
from pathlib import Path

from PySide6.QtCore import QByteArray, QSettings, QStandardPaths

from app.console import files
from app.io.regular_file import open_regular

RECENT_LIMIT = 10
MAX_BYTES = 1 << 20  # the layout and ten paths take a few KiB
MAX_PATH = 4096
_CONTROL = re.compile(r"[\x00-\x1f\x7f-\x9f]")


def settings_path() -> Path:
    return files.config_dir() / "window.ini"


def settings_problem() -> str | None:
    """Why window.ini cannot be used (a FIFO, a folder, too big: "PATH: REASON"), or None: it can, or is not there."""
    path = settings_path()
    try:
        open_regular(path, MAX_BYTES).close()
    except FileNotFoundError:
        return None
    except OSError as exc:
        return f"{path}: {exc.strerror or exc}"
    return None


class _Unkept:
    """What settings() gives when window.ini cannot be used: every value its default, nothing written."""

    def value(self, _key: str, default=None, type=None):  # QSettings.value's keywords
        return default

    def setValue(self, _key: str, _value) -> None:  # QSettings's name
        pass


def settings() -> QSettings | _Unkept:
    return _Unkept() if settings_problem() else QSettings(str(settings_path()), QSettings.Format.IniFormat)


class Layout:
    """The window's geometry and dock layout: restored at start, saved on close. The layout the window was
    built with is the default that Reset Layout puts back."""

    def __init__(self, window) -> None:
        self.window = window
        self.default = window.saveState()

    def restore(self) -> bool:
        """The layout window.ini keeps, where it is one (Qt refuses a malformed one and keeps the default); a
        window.ini that cannot be read at all is said in the console. False: no dock layout was kept."""
        problem = settings_problem()
        if problem:
            self.window.editor.console.error(f"{problem}; the window's layout, recent files and folders are not "
                                             "kept this session (remove it to have them kept)")
        stored = settings()
        geometry, state = stored.value("window/geometry"), stored.value("window/state")
        if isinstance(geometry, QByteArray):  # a value of any other type (text, a number) is not one Qt wrote
            self.window.restoreGeometry(geometry)
        if isinstance(state, QByteArray):
            self.window.restoreState(state)
        return isinstance(state, QByteArray)

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
        """The files kept, newest first: those that are absolute paths Shadelab could have written there."""
        kept = settings().value(self.KEY, [])
        kept = [kept] if isinstance(kept, str) else kept if isinstance(kept, list) else []
        return [p for p in kept if _is_path(p)][:RECENT_LIMIT]

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


def _is_path(value) -> bool:
    """An absolute path in text a menu can show: no control character, no longer than MAX_PATH."""
    return (isinstance(value, str) and len(value) <= MAX_PATH and not _CONTROL.search(value)
            and Path(value).is_absolute())


def _is_folder(value) -> bool:
    try:
        return _is_path(value) and Path(value).is_dir()
    except (OSError, ValueError):  # a name too long
        return False
