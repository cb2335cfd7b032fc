"""Volume files: Tex3Dtrace's R3, numbered image series, .npy, TIFF stacks and NRRD.

A volume is a C-contiguous uint8 array (depth, height, width, 4): z, y, x order, RGBA, every side 1..4096.
Readers validate the whole file and return a fresh array or raise FormatError (a ValueError whose message names
the file); the voxel size is checked against `max_bytes` before any voxel data is allocated or read, and a read
peaks at twice the returned volume's size. Only regular files are opened (app.io.regular_file). Writers go
through app.io.atomic, so a failed save never replaces a good file with a half-written one.

Greyscale arrays (.npy, TIFF, NRRD) of uint8 values are densities: grey goes into R, G and B and alpha is 255
where the voxel is non-zero, 0 elsewhere, so empty space stays clear. Greyscale arrays of the other integer types
or floats (SCALAR_TYPES: int8 and 16- and 32-bit integers, floats; CT, MRI, microscopy) are scalars: the
reader returns them as they are, (depth, height, width) in native byte order, and the model colours them
through a transfer function (app/model/volume/scalars.py); their size counts the colours they become, 4 bytes a
voxel, besides their own. The array formats also write scalars;
NRRD keeps their window and colour map too, in a key/value field of its header (read_volume_file).
Greyscale *images* in a series are pictures: they get alpha 255 unless the image itself says which pixels are
transparent.
"""
from __future__ import annotations

import bz2
import hashlib
import io
import json
import logging
import lzma
import math
import os
import re
import struct
import warnings
import zlib
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import BinaryIO

import nrrd
import numpy as np
import tifffile
from PIL import Image, UnidentifiedImageError

from app.io.atomic import Batch, write_bytes
from app.io.json_file import array, read_versioned, validator
from app.io.regular_file import open_regular
from app.model.volume.scalars import SCALAR_TYPES, TransferFunction

MAX_SIDE = 4096
DEFAULT_MAX_BYTES = 2 * 2**30

PathLike = str | os.PathLike


class FormatError(ValueError):
    """A volume file that cannot be read or written; the message names the file and says what is wrong."""


@dataclass(frozen=True)
class VolumeFile:
    """What a volume file holds: an RGBA volume or scalars, as read_volume returns them, and the window and colour
    map the file keeps its scalars with (WINDOW_SUFFIXES), else None."""
    data: np.ndarray
    transfer: TransferFunction | None = None


# --- shared checks ---------------------------------------------------------------------------------------------


def _open(path: PathLike, max_bytes: int) -> BinaryIO:
    """path, if it is a regular file of at most 2 * max_bytes + 1 MiB: no volume within max_bytes needs more (data
    that compression made bigger, headers), so a bigger file is refused unread. Each format's sizes bound its reads."""
    try:
        return open_regular(path, 2 * max_bytes + (1 << 20))
    except OSError as exc:
        raise FormatError(f"cannot read {path}: {exc.strerror or exc}") from None


@contextmanager
def _library_errors(path: PathLike, what: str) -> Iterator[None]:
    """Decoders raise anything (struct.error, KeyError, OSError...) on a malformed file; the editor sees FormatError."""
    try:
        yield
    except FormatError:
        raise
    except Exception as exc:
        raise FormatError(f"{path} is not a valid {what}: {exc or type(exc).__name__}") from exc


def _check_shape(path: PathLike, shape: tuple[int, ...], max_bytes: float = math.inf, scalar_bytes: int = 0) -> None:
    """shape is (depth, height, width); the RGBA volume it becomes, and its scalars, must fit max_bytes."""
    d, h, w = (int(n) for n in shape)
    size = f"{w}x{h}x{d}"
    if min(d, h, w) < 1:
        raise FormatError(f"{path}: volume size {size} (width x height x depth) has an empty side")
    if max(d, h, w) > MAX_SIDE:
        raise FormatError(f"{path}: volume size {size} exceeds {MAX_SIDE} voxels a side")
    need = d * h * w * (4 + scalar_bytes)
    if need > max_bytes:
        what = " (its scalars and their colours)" if scalar_bytes else ""
        raise FormatError(f"{path}: a {size} volume needs {need} bytes{what}, over the size limit of {max_bytes} bytes")


def _is_scalar(dtype: np.dtype) -> bool:
    return dtype.newbyteorder("=") in SCALAR_TYPES


