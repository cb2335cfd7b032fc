"""Volume files: Tex3Dtrace's R3, numbered image series, .npy and .npz, TIFF stacks, NRRD, NIfTI and DICOM; one
module a format, this one choosing among them.

A volume is a C-contiguous uint8 array (depth, height, width, 4): z, y, x order, RGBA, every side 1..4096.
Readers validate the whole file and return a fresh array or raise FormatError (a ValueError whose message names
the file); the voxel size is checked against `max_bytes` before any voxel data is allocated or read, and a read
peaks at twice the returned volume's size. Only regular files are opened (app.io.regular_file). Writers go
through app.io.atomic, so a failed save never replaces a good file with a half-written one.

Greyscale arrays (.npy, .npz, TIFF, NRRD, NIfTI, DICOM) of uint8 values are densities: grey goes into R, G and B
and alpha is 255 where the voxel is non-zero, 0 elsewhere, so empty space stays clear. Greyscale arrays of the
other integer types or floats (SCALAR_TYPES: int8 and 16- and 32-bit integers, floats; CT, MRI, microscopy) are
scalars: the reader returns them as they are, (depth, height, width) in native byte order (a scanner's rescale
applied), and the model colours them through a transfer function (app/model/volume/scalars.py); their size counts
the colours they become, 4 bytes a voxel, besides their own. The array formats also write scalars;
NRRD keeps their window and colour map too, in a key/value field of its header (read_volume_file), and the
voxels' spacing. Greyscale *images* in a series are pictures: they get alpha 255 unless the image itself says
which pixels are transparent.

NIfTI, DICOM and .npz are read, never written (READ_ONLY). A DICOM series is a folder, or its files
(read_dicom_files); a file of no known suffix is read as DICOM if it says so after its preamble.
"""
from __future__ import annotations

import os
from collections.abc import Callable
from pathlib import Path

import numpy as np

from app.io.volume_formats import dicom, image_series, nifti, npy, nrrd, r3, tiff
from app.io.volume_formats.checks import (DEFAULT_MAX_BYTES, MAX_SIDE, PathLike, Spacing, FormatError, VolumeFile,
                                          check_shape, is_scalar)
from app.io.volume_formats.nrrd import read_nrrd
from app.model.volume.scalars import TransferFunction

__all__ = ["DEFAULT_MAX_BYTES", "MAX_SIDE", "FormatError", "PathLike", "VolumeFile", "SUPPORTED", "READ_ONLY",
           "SCALAR_SUFFIXES", "WINDOW_SUFFIXES", "SPACING_SUFFIXES", "suffix_of", "is_volume_source", "read_volume",
           "read_volume_file", "read_dicom_files", "read_nrrd", "write_volume"]

_READERS: dict[str, Callable[[PathLike, int], VolumeFile]] = {
    ".r3": r3.read, ".raw": r3.read, ".npy": npy.read, ".npz": npy.read_npz, ".tif": tiff.read, ".tiff": tiff.read,
    ".nrrd": nrrd.read, ".nii": nifti.read, ".nii.gz": nifti.read, **dict.fromkeys(dicom.SUFFIXES, dicom.read_file),
    **dict.fromkeys(image_series.IMAGE_FORMATS, image_series.read),
}
_WRITERS: dict[str, Callable[..., None]] = {
    ".r3": r3.write, ".raw": r3.write, ".npy": npy.write, ".tif": tiff.write, ".tiff": tiff.write,
    ".nrrd": nrrd.write, **dict.fromkeys(image_series.IMAGE_FORMATS, image_series.write),
}

# Image extensions only as numbered series: a path with %i (or %d, %03i...) in its file name.
SUPPORTED: tuple[str, ...] = tuple(_READERS)
READ_ONLY = tuple(s for s in SUPPORTED if s not in _WRITERS)
SCALAR_SUFFIXES = (".npy", ".nrrd", ".tif", ".tiff")  # the formats that hold scalars, read and written
WINDOW_SUFFIXES = (".nrrd",)  # those that keep the scalars' window and colour map with them
SPACING_SUFFIXES = (".nrrd",)  # and those that keep the voxels' spacing


def suffix_of(path: PathLike) -> str:
    """The supported suffix `path` ends with, lower case (".nii.gz" rather than ".gz"), else its last suffix."""
    name = Path(path).name.lower()
    return max((s for s in SUPPORTED if name.endswith(s)), key=len, default=Path(name).suffix)


def _unsupported(action: str, path: PathLike) -> FormatError:
    suffix = suffix_of(path) or "(none)"
    return FormatError(
        f"cannot {action} {path}: unsupported file type {suffix}; supported: {', '.join(SUPPORTED)} "
        "(image types as numbered series such as slice_%i.png; a folder of DICOM files)"
    )


