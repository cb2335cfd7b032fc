"""NumPy files: .npy (one array) and .npz (a zip of .npy arrays, one of them chosen by name); never a pickle."""
from __future__ import annotations

import io
import os
import struct
import zipfile
from typing import BinaryIO

import numpy as np

from app.io.atomic import write_bytes
from app.io.volume_formats.checks import (PathLike, VolumeFile, FormatError, as_volume, check_array, library_errors,
                                          open_file)

# An .npz's zip directory: its end record (22 bytes and a comment of up to 64 KiB) says how many members it lists
# and how long it is, which bounds what zipfile reads before any member; a volume needs one array.
_END_RECORD = struct.Struct("<4s4H2LH")
_MAX_MEMBERS = 256
_MAX_DIRECTORY = 1 << 20


def _check_header(path: PathLike, f: BinaryIO, max_bytes: int, what: str = "") -> None:
    """The .npy header at f's position: its shape and type must make a volume within max_bytes."""
    version = np.lib.format.read_magic(f)
    if version == (1, 0):
        shape, _, dtype = np.lib.format.read_array_header_1_0(f)
    elif version == (2, 0):
        shape, _, dtype = np.lib.format.read_array_header_2_0(f)
    else:  # 3.0 only exists for structured dtypes with unicode field names, which are no volume anyway
        raise FormatError(f"{path}{what}: unsupported .npy version {version[0]}.{version[1]}")
    check_array(f"{path}{what}", shape, dtype, max_bytes)


def read(path: PathLike, max_bytes: int) -> VolumeFile:
    with open_file(path, max_bytes) as f, library_errors(path, ".npy file"):
        _check_header(path, f, max_bytes)
        f.seek(0)
        array = np.load(f, allow_pickle=False)
    return VolumeFile(as_volume(array))


def write(path: PathLike, data: np.ndarray) -> None:
    buffer = io.BytesIO()
    np.save(buffer, data, allow_pickle=False)
    write_bytes(path, buffer.getvalue())


def _check_directory(path: PathLike, f: BinaryIO) -> None:
    size = os.fstat(f.fileno()).st_size
    tail_at = max(0, size - _END_RECORD.size - (1 << 16))
    f.seek(tail_at)
    tail = f.read()
    at = tail.rfind(b"PK\x05\x06")
    if at < 0 or len(tail) - at < _END_RECORD.size:
        raise FormatError(f"{path} is not an .npz file: it has no zip directory")
    _, _, _, _, members, length, _, _ = _END_RECORD.unpack_from(tail, at)
    if members > _MAX_MEMBERS or length > _MAX_DIRECTORY:
        raise FormatError(f"{path}: an .npz of {members} members ({length}-byte directory) is not a volume; a volume "
                          f"file holds at most {_MAX_MEMBERS}")
    f.seek(0)


def read_npz(path: PathLike, max_bytes: int, name: str | None = None) -> VolumeFile:
    """The array called `name`, or the only one the file holds: an .npz of several is refused naming them."""
    with open_file(path, max_bytes) as f, library_errors(path, ".npz file"):
        _check_directory(path, f)
        with zipfile.ZipFile(f) as zf:
            names = [m.filename[:-4] for m in zf.infolist() if m.filename.endswith(".npy")]
            if not names:
                raise FormatError(f"{path} holds no arrays")
            if name is None and len(names) > 1:
                raise FormatError(f"{path} holds {len(names)} arrays: {', '.join(names)}; choose one by its name "
                                  f"(load {os.fspath(path)} {names[0]})")
            name = names[0] if name is None else name
            if name not in names:
                raise FormatError(f"{path} holds no array {name!r}; it holds {', '.join(names)}")
            member = zf.getinfo(name + ".npy")
            if member.file_size > max_bytes + (1 << 16):  # the volume and a header
                raise FormatError(f"{path}: its array {name!r} is {member.file_size} bytes, over the size limit of "
                                  f"{max_bytes} bytes")
            with zf.open(member) as stream:
                _check_header(path, stream, max_bytes, f" (array {name!r})")
            with zf.open(member) as stream:  # read in pieces of 256 KiB into the array: no second copy
                array = np.lib.format.read_array(stream, allow_pickle=False)
    return VolumeFile(as_volume(array), notes=(f"array {name!r}",) if len(names) > 1 else ())