_SCALAR_NAMES = ", ".join(str(t) for t in SCALAR_TYPES)


def _check_array(path: PathLike, shape: tuple[int, ...], dtype: np.dtype, max_bytes: int) -> None:
    """The array layouts .npy, TIFF and NRRD share: (d, h, w) grey, (d, h, w, 3) RGB or (d, h, w, 4) RGBA, uint8;
    or (d, h, w) scalars of SCALAR_TYPES."""
    if dtype != np.uint8 and not _is_scalar(dtype):
        raise FormatError(f"{path}: voxels are {dtype}; Shadelab reads 8-bit (uint8) volumes and scalar volumes of "
                          f"{_SCALAR_NAMES}")
    if _is_scalar(dtype) and len(shape) != 3:
        raise FormatError(f"{path}: {dtype} array of shape {tuple(shape)} is not a scalar volume; expected (depth, "
                          "height, width): one value a voxel (colour volumes are 8-bit)")
    if not (len(shape) == 3 or len(shape) == 4 and shape[3] in (3, 4)):
        raise FormatError(
            f"{path}: array shape {tuple(shape)} is not a volume; expected (depth, height, width) greyscale "
            "or (depth, height, width, 3 or 4) RGB/RGBA"
        )
    _check_shape(path, shape[:3], max_bytes, dtype.itemsize if _is_scalar(dtype) else 0)


def _as_volume(array: np.ndarray) -> np.ndarray:
    """A read array as the volume readers return: scalars as they are, C-ordered in native byte order (swapped in
    place where the file's was not); 8-bit arrays as RGBA, the only allocation: every step is uint8 and in place
    (np.where(array > 0, 255, 0) would make an int64 array twice the RGBA volume's size)."""
    if _is_scalar(array.dtype):
        array = np.ascontiguousarray(array)
        if not array.dtype.isnative:
            array = array.byteswap(inplace=array.flags.writeable).view(array.dtype.newbyteorder("="))
        return array
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


def _check_length(path: PathLike, expected: int, found: int) -> None:
    if found < expected:
        raise FormatError(f"{path} is truncated: expected {expected} bytes of voxel data, found {found}")
    if found > expected:
        raise FormatError(f"{path} has trailing data: expected {expected} bytes of voxel data, found {found}")


def _read_exact(path: PathLike, f: BinaryIO, n: int) -> bytearray:
    """Exactly the n bytes left in f; a short or long file is refused before the buffer is allocated."""
    _check_length(path, n, os.fstat(f.fileno()).st_size - f.tell())
    data = bytearray(n)
    got = f.readinto(data)
    _check_length(path, n, got + len(f.read(1)))  # the file changed since fstat
    return data


def _check_volume(path: PathLike, data: np.ndarray) -> None:
    """An RGBA volume, or scalars for a format that holds them (SCALAR_SUFFIXES)."""
    scalars = isinstance(data, np.ndarray) and data.ndim == 3 and _is_scalar(data.dtype)
    if scalars and Path(path).suffix.lower() not in SCALAR_SUFFIXES:
        raise FormatError(f"cannot write {path}: {data.dtype} scalars go into {', '.join(SCALAR_SUFFIXES)} files; "
                          f"{Path(path).suffix} holds colours")
    if not scalars and (not isinstance(data, np.ndarray) or data.dtype != np.uint8 or data.ndim != 4
                        or data.shape[3] != 4):
        what = f"{data.dtype} array of shape {data.shape}" if isinstance(data, np.ndarray) else type(data).__name__
        raise FormatError(f"cannot write {path}: a volume is a (depth, height, width, 4) uint8 array or "
                          f"(depth, height, width) scalars, not a {what}")
    _check_shape(path, data.shape[:3])


# --- R3 --------------------------------------------------------------------------------------------------------

# Tex3Dtrace's raw volume: b"R3", uint16 width, height, depth (little-endian), then the voxels in z, y, x order.
# The original calls them "4-byte colours"; Shadelab reads and writes them as R, G, B, A bytes.
_R3_HEADER = struct.Struct("<2sHHH")


def _read_r3(path: PathLike, max_bytes: int) -> VolumeFile:
    with _open(path, max_bytes) as f:
        header = f.read(_R3_HEADER.size)
        if header[:2] != b"R3":
            raise FormatError(f"{path} is not an R3 volume: it does not start with 'R3'")
        if len(header) < _R3_HEADER.size:
            raise FormatError(f"{path}: the R3 header is truncated ({len(header)} of {_R3_HEADER.size} bytes)")
        _, w, h, d = _R3_HEADER.unpack(header)
        _check_shape(path, (d, h, w), max_bytes)
        data = _read_exact(path, f, d * h * w * 4)
    return VolumeFile(np.frombuffer(data, np.uint8).reshape(d, h, w, 4))


