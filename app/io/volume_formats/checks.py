"""What every volume reader shares: the error, what a file holds, bounded opening and reading, the size checks and
the array layouts (see the package's docstring for the rules they keep)."""
from __future__ import annotations

import math
import os
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from typing import BinaryIO

import numpy as np

from app.io.regular_file import open_regular
from app.model.volume.scalars import SCALAR_TYPES, TransferFunction
from app.model.volume.voxels import Spacing, check_spacing

MAX_SIDE = 4096
DEFAULT_MAX_BYTES = 2 * 2**30

PathLike = str | os.PathLike


class FormatError(ValueError):
    """A volume file that cannot be read or written; the message names the file and says what is wrong."""


@dataclass(frozen=True)
class VolumeFile:
    """What a volume file holds: an RGBA volume or scalars, as read_volume returns them; the window and colour map
    the file keeps its scalars with (WINDOW_SUFFIXES), else None; the voxels' spacing (x, y, z) where the file
    states it, else None; and `notes` for the user: what the reader chose where the file left a choice (the
    first volume of several, a series' slice gaps, the orientation set aside)."""
    data: np.ndarray
    transfer: TransferFunction | None = None
    spacing: Spacing | None = None
    notes: tuple[str, ...] = ()


def open_file(path: PathLike, max_bytes: int) -> BinaryIO:
    """path, if it is a regular file of at most 2 * max_bytes + 1 MiB: no volume within max_bytes needs more (data
    that compression made bigger, headers), so a bigger file is refused unread. Each format's sizes bound its reads."""
    try:
        return open_regular(path, 2 * max_bytes + (1 << 20))
    except OSError as exc:
        raise FormatError(f"cannot read {path}: {exc.strerror or exc}") from None


@contextmanager
def library_errors(path: PathLike, what: str) -> Iterator[None]:
    """Decoders raise anything (struct.error, KeyError, OSError...) on a malformed file; the editor sees FormatError."""
    try:
        yield
    except FormatError:
        raise
    except Exception as exc:
        raise FormatError(f"{path} is not a valid {what}: {exc or type(exc).__name__}") from exc


def check_shape(path: PathLike, shape: tuple[int, ...], max_bytes: float = math.inf, scalar_bytes: int = 0) -> None:
    """shape is (depth, height, width); the RGBA volume it becomes (4 bytes a voxel), or a scan's values and a label
    byte a voxel (what the model holds of a scan: app/model/volume/volume.py), must fit max_bytes."""
    d, h, w = (int(n) for n in shape)
    size = f"{w}x{h}x{d}"
    if min(d, h, w) < 1:
        raise FormatError(f"{path}: volume size {size} (width x height x depth) has an empty side")
    if max(d, h, w) > MAX_SIDE:
        raise FormatError(f"{path}: volume size {size} exceeds {MAX_SIDE} voxels a side")
    need = d * h * w * (scalar_bytes + 1 if scalar_bytes else 4)
    if need > max_bytes:
        what = " (its values and a label byte a voxel)" if scalar_bytes else ""
        raise FormatError(f"{path}: a {size} volume needs {need} bytes{what}, over the size limit of {max_bytes} bytes")


def is_scalar(dtype: np.dtype) -> bool:
    return dtype.newbyteorder("=") in SCALAR_TYPES


SCALAR_NAMES = ", ".join(str(t) for t in SCALAR_TYPES)


def check_array(path: PathLike, shape: tuple[int, ...], dtype: np.dtype, max_bytes: int) -> None:
    """The array layouts .npy, TIFF, NRRD, NIfTI and DICOM share: (d, h, w) grey, (d, h, w, 3) RGB or (d, h, w, 4)
    RGBA, uint8; or (d, h, w) scalars of SCALAR_TYPES."""
    if dtype != np.uint8 and not is_scalar(dtype):
        raise FormatError(f"{path}: voxels are {dtype}; Shadelab reads 8-bit (uint8) volumes and scalar volumes of "
                          f"{SCALAR_NAMES}")
    if is_scalar(dtype) and len(shape) != 3:
        raise FormatError(f"{path}: {dtype} array of shape {tuple(shape)} is not a scalar volume; expected (depth, "
                          "height, width): one value a voxel (colour volumes are 8-bit)")
    if not (len(shape) == 3 or len(shape) == 4 and shape[3] in (3, 4)):
        raise FormatError(
            f"{path}: array shape {tuple(shape)} is not a volume; expected (depth, height, width) greyscale "
            "or (depth, height, width, 3 or 4) RGB/RGBA"
        )
    check_shape(path, shape[:3], max_bytes, dtype.itemsize if is_scalar(dtype) else 0)


def native(array: np.ndarray) -> np.ndarray:
    """array C-ordered in native byte order: swapped in place where the file's was not (and it may be written)."""
    array = np.ascontiguousarray(array)
    if not array.dtype.isnative:
        array = array.byteswap(inplace=array.flags.writeable).view(array.dtype.newbyteorder("="))
    return array


