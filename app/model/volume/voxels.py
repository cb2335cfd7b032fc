"""A 3D RGBA raster's voxels (and a scalar volume's values under them, and the labels painted over those): read by
voxel, slice or box, written by the volume's painting and history, with a record of the boxes changed for consumers
such as GPU uploads."""
from __future__ import annotations

import hashlib
import math
import operator
import os
from collections import deque
from dataclasses import dataclass
from functools import reduce
from itertools import islice

import numpy as np

from app.model.volume.scalars import Scalars, TransferFunction, colour

AXES = ("x", "y", "z")
MAX_SIDE = 4096          # voxels a side; also the largest brush
CHANGE_RECORDS = 4096    # consumers further behind than this many changes get the full box
# A voxel's sides (x, y, z) in the file's length unit (mm for CT, MRI and NIfTI): the box has the physical shape.
Spacing = tuple[float, float, float]
DEFAULT_SPACING: Spacing = (1.0, 1.0, 1.0)
MIN_SPACING, MAX_SPACING = 1e-6, 1e6  # a scan in metres or in micrometres fits either way
_ARRAY_AXIS = {"z": 0, "y": 1, "x": 2}          # axis name -> axis of Voxels.data
_ROT90_AXES = {"z": (2, 1), "x": (1, 0), "y": (0, 2)}  # np.rot90 axes turning x->y, y->z, z->x respectively