def _write_r3(path: PathLike, data: np.ndarray) -> None:
    d, h, w, _ = data.shape
    write_bytes(path, _R3_HEADER.pack(b"R3", w, h, d) + data.tobytes())


# --- .npy ------------------------------------------------------------------------------------------------------


def _read_npy(path: PathLike, max_bytes: int) -> VolumeFile:
    with _open(path, max_bytes) as f, _library_errors(path, ".npy file"):
        version = np.lib.format.read_magic(f)
        if version == (1, 0):
            shape, _, dtype = np.lib.format.read_array_header_1_0(f)
        elif version == (2, 0):
            shape, _, dtype = np.lib.format.read_array_header_2_0(f)
        else:  # 3.0 only exists for structured dtypes with unicode field names, which are no volume anyway
            raise FormatError(f"{path}: unsupported .npy version {version[0]}.{version[1]}")
        _check_array(path, shape, dtype, max_bytes)
        f.seek(0)
        array = np.load(f, allow_pickle=False)
    return VolumeFile(_as_volume(array))


def _write_npy(path: PathLike, data: np.ndarray) -> None:
    buffer = io.BytesIO()
    np.save(buffer, data, allow_pickle=False)
    write_bytes(path, buffer.getvalue())


# --- TIFF ------------------------------------------------------------------------------------------------------


class _LogRecords(logging.Handler):
    def __init__(self) -> None:
        super().__init__(logging.WARNING)
        self.messages: list[str] = []

    def emit(self, record: logging.LogRecord) -> None:
        self.messages.append(record.getMessage())


# Without imagecodecs, tifffile inflates a zlib or LZMA segment whole, whatever size its page gives it; an LZMA
# decoder also allocates the dictionary its stream declares (8 MiB by default, up to 4 GiB), here within max_bytes.
_TIFF_INFLATERS = {  # compression: a decompressor within max_bytes
    **dict.fromkeys((8, 32946, 50013), lambda max_bytes: zlib.decompressobj()),
    34925: lambda max_bytes: lzma.LZMADecompressor(memlimit=max_bytes),
}


def _check_segments(path: PathLike, f: BinaryIO, keyframe: tifffile.TiffPage, pages: list, max_bytes: int) -> None:
    """tifffile reads as many bytes as a strip's or tile's byte count says and inflates a compressed one whole (64 MiB
    of zeros fit in a 64 KiB zlib strip). So each must lie within the file, its declared size (a tile may be declared
    far larger than its image) within max_bytes, and a compressed one must inflate to no more than that."""
    size = math.prod(keyframe.chunks) * keyframe.dtype.itemsize
    if size > max_bytes:
        raise FormatError(f"{path}: a TIFF tile or strip of {size} bytes is over the size limit of {max_bytes} bytes")
    inflater = _TIFF_INFLATERS.get(keyframe.compression)
    file_size = os.fstat(f.fileno()).st_size
    for page in pages:
        for offset, count in zip(page.dataoffsets, page.databytecounts):
            if offset + count > file_size:
                raise FormatError(f"{path} is truncated: a TIFF strip or tile ends at byte {offset + count}, "
                                  f"the file at {file_size}")
            if inflater is None:
                continue
            f.seek(offset)
            if len(inflater(max_bytes).decompress(f.read(count), size + 1)) > size:
                raise FormatError(f"{path}: a compressed TIFF strip or tile holds more than its {size} bytes")