def as_scan(array: np.ndarray, notes: list[str]) -> np.ndarray:
    """What a scanner or a neuroimaging tool wrote (NIfTI, DICOM) is a scan, 8-bit too: grey uint8 widened to
    uint16, its values kept, so it opens windowed in the scalar modes with the transfer function and labels, as any
    scan (an 8-bit MRI template opened as painted grey colours before). Other arrays as they are."""
    if array.dtype != np.uint8 or array.ndim != 3:
        return array
    notes.append("8-bit values: opened as a scan (uint16), windowed")
    return array.astype(np.uint16)


def as_volume(array: np.ndarray) -> np.ndarray:
    """A read array as the volume readers return: scalars as they are, C-ordered in native byte order (swapped in
    place where the file's was not); 8-bit arrays as RGBA, the only allocation: every step is uint8 and in place
    (np.where(array > 0, 255, 0) would make an int64 array twice the RGBA volume's size)."""
    if is_scalar(array.dtype):
        return native(array)
    if array.ndim == 4 and array.shape[3] == 4:
        return np.ascontiguousarray(array)
    rgba = np.empty(array.shape[:3] + (4,), np.uint8)
    alpha = rgba[..., 3]
    if array.ndim == 3:
        rgba[..., :3] = array[..., None]
        np.minimum(array, 1, out=alpha)
        alpha *= 255
    else:
        rgba[..., :3] = array
        alpha[...] = 255
    return rgba


def check_length(path: PathLike, expected: int, found: int) -> None:
    if found < expected:
        raise FormatError(f"{path} is truncated: expected {expected} bytes of voxel data, found {found}")
    if found > expected:
        raise FormatError(f"{path} has trailing data: expected {expected} bytes of voxel data, found {found}")


def read_exact(path: PathLike, f: BinaryIO, n: int) -> bytearray:
    """Exactly the n bytes left in f; a short or long file is refused before the buffer is allocated."""
    check_length(path, n, os.fstat(f.fileno()).st_size - f.tell())
    data = bytearray(n)
    got = f.readinto(data)
    check_length(path, n, got + len(f.read(1)))  # the file changed since fstat
    return data


# The integer SCALAR_TYPES, narrowest first: what whole-number rescaling keeps (uint8 stays a density, not a scalar).
_WHOLE_TYPES = sorted((t for t in SCALAR_TYPES if t.kind in "iu"), key=lambda t: t.itemsize)
_RESCALE_CHUNK = 1 << 18  # values rescaled at a time: 2 MiB of int64 or float64


def rescaled(path: PathLike, values: np.ndarray, slope: float | None, inter: float | None, notes: list[str],
             max_bytes: int) -> np.ndarray:
    """values * slope + inter: a scanner's stored values in its units (CT's Hounsfield units). `values` is the
    reader's own writable, native array. The result is of the narrowest SCALAR_TYPES type that holds every value
    exactly: a whole-number slope and intercept keep whole numbers (uint16 CT with intercept -1024 becomes int16,
    rescaled in place), others give float32 (float64 for 32-bit or double stored values). A wider result is one
    new array, checked against max_bytes first. A slope that is missing, 0 or not finite means none (NIfTI's
    rule); so does a missing or non-finite intercept. A note says what was done."""
    slope = 1.0 if slope is None or not math.isfinite(slope) or slope == 0 else float(slope)
    inter = 0.0 if inter is None or not math.isfinite(inter) else float(inter)
    if slope == 1 and inter == 0:
        return values
    stored = values.dtype
    if stored.kind in "iu" and slope.is_integer() and inter.is_integer():
        ends = sorted(int(v) * int(slope) + int(inter) for v in (values.min(), values.max()))
        fits = [t for t in _WHOLE_TYPES if np.iinfo(t).min <= ends[0] and ends[1] <= np.iinfo(t).max]
        fits.sort(key=lambda t: (t.itemsize, t != stored))  # narrowest; of equal widths the stored type (in place)
        kind, work, scale = (fits[0], np.int64, (int(slope), int(inter))) if fits else (np.dtype(np.float64),
                                                                                     np.float64, (slope, inter))
    else:
        kind = np.dtype(np.float32 if stored.itemsize <= 2 or stored == np.float32 else np.float64)
        work, scale = np.float64, (slope, inter)
    if kind.itemsize == stored.itemsize:
        out = values.view(kind)
    else:
        check_array(path, values.shape, kind, max_bytes)
        out = np.empty(values.shape, kind)
    source, target = values.reshape(-1), out.reshape(-1)
    for start in range(0, source.size, _RESCALE_CHUNK):
        block = source[start:start + _RESCALE_CHUNK].astype(work)  # a copy: writing `out` in place reads it no more
        block *= scale[0]
        block += scale[1]
        target[start:start + _RESCALE_CHUNK] = block
    notes.append(f"values rescaled by slope {slope:g} and intercept {inter:g} into {kind}")
    return out


def usable_spacing(spacing, notes: list[str], where: str) -> Spacing | None:
    """The (x, y, z) spacing a file states, if the model takes it (check_spacing); else None, so the volume keeps
    1 1 1, and a note saying why: a file's spacing is advice, and a bad one never refuses the file."""
    try:
        return check_spacing(*spacing)
    except (TypeError, ValueError) as exc:  # VolumeError is a ValueError
        notes.append(f"its {where} is not used ({exc}); the volume opens at spacing 1 1 1 (vol.spacing sets it)")
        return None
