"""Atomic writes: durable renames, permission bits, symlinks, stale temporary files, batches."""
from __future__ import annotations

import os
import stat
import time

import pytest

from app.io import atomic
from app.io.atomic import Batch, write_bytes


def mode(path) -> int:
    return stat.S_IMODE(os.stat(path).st_mode)


def temp_files(folder) -> list[str]:
    return sorted(p.name for p in folder.iterdir() if p.name.endswith(".tmp"))


@pytest.fixture
def umask_022():
    old = os.umask(0o022)
    yield
    os.umask(old)


def test_the_folder_is_fsynced_after_the_rename(tmp_path, monkeypatch):
    calls = []
    real_fsync, real_replace = os.fsync, os.replace

    def fsync(fd: int) -> None:
        calls.append("fsync folder" if stat.S_ISDIR(os.fstat(fd).st_mode) else "fsync file")
        real_fsync(fd)

    def replace(src, dst) -> None:
        calls.append("rename")
        real_replace(src, dst)

    monkeypatch.setattr(atomic.os, "fsync", fsync)
    monkeypatch.setattr(atomic.os, "replace", replace)
    write_bytes(tmp_path / "a.cfg", b"new")
    assert calls == ["fsync file", "rename", "fsync folder"]


def test_a_new_file_gets_the_umask_mode_and_a_replaced_one_keeps_its_own(tmp_path, umask_022):
    write_bytes(tmp_path / "new.cfg", b"x")
    assert mode(tmp_path / "new.cfg") == 0o644  # mkstemp made every saved file 0600
    (tmp_path / "config.cfg").write_bytes(b"old")
    os.chmod(tmp_path / "config.cfg", 0o640)
    write_bytes(tmp_path / "config.cfg", b"new")
    assert mode(tmp_path / "config.cfg") == 0o640 and (tmp_path / "config.cfg").read_bytes() == b"new"


def test_saving_to_a_symlink_replaces_the_file_it_names(tmp_path):
    (tmp_path / "real").mkdir()
    (tmp_path / "real" / "config.cfg").write_bytes(b"old")
    (tmp_path / "link.cfg").symlink_to(tmp_path / "real" / "config.cfg")
    write_bytes(tmp_path / "link.cfg", b"new")
    assert (tmp_path / "link.cfg").is_symlink() and (tmp_path / "real" / "config.cfg").read_bytes() == b"new"
    assert temp_files(tmp_path) == [] and temp_files(tmp_path / "real") == []
    (tmp_path / "dangling.cfg").symlink_to(tmp_path / "real" / "made.cfg")
    write_bytes(tmp_path / "dangling.cfg", b"made")
    assert (tmp_path / "real" / "made.cfg").read_bytes() == b"made" and (tmp_path / "dangling.cfg").is_symlink()


def test_stale_temporary_files_of_the_same_name_are_removed(tmp_path):
    stale = [".config.cfg.ab12cd34.tmp", ".config.cfg.k_x9q0zz.tmp"]  # the second as mkstemp named them
    fresh = ".config.cfg.0f0f0f0f.tmp"  # a concurrent save, still writing
    other = ".history.ab12cd34.tmp"  # another file's: its own save tidies it
    old = time.time() - 3600
    for name in [*stale, fresh, other]:
        (tmp_path / name).write_bytes(b"partial")
        if name != fresh:
            os.utime(tmp_path / name, (old, old))
    write_bytes(tmp_path / "config.cfg", b"new")
    assert temp_files(tmp_path) == sorted([fresh, other])
    assert atomic.STALE_AFTER_S < 3600


def test_a_batch_that_fails_while_staging_changes_no_target(tmp_path, monkeypatch):
    for name in "ab":
        (tmp_path / name).write_bytes(b"old")
    real_fsync = os.fsync

    def full_after_one(fd: int) -> None:  # the disk fills while the second file is written
        if len(temp_files(tmp_path)) > 1:
            raise OSError(28, "No space left on device")
        real_fsync(fd)

    monkeypatch.setattr(atomic.os, "fsync", full_after_one)
    with pytest.raises(OSError, match="No space left"), Batch() as batch:
        batch.stage(tmp_path / "a", b"new")
        batch.stage(tmp_path / "b", b"new")
        batch.commit()
    assert [(tmp_path / n).read_bytes() for n in "ab"] == [b"old", b"old"] and temp_files(tmp_path) == []
    monkeypatch.undo()
    with Batch() as batch:
        batch.stage(tmp_path / "a", b"new")
        batch.stage(tmp_path / "b", b"new")
        assert [(tmp_path / n).read_bytes() for n in "ab"] == [b"old", b"old"]
    assert temp_files(tmp_path) == []  # left without commit: nothing renamed, nothing left over
