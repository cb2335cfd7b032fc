"""DICOM (pydicom): a series of slice files (a folder, or its files), or one file of one or several frames.

Every file's header is read first (pydicom, stopping before the pixels), so the whole series is checked (one
series, one size, one orientation, a voxel type Shadelab reads) and its size held to the limit before any voxel is
read; then each file's pixels go straight into their slice of the volume, one file at a time. Slices are ordered
by their position along the slice normal (ImagePositionPatient . (row x column direction)), so the file names and
their order on disk do not matter; the slice spacing is the distance between successive slices (their median,
with a note where the gaps differ), the pixel spacing PixelSpacing's. RescaleSlope and RescaleIntercept are
applied (checks.rescaled): a CT opens in Hounsfield units. Pixel data must be uncompressed (the three native
transfer syntaxes): a compressed file is refused by its transfer syntax's name, since its decoders would size
their own output.
"""
from __future__ import annotations

import math
import os
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pydicom
from pydicom.dataset import Dataset
from pydicom.uid import ExplicitVRBigEndian, ExplicitVRLittleEndian, ImplicitVRLittleEndian

from app.io.volume_formats.checks import (MAX_SIDE, PathLike, VolumeFile, FormatError, as_scan, as_volume,
                                          check_array, library_errors, open_file, rescaled, usable_spacing)

SUFFIXES = (".dcm", ".dicom")  # besides these, a file that says "DICM" after its 128-byte preamble is DICOM
_NATIVE = (ImplicitVRLittleEndian, ExplicitVRLittleEndian, ExplicitVRBigEndian)
_PREAMBLE = 128
_MAX_FILES = 4 * MAX_SIDE  # entries a folder may hold: a series has at most MAX_SIDE slices, besides a few others
_SAME_DIRECTION = 1e-4     # orientation cosines closer than this are one orientation
_GAP_TOLERANCE = 0.01      # slice gaps within 1 % of their median are one spacing


def is_dicom(path: PathLike, max_bytes: int) -> bool:
    """Whether a file says it is DICOM ("DICM" after the preamble)."""
    with open_file(path, max_bytes) as f:
        return f.read(_PREAMBLE + 4)[_PREAMBLE:] == b"DICM"


@dataclass(frozen=True)
class _Slice:
    """One file's header: what the series checks and the order need."""
    path: Path
    series: str
    label: str            # the series' modality and description, for a message
    rows: int
    columns: int
    frames: int
    samples: int
    dtype: np.dtype       # as stored
    orientation: tuple[float, ...] | None  # row and column direction cosines
    position: tuple[float, ...] | None
    pixel_spacing: tuple[float, float] | None  # between rows, between columns
    slice_spacing: float | None  # SpacingBetweenSlices, SliceThickness or a frame offset grid's step
    slope: float | None
    intercept: float | None
    instance: int

    @property
    def size(self) -> str:
        return f"{self.columns}x{self.rows}" + (f"x{self.frames}" if self.frames > 1 else "")


def _number(value: object) -> float | None:
    try:
        number = None if value is None or value == "" else float(value)
    except (TypeError, ValueError):
        return None
    return number if number is not None and math.isfinite(number) else None


def _numbers(value: object, count: int) -> tuple[float, ...] | None:
    try:
        numbers = tuple(float(v) for v in value) if value is not None else ()
    except (TypeError, ValueError):
        return None
    return numbers if len(numbers) == count and all(map(math.isfinite, numbers)) else None


def _value(ds: Dataset, sequence: str, keyword: str) -> object:
    """ds's `keyword`, else the value an enhanced multi-frame object keeps in its shared functional groups."""
    if keyword in ds:
        return ds.get(keyword)
    try:
        return ds.SharedFunctionalGroupsSequence[0][sequence][0].get(keyword)
    except (AttributeError, KeyError, IndexError, TypeError):
        return None


