"""Reading a file only when it is a regular one, and only up to a bound: a device (/dev/zero), a FIFO or
a folder is refused before a byte is read, and a huge file before it fills memory.

A minimal stand-in for the shared app/io/regular_file.py being written on another branch; the two are
to be unified when both land."""
from __future__ import annotations

import errno
import os
import stat

# O_NONBLOCK: opening a FIFO must not wait for a writer (it changes nothing for a regular file).
_FLAGS = os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_CLOEXEC", 0) | getattr(os, "O_BINARY", 0)


def read_regular(path: str | os.PathLike, limit: int) -> bytes:
    """The whole file if it is a regular file of at most `limit` bytes; else OSError whose strerror says why."""
    fd = os.open(path, _FLAGS)
    try:
        if not stat.S_ISREG(os.fstat(fd).st_mode):
            raise OSError(errno.EINVAL, "not a regular file", os.fspath(path))
        file = os.fdopen(fd, "rb")
    except BaseException:
        os.close(fd)
        raise
    with file:
        data = file.read(limit + 1)  # bounded even if the file grows after fstat
    if len(data) > limit:
        raise OSError(errno.EFBIG, f"larger than {limit:,} bytes", os.fspath(path))
    return data