def is_volume_source(path: PathLike, max_bytes: int = DEFAULT_MAX_BYTES) -> bool:
    """Whether read_volume_file takes `path` though its suffix is none of SUPPORTED: a folder (a DICOM series), or
    a file that says it is DICOM."""
    path = Path(path)
    if suffix_of(path) in SUPPORTED:
        return False
    try:
        return path.is_dir() or path.is_file() and dicom.is_dicom(path, max_bytes)
    except FormatError:
        return False


def read_volume(path: PathLike, max_bytes: int = DEFAULT_MAX_BYTES) -> np.ndarray:
    """The (depth, height, width, 4) uint8 volume in path, or the (depth, height, width) scalars of a 16-bit or
    float file (SCALAR_TYPES); chosen by extension; FormatError for anything wrong."""
    return read_volume_file(path, max_bytes).data


def read_volume_file(path: PathLike, max_bytes: int = DEFAULT_MAX_BYTES, array: str | None = None) -> VolumeFile:
    """read_volume's volume or scalars, with the window and colour map the file keeps them with, its spacing and
    notes. A folder (of no volume file's suffix) is a DICOM series; `array` names the array of an .npz that holds
    several."""
    suffix = suffix_of(path)
    if array is not None and suffix != ".npz":
        raise FormatError(f"cannot read {path}: only an .npz file holds arrays chosen by name ({array!r})")
    if array is not None:
        return npy.read_npz(path, max_bytes, array)
    reader = _READERS.get(suffix)
    if reader is None and os.path.isdir(path):
        reader = dicom.read_folder
    elif reader is None and os.path.isfile(path) and dicom.is_dicom(path, max_bytes):
        reader = dicom.read_file
    if reader is None:
        raise _unsupported("read", path)
    return reader(path, max_bytes)


def read_dicom_files(paths: list[PathLike], max_bytes: int = DEFAULT_MAX_BYTES) -> VolumeFile:
    """The files of one DICOM series, in any order: the slices are ordered by their positions."""
    return dicom.read_files(paths, max_bytes)


def _check_volume(path: PathLike, data: np.ndarray) -> None:
    """An RGBA volume, or scalars for a format that holds them (SCALAR_SUFFIXES)."""
    scalars = isinstance(data, np.ndarray) and data.ndim == 3 and is_scalar(data.dtype)
    if scalars and Path(path).suffix.lower() not in SCALAR_SUFFIXES:
        raise FormatError(f"cannot write {path}: {data.dtype} scalars go into {', '.join(SCALAR_SUFFIXES)} files; "
                          f"{Path(path).suffix} holds colours")
    if not scalars and (not isinstance(data, np.ndarray) or data.dtype != np.uint8 or data.ndim != 4
                        or data.shape[3] != 4):
        what = f"{data.dtype} array of shape {data.shape}" if isinstance(data, np.ndarray) else type(data).__name__
        raise FormatError(f"cannot write {path}: a volume is a (depth, height, width, 4) uint8 array or "
                          f"(depth, height, width) scalars, not a {what}")
    check_shape(path, data.shape[:3])


def write_volume(path: PathLike, data: np.ndarray, transfer: TransferFunction | None = None,
                 spacing: Spacing | None = None) -> None:
    """`transfer`: the window and colour map of scalars, kept where the format has room (WINDOW_SUFFIXES);
    `spacing`: the voxels' sides (x, y, z), kept where the format has room (SPACING_SUFFIXES)."""
    suffix = suffix_of(path)
    writer = _WRITERS.get(suffix)
    if writer is None:
        if suffix in READ_ONLY:
            raise FormatError(f"cannot write {path}: Shadelab reads {suffix} files but does not write them; save as "
                              f"{', '.join(s for s in _WRITERS if s in SCALAR_SUFFIXES)} (.nrrd keeps the window "
                              "and the spacing)")
        raise _unsupported("write", path)
    _check_volume(path, data)
    if transfer is not None and data.ndim != 3:
        raise FormatError(f"cannot write {path}: a window goes with scalars, not with colours")
    kept = {"transfer": transfer} if transfer is not None and suffix in WINDOW_SUFFIXES else {}
    if spacing is not None and suffix in SPACING_SUFFIXES:
        kept["spacing"] = spacing
    try:
        writer(path, np.ascontiguousarray(data), **kept)
    except OSError as exc:
        raise FormatError(f"cannot write {exc.filename or path}: {exc.strerror or exc}") from exc
