"""Atomic writes: a crash mid-save never leaves a half-written file in place of a good one.

A save writes the whole file to `.NAME.XXXXXXXX.tmp` beside the target, fsyncs it, renames it over the target
and fsyncs the folder, so the rename itself survives a power cut. Saving to a symlink replaces the file it points
to (the link stays); a replaced file keeps its permission bits, and a new one gets what the umask gives any new
file (0644 under umask 022). A temporary file left by a killed save is removed by a later save of the same name
once it is STALE_AFTER_S old; a live save only writes its temporary file for as long as one write() takes, so a
concurrent save of the same name never loses its file. A name so long that the temporary file's would pass the
file system's limit is cut short in the temporary file's name, so every name the file system takes can be saved.
"""
from __future__ import annotations

import os
import re
import secrets
import stat
import time
from contextlib import suppress
from pathlib import Path

STALE_AFTER_S = 600
NAME_MAX = 255  # bytes in a file name, where the file system does not say (POSIX's NAME_MAX on Linux and macOS)
_TEMP_NAME = re.compile(r"\.(.+)\.[a-z0-9_]{8}\.tmp")  # also matches the names tempfile.mkstemp used to make
_TEMP_EXTRA = len("..12345678.tmp")  # what a temporary file's name adds to its target's


class Batch:
    """Files replaced together: stage() writes each in full to its temporary file, commit() then renames them all
    into place in staging order. A failed stage() (a full disk) leaves every target untouched; leaving the
    `with` block removes the temporary files that were not renamed."""

    def __init__(self) -> None:
        self._staged: list[tuple[Path, Path]] = []  # (temporary file, target)
        self._stale: dict[Path, dict[str, list[Path]]] = {}  # folder -> target name -> its stale temporary files

    def __enter__(self) -> Batch:
        return self

    def __exit__(self, *exc_info: object) -> None:
        for tmp, _ in self._staged:
            tmp.unlink(missing_ok=True)
        self._staged.clear()

    def stage(self, path: str | os.PathLike, data: bytes) -> None:
        target = Path(os.path.realpath(path))  # through symlinks: the link stays, the file it names is replaced
        target.parent.mkdir(parents=True, exist_ok=True)
        for stale in self._stale_temps(target.parent).pop(_temp_stem(target), []):
            with suppress(OSError):  # tidying up: a file someone else owns must not fail this save
                stale.unlink(missing_ok=True)  # first, so the space it holds is free for this save
        self._staged.append((_write_temp(target, data), target))

    def commit(self) -> None:
        """Rename every staged file over its target, in staging order, then fsync their folders."""
        for tmp, target in self._staged:
            os.replace(tmp, target)
        for folder in dict.fromkeys(target.parent for _, target in self._staged):
            _fsync_folder(folder)
        self._staged.clear()

    def _stale_temps(self, folder: Path) -> dict[str, list[Path]]:
        """Listed once per folder: a series saves thousands of files into one."""
        if folder not in self._stale:
            self._stale[folder] = _stale_temps(folder)
        return self._stale[folder]


def _stale_temps(folder: Path) -> dict[str, list[Path]]:
    cutoff = time.time() - STALE_AFTER_S
    found: dict[str, list[Path]] = {}
    with suppress(OSError), os.scandir(folder) as entries:  # a folder we may write but not list: nothing to tidy
        for entry in entries:
            match = _TEMP_NAME.fullmatch(entry.name)
            if match and entry.is_file(follow_symlinks=False) and entry.stat(follow_symlinks=False).st_mtime < cutoff:
                found.setdefault(match[1], []).append(Path(entry.path))
    return found


def name_max(folder: str | os.PathLike) -> int:
    """The most bytes a file name may have in `folder` (NAME_MAX where the file system says nothing)."""
    try:
        return os.pathconf(folder, "PC_NAME_MAX")
    except (OSError, ValueError):
        return NAME_MAX


def _temp_stem(target: Path) -> str:
    """target's name as its temporary files hold it: cut (in bytes) to leave room for what they add."""
    raw = os.fsencode(target.name)
    room = name_max(target.parent) - _TEMP_EXTRA
    return target.name if len(raw) <= room else os.fsdecode(raw[:room])  # a cut UTF-8 sequence stays as bytes


def _write_temp(target: Path, data: bytes) -> Path:
    """A new file beside target holding data, fsynced, with target's permission bits if it exists.

    Created with mode 0666 for the umask to narrow, as any new file is: mkstemp's 0600 would make every saved
    file private to its owner.
    """
    tmp = target.with_name(f".{_temp_stem(target)}.{secrets.token_hex(4)}.tmp")
    fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666)
    try:
        with os.fdopen(fd, "wb") as f:
            if target.exists():
                os.chmod(f.fileno(), stat.S_IMODE(target.stat().st_mode))
            f.write(data)
            f.flush()
            os.fsync(f.fileno())
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
    return tmp


def _fsync_folder(folder: Path) -> None:
    fd = os.open(folder, os.O_RDONLY)
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


def write_bytes(path: str | os.PathLike, data: bytes) -> None:
    with Batch() as batch:
        batch.stage(path, data)
        batch.commit()


def write_text(path: str | os.PathLike, text: str) -> None:
    write_bytes(path, text.encode("utf-8"))
