"""Numbered image series (slice_%i.png...): one image a z slice, with a manifest of digests when Shadelab wrote it."""
from __future__ import annotations

import hashlib
import io
import json
import re
import warnings
from dataclasses import dataclass
from pathlib import Path
from typing import BinaryIO

import numpy as np
from PIL import Image, UnidentifiedImageError

from app.io.atomic import Batch
from app.io.json_file import array, read_versioned, validator
from app.io.volume_formats.checks import (MAX_SIDE, PathLike, VolumeFile, FormatError, check_shape, library_errors,
                                          open_file)

_SLICE_NUMBER = re.compile(r"%(0\d+)?[id]")
_MAX_NUMBER_WIDTH = 9  # 4096 slices need 4 digits; %0500000000i would only cost memory, 500 MB for each name
IMAGE_FORMATS = {".png": "PNG", ".bmp": "BMP", ".jpg": "JPEG", ".jpeg": "JPEG", ".gif": "GIF", ".tga": "TGA"}
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


def read(pattern: PathLike, max_bytes: int) -> VolumeFile:
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
        with open_file(path, max_bytes) as f:
            if digests is not None:
                _check_digest(path, f, digests[z], series.manifest)
            with library_errors(path, "image"), _open_image(path, f) as image:
                if image.mode.startswith(("I", "F")):
                    raise FormatError(f"{path}: {image.mode} images are not supported; save the slices as 8-bit images")
                if volume is None:
                    check_shape(pattern, (depth, image.height, image.width), max_bytes)
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


def write(pattern: PathLike, data: np.ndarray) -> None:
    """One file per z slice, in the format of the pattern's extension, and a manifest of their digests.

    JPEG is lossy and, like BMP, keeps no alpha (it reads back as 255); GIF keeps at most 256 colours and on/off
    transparency. Every slice is written to a temporary file first, so a save that fails there (a full disk)
    leaves the old series as it was. The renames after that are one file at a time, so the manifest goes first:
    a series a crash leaves half renamed fails the reader's manifest check instead of loading as a mix of two
    volumes. Higher-numbered slices left over from a deeper volume are deleted: they would read back as part of
    this one.
    """
    series = _Series.parse(pattern, "write")
    image_format = IMAGE_FORMATS[Path(pattern).suffix.lower()]
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
