"""Tex3Dtrace's raw volume (.r3, .raw): a small header and the RGBA voxels."""
from __future__ import annotations

import struct

import numpy as np

from app.io.atomic import write_bytes
from app.io.volume_formats.checks import PathLike, VolumeFile, FormatError, check_shape, open_file, read_exact

# Tex3Dtrace's raw volume: b"R3", uint16 width, height, depth (little-endian), then the voxels in z, y, x order.
# The original calls them "4-byte colours"; Shadelab reads and writes them as R, G, B, A bytes.
_R3_HEADER = struct.Struct("<2sHHH")


def read(path: PathLike, max_bytes: int) -> VolumeFile:
    with open_file(path, max_bytes) as f:
        header = f.read(_R3_HEADER.size)
        if header[:2] != b"R3":
            raise FormatError(f"{path} is not an R3 volume: it does not start with 'R3'")
        if len(header) < _R3_HEADER.size:
            raise FormatError(f"{path}: the R3 header is truncated ({len(header)} of {_R3_HEADER.size} bytes)")
        _, w, h, d = _R3_HEADER.unpack(header)
        check_shape(path, (d, h, w), max_bytes)
        data = read_exact(path, f, d * h * w * 4)
    return VolumeFile(np.frombuffer(data, np.uint8).reshape(d, h, w, 4))


def write(path: PathLike, data: np.ndarray) -> None:
    d, h, w, _ = data.shape
    write_bytes(path, _R3_HEADER.pack(b"R3", w, h, d) + data.tobytes())
