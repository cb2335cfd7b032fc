"""Opening only regular files: FIFOs, devices, sockets and folders are refused at once, sizes are bounded."""
from __future__ import annotations

import errno
import os
import signal
import socket

import pytest

from app.io.regular_file import open_regular, read_regular_bytes


def test_a_regular_file_opens_under_its_own_name(tmp_path):
    (tmp_path / "a.bin").write_bytes(b"abc")
    with open_regular(tmp_path / "a.bin", max_bytes=3) as f:
        assert f.read() == b"abc" and f.name == str(tmp_path / "a.bin")
    assert read_regular_bytes(tmp_path / "a.bin", 3) == b"abc"
    (tmp_path / "link").symlink_to(tmp_path / "a.bin")
    assert read_regular_bytes(tmp_path / "link", 10) == b"abc"


def _blocked(_signum, _frame):
    raise AssertionError("the open blocked (a FIFO without a writer)")


def refusal(path, max_bytes: int | None = None) -> OSError:
    # A blocking open of a FIFO with no writer never returns: the alarm turns that hang into a failure.
    previous = signal.signal(signal.SIGALRM, _blocked)
    signal.alarm(30)
    try:
        with pytest.raises(OSError) as info:
            open_regular(path, max_bytes)
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)
    assert info.value.filename == str(path)
    return info.value


def test_fifos_devices_sockets_and_folders_are_refused(tmp_path):
    os.mkfifo(tmp_path / "pipe")
    assert refusal(tmp_path / "pipe").strerror == "is a FIFO (named pipe), not a regular file"
    assert refusal("/dev/zero").strerror == "is a device, not a regular file"
    with socket.socket(socket.AF_UNIX) as server:
        server.bind(str(tmp_path / "sock"))
        assert refusal(tmp_path / "sock").errno == errno.ENXIO  # Linux refuses to open() a socket at all
    error = refusal(tmp_path)
    assert error.errno == errno.EISDIR and error.strerror == "is a folder, not a regular file"
    assert refusal(tmp_path / "missing").errno == errno.ENOENT


def test_sizes_over_the_limit_are_refused(tmp_path):
    (tmp_path / "big").write_bytes(bytes(11))
    error = refusal(tmp_path / "big", max_bytes=10)
    assert error.errno == errno.EFBIG and error.strerror == "the file is over the size limit of 10 bytes (11 bytes)"
    with pytest.raises(OSError, match="over the size limit of 10 bytes"):
        read_regular_bytes(tmp_path / "big", 10)


def test_reads_stop_at_the_size_the_file_had_when_opened(tmp_path):
    (tmp_path / "a.bin").write_bytes(b"abc")
    with open_regular(tmp_path / "a.bin") as f:
        assert f.read(1 << 50) == b"abc"  # a plain file object allocates the 1 PiB first, and fails
        with open(tmp_path / "a.bin", "ab") as writer:
            writer.write(b"def")
        f.seek(1)
        assert f.read() == b"bc" and f.read1(10) == b""
    assert read_regular_bytes(tmp_path / "a.bin", 6) == b"abcdef"