def _read_tiff(path: PathLike, max_bytes: int) -> VolumeFile:
    """Pages are z slices. 16-bit and float greyscale stacks are scalars: the model's window maps them to colours.

    tifffile only logs a broken page chain and returns the pages before it, so anything it logs is an error here:
    a damaged file must not load as a thinner volume.
    """
    log = _LogRecords()
    logger = tifffile.logger()
    logger.addHandler(log)
    try:
        with _open(path, max_bytes) as f, _library_errors(path, "TIFF file"), tifffile.TiffFile(f) as tif:
            # Index the page chain first: that walk stops at an IFD pointing back into the chain (and logs it),
            # while `series` walks it page by page without that check and loops for ever on one.
            len(tif.pages)
            if not tif.series:
                raise FormatError(f"{path} is not a valid TIFF file: it holds no images")
            if len(tif.series) != 1:
                raise FormatError(
                    f"{path} holds {len(tif.series)} image series (pages of different sizes or types), not one stack"
                )
            series = tif.series[0]
            axes, shape = series.axes, series.shape
            if "S" in axes:  # samples (colour channels): last when interleaved, before YX when stored planar
                s = axes.index("S")
                axes, shape, samples = axes[:s] + axes[s + 1 :], shape[:s] + shape[s + 1 :], shape[s : s + 1]
            else:
                samples = ()
            # Every axis before YX is "pages" (ImageJ may call them Z, C, T, Q...); two of them would be a hyperstack.
            if not axes.endswith("YX") or sum(n > 1 for n in shape[:-2]) > 1:
                raise FormatError(f"{path}: TIFF layout {series.axes} {series.shape} is not a single stack of slices")
            volume_shape = (math.prod(shape[:-2]), *shape[-2:], *samples)
            _check_array(path, volume_shape, series.dtype, max_bytes)
            photometric = series.keyframe.photometric
            if photometric not in (tifffile.PHOTOMETRIC.MINISBLACK, tifffile.PHOTOMETRIC.RGB):
                raise FormatError(
                    f"{path}: TIFF colour model {photometric.name} is not supported (greyscale or RGB/RGBA)"
                )
            _check_segments(path, f, series.keyframe, series.pages, max_bytes)
            array = series.asarray(maxworkers=1)  # one segment decoded at a time: _check_segments bounds each
    finally:
        logger.removeHandler(log)
    if log.messages:
        raise FormatError(f"{path} is a damaged TIFF file: {log.messages[0]}")
    if "S" in series.axes:
        array = np.moveaxis(array, series.axes.index("S"), -1)
    # A statement of its own: should the reshape copy (page axes merged across planar samples), the original is
    # freed before _as_volume allocates the RGBA volume.
    array = array.reshape(volume_shape)
    return VolumeFile(_as_volume(array))


def _write_tiff(path: PathLike, data: np.ndarray) -> None:
    buffer = io.BytesIO()
    if data.ndim == 3:
        tifffile.imwrite(buffer, data, photometric="minisblack")
    else:  # straight (not premultiplied) alpha
        tifffile.imwrite(buffer, data, photometric="rgb", extrasamples=["unassalpha"])
    write_bytes(path, buffer.getvalue())


# --- NRRD ------------------------------------------------------------------------------------------------------

# NRRD's type names (the spec's, as pynrrd reads them) of the types Shadelab reads: uint8 and SCALAR_TYPES.
_NRRD_TYPES = {
    **dict.fromkeys(("uchar", "unsigned char", "uint8", "uint8_t"), "u1"),
    **dict.fromkeys(("signed char", "int8", "int8_t"), "i1"),
    **dict.fromkeys(("short", "short int", "signed short", "signed short int", "int16", "int16_t"), "i2"),
    **dict.fromkeys(("ushort", "unsigned short", "unsigned short int", "uint16", "uint16_t"), "u2"),
    **dict.fromkeys(("int", "signed int", "int32", "int32_t"), "i4"),
    **dict.fromkeys(("uint", "unsigned int", "uint32", "uint32_t"), "u4"),
    "float": "f4", "double": "f8",
}
_NRRD_ENDIAN = {"little": "<", "big": ">"}
_NRRD_ENCODINGS = ("raw", "gzip", "gz", "bzip2", "bz2")
_NRRD_MAX_HEADER = 1 << 16
_NRRD_WINDOW = "shadelab_window"  # a key/value field: a scalar volume's window and colour map
_PIECE = 1 << 16  # bytes read, and inflated, at a time


def _nrrd_header_lines(path: PathLike, f: BinaryIO) -> list[bytes]:
    """The header up to its blank line, read with a bound: pynrrd would slurp a binary file without newlines whole."""
    lines: list[bytes] = []
    while True:
        line = f.readline(_NRRD_MAX_HEADER)
        if not lines and not line.startswith(b"NRRD"):
            raise FormatError(f"{path} is not a NRRD file: it does not start with 'NRRD'")
        if not line.endswith(b"\n") or f.tell() > _NRRD_MAX_HEADER:
            raise FormatError(f"{path}: the NRRD header is truncated or longer than {_NRRD_MAX_HEADER} bytes")
        lines.append(line)
        if not line.strip():
            return lines


