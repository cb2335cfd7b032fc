"""TIFF stacks: pages are z slices (tifffile), every strip and tile bounded before it is read."""
from __future__ import annotations

import io
import logging
import lzma
import math
import os
import zlib
from typing import BinaryIO

import numpy as np
import tifffile

from app.io.atomic import write_bytes
from app.io.volume_formats.checks import (PathLike, Spacing, VolumeFile, FormatError, as_volume, check_array,
                                          library_errors, open_file, usable_spacing)

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


def read(path: PathLike, max_bytes: int) -> VolumeFile:
    """Pages are z slices. 16-bit and float greyscale stacks are scalars: the model's window maps them to colours.

    tifffile only logs a broken page chain and returns the pages before it, so anything it logs is an error here:
    a damaged file must not load as a thinner volume.
    """
    log = _LogRecords()
    logger = tifffile.logger()
    logger.addHandler(log)
    try:
        with open_file(path, max_bytes) as f, library_errors(path, "TIFF file"), tifffile.TiffFile(f) as tif:
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
            check_array(path, volume_shape, series.dtype, max_bytes)
            photometric = series.keyframe.photometric
            if photometric not in (tifffile.PHOTOMETRIC.MINISBLACK, tifffile.PHOTOMETRIC.RGB):
                raise FormatError(
                    f"{path}: TIFF colour model {photometric.name} is not supported (greyscale or RGB/RGBA)"
                )
            _check_segments(path, f, series.keyframe, series.pages, max_bytes)
            array = series.asarray(maxworkers=1)  # one segment decoded at a time: _check_segments bounds each
            notes: list[str] = []
            spacing = _spacing(tif, series.keyframe, notes)
    finally:
        logger.removeHandler(log)
    if log.messages:
        raise FormatError(f"{path} is a damaged TIFF file: {log.messages[0]}")
    if "S" in series.axes:
        array = np.moveaxis(array, series.axes.index("S"), -1)
    # A statement of its own: should the reshape copy (page axes merged across planar samples), the original is
    # freed before _as_volume allocates the RGBA volume.
    array = array.reshape(volume_shape)
    return VolumeFile(as_volume(array), spacing=spacing, notes=tuple(notes))


def _spacing(tif: tifffile.TiffFile, page: tifffile.TiffPage, notes: list[str]) -> Spacing | None:
    """The pixel size from the X and Y resolution tags (pixels per unit); the slice spacing from ImageJ's
    `spacing` (ImageJ's own default is 1), else, not being in the file, the pixel's width. None where the
    resolution is the tags' default 1 and nothing else is said."""
    ij = tif.imagej_metadata or {}
    if 282 not in page.tags and "spacing" not in ij:
        return None
    try:
        x, y = (1.0 / float(r) for r in page.resolution)
        z = float(ij.get("spacing", 1.0 if tif.is_imagej else x))
    except (TypeError, ValueError, ZeroDivisionError):
        x = y = z = math.nan  # usable_spacing says why
    if (x, y, z) == (1.0, 1.0, 1.0):
        return None
    unit = ij.get("unit") or {2: "inch", 3: "cm"}.get(int(page.resolutionunit), "")
    if not tif.is_imagej:
        notes.append("the slice spacing is not in the file: the slices are taken as far apart as the pixels are wide")
    found = usable_spacing((x, y, z), notes, "TIFF resolution")
    if found is not None:
        notes.append(f"spacing {x:g} {y:g} {z:g}{' ' + str(unit) if unit else ''} (its resolution)")
    return found


def write(path: PathLike, data: np.ndarray) -> None:
    buffer = io.BytesIO()
    if data.ndim == 3:
        tifffile.imwrite(buffer, data, photometric="minisblack")
    else:  # straight (not premultiplied) alpha
        tifffile.imwrite(buffer, data, photometric="rgb", extrasamples=["unassalpha"])
    write_bytes(path, buffer.getvalue())