def _default_max_bytes() -> int:
    """4 GiB, or half the free memory if less: the biggest edits (smooth, a rotation, loading a file) hold a
    second copy of the volume while they run, and nothing more than small fixed-size temporaries."""
    limit = 4 << 30
    try:
        avail = os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (AttributeError, ValueError, OSError):
        return limit
    return min(limit, avail // 2) if avail > 0 else limit


MAX_BYTES = _default_max_bytes()


class VolumeError(ValueError):
    """A value the volume refuses; the message is meant for the user. The volume is unchanged."""


@dataclass(frozen=True)
class Box:
    """Half-open voxel box: x0 <= x < x1, y0 <= y < y1, z0 <= z < z1."""

    x0: int
    y0: int
    z0: int
    x1: int
    y1: int
    z1: int

    def union(self, other: Box) -> Box:
        if self.empty:
            return other
        if other.empty:
            return self
        return Box(min(self.x0, other.x0), min(self.y0, other.y0), min(self.z0, other.z0),
                   max(self.x1, other.x1), max(self.y1, other.y1), max(self.z1, other.z1))

    def intersect(self, other: Box) -> Box:
        return Box(max(self.x0, other.x0), max(self.y0, other.y0), max(self.z0, other.z0),
                   min(self.x1, other.x1), min(self.y1, other.y1), min(self.z1, other.z1))

    @property
    def shape(self) -> tuple[int, int, int]:
        return self.x1 - self.x0, self.y1 - self.y0, self.z1 - self.z0

    @property
    def empty(self) -> bool:
        return min(self.shape) <= 0

    def slices(self) -> tuple[slice, slice, slice]:
        """(z, y, x) slices into Voxels.data."""
        return slice(self.z0, self.z1), slice(self.y0, self.y1), slice(self.x0, self.x1)


def _fmt_bytes(n: int) -> str:
    return f"{n / 2**30:.1f} GiB" if n >= 2**30 else f"{n / 2**20:.1f} MiB"


def check_size(w: int, h: int, d: int, scalar_bytes: int = 0) -> None:
    """scalar_bytes: what a scalar volume keeps a voxel beside its colours (its value, and room for a label)."""
    if min(w, h, d) < 1 or max(w, h, d) > MAX_SIDE:
        raise VolumeError(f"volume sides must be within 1..{MAX_SIDE}, got {w} x {h} x {d}")
    need = w * h * d * (4 + scalar_bytes)
    if need > MAX_BYTES:
        what = "RGBA data, scalars and labels" if scalar_bytes else "RGBA data"
        raise VolumeError(f"a {w} x {h} x {d} volume needs {_fmt_bytes(need)} of {what},"
                          f" over the {_fmt_bytes(MAX_BYTES)} limit")


def check_spacing(sx: float, sy: float, sz: float) -> Spacing:
    """(sx, sy, sz) as floats, if each is finite and within MIN_SPACING..MAX_SPACING; else VolumeError."""
    spacing = tuple(float(s) for s in (sx, sy, sz))
    if not all(math.isfinite(s) and MIN_SPACING <= s <= MAX_SPACING for s in spacing):
        raise VolumeError(f"each spacing must be within {MIN_SPACING:g}..{MAX_SPACING:g}, got "
                          f"{' '.join(f'{s:g}' for s in spacing)}")
    return spacing


def whole(name: str, value: object) -> int:
    try:
        return operator.index(value)
    except TypeError:
        raise VolumeError(f"{name} must be a whole number, got {value!r}") from None


def check_axis(axis: str) -> str:
    if axis not in AXES:
        raise VolumeError(f"axis must be one of x, y, z, got {axis!r}")
    return axis


def transparent(w: int, h: int, d: int) -> np.ndarray:
    """A fully transparent RGBA image; the size is checked before anything is allocated."""
    w, h, d = whole("width", w), whole("height", h), whole("depth", d)
    check_size(w, h, d)
    return np.zeros((d, h, w, 4), dtype=np.uint8)


def own_rgba(data: np.ndarray) -> np.ndarray:
    """A checked, C-contiguous copy of a (depth, height, width, 4) uint8 image."""
    if not isinstance(data, np.ndarray) or data.dtype != np.uint8 or data.ndim != 4 or data.shape[3] != 4:
        shape = getattr(data, "shape", None)
        raise VolumeError(f"a volume must be a (depth, height, width, 4) uint8 RGBA array, got "
                          f"{getattr(data, 'dtype', type(data).__name__)} of shape {shape}")
    d, h, w, _ = data.shape
    check_size(w, h, d)
    return np.array(data, order="C", copy=True)


class ChangeRecord:
    """What changed where in an array of voxels: `version` counts changes, `changed_since` says where. Whoever
    writes the array marks the box with `changed`; subclasses say what the whole box is (`full_box`)."""

    def __init__(self) -> None:
        self.version = 0
        self._log: deque[tuple[int, Box | None]] = deque()  # (version, changed box or None = everything)
        self._log_floor = 0  # the log holds every change after this version

    def full_box(self) -> Box:
        raise NotImplementedError

    def changed_since(self, version: int) -> Box | None:
        """The union of boxes changed after `version`; the full box after a reshape or beyond the record."""
        if version >= self.version:
            return None
        if version < self._log_floor:
            return self.full_box()
        boxes = [b for _, b in islice(reversed(self._log), self.version - version)]
        if any(b is None for b in boxes):
            return self.full_box()
        return reduce(Box.union, boxes)

    def changed(self, box: Box | None) -> None:
        """Record a change of `box` (None: of everything, the shape perhaps)."""
        self.version += 1
        self._log.append((self.version, box))
        if len(self._log) > CHANGE_RECORDS:
            self._log_floor = self._log.popleft()[0]


class Voxels(ChangeRecord):
    """The RGBA voxels (`data`, indexed z, y, x) and, for a volume loaded from scalars, those `scalars`: the voxels
    are their colours through its transfer function; a scalar volume's `labels` (app/model/volume/labels.py),
    painted over the scan with a change record of their own; the `spacing` of the voxels (x, y, z), which the box's
    shape follows. `version` counts changes of `data`; `changed_since` says where.

    Whoever writes `data` (the painting, the history) marks the box with `changed`; the other writes here do."""

    def __init__(self, data: np.ndarray) -> None:
        super().__init__()
        self.data = own_rgba(data)
        self.scalars: Scalars | None = None
        self.labels = None  # a scalar volume's Labels (app/model/volume/labels.py), even before any is painted
        self.spacing = DEFAULT_SPACING

    @property
    def size(self) -> tuple[int, int, int]:
        d, h, w, _ = self.data.shape
        return w, h, d

    def full_box(self) -> Box:
        w, h, d = self.size
        return Box(0, 0, 0, w, h, d)

    # --- reading --------------------------------------------------------------------------------

    def slice_size(self, axis: str) -> tuple[int, int]:
        w, h, d = self.size
        return {"z": (w, h), "y": (w, d), "x": (h, d)}[check_axis(axis)]

    def slice_spacing(self, axis: str) -> tuple[float, float]:
        """The spacing along a slice's u and v (as slice_size orders them)."""
        sx, sy, sz = self.spacing
        return {"z": (sx, sy), "y": (sx, sz), "x": (sy, sz)}[check_axis(axis)]

    def depth(self, axis: str) -> int:
        return self.data.shape[_ARRAY_AXIS[check_axis(axis)]]

    def slice(self, axis: str, index: int) -> np.ndarray:
        """(v, u, 4) read-only view; copy it to keep it past the next edit."""
        view = self.plane(axis, index).view()
        view.flags.writeable = False
        return view

    def voxel_of(self, axis: str, index: int, u: int, v: int) -> tuple[int, int, int]:
        index, u, v = self._index(axis, index), whole("u", u), whole("v", v)
        us, vs = self.slice_size(axis)
        if not (0 <= u < us and 0 <= v < vs):
            raise VolumeError(f"({u}, {v}) is outside the {us} x {vs} slice")
        return {"z": (u, v, index), "y": (u, index, v), "x": (index, u, v)}[axis]

    def pick(self, x: int, y: int, z: int) -> tuple[int, int, int, int]:
        return tuple(int(c) for c in self.data[self.array_index(x, y, z)])

    def scalar_at(self, x: int, y: int, z: int) -> float | None:
        """The loaded value under a voxel's colour, for a scalar volume; None for an RGBA one."""
        return None if self.scalars is None else float(self.scalars.values[self.array_index(x, y, z)])

    def label_at(self, x: int, y: int, z: int) -> int | None:
        """The label painted over a scan's voxel (0: none); None for an RGBA volume, which has no labels."""
        return None if self.labels is None else self.labels.at(self.array_index(x, y, z))

    def require_labels(self):
        """A scan's Labels, or a VolumeError for an RGBA volume, whose colours are painted instead."""
        if self.labels is None:
            raise VolumeError("labels are painted over a scan (a 16-bit or float file); this volume is RGBA: paint "
                              "its colours (stroke, fill, voxel)")
        return self.labels

    def require_colours(self) -> None:
        """Nothing for an RGBA volume; a VolumeError for a scan, whose values are never painted."""
        if self.scalars is not None:
            raise VolumeError("a scan's values are never painted: paint labels over it (label.stroke, label.fill, "
                              "label.voxel; brush_label picks the label)")

    def require_scalars(self) -> Scalars:
        """The scalars, or a VolumeError that says how a volume gets some."""
        if self.scalars is None:
            raise VolumeError("this volume has no scalars to window: load a 16-bit or float NRRD, TIFF or .npy "
                              "file")
        return self.scalars

    def digest(self) -> str:
        h = hashlib.sha256("{}x{}x{};".format(*self.size).encode())
        if self.spacing != DEFAULT_SPACING:  # only then: a volume of 1 1 1 keeps the digest it had before spacing
            h.update("spacing {!r} {!r} {!r};".format(*self.spacing).encode())
        if self.scalars is None:
            h.update(self.data.data)
        else:  # the colours follow from the values and the window: hashing them too would add 4 bytes a voxel
            h.update(f";{self.scalars.values.dtype.str};{self.scalars.transfer!r};".encode())
            h.update(self.scalars.values.data)
        if self.labels is not None:  # adds nothing until a label is painted or coloured: older digests hold
            self.labels.hash_into(h)
        return h.hexdigest()[:16]

    # --- writing ----------------------------------------------------------------------------------

    def array_index(self, x: int, y: int, z: int) -> tuple[int, int, int]:
        """The (z, y, x) index of a voxel into `data`, or a VolumeError for one outside the volume."""
        x, y, z = whole("x", x), whole("y", y), whole("z", z)
        w, h, d = self.size
        if not (0 <= x < w and 0 <= y < h and 0 <= z < d):
            raise VolumeError(f"voxel ({x}, {y}, {z}) is outside the {w} x {h} x {d} volume")
        return z, y, x

    def plane(self, axis: str, index: int) -> np.ndarray:
        """The writable (v, u, 4) view of a slice."""
        index = self._index(axis, index)
        return self.data[(slice(None),) * _ARRAY_AXIS[axis] + (index,)]

    def turn(self, axis: str, turns: int) -> None:
        """Quarter turns about an axis, the scalars, labels and spacing with the voxels."""
        self.data = np.ascontiguousarray(np.rot90(self.data, turns, axes=_ROT90_AXES[axis]))
        if turns % 2:  # the two axes across the turning one trade places
            sx, sy, sz = self.spacing
            self.spacing = {"x": (sx, sz, sy), "y": (sz, sy, sx), "z": (sy, sx, sz)}[axis]
        if self.scalars is not None:
            values = np.ascontiguousarray(np.rot90(self.scalars.values, turns, axes=_ROT90_AXES[axis]))
            values.flags.writeable = False
            self.scalars = Scalars(values, self.scalars.transfer)
        if self.labels is not None:
            self.labels.turn(_ROT90_AXES[axis], turns)
        self.changed(None)

    def swap(self, data: np.ndarray, scalars: Scalars | None,
             spacing: Spacing = DEFAULT_SPACING) -> tuple[np.ndarray, Scalars | None, Spacing]:
        """Show another whole image (checked by the caller); returns the one shown before."""
        shown = self.data, self.scalars, self.spacing
        self.data, self.scalars, self.spacing = data, scalars, spacing
        self.changed(None)
        return shown

    def respace(self, spacing: Spacing) -> Spacing:
        """Give the voxels another spacing (checked by the caller); returns the one before. No voxel changes, so
        `version` stays (nothing is uploaded again); the workspace's version shows the box's new shape."""
        shown, self.spacing = self.spacing, spacing
        return shown

    def recolour(self, transfer: TransferFunction) -> None:
        """Every voxel again from the scalars: the texture uploads the volume once. A transfer function that differs
        in its opacity curve alone colours nothing again: no voxel changes, so `version` stays."""
        same = self.scalars.transfer.same_colours(transfer)
        self.scalars = Scalars(self.scalars.values, transfer)
        if not same:
            colour(self.scalars.values, transfer, self.data)
            self.changed(self.full_box())

    def _index(self, axis: str, index: int) -> int:
        n = self.depth(axis)
        index = whole("slice index", index)
        if not 0 <= index < n:
            raise VolumeError(f"slice {axis} = {index} is outside 0..{n - 1}")
        return index


class VolumeWatch:
    """One consumer's view of a volume's changes (a GPU texture, a distance field): what changed since
    it last looked. A different Voxels object counts as changed everywhere."""

    def __init__(self) -> None:
        self.source: Voxels | None = None
        self.seen = -1

    def changes(self, voxels: Voxels) -> Box | None:
        if self.source is not voxels:
            self.source, self.seen = voxels, -1  # changed_since(-1): the whole volume
        box = voxels.changed_since(self.seen)
        self.seen = voxels.version
        return box