def _nrrd_inflate(path: PathLike, f: BinaryIO, encoding: str, n: int) -> bytearray:
    """Decompress into a buffer of n bytes, a piece of at most _PIECE bytes at a time (so a read holds the voxel data
    and one piece): a stream that inflates beyond its header's sizes is refused, not unpacked."""
    bz = encoding.startswith("bz")
    inflater = bz2.BZ2Decompressor() if bz else zlib.decompressobj(zlib.MAX_WBITS | 32)
    data, filled, pending = bytearray(n), 0, b""
    with _library_errors(path, f"NRRD file ({encoding} data)"):
        while not inflater.eof:
            fresh = b""
            if inflater.needs_input if bz else not pending:
                fresh = pending = f.read(_PIECE)
            piece = inflater.decompress(pending, min(_PIECE, n + 1 - filled))
            pending = b"" if bz else inflater.unconsumed_tail  # zlib hands back what it did not take
            if filled + len(piece) > n:
                raise FormatError(f"{path} has trailing data: more than the {n} bytes of voxel data its sizes describe")
            data[filled:filled + len(piece)] = piece
            filled += len(piece)
            if not piece and not fresh:  # nothing more to read and nothing made of it: the stream stops short
                break
    if inflater.unused_data or pending or f.read(1):
        raise FormatError(f"{path} has trailing data: more than the {n} bytes of voxel data its sizes describe")
    if not inflater.eof or filled < n:
        raise FormatError(f"{path} is truncated: expected {n} bytes of voxel data, {encoding} data holds {filled}")
    return data


def _read_nrrd(path: PathLike, max_bytes: int) -> VolumeFile:
    header, array = read_nrrd(path, max_bytes)
    return VolumeFile(_as_volume(array), _nrrd_transfer(path, header, array.dtype))


def read_nrrd(path: PathLike, max_bytes: int) -> tuple[dict, np.ndarray]:
    """The header (pynrrd's fields) and the array of a NRRD file of a volume's layout as the file holds it (its
    type and byte order, numpy's C order; a scan's labels are read so). Attached raw, gzip or bzip2 data; pynrrd
    parses the header, the payload is read here with bounds."""
    with _open(path, max_bytes) as f:
        lines = _nrrd_header_lines(path, f)
        with _library_errors(path, "NRRD header"):
            header = nrrd.read_header(lines)
        if "data file" in header or "datafile" in header:
            raise FormatError(f"{path}: detached NRRD data (a 'data file' field) is not supported")
        if any(header.get(field, 0) != 0 for field in ("line skip", "lineskip", "byte skip", "byteskip")):
            raise FormatError(f"{path}: NRRD line/byte skips are not supported")
        dtype = _nrrd_dtype(path, header)
        encoding = header.get("encoding")
        if encoding not in _NRRD_ENCODINGS:
            raise FormatError(f"{path}: NRRD encoding {encoding!r} is not supported ({', '.join(_NRRD_ENCODINGS)})")
        sizes = header.get("sizes")
        if sizes is None or header.get("dimension") != len(sizes):
            raise FormatError(f"{path}: the NRRD header's dimension and sizes disagree or are missing")
        # NRRD lists sizes fastest axis first: "sizes: 4 w h d" for a colour volume, components first. Reversed,
        # that is numpy's C order (d, h, w, 4), what pynrrd's index_order='C' returns; 'F' would give (4, w, h, d).
        shape = tuple(int(n) for n in reversed(sizes))
        _check_array(path, shape, dtype, max_bytes)
        n = math.prod(shape) * dtype.itemsize
        data = _read_exact(path, f, n) if encoding == "raw" else _nrrd_inflate(path, f, encoding, n)
    return header, np.frombuffer(data, dtype).reshape(shape)


def _nrrd_transfer(path: PathLike, header: dict, dtype: np.dtype) -> TransferFunction | None:
    """The scalars' window and colour map the header keeps ("shadelab_window:=low high colourmap"), checked as the
    model checks them; None where it keeps none."""
    text = header.get(_NRRD_WINDOW)
    if text is None:
        return None
    words = str(text).split()
    if not _is_scalar(dtype) or len(words) != 3:
        raise FormatError(f"{path}: its {_NRRD_WINDOW} field must be 'low high colour-map' and go with 16-bit or "
                          f"float voxels, not {str(text)[:60]!r} with {dtype} voxels")
    try:
        return TransferFunction(float(words[0]), float(words[1]), words[2])
    except ValueError as exc:  # not a number, or a window or colour map the model refuses
        raise FormatError(f"{path}: its {_NRRD_WINDOW} field: {exc}") from None


