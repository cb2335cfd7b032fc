"""Opening a file for reading only when it is a regular file: never a FIFO, device, socket or folder.

open() on a FIFO waits for a writer, and /dev/zero or /dev/urandom never end, so a reader that trusts the
path can hang or read until memory runs out. Errors are OSError with a `strerror` meant for the user, so
callers that already turn OSError into their own message ("cannot read PATH: REASON") need no new branch.
"""
from __future__ import annotations

import errno
import io
import os
import stat
from typing import BinaryIO

# O_NONBLOCK: opening a FIFO returns at once instead of waiting for a writer. It means nothing for a regular
# file, and is cleared again once fstat has shown that is what was opened.
_OPEN_FLAGS = os.O_RDONLY | os.O_NONBLOCK


def kind(mode: int) -> str:
    """What a stat() or lstat() mode is, for a message: "a folder", "a FIFO (named pipe)", "a symbolic link"..."""
    for test, name in ((stat.S_ISREG, "a regular file"), (stat.S_ISDIR, "a folder"), (stat.S_ISLNK, "a symbolic link"),
                       (stat.S_ISFIFO, "a FIFO (named pipe)"), (stat.S_ISCHR, "a device"), (stat.S_ISBLK, "a device")):
        if test(mode):
            return name
    return "a special file"  # a socket, where open() does not already refuse one as Linux does


def _refuse_irregular(path: str | os.PathLike, st: os.stat_result, max_bytes: int | None) -> None:
    if not stat.S_ISREG(st.st_mode):
        code = errno.EISDIR if stat.S_ISDIR(st.st_mode) else errno.EINVAL
        raise OSError(code, f"is {kind(st.st_mode)}, not a regular file", os.fspath(path))
    if max_bytes is not None and st.st_size > max_bytes:
        raise OSError(errno.EFBIG, f"the file is over the size limit of {max_bytes} bytes ({st.st_size} bytes)",
                      os.fspath(path))




class _SizedReader(io.BufferedReader):
    """Reads that stop at the file's size when it was opened. BufferedReader.read(n) allocates n bytes before it
    reads any, so a 4 GiB length field in a small file (a PNG chunk, a .npy header) cost 4 GiB; and a file that
    grows while it is read is read as it was."""

    def __init__(self, raw: io.FileIO, size: int) -> None:
        super().__init__(raw)
        self._size = size

    def _capped(self, n: int | None) -> int:
        left = max(self._size - self.tell(), 0)
        return left if n is None or n < 0 else min(n, left)

    def read(self, n: int | None = -1, /) -> bytes:
        return super().read(self._capped(n))

    def read1(self, n: int = -1, /) -> bytes:
        return super().read1(self._capped(n))


def open_regular(path: str | os.PathLike, max_bytes: int | None = None) -> BinaryIO:
    """path opened for binary reading (a buffered file object named path), once os.fstat of the opened file
    shows a regular file of at most max_bytes bytes (None: any size). Its read() and read1() never go past the
    size the file had then, nor allocate more than what is left of it, whatever size they are asked for.

    The check is on the file actually opened, so a path swapped for a FIFO after a stat() cannot slip through.
    Raises OSError, exc.filename the path and exc.strerror the reason alone: the open's own (ENOENT, EACCES;
    ENXIO for a socket on Linux); EISDIR "is a folder, not a regular file"; EINVAL "is a FIFO (named pipe), not
    a regular file", "is a device, ..." or "is a special file, ..."; EFBIG "the file is over the size limit of
    M bytes (N bytes)".
    """
    fd = os.open(path, _OPEN_FLAGS)
    try:
        st = os.fstat(fd)
        _refuse_irregular(path, st, max_bytes)
        os.set_blocking(fd, True)
        raw = io.FileIO(fd, "rb")
    except BaseException:
        os.close(fd)
        raise
    raw.name = os.fspath(path)  # as open() names it; the fd number would be its name, and decoders show or need it
    return _SizedReader(raw, st.st_size)


def read_regular_bytes(path: str | os.PathLike, max_bytes: int) -> bytes:
    """The content of a regular file of at most max_bytes bytes (as far as it went when opened); open_regular's
    OSErrors."""
    with open_regular(path, max_bytes) as f:
        return f.read()
