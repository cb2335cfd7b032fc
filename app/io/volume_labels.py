"""A scan's labels file: a uint8 NRRD beside the scan, named as 3D Slicer names a segmentation (`ct.nrrd` ->
`ct.seg.nrrd`), one label a voxel (0 clear). Each label it holds is a segment in Slicer's header fields
(Segment<i>_LabelValue, _Color, _Name, _ID, _Layer, _Extent, and the Segmentation_* fields), as Slicer writes its
own; reading takes the colours those fields give (Slicer's files included). Read with the bounds of
app/io/volume_formats/nrrd.py's reader; written atomically."""
from __future__ import annotations

import io
import math
from pathlib import Path

import nrrd
import numpy as np

from app.io.atomic import write_bytes
from app.io.volume_formats import SUPPORTED, FormatError, PathLike, read_nrrd

LABELS_SUFFIX = ".seg.nrrd"
_SEGMENT = "Segment{}_{}"
_MAX_SEGMENTS = 256  # a header naming more segments than labels exist is not read further


def labels_path(scan: PathLike) -> Path:
    """Where a scan's labels are: its name less its volume suffix, plus .seg.nrrd (`ct.nrrd` -> `ct.seg.nrrd`; a
    DICOM folder `series` -> `series.seg.nrrd` beside it)."""
    scan = Path(scan)
    name = scan.name
    suffix = max((s for s in SUPPORTED if name.lower().endswith(s)), key=len, default="")
    return scan.with_name(name[:len(name) - len(suffix)] + LABELS_SUFFIX)


def write_labels(path: PathLike, labels: np.ndarray, colours: np.ndarray) -> None:
    """`labels` (d, h, w) uint8, each label present as a Slicer segment with its colour from `colours` (256, 3)."""
    counts = np.bincount(labels.reshape(-1), minlength=256)
    header: dict = {"encoding": "gzip", "kinds": ["domain"] * 3,
                    "Segmentation_MasterRepresentation": "Binary labelmap",
                    "Segmentation_ContainedRepresentationNames": "Binary labelmap|",
                    "Segmentation_ReferenceImageExtentOffset": "0 0 0"}
    for i, label in enumerate(int(n) for n in np.flatnonzero(counts[1:]) + 1):
        extent = _extent(labels == label)
        fields = {"ID": f"Label_{label}", "Name": f"Label {label}", "LabelValue": str(label), "Layer": "0",
                  "Color": " ".join(f"{c / 255:.6g}" for c in colours[label]), "Extent": extent}
        header.update({_SEGMENT.format(i, key): value for key, value in fields.items()})
    buffer = io.BytesIO()
    nrrd.write(buffer, np.ascontiguousarray(labels), header, compression_level=1, index_order="C")
    try:
        write_bytes(path, buffer.getvalue())
    except OSError as exc:
        raise FormatError(f"cannot write {exc.filename or path}: {exc.strerror or exc}") from exc


def _extent(mask: np.ndarray) -> str:
    """Slicer's extent of a segment: first and last voxel along x, y and z."""
    spans = []
    for axis in (2, 1, 0):
        hit = np.flatnonzero(mask.any(axis=tuple(a for a in range(3) if a != axis)))
        spans += [str(hit[0]), str(hit[-1])]
    return " ".join(spans)


def read_labels(path: PathLike, max_bytes: int) -> tuple[np.ndarray, dict[int, tuple[int, int, int]]]:
    """The labels (d, h, w) uint8 and the colours its segments give, by label; FormatError for anything wrong."""
    header, labels = read_nrrd(path, max_bytes)
    if labels.dtype != np.uint8 or labels.ndim != 3:
        raise FormatError(f"{path}: labels are one uint8 a voxel (a 3D NRRD of unsigned char), not {labels.dtype} "
                          f"of shape {labels.shape} (Shadelab reads one layer of segments)")
    return labels, _colours(path, header)


def _colours(path: PathLike, header: dict) -> dict[int, tuple[int, int, int]]:
    colours = {}
    for i in range(_MAX_SEGMENTS):
        value, colour = header.get(_SEGMENT.format(i, "LabelValue")), header.get(_SEGMENT.format(i, "Color"))
        if value is None:
            break
        if colour is None:
            continue
        try:
            label, rgb = int(value), [float(c) for c in str(colour).split()]
        except ValueError:
            label, rgb = -1, []
        if not 1 <= label <= 255 or len(rgb) != 3 or not all(math.isfinite(c) and 0 <= c <= 1 for c in rgb):
            raise FormatError(f"{path}: segment {i} has label value {str(value)[:20]!r} and colour "
                              f"{str(colour)[:40]!r}; a label is 1..255, a colour three numbers 0..1")
        colours[label] = tuple(round(c * 255) for c in rgb)
    return colours