def _nrrd_dtype(path: PathLike, header: dict) -> np.dtype:
    """The voxels' type, with the byte order a multi-byte type must state."""
    code = _NRRD_TYPES.get(header.get("type"))
    if code is None:
        raise FormatError(f"{path}: voxels are {header.get('type')}; Shadelab reads 8-bit (uint8) volumes and scalar "
                          f"volumes of {_SCALAR_NAMES}")
    if code[1] == "1":
        return np.dtype(code)
    if header.get("endian") not in _NRRD_ENDIAN:
        raise FormatError(f"{path}: a NRRD file of {header['type']} voxels must say 'endian: little' or 'endian: "
                          f"big', not {header.get('endian')!r}")
    return np.dtype(_NRRD_ENDIAN[header["endian"]] + code)


def _write_nrrd(path: PathLike, data: np.ndarray, transfer: TransferFunction | None = None) -> None:
    buffer = io.BytesIO()
    kinds = ["domain"] * 3 if data.ndim == 3 else ["RGBA-color", "domain", "domain", "domain"]
    header = {"encoding": "gzip", "kinds": kinds}
    if transfer is not None:  # a key/value field (":="), which other NRRD readers pass over
        header[_NRRD_WINDOW] = f"{transfer.low!r} {transfer.high!r} {transfer.colormap}"
    # C order: sizes come out as 4 w h d (w h d for scalars); pynrrd states the byte order of wider types. Level 1:
    # a 256^3 int16 CT phantom gzips in 0.4 s to 15.0 MB, level 6 in 2.0 s to 14.6 MB (autosaves write these).
    nrrd.write(buffer, data, header, compression_level=1, index_order="C")
    write_bytes(path, buffer.getvalue())


# --- numbered image series -------------------------------------------------------------------------------------

_SLICE_NUMBER = re.compile(r"%(0\d+)?[id]")
_MAX_NUMBER_WIDTH = 9  # 4096 slices need 4 digits; %0500000000i would only cost memory, 500 MB for each name
_IMAGE_FORMATS = {".png": "PNG", ".bmp": "BMP", ".jpg": "JPEG", ".jpeg": "JPEG", ".gif": "GIF", ".tga": "TGA"}
_PIL_FORMATS = ("BMP", "PNG", "JPEG", "GIF", "TGA")
_NO_ALPHA = ("JPEG", "BMP")  # Pillow writes BMP alpha but reads it back as RGB, as most BMP readers do
_MANIFEST_FORMAT = "shadelab-image-series"


@dataclass(frozen=True)
class _Series:
    """slice_%i.png, slice_%d.png or slice_%03i.png: slice z is folder/head + z, zero-padded to width, + tail."""

    folder: Path
    head: str
    width: int
    tail: str

    @classmethod
    def parse(cls, pattern: PathLike, action: str) -> _Series:
        """Only the file name may hold the number."""
        path = Path(pattern)
        matches = list(_SLICE_NUMBER.finditer(path.name))
        if len(matches) != 1:
            raise FormatError(
                f"cannot {action} {pattern}: image volumes are numbered series, "
                "put one %i in the file name (e.g. slice_%i.png)"
            )
        width = (matches[0][1] or "0").lstrip("0") or "0"
        if len(width) > len(str(_MAX_NUMBER_WIDTH)) or int(width) > _MAX_NUMBER_WIDTH:  # int() of a short string only
            raise FormatError(
                f"cannot {action} {pattern}: slice numbers are padded to {_MAX_NUMBER_WIDTH} digits at most "
                f"(%0{_MAX_NUMBER_WIDTH}i)"
            )
        return cls(path.parent, path.name[: matches[0].start()], int(width), path.name[matches[0].end() :])

    def slice(self, z: int) -> Path:
        return self.folder / f"{self.head}{str(z).zfill(self.width)}{self.tail}"

    @property
    def manifest(self) -> Path:
        """One name for the pattern's spellings of the same files: slice_%i.png and slice_%d.png share it."""
        number = f"%0{self.width}i" if self.width > 1 else "%i"
        return self.folder / f"{self.head}{number}{self.tail}.series.json"

    def depth(self, start: int = 0) -> int:
        """The first missing slice number from start on, at most MAX_SIDE + 1 (one past, so _check_shape says why)."""
        depth = start
        while depth <= MAX_SIDE and self.slice(depth).is_file():
            depth += 1
        return depth