def _slice_spacing(ds: Dataset) -> float | None:
    offsets = _numbers(ds.get("GridFrameOffsetVector"), int(ds.get("NumberOfFrames") or 1))
    if offsets is not None and len(offsets) > 1:  # RT dose: frames at these offsets
        return abs(float(np.median(np.diff(offsets))))
    for keyword in ("SpacingBetweenSlices", "SliceThickness"):
        value = _number(_value(ds, "PixelMeasuresSequence", keyword))
        if value:
            return abs(value)
    return None


def _header(path: Path, max_bytes: int) -> _Slice | None:
    """The file's header, checked; None for a DICOM file that holds no image (a DICOMDIR, a report)."""
    with open_file(path, max_bytes) as f, library_errors(path, "DICOM file"), warnings.catch_warnings():
        warnings.simplefilter("ignore")  # pydicom warns of values that break the standard; those used are checked
        ds = pydicom.dcmread(f, stop_before_pixels=True)
        if "Rows" not in ds or "Columns" not in ds:
            return None
        syntax = getattr(ds.file_meta, "TransferSyntaxUID", None)
        if syntax not in _NATIVE:
            name = getattr(syntax, "name", None) or syntax or "none stated"
            raise FormatError(f"{path}: DICOM pixel data in the transfer syntax {name} is not supported; Shadelab "
                              "reads uncompressed files (e.g. `gdcmconv --raw` or `dcmdjpeg` decompress one)")
        bits, signed, samples = ds.get("BitsAllocated"), ds.get("PixelRepresentation", 0), ds.get("SamplesPerPixel", 1)
        if bits not in (8, 16, 32) or signed not in (0, 1):
            raise FormatError(f"{path}: DICOM pixels of {bits} bits (pixel representation {signed}) are not "
                              "supported: 8, 16 or 32 bits")
        photometric = str(ds.get("PhotometricInterpretation", "")).strip()
        if (samples, photometric) not in ((1, "MONOCHROME1"), (1, "MONOCHROME2"), (3, "RGB")) or (
                samples == 3 and bits != 8):
            raise FormatError(f"{path}: DICOM {photometric or 'images'} of {samples} samples of {bits} bits are not "
                              "supported: greyscale (MONOCHROME1 or 2), or 8-bit RGB")
        slope = _number(_value(ds, "PixelValueTransformationSequence", "RescaleSlope"))
        return _Slice(
            path, str(ds.get("SeriesInstanceUID", "(no series UID)")),
            " ".join(str(v) for v in (ds.get("Modality"), ds.get("SeriesDescription")) if v) or "no description",
            int(ds.Rows), int(ds.Columns), int(ds.get("NumberOfFrames") or 1), int(samples),
            np.dtype(f"{'>' if syntax == ExplicitVRBigEndian else '<'}{'iu'[signed == 0]}{bits // 8}"),
            _numbers(ds.get("ImageOrientationPatient"), 6), _numbers(ds.get("ImagePositionPatient"), 3),
            _numbers(_value(ds, "PixelMeasuresSequence", "PixelSpacing"), 2), _slice_spacing(ds),
            _number(ds.get("DoseGridScaling")) if slope is None else slope,  # RT dose: stored values times it are Gy
            _number(_value(ds, "PixelValueTransformationSequence", "RescaleIntercept")),
            int(_number(ds.get("InstanceNumber")) or 0))


def _image(path: Path, max_bytes: int) -> _Slice:
    """A file given as a DICOM image: one without an image is refused."""
    found = _header(path, max_bytes)
    if found is None:
        raise FormatError(f"{path} is a DICOM file without an image (no Rows and Columns)")
    return found


def _listing(groups: dict, describe, shown: int = 6) -> str:
    """The first `shown` groups of files, each described with its count of files."""
    listed = [f"{describe(key, members)} ({len(members)} file{'s' * (len(members) > 1)})"
              for key, members in list(groups.items())[:shown]]
    return "; ".join(listed) + (f"; and {len(groups) - shown} more" if len(groups) > shown else "")


def _group(slices: list[_Slice], key) -> dict:
    groups: dict = {}
    for s in slices:
        groups.setdefault(key(s), []).append(s)
    return groups


