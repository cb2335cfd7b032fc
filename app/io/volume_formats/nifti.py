"""NIfTI-1 and NIfTI-2 (.nii, .nii.gz), as neuroimaging tools write them: nibabel parses the header, the first
volume's voxels are read here with bounds.

The header is read alone (348 or 540 bytes; extensions are skipped unread) and its sizes checked before any voxel
is read; a .nii.gz is inflated only as far as the first volume's last byte. NIfTI stores i fastest, so the data
of a volume (i, j, k) is already the C-ordered (k, j, i) array the model keeps: x = i, y = j, z = k, as the file
lies (the affine's orientation is noted, not applied). Voxel sizes come from the affine; scl_slope and scl_inter
are applied (checks.rescaled). A 4D file opens its first volume, and says so.
"""
from __future__ import annotations

import gzip
import math
import os
import struct
from typing import BinaryIO

import nibabel as nib
import numpy as np
from nibabel.affines import voxel_sizes

from app.io.volume_formats.checks import (PathLike, VolumeFile, FormatError, as_scan, as_volume, check_array,
                                          library_errors, native, open_file, rescaled, usable_spacing)

_HEADERS = {348: (nib.Nifti1Header, (b"n+1\x00", b"ni1\x00")), 540: (nib.Nifti2Header, (b"n+2\x00", b"ni2\x00"))}
_SKIP = 1 << 16  # bytes skipped at a time between the header and the voxels (extensions)
_PIECE = 1 << 18  # bytes read at a time into the voxels: gzip's readinto makes a copy of what it is asked for


def _header(path: PathLike, stream: BinaryIO) -> nib.Nifti1Header:
    """The fixed header: its size (either byte order) says NIfTI-1 or -2; its magic must be a single file's."""
    first = stream.read(4)
    sizes = {struct.unpack(order + "i", first)[0] for order in "<>"} if len(first) == 4 else set()
    found = sizes & _HEADERS.keys()
    if not found:
        raise FormatError(f"{path} is not a NIfTI file: its header does not start with the size 348 or 540")
    size = found.pop()
    kind, magics = _HEADERS[size]
    block = first + stream.read(size - 4)
    if len(block) < size:
        raise FormatError(f"{path} is truncated: its NIfTI header has {len(block)} of {size} bytes")
    header = kind(block, check=False)
    magic = bytes(header["magic"]).ljust(4, b"\x00")[:4]
    if magic == magics[1]:
        raise FormatError(f"{path}: a NIfTI header whose voxels are in a separate .img file (magic "
                          f"{magic.rstrip(bytes(1)).decode()}) is not supported; open a single-file .nii")
    if magic != magics[0]:
        raise FormatError(f"{path} is not a NIfTI file: its magic is {magic!r}, not {magics[0]!r}")
    return header


def _skip_to(path: PathLike, stream: BinaryIO, at: int, offset: int) -> None:
    """Read past the extensions up to the voxels at `offset`, a piece at a time (gzip streams cannot seek cheaply)."""
    if offset < at:
        raise FormatError(f"{path}: the NIfTI voxels start at byte {offset}, inside its {at}-byte header")
    while at < offset:
        piece = stream.read(min(_SKIP, offset - at))
        if not piece:
            raise FormatError(f"{path} is truncated: it ends at byte {at}, before its voxels at byte {offset}")
        at += len(piece)


def _read_into(path: PathLike, stream: BinaryIO, n: int) -> bytearray:
    data = bytearray(n)
    view, filled = memoryview(data), 0
    while filled < n:
        got = stream.readinto(view[filled:filled + _PIECE])
        if not got:
            raise FormatError(f"{path} is truncated: expected {n} bytes of voxel data, found {filled}")
        filled += got
    return data


def read(path: PathLike, max_bytes: int) -> VolumeFile:
    notes: list[str] = []
    compressed = os.fspath(path).lower().endswith(".gz")
    with open_file(path, max_bytes) as f, library_errors(path, "NIfTI file"):
        stream = gzip.GzipFile(fileobj=f, mode="rb") if compressed else f
        header = _header(path, stream)
        shape = tuple(int(n) for n in header.get_data_shape())
        volumes = math.prod(shape[3:])
        if len(shape) not in (3, 4) or min(shape, default=0) < 1:
            raise FormatError(f"{path}: NIfTI data of shape {shape} is not a volume (3D, or 4D whose first volume "
                              "opens)")
        if volumes > 1:
            notes.append(f"a 4D file of {volumes} volumes: the first opens")
        dtype = header.get_data_dtype()
        i, j, k = shape[:3]
        check_array(path, (k, j, i), dtype, max_bytes)
        offset = int(header.get_data_offset())
        if not compressed and os.fstat(f.fileno()).st_size < offset + i * j * k * dtype.itemsize:
            raise FormatError(f"{path} is truncated: its first volume needs {offset + i * j * k * dtype.itemsize} "
                              f"bytes, the file has {os.fstat(f.fileno()).st_size}")
        _skip_to(path, stream, header.sizeof_hdr, offset)
        data = _read_into(path, stream, i * j * k * dtype.itemsize)
        affine = header.get_best_affine()
        unit = header.get_xyzt_units()[0]
        slope, inter = header.get_slope_inter()
    sizes = [float(f"{s:.7g}") for s in voxel_sizes(affine)]  # the affine is float32: 2.0000000529 is 2
    spacing = usable_spacing(sizes, notes, "affine's voxel sizes")
    axes = orientation(affine)
    notes.append(f"voxel sizes {' '.join(f'{s:g}' for s in sizes)}"
                 f"{'' if unit == 'unknown' else ' ' + unit}; orientation {axes} (the affine's) is not applied: "
                 "x, y, z are the file's i, j, k")
    values = rescaled(path, native(np.frombuffer(data, dtype).reshape(k, j, i)), slope, inter, notes, max_bytes)
    return VolumeFile(as_volume(as_scan(values, notes)), spacing=spacing, notes=tuple(notes))


def orientation(affine: np.ndarray) -> str:
    """The affine's axis codes ("RAS"), "?" for an axis it leaves undefined, or "unknown" where it has none (NaN,
    or a matrix whose SVD does not converge): the orientation is only a note, so a bad one never refuses a file."""
    try:
        codes = nib.aff2axcodes(affine)
    except (ValueError, np.linalg.LinAlgError):
        return "unknown"
    return "".join(code or "?" for code in codes)