def _open_image(path: Path, f: BinaryIO) -> Image.Image:
    try:
        with warnings.catch_warnings():  # Pillow's warning of a big image: _check_shape refuses it by its size
            warnings.simplefilter("ignore", Image.DecompressionBombWarning)
            return Image.open(f, formats=_PIL_FORMATS)
    except UnidentifiedImageError:  # its message shows the file object's repr, not a name
        raise FormatError(f"{path} is not a {', '.join(_PIL_FORMATS[:-1])} or {_PIL_FORMATS[-1]} image") from None


_MANIFEST_SCHEMA = validator({"sha256": array({"type": "string", "pattern": "^[0-9a-f]{64}$"}, MAX_SIDE, 1,
                                            "digests")}, required=["sha256"])


def _mixed(manifest: Path) -> str:
    return (
        "the slices are not the ones saved together (a save that did not finish, or slices changed by another "
        f"program); delete {manifest.name} to read them as they are"
    )


def _manifest_digests(pattern: PathLike, series: _Series, depth: int) -> list[str] | None:
    """The SHA-256 of each slice file, as the series' manifest lists them; None for a series without one."""
    manifest = series.manifest
    if not manifest.is_file():  # series written by other programs have none
        return None
    digests = read_versioned(manifest, _MANIFEST_FORMAT, 1, FormatError, _MANIFEST_SCHEMA)["sha256"]
    if len(digests) != depth:
        raise FormatError(
            f"cannot read {pattern}: {depth} slices found, {manifest.name} lists {len(digests)}: {_mixed(manifest)}"
        )
    return digests


def _check_digest(path: Path, f: BinaryIO, digest: str, manifest: Path) -> None:
    sha256 = hashlib.sha256()
    while chunk := f.read(1 << 20):
        sha256.update(chunk)
    if sha256.hexdigest() != digest:
        raise FormatError(f"{path} is not the slice {manifest.name} lists: {_mixed(manifest)}")
    f.seek(0)


def _read_series(pattern: PathLike, max_bytes: int) -> VolumeFile:
    """Slices numbered from 0 up to the first missing number; each image is one z slice, its top row y = 0.

    Any of BMP, PNG, JPEG, GIF (first frame) and TGA is read whatever the extension; 16-bit and float images are
    refused. A series with a manifest (Shadelab writes one) must be exactly the slices it lists.
    """
    series = _Series.parse(pattern, "read")
    depth = series.depth()
    if depth == 0:
        raise FormatError(f"cannot read {pattern}: slice 0 ({series.slice(0)}): No such file or directory")
    digests = _manifest_digests(pattern, series, depth)
    volume = None
    for z in range(depth):
        path = series.slice(z)
        with _open(path, max_bytes) as f:
            if digests is not None:
                _check_digest(path, f, digests[z], series.manifest)
            with _library_errors(path, "image"), _open_image(path, f) as image:
                if image.mode.startswith(("I", "F")):
                    raise FormatError(f"{path}: {image.mode} images are not supported; save the slices as 8-bit images")
                if volume is None:
                    _check_shape(pattern, (depth, image.height, image.width), max_bytes)
                    volume = np.empty((depth, image.height, image.width, 4), np.uint8)
                elif image.size != volume.shape[2:0:-1]:
                    raise FormatError(
                        f"{path}: slice is {image.width}x{image.height}, "
                        f"but slice 0 ({series.slice(0)}) is {volume.shape[2]}x{volume.shape[1]}"
                    )
                volume[z] = np.asarray(image.convert("RGBA"))
    return VolumeFile(volume)


def _encode_slice(rgba: np.ndarray, image_format: str) -> bytes:
    image = Image.fromarray(rgba)
    buffer = io.BytesIO()
    if image_format in _NO_ALPHA:
        image = image.convert("RGB")
    # Full-resolution chroma: 4:2:0 would smear colour across neighbouring voxels.
    options = {"quality": 95, "subsampling": 0} if image_format == "JPEG" else {}
    image.save(buffer, image_format, **options)
    return buffer.getvalue()