def _check_one_series(source: PathLike, slices: list[_Slice]) -> None:
    """One series, of one size, type and orientation, and of single frames unless it is one file."""
    series = _group(slices, lambda s: s.series)
    if len(series) > 1:
        raise FormatError(f"{source} holds {len(series)} DICOM series; open one (its files, or a folder of it "
                          f"alone): {_listing(series, lambda uid, m: f'{uid} {m[0].label}')}")
    layouts = _group(slices, lambda s: (s.size, s.samples, s.dtype.str[1:]))
    if len(layouts) > 1:
        raise FormatError(f"{source}: its DICOM slices differ in size or voxel type, so they make no volume: "
                          f"{_listing(layouts, lambda k, m: f'{k[0]} {k[2]}' + ' RGB' * (k[1] == 3))}")
    if len(slices) > 1 and slices[0].frames > 1:
        raise FormatError(f"{source}: a series of {len(slices)} multi-frame DICOM files is not supported; open one")
    rounded = _group(slices, lambda s: s.orientation and tuple(round(c / _SAME_DIRECTION) for c in s.orientation))
    if len(rounded) > 1:
        raise FormatError(f"{source}: its DICOM slices lie in {len(rounded)} orientations, so they make no volume "
                          "(a localiser, or a radial acquisition): "
                          f"{_listing(rounded, lambda k, m: ' '.join(f'{c:g}' for c in m[0].orientation or ()))}")


def _ordered(slices: list[_Slice], notes: list[str]) -> tuple[list[_Slice], float | None]:
    """The slices by their position along the slice normal, and the distance between successive ones; by instance
    number (and no distance) where a position or orientation is missing."""
    first = slices[0]
    if len(slices) == 1:
        return slices, first.slice_spacing
    if first.orientation is None or any(s.position is None for s in slices):
        notes.append("slices ordered by instance number: not all of them state their position and orientation")
        return sorted(slices, key=lambda s: s.instance), first.slice_spacing
    normal = np.cross(first.orientation[:3], first.orientation[3:])
    along = {id(s): float(np.dot(s.position, normal)) for s in slices}
    ordered = sorted(slices, key=lambda s: along[id(s)])
    gaps = np.diff([along[id(s)] for s in ordered])
    if gaps.min() <= 1e-4:
        at = int(np.argmin(gaps))
        raise FormatError(f"{ordered[at].path} and {ordered[at + 1].path.name} lie at the same position "
                          f"({along[id(ordered[at])]:g} mm along the slice normal): the series holds several volumes "
                          "(echoes, phases or time points); open the files of one")
    spacing = float(np.median(gaps))
    if gaps.max() - gaps.min() > _GAP_TOLERANCE * spacing:
        notes.append(f"slice gaps differ from {gaps.min():g} to {gaps.max():g} mm: the slices are shown evenly, "
                     f"{spacing:g} mm apart (their median)")
    return ordered, spacing


def _read_pixels(s: _Slice, max_bytes: int) -> np.ndarray:
    with open_file(s.path, max_bytes) as f, library_errors(s.path, "DICOM file"), warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ds = pydicom.dcmread(f)
        if (ds.get("Rows"), ds.get("Columns"), int(ds.get("NumberOfFrames") or 1)) != (s.rows, s.columns, s.frames):
            raise FormatError(f"{s.path} changed while it was read")
        pixels = ds.pixel_array
    shape = (s.frames,) * (s.frames > 1) + (s.rows, s.columns) + (3,) * (s.samples == 3)
    if pixels.shape != shape:
        raise FormatError(f"{s.path}: its DICOM pixel data holds {pixels.shape}, its header says {shape}")
    return pixels


