"""NRRD: pynrrd parses the header; the attached raw, gzip or bzip2 payload is read here with bounds."""
from __future__ import annotations

import bz2
import io
import math
import zlib
from dataclasses import replace
from typing import BinaryIO

import nrrd
import numpy as np

from app.io.atomic import write_bytes
from app.io.volume_formats.checks import (SCALAR_NAMES, PathLike, Spacing, VolumeFile, FormatError, as_volume,
                                          check_array, is_scalar, library_errors, open_file, read_exact,
                                          usable_spacing)
from app.model.volume.scalars import TransferFunction

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
_NRRD_OPACITY = "shadelab_opacity"  # and its opacity curve where it has one: "v0 a0 v1 a1 ..."
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
    with library_errors(path, f"NRRD file ({encoding} data)"):
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


def read(path: PathLike, max_bytes: int) -> VolumeFile:
    header, array = read_nrrd(path, max_bytes)
    notes: list[str] = []
    spacing = _nrrd_spacing(header, array.ndim == 4, notes)
    return VolumeFile(as_volume(array), _nrrd_transfer(path, header, array.dtype), spacing, tuple(notes))


def read_nrrd(path: PathLike, max_bytes: int) -> tuple[dict, np.ndarray]:
    """The header (pynrrd's fields) and the array of a NRRD file of a volume's layout as the file holds it (its
    type and byte order, numpy's C order; a scan's labels are read so). Attached raw, gzip or bzip2 data; pynrrd
    parses the header, the payload is read here with bounds."""
    with open_file(path, max_bytes) as f:
        lines = _nrrd_header_lines(path, f)
        with library_errors(path, "NRRD header"):
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
        check_array(path, shape, dtype, max_bytes)
        n = math.prod(shape) * dtype.itemsize
        data = read_exact(path, f, n) if encoding == "raw" else _nrrd_inflate(path, f, encoding, n)
    return header, np.frombuffer(data, dtype).reshape(shape)


def _nrrd_spacing(header: dict, colour: bool, notes: list[str]) -> Spacing | None:
    """The voxels' sides: the lengths of the space directions (Slicer writes them), else the spacings; a colour
    volume's first axis (its components) has none. An orientation the directions give is not applied."""
    field = "space directions" if "space directions" in header else "spacings" if "spacings" in header else None
    if field is None:
        return None
    try:
        values = np.asarray(header[field], dtype=float)[int(colour):]
        if field == "space directions":
            if (np.count_nonzero(values, axis=-1) > 1).any():
                notes.append("its space directions are oblique: their lengths are the spacing, the orientation "
                             "is not applied")
            values = np.linalg.norm(values, axis=-1)
    except (TypeError, ValueError):
        values = header[field]
    return usable_spacing(values, notes, f"NRRD {field}")


def _nrrd_transfer(path: PathLike, header: dict, dtype: np.dtype) -> TransferFunction | None:
    """The scalars' window and colour map the header keeps ("shadelab_window:=low high colourmap"), checked as the
    model checks them; None where it keeps none."""
    text = header.get(_NRRD_WINDOW)
    if text is None:
        return None
    words = str(text).split()
    if not is_scalar(dtype) or len(words) != 3:
        raise FormatError(f"{path}: its {_NRRD_WINDOW} field must be 'low high colour-map' and go with 16-bit or "
                          f"float voxels, not {str(text)[:60]!r} with {dtype} voxels")
    try:
        transfer = TransferFunction(float(words[0]), float(words[1]), words[2])
    except ValueError as exc:  # not a number, or a window or colour map the model refuses
        raise FormatError(f"{path}: its {_NRRD_WINDOW} field: {exc}") from None
    curve = header.get(_NRRD_OPACITY)
    if curve is None:
        return transfer
    try:
        numbers = [float(w) for w in str(curve).split()]
        if len(numbers) % 2:
            raise ValueError(f"{len(numbers)} numbers are no (value, opacity) pairs")
        return replace(transfer, points=tuple(zip(numbers[0::2], numbers[1::2])))
    except ValueError as exc:  # not a number, or a curve the model refuses
        raise FormatError(f"{path}: its {_NRRD_OPACITY} field: {exc}") from None


def _nrrd_dtype(path: PathLike, header: dict) -> np.dtype:
    """The voxels' type, with the byte order a multi-byte type must state."""
    code = _NRRD_TYPES.get(header.get("type"))
    if code is None:
        raise FormatError(f"{path}: voxels are {header.get('type')}; Shadelab reads 8-bit (uint8) volumes and scalar "
                          f"volumes of {SCALAR_NAMES}")
    if code[1] == "1":
        return np.dtype(code)
    if header.get("endian") not in _NRRD_ENDIAN:
        raise FormatError(f"{path}: a NRRD file of {header['type']} voxels must say 'endian: little' or 'endian: "
                          f"big', not {header.get('endian')!r}")
    return np.dtype(_NRRD_ENDIAN[header["endian"]] + code)


def write(path: PathLike, data: np.ndarray, transfer: TransferFunction | None = None,
          spacing: Spacing | None = None) -> None:
    buffer = io.BytesIO()
    kinds = ["domain"] * 3 if data.ndim == 3 else ["RGBA-color", "domain", "domain", "domain"]
    header = {"encoding": "gzip", "kinds": kinds}
    if spacing is not None:  # x y z, fastest axis first as the sizes; a colour axis has none
        header["spacings"] = [math.nan] * (data.ndim - 3) + list(spacing)
    if transfer is not None:  # a key/value field (":="), which other NRRD readers pass over
        header[_NRRD_WINDOW] = f"{transfer.low!r} {transfer.high!r} {transfer.colormap}"
        if transfer.points is not None:
            header[_NRRD_OPACITY] = " ".join(f"{v!r} {a!r}" for v, a in transfer.points)
    # C order: sizes come out as 4 w h d (w h d for scalars); pynrrd states the byte order of wider types. Level 1:
    # a 256^3 int16 CT phantom gzips in 0.4 s to 15.0 MB, level 6 in 2.0 s to 14.6 MB (autosaves write these).
    nrrd.write(buffer, data, header, compression_level=1, index_order="C")
    write_bytes(path, buffer.getvalue())