def _write_series(pattern: PathLike, data: np.ndarray) -> None:
    """One file per z slice, in the format of the pattern's extension, and a manifest of their digests.

    JPEG is lossy and, like BMP, keeps no alpha (it reads back as 255); GIF keeps at most 256 colours and on/off
    transparency. Every slice is written to a temporary file first, so a save that fails there (a full disk)
    leaves the old series as it was. The renames after that are one file at a time, so the manifest goes first:
    a series a crash leaves half renamed fails the reader's manifest check instead of loading as a mix of two
    volumes. Higher-numbered slices left over from a deeper volume are deleted: they would read back as part of
    this one.
    """
    series = _Series.parse(pattern, "write")
    image_format = _IMAGE_FORMATS[Path(pattern).suffix.lower()]
    encoded = [_encode_slice(rgba, image_format) for rgba in data]  # every slice before the first file changes
    manifest = {"format": _MANIFEST_FORMAT, "version": 1, "sha256": [hashlib.sha256(b).hexdigest() for b in encoded]}
    with Batch() as slices, Batch() as index:
        for z, blob in enumerate(encoded):
            slices.stage(series.slice(z), blob)
        index.stage(series.manifest, json.dumps(manifest, indent=1).encode())
        index.commit()
        for z in range(len(encoded), series.depth(len(encoded))):
            series.slice(z).unlink()
        slices.commit()


# --- dispatch --------------------------------------------------------------------------------------------------

_READERS: dict[str, Callable[[PathLike, int], VolumeFile]] = {
    ".r3": _read_r3, ".raw": _read_r3, ".npy": _read_npy, ".tif": _read_tiff, ".tiff": _read_tiff,
    ".nrrd": _read_nrrd, **dict.fromkeys(_IMAGE_FORMATS, _read_series),
}
_WRITERS: dict[str, Callable[[PathLike, np.ndarray], None]] = {
    ".r3": _write_r3, ".raw": _write_r3, ".npy": _write_npy, ".tif": _write_tiff, ".tiff": _write_tiff,
    ".nrrd": _write_nrrd, **dict.fromkeys(_IMAGE_FORMATS, _write_series),
}

# Image extensions only as numbered series: a path with %i (or %d, %03i...) in its file name.
SUPPORTED: tuple[str, ...] = tuple(_READERS)
SCALAR_SUFFIXES = (".npy", ".nrrd", ".tif", ".tiff")  # the formats that hold scalars, read and written
WINDOW_SUFFIXES = (".nrrd",)  # those that keep the scalars' window and colour map with them


def _unsupported(action: str, path: PathLike) -> FormatError:
    suffix = Path(path).suffix or "(none)"
    return FormatError(
        f"cannot {action} {path}: unsupported file type {suffix}; supported: {', '.join(SUPPORTED)} "
        "(image types as numbered series such as slice_%i.png)"
    )


def read_volume(path: PathLike, max_bytes: int = DEFAULT_MAX_BYTES) -> np.ndarray:
    """The (depth, height, width, 4) uint8 volume in path, or the (depth, height, width) scalars of a 16-bit or
    float file (SCALAR_TYPES); chosen by extension; FormatError for anything wrong."""
    return read_volume_file(path, max_bytes).data


def read_volume_file(path: PathLike, max_bytes: int = DEFAULT_MAX_BYTES) -> VolumeFile:
    """read_volume's volume or scalars, with the window and colour map the file keeps them with."""
    reader = _READERS.get(Path(path).suffix.lower())
    if reader is None:
        raise _unsupported("read", path)
    return reader(path, max_bytes)


def write_volume(path: PathLike, data: np.ndarray, transfer: TransferFunction | None = None) -> None:
    """`transfer`: the window and colour map of scalars, kept where the format has room (WINDOW_SUFFIXES)."""
    suffix = Path(path).suffix.lower()
    writer = _WRITERS.get(suffix)
    if writer is None:
        raise _unsupported("write", path)
    _check_volume(path, data)
    if transfer is not None and data.ndim != 3:
        raise FormatError(f"cannot write {path}: a window goes with scalars, not with colours")
    kept = {"transfer": transfer} if transfer is not None and suffix in WINDOW_SUFFIXES else {}
    try:
        writer(path, np.ascontiguousarray(data), **kept)
    except OSError as exc:
        raise FormatError(f"cannot write {exc.filename or path}: {exc.strerror or exc}") from exc