def _assemble(source: PathLike, slices: list[_Slice], max_bytes: int, notes: list[str]) -> VolumeFile:
    _check_one_series(source, slices)
    ordered, slice_spacing = _ordered(slices, notes)
    first = ordered[0]
    depth = first.frames if first.frames > 1 else len(ordered)
    shape = (depth, first.rows, first.columns) + (3,) * (first.samples == 3)
    rescales = {(s.slope, s.intercept) for s in ordered}
    per_slice = len(rescales) > 1  # PET rescales each slice: one float volume, each slice rescaled as it is read
    stored = first.dtype.newbyteorder("=")
    kind = np.dtype(np.float32 if stored.itemsize <= 2 else np.float64) if per_slice else stored
    check_array(source, shape, kind, max_bytes)
    volume = np.empty(shape, kind)
    for z, s in enumerate(ordered):
        pixels = _read_pixels(s, max_bytes)
        if first.frames > 1:
            volume[...] = pixels
        elif per_slice:
            volume[z] = rescaled(s.path, pixels.astype(kind), s.slope, s.intercept, [], max_bytes)
        else:
            volume[z] = pixels
    if per_slice:
        notes.append(f"each slice rescaled by its own slope and intercept into {kind}")
    else:
        volume = rescaled(source, volume, first.slope, first.intercept, notes, max_bytes)
    if first.pixel_spacing is None:
        notes.append("no PixelSpacing: the pixels are taken as squares")
    row_gap, column_gap = first.pixel_spacing or (1.0, 1.0)
    if slice_spacing is None:
        notes.append("no slice spacing stated: the slices are taken as far apart as the pixels are wide")
    spacing = usable_spacing((column_gap, row_gap, slice_spacing or column_gap), notes, "DICOM spacing")
    notes.insert(0, f"DICOM {first.label}: {depth} slice{'s' * (depth > 1)} of {first.columns}x{first.rows}, "
                 f"spacing {column_gap:g} {row_gap:g} {slice_spacing or column_gap:g} mm")
    return VolumeFile(as_volume(as_scan(volume, notes)), spacing=spacing, notes=tuple(notes))


def read_file(path: PathLike, max_bytes: int) -> VolumeFile:
    """One DICOM file: a slice, or the frames of a multi-frame object."""
    return _assemble(path, [_image(Path(path), max_bytes)], max_bytes, [])


def read_files(paths: list[PathLike], max_bytes: int) -> VolumeFile:
    """The files of one series, each a DICOM image."""
    if len(paths) > MAX_SIDE:
        raise FormatError(f"{len(paths)} DICOM files are more slices than {MAX_SIDE}")
    slices = [_image(Path(p), max_bytes) for p in paths]
    return _assemble(f"{len(paths)} DICOM files in {Path(paths[0]).parent}", slices, max_bytes, [])


def read_folder(folder: PathLike, max_bytes: int) -> VolumeFile:
    """The DICOM images directly in `folder` (files that are not, such as a DICOMDIR or a README, and subfolders
    are passed over, and said so): they must be one series."""
    folder = Path(folder)
    try:
        with os.scandir(folder) as scan:
            entries = []
            for entry in scan:
                entries.append(entry)
                if len(entries) > _MAX_FILES:
                    raise FormatError(f"{folder} holds more than {_MAX_FILES} entries; a DICOM series folder holds "
                                      f"at most {MAX_SIDE} slices")
    except OSError as exc:
        raise FormatError(f"cannot read {folder}: {exc.strerror or exc}") from None
    notes: list[str] = []
    slices, passed = [], []
    for entry in sorted(entries, key=lambda e: e.name):
        path = Path(entry.path)
        if not entry.is_file() or entry.name.startswith("."):
            passed.append(entry.name + "/" * entry.is_dir())
        elif not is_dicom(path, max_bytes) or (found := _header(path, max_bytes)) is None:
            passed.append(entry.name)
        else:
            slices.append(found)
    if not slices:
        raise FormatError(f"{folder} holds no DICOM images" + (f" (only {', '.join(passed[:5])}"
                                                               f"{'...' * (len(passed) > 5)})" if passed else ""))
    if len(slices) > MAX_SIDE:
        raise FormatError(f"{folder} holds {len(slices)} DICOM images, more slices than {MAX_SIDE}")
    if passed:
        notes.append(f"passed over what is no DICOM image: {', '.join(passed[:5])}"
                     f"{f' and {len(passed) - 5} more' if len(passed) > 5 else ''}")
    return _assemble(folder, slices, max_bytes, notes)
