"""A 3D RGBA raster painted slice by slice, with sub-box undo and dirty boxes for GPU uploads."""
from __future__ import annotations

import hashlib
import math
import operator
import os
from collections import deque
from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from functools import lru_cache, reduce
from itertools import islice

import numpy as np
from scipy import ndimage

from app.model.volume.scalars import Scalars, TransferFunction, check_values, colour, default_window, own_values

AXES = ("x", "y", "z")
MAX_SIDE = 4096          # voxels a side; also the largest brush
MAX_COORD = 1 << 24      # stroke points beyond this are no mouse position: refuse before the line maths overflows
UNDO_STEPS = 256
UNDO_BYTES = 512 << 20
_SMOOTH_TILE = 1 << 15   # voxels smoothed at once: their uint16 temporaries stay near 1 MiB
CHANGE_RECORDS = 4096    # consumers further behind than this many changes get the full box
_ARRAY_AXIS = {"z": 0, "y": 1, "x": 2}          # axis name -> axis of Volume.data
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
        """(z, y, x) slices into Volume.data."""
        return slice(self.z0, self.z1), slice(self.y0, self.y1), slice(self.x0, self.x1)


@dataclass
class _Patch:
    """A changed sub-box; `other` holds its contents in the state not currently shown (swapped on undo/redo).
    An edit of a scalar volume bakes its window into the colours: `scalars` holds the scalars in the state not
    shown, as `other` does the voxels (and `baked` their size, counted whichever state holds them)."""

    box: Box
    other: np.ndarray
    serial: int = 0  # when it was pushed: a batch groups the steps pushed after its mark
    scalars: Scalars | None = None
    baked: int = 0
    name: str = ""  # what Edit > Undo calls it ("Stroke")

    @property
    def nbytes(self) -> int:
        return self.other.nbytes + self.baked


@dataclass
class _Rotate:
    axis: str
    turns: int
    nbytes: int = 0  # stores no voxels: undo is the inverse turn
    serial: int = 0
    name: str = "Rotate"


@dataclass
class _Replace:
    other: np.ndarray  # the whole image not currently shown
    scalars: Scalars | None  # and its scalars
    nbytes: int  # what the replaced image held: fixed, as undo and redo swap images of other sizes in and out
    serial: int = 0
    name: str = ""

    @classmethod
    def of(cls, data: np.ndarray, scalars: Scalars | None, name: str) -> _Replace:
        return cls(data, scalars, data.nbytes + (scalars.nbytes if scalars else 0), name=name)


@dataclass
class _Window:
    transfer: TransferFunction  # the scalars' transfer function not currently shown
    nbytes: int = 0  # the colours are made again from the scalars
    serial: int = 0
    name: str = "Set Window"


@dataclass
class _Group:
    """Steps undone and redone together (the edits of one script)."""

    steps: list
    serial: int = 0
    name: str = ""

    @property
    def nbytes(self) -> int:
        return sum(s.nbytes for s in self.steps)


_Step = _Patch | _Rotate | _Replace | _Window | _Group


def _fmt_bytes(n: int) -> str:
    return f"{n / 2**30:.1f} GiB" if n >= 2**30 else f"{n / 2**20:.1f} MiB"


def _check_size(w: int, h: int, d: int, scalar_bytes: int = 0) -> None:
    """scalar_bytes: the size of a scalar volume's value, kept beside its colours."""
    if min(w, h, d) < 1 or max(w, h, d) > MAX_SIDE:
        raise VolumeError(f"volume sides must be within 1..{MAX_SIDE}, got {w} x {h} x {d}")
    need = w * h * d * (4 + scalar_bytes)
    if need > MAX_BYTES:
        what = "RGBA data and scalars" if scalar_bytes else "RGBA data"
        raise VolumeError(f"a {w} x {h} x {d} volume needs {_fmt_bytes(need)} of {what},"
                          f" over the {_fmt_bytes(MAX_BYTES)} limit")


def _int(name: str, value: object) -> int:
    try:
        return operator.index(value)
    except TypeError:
        raise VolumeError(f"{name} must be a whole number, got {value!r}") from None


def _colour(rgba: Sequence[int]) -> np.ndarray:
    try:
        vals = [operator.index(c) for c in rgba]
    except TypeError:
        vals = []
    if len(vals) != 4 or not all(0 <= c <= 255 for c in vals):
        raise VolumeError(f"colour must be four whole numbers 0..255 (r, g, b, a), got {rgba!r}")
    return np.array(vals if vals[3] else [0, 0, 0, 0], dtype=np.uint8)  # alpha 0 erases


def _bounds(mask: np.ndarray) -> list[tuple[int, int]] | None:
    """Per axis, the half-open range holding every True of `mask`; None when there is none."""
    if not mask.any():
        return None
    out = []
    for ax in range(mask.ndim):
        hit = np.flatnonzero(mask.any(axis=tuple(i for i in range(mask.ndim) if i != ax)))
        out.append((int(hit[0]), int(hit[-1]) + 1))
    return out


def _mean27(near: np.ndarray) -> np.ndarray:
    """The rounded mean of each 3x3x3 neighbourhood inside `near` (uint8, a one-voxel border around the result).

    Summed one axis at a time into uint16 (27 * 255 fits), in place where it can be: at most two sums exist at once.
    """
    z_sum = np.add(near[:-2], near[1:-1], dtype=np.uint16)
    z_sum += near[2:]
    zy_sum = np.add(z_sum[:, :-2], z_sum[:, 1:-1])
    zy_sum += z_sum[:, 2:]
    del z_sum
    total = np.add(zy_sum[:, :, :-2], zy_sum[:, :, 1:-1])
    total += zy_sum[:, :, 2:]
    del zy_sum
    total += 13  # round to nearest; n/27 is never a tie
    total //= 27
    return total.astype(np.uint8)


def _within(inner: Box, outer: Box) -> tuple[slice, slice, slice]:
    """inner's (z, y, x) slices into an array that holds outer."""
    return (slice(inner.z0 - outer.z0, inner.z1 - outer.z0), slice(inner.y0 - outer.y0, inner.y1 - outer.y0),
            slice(inner.x0 - outer.x0, inner.x1 - outer.x0))


@lru_cache(maxsize=64)
def _brush_rows(size: int, round_brush: bool) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(dv, lo, hi): for each brush row offset dv, the painted u offsets lo..hi (inclusive).

    Offsets span -(size-1)//2 .. size//2; a round brush keeps cells whose centre lies within
    size/2 of the stamp centre (offset 0.5 for even sizes), in integers: doubled coordinates.
    """
    off = np.arange(-((size - 1) // 2), size // 2 + 1)
    if not round_brush:
        return off, np.full(size, off[0]), np.full(size, off[-1])
    c2 = 1 - size % 2
    half = np.array([math.isqrt(size * size - int(t) ** 2) for t in 2 * off - c2])
    return off, -((half - c2) // 2), (half + c2) // 2


def _line(p0: tuple[int, int], p1: tuple[int, int], lo: tuple[int, int], hi: tuple[int, int]) -> np.ndarray:
    """The 8-connected steps from p0 to p1 (rounded DDA, Bresenham-equivalent) that lie near lo..hi.

    Only the steps whose parameter can reach the window are generated, so a point far off the
    slice costs nothing; the result is the same as rasterising the whole line and cropping.
    """
    d = (p1[0] - p0[0], p1[1] - p0[1])
    n = max(abs(d[0]), abs(d[1]))
    if n == 0:
        return np.array([p0])
    t0, t1 = 0, n
    for k in range(2):
        if d[k] == 0:
            if not lo[k] <= p0[k] <= hi[k]:
                return np.empty((0, 2), dtype=np.int64)
            continue
        a, b = sorted(((lo[k] - p0[k]) * n / d[k], (hi[k] - p0[k]) * n / d[k]))
        t0, t1 = max(t0, math.floor(a) - 1), min(t1, math.ceil(b) + 1)
    t = np.arange(t0, t1 + 1, dtype=np.int64)
    return np.stack([p0[k] + (2 * t * d[k] + n) // (2 * n) for k in range(2)], axis=1)


class Volume:
    """The voxels, their undo history, and a record of changed boxes for consumers such as GPU uploads.

    A volume loaded from scalars (`replace_scalars`) keeps them in `scalars`: its voxels are their colours
    through the transfer function, made again whenever that changes (`set_transfer`). Editing voxels (a
    stroke, fill, voxel or smoothing) bakes the window into the colours: the scalars are set aside with that
    edit's undo step, so undoing it brings them back. Rotations turn the scalars with the voxels."""

    def __init__(self, data: np.ndarray, *, max_undo_steps: int = UNDO_STEPS,
                 max_undo_bytes: int = UNDO_BYTES) -> None:
        self.data = self._validated(data)
        self.scalars: Scalars | None = None
        self.version = 0
        self.max_undo_steps = max_undo_steps
        self.max_undo_bytes = max_undo_bytes
        self._undo: deque[_Step] = deque()
        self._redo: list[_Step] = []
        self._pushes = 0
        self._preview: _Patch | None = None
        self._previewing = False
        self._history_bytes = 0  # undo + redo; a push clears redo, undo/redo only move steps
        self._log: deque[tuple[int, Box | None]] = deque()  # (version, changed box or None = everything)
        self._log_floor = 0  # the log holds every change after this version

    @classmethod
    def new(cls, w: int, h: int, d: int, **history: int) -> Volume:
        """A fully transparent volume; the size is checked before anything is allocated."""
        w, h, d = _int("width", w), _int("height", h), _int("depth", d)
        _check_size(w, h, d)
        return cls(np.zeros((d, h, w, 4), dtype=np.uint8), **history)

    @staticmethod
    def _validated(data: np.ndarray) -> np.ndarray:
        if not isinstance(data, np.ndarray) or data.dtype != np.uint8 or data.ndim != 4 or data.shape[3] != 4:
            shape = getattr(data, "shape", None)
            raise VolumeError(f"a volume must be a (depth, height, width, 4) uint8 RGBA array, got "
                              f"{getattr(data, 'dtype', type(data).__name__)} of shape {shape}")
        d, h, w, _ = data.shape
        _check_size(w, h, d)
        return np.array(data, order="C", copy=True)

    @property
    def size(self) -> tuple[int, int, int]:
        d, h, w, _ = self.data.shape
        return w, h, d

    def full_box(self) -> Box:
        w, h, d = self.size
        return Box(0, 0, 0, w, h, d)

    # --- slices ---------------------------------------------------------------------------------

    def slice_size(self, axis: str) -> tuple[int, int]:
        w, h, d = self.size
        return {"z": (w, h), "y": (w, d), "x": (h, d)}[self._axis(axis)]

    def depth(self, axis: str) -> int:
        return self.data.shape[_ARRAY_AXIS[self._axis(axis)]]

    def slice(self, axis: str, index: int) -> np.ndarray:
        """(v, u, 4) read-only view; copy it to keep it past the next edit."""
        view = self._plane(axis, index).view()
        view.flags.writeable = False
        return view

    def voxel_of(self, axis: str, index: int, u: int, v: int) -> tuple[int, int, int]:
        index, u, v = self._index(axis, index), _int("u", u), _int("v", v)
        us, vs = self.slice_size(axis)
        if not (0 <= u < us and 0 <= v < vs):
            raise VolumeError(f"({u}, {v}) is outside the {us} x {vs} slice")
        return {"z": (u, v, index), "y": (u, index, v), "x": (index, u, v)}[axis]

    def pick(self, x: int, y: int, z: int) -> tuple[int, int, int, int]:
        return tuple(int(c) for c in self.data[self._voxel(x, y, z)])

    def scalar_at(self, x: int, y: int, z: int) -> float | None:
        """The loaded value under a voxel's colour, for a scalar volume; None for an RGBA one."""
        return None if self.scalars is None else float(self.scalars.values[self._voxel(x, y, z)])

    # --- edits ----------------------------------------------------------------------------------

    def set_voxel(self, x: int, y: int, z: int, rgba: Sequence[int]) -> None:
        self._settle_preview()
        z, y, x = self._voxel(x, y, z)
        colour = _colour(rgba)
        if not np.array_equal(self.data[z, y, x], colour):
            self._patch(Box(x, y, z, x + 1, y + 1, z + 1), colour, "Paint Voxel")

    def stroke(self, axis: str, index: int, size: int, rgba: Sequence[int], points: list[tuple[int, int]],
               round_brush: bool = True) -> Box | None:
        """Stamp the brush along the polyline through `points` (slice u, v); returns the changed box."""
        self._settle_preview()
        plane = self._plane(axis, index)
        size, colour = _int("brush size", size), _colour(rgba)
        if not 1 <= size <= MAX_SIDE:
            raise VolumeError(f"brush size must be within 1..{MAX_SIDE}, got {size}")
        pts = []
        for p in points:
            try:
                u, v = p
            except (TypeError, ValueError):
                raise VolumeError(f"a stroke point must be (u, v), got {p!r}") from None
            u, v = _int("stroke u", u), _int("stroke v", v)
            if max(abs(u), abs(v)) > MAX_COORD:
                raise VolumeError(f"stroke point ({u}, {v}) is too far outside the slice")
            pts.append((u, v))
        if not pts:
            return None
        du, lo, hi = _brush_rows(size, bool(round_brush))
        vs, us = plane.shape[:2]
        win_lo, win_hi = (-size, -size), (us - 1 + size, vs - 1 + size)  # centres whose stamp may touch
        lines = [_line(a, b, win_lo, win_hi) for a, b in zip(pts, pts[1:])] or [np.array(pts)]
        stamped = self._stamp(np.unique(np.concatenate(lines), axis=0), du, lo, hi, us, vs)
        if stamped is None:
            return None
        cover, u0, v0 = stamped
        region = plane[v0:v0 + cover.shape[0], u0:u0 + cover.shape[1]]
        return self._paint_plane(axis, index, region, cover & (region != colour).any(-1), colour, u0, v0, "Stroke")

    def fill(self, axis: str, index: int, u: int, v: int, rgba: Sequence[int], tolerance: int = 0) -> Box | None:
        """Flood the 4-connected region of the slice around (u, v) whose every channel (r, g, b, a) is within
        `tolerance` (0..255) of the colour at (u, v); 0: exactly that colour."""
        self._settle_preview()
        plane = self._plane(axis, index)
        u, v, colour, tolerance = _int("u", u), _int("v", v), _colour(rgba), _int("fill tolerance", tolerance)
        vs, us = plane.shape[:2]
        if not (0 <= u < us and 0 <= v < vs):
            raise VolumeError(f"fill point ({u}, {v}) is outside the {us} x {vs} slice")
        if not 0 <= tolerance <= 255:
            raise VolumeError(f"fill tolerance must be within 0..255, got {tolerance}")
        seed = plane[v, u].tolist()
        similar = np.ones((vs, us), bool)
        for c in range(4):  # a channel at a time, compared in the voxels' own uint8
            lo, hi = max(seed[c] - tolerance, 0), min(seed[c] + tolerance, 255)
            similar &= (plane[..., c] >= lo) & (plane[..., c] <= hi)
        labels, _ = ndimage.label(similar)  # default structure: 4-connected
        changes = (labels == labels[v, u]) & (plane != colour).any(-1)  # nothing when the seed has the colour
        return self._paint_plane(axis, index, plane, changes, colour, 0, 0, "Fill")

    def smooth(self, box: Box | None = None) -> Box | None:
        """3x3x3 box filter over `box` (default: all), reading neighbours beyond it, edge-clamped at the border.

        Memory: the volume, one copy of the box that changes (the undo step) and one tile's temporaries. A first
        pass finds that box without keeping results; the second writes it tile by tile, its neighbours coming
        from the undo copy where earlier tiles have already overwritten them.
        """
        self._settle_preview()
        full = self.full_box()
        box = full if box is None else box.intersect(full)
        if box.empty:
            return None
        changed = self._smooth_changes(box)
        if changed is None:
            return None
        before = self.data[changed.slices()].copy()
        for tile, mean in self._smoothed_tiles(changed, before):
            self.data[tile.slices()] = mean
        return self._record(changed, before, "Smooth")

    def rotate(self, axis: str, turns: int = 1) -> None:
        """Quarter turns about an axis, counter-clockwise looking from +axis towards the origin."""
        self._settle_preview()
        turns = _int("turns", turns) % 4
        self._axis(axis)
        if turns:
            self._rotate(axis, turns)
            self._push(_Rotate(axis, turns))

    def replace(self, data: np.ndarray, name: str = "Replace Volume") -> None:
        """Swap in a whole new image (a loaded file) as one undo step called `name`."""
        self._settle_preview()
        new = self._validated(data)
        self._push(_Replace.of(self.data, self.scalars, name))
        self.data, self.scalars = new, None
        self._changed(None)

    def replace_scalars(self, values: np.ndarray, transfer: TransferFunction | None = None,
                        name: str = "Replace Volume", copy: bool = True) -> None:
        """Swap in a scalar volume (a loaded 16-bit or float file) as one undo step called `name`, coloured through
        `transfer` (by default the window from the values' percentiles, grey). The size is checked before anything
        is allocated; the values are copied, unless `copy` is False: then the volume keeps `values` itself (made
        read-only), which its caller hands over (a reader's fresh array, not a second copy of it)."""
        self._settle_preview()
        d, h, w = check_values(values)
        _check_size(w, h, d, values.itemsize)
        values = own_values(values, copy)
        scalars = Scalars(values, transfer or TransferFunction(*default_window(values)))
        data = np.empty(values.shape + (4,), np.uint8)
        colour(values, scalars.transfer, data)
        self._push(_Replace.of(self.data, self.scalars, name))
        self.data, self.scalars = data, scalars
        self._changed(None)

    def require_scalars(self) -> Scalars:
        """The scalars, or a VolumeError that says how a volume gets some."""
        if self.scalars is None:
            raise VolumeError("this volume has no scalars to window: load a 16-bit or float NRRD, TIFF or .npy "
                              "file (editing the voxels of a scalar volume bakes its window in; undo the edit to "
                              "window it again)")
        return self.scalars

    def set_transfer(self, transfer: TransferFunction) -> bool:
        """Colour the scalars through another window or colour map, as one undo step; False if it is the same."""
        self._settle_preview()
        if transfer == self.require_scalars().transfer:
            return False
        self._push(_Window(self.scalars.transfer))
        self._recolour(transfer)
        return True

    # --- undo / redo ----------------------------------------------------------------------------

    @property
    def undo_depth(self) -> int:
        return len(self._undo)

    @property
    def redo_depth(self) -> int:
        return len(self._redo)

    def undo(self) -> bool:
        self._settle_preview()
        if not self._undo:
            return False
        step = self._undo.pop()
        self._apply(step, undo=True)
        self._redo.append(step)
        return True

    def redo(self) -> bool:
        self._settle_preview()
        if not self._redo:
            return False
        step = self._redo.pop()
        self._apply(step, undo=False)
        self._undo.append(step)
        return True

    def undo_name(self) -> str | None:
        """What the step undo would take back is called ("Stroke"); None: nothing to undo."""
        return self._undo[-1].name if self._undo else None

    def redo_name(self) -> str | None:
        return self._redo[-1].name if self._redo else None

    @property
    def history_key(self) -> tuple[int, int, bool]:
        """Changes with every edit pushed, undone or redone and when a preview shows or goes, but not as a preview
        is painted again under the mouse: what the document's digest is kept by (a big volume takes a while to
        hash, and a preview changes `version` at every move)."""
        return self._pushes, len(self._undo), self._preview is not None

    @property
    def edits(self) -> int:
        """Undo steps pushed so far, ever: mark it before a batch of edits, then `group_since(mark)`."""
        return self._pushes

    def group_since(self, mark: int, name: str = "Script") -> None:
        """Fold the steps pushed since `edits` was `mark` into one called `name`, so one undo takes them
        all back. Steps from before the mark stay apart, even if the batch undid and redid some of them."""
        steps = []
        while self._undo and self._undo[-1].serial > mark:
            steps.append(self._undo.pop())
        if len(steps) == 1:
            self._undo.append(steps[0])
        elif steps:
            self._undo.append(_Group(steps[::-1], serial=steps[0].serial, name=name))

    # --- preview: an edit shown but kept out of the history ----------------------------------

    def preview_stroke(self, *args, **kwargs) -> Box | None:
        """Paint a stroke that is shown (and marked changed) but not recorded: the next preview, any
        edit, undo or redo first puts the voxels back, so it can never mix with the history."""
        self.clear_preview()
        self._previewing = True
        try:
            return self.stroke(*args, **kwargs)
        finally:
            self._previewing = False

    def _settle_preview(self) -> None:
        if not self._previewing:
            self.clear_preview()

    def clear_preview(self) -> None:
        if self._preview is not None:
            patch, self._preview = self._preview, None
            self.data[patch.box.slices()] = patch.other
            self._changed(patch.box)

    # --- consumers ------------------------------------------------------------------------------

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

    def digest(self) -> str:
        h = hashlib.sha256("{}x{}x{};".format(*self.size).encode())
        if self.scalars is None:
            h.update(self.data.data)
        else:  # the colours follow from the values and the window: hashing them too would add 4 bytes a voxel
            h.update(f";{self.scalars.values.dtype.str};{self.scalars.transfer!r};".encode())
            h.update(self.scalars.values.data)
        return h.hexdigest()[:16]

    # --- internals ------------------------------------------------------------------------------

    @staticmethod
    def _axis(axis: str) -> str:
        if axis not in AXES:
            raise VolumeError(f"axis must be one of x, y, z, got {axis!r}")
        return axis

    def _index(self, axis: str, index: int) -> int:
        n = self.depth(axis)
        index = _int("slice index", index)
        if not 0 <= index < n:
            raise VolumeError(f"slice {axis} = {index} is outside 0..{n - 1}")
        return index

    def _voxel(self, x: int, y: int, z: int) -> tuple[int, int, int]:
        x, y, z = _int("x", x), _int("y", y), _int("z", z)
        w, h, d = self.size
        if not (0 <= x < w and 0 <= y < h and 0 <= z < d):
            raise VolumeError(f"voxel ({x}, {y}, {z}) is outside the {w} x {h} x {d} volume")
        return z, y, x

    def _plane(self, axis: str, index: int) -> np.ndarray:
        """The writable (v, u, 4) view of a slice."""
        index = self._index(axis, index)
        return self.data[(slice(None),) * _ARRAY_AXIS[axis] + (index,)]

    @staticmethod
    def _stamp(centres: np.ndarray, du: np.ndarray, lo: np.ndarray, hi: np.ndarray,
               us: int, vs: int) -> tuple[np.ndarray, int, int] | None:
        """The brush footprint of all centres, clipped to the slice: (mask, u0, v0) of its bounding rectangle.

        Each centre paints one run per brush row; runs go into a difference image whose row-wise
        cumulative sum is the coverage, so the cost is centres x rows, not centres x brush area.
        """
        if not len(centres):
            return None
        cu, cv = centres[:, 0], centres[:, 1]
        v0, v1 = max(int(cv.min() + du[0]), 0), min(int(cv.max() + du[-1]) + 1, vs)
        u0, u1 = max(int(cu.min() + lo.min()), 0), min(int(cu.max() + hi.max()) + 1, us)
        if v0 >= v1 or u0 >= u1:
            return None
        width = u1 - u0 + 1
        diff = np.zeros((v1 - v0) * width, dtype=np.int32)
        chunk = max(1, (1 << 20) // len(du))  # bounds the temporaries for huge brushes on long strokes
        for i in range(0, len(cu), chunk):
            rows = cv[i:i + chunk, None] + du
            a, b = cu[i:i + chunk, None] + lo, cu[i:i + chunk, None] + hi + 1
            keep = (rows >= v0) & (rows < v1) & (b > u0) & (a < u1)
            base = (rows[keep] - v0) * width - u0
            np.add.at(diff, base + np.maximum(a[keep], u0), 1)
            np.add.at(diff, base + np.minimum(b[keep], u1), -1)
        cover = np.cumsum(diff.reshape(v1 - v0, width), axis=1)[:, :-1] > 0
        return cover, u0, v0

    def _smooth_changes(self, box: Box) -> Box | None:
        """The part of `box` that smoothing changes, None if nothing."""
        bw, bh, bd = box.shape
        z_hit, y_hit, x_hit = np.zeros(bd, bool), np.zeros(bh, bool), np.zeros(bw, bool)
        for tile, mean in self._smoothed_tiles(box):
            differs = (mean != self.data[tile.slices()]).any(-1)
            z_hit[tile.z0 - box.z0:tile.z1 - box.z0] |= differs.any((1, 2))
            y_hit[tile.y0 - box.y0:tile.y1 - box.y0] |= differs.any((0, 2))
            x_hit |= differs.any((0, 1))  # every tile spans the box's width
        if not z_hit.any():
            return None
        (z0, z1), (y0, y1), (x0, x1) = (_bounds(hit)[0] for hit in (z_hit, y_hit, x_hit))
        return Box(box.x0 + x0, box.y0 + y0, box.z0 + z0, box.x0 + x1, box.y0 + y1, box.z0 + z1)

    def _smoothed_tiles(self, box: Box, before: np.ndarray | None = None) -> Iterator[tuple[Box, np.ndarray]]:
        """(tile, its smoothed voxels) for tiles of `box` of at most _SMOOTH_TILE voxels, in z, y order; `before`,
        when given, holds the original voxels of `box`, which the caller is overwriting tile by tile."""
        bw, bh, _ = box.shape
        rows = max(1, min(bh, _SMOOTH_TILE // bw))
        layers = max(1, _SMOOTH_TILE // (bw * bh)) if rows == bh else 1
        for z in range(box.z0, box.z1, layers):
            for y in range(box.y0, box.y1, rows):
                tile = Box(box.x0, y, z, box.x1, min(y + rows, box.y1), min(z + layers, box.z1))
                yield tile, _mean27(self._neighbourhood(tile, box, before))

    def _neighbourhood(self, tile: Box, box: Box, before: np.ndarray | None) -> np.ndarray:
        """The voxels `tile` is smoothed from: one more on every side, the border repeated beyond the volume's
        edge; the voxels of `box` as `before` holds them, when given."""
        around = Box(tile.x0 - 1, tile.y0 - 1, tile.z0 - 1, tile.x1 + 1, tile.y1 + 1, tile.z1 + 1)
        inside = around.intersect(self.full_box())
        region = self.data[inside.slices()]
        if before is not None:
            region = region.copy()
            restored = inside.intersect(box)
            region[_within(restored, inside)] = before[_within(restored, box)]
        w, h, d = self.size
        edges = [(int(lo == 0), int(hi == n)) for lo, hi, n in ((tile.z0, tile.z1, d), (tile.y0, tile.y1, h),
                                                                (tile.x0, tile.x1, w))]
        return np.pad(region, edges + [(0, 0)], mode="edge") if any(map(any, edges)) else region

    def _paint_plane(self, axis: str, index: int, region: np.ndarray, mask: np.ndarray,
                     colour: np.ndarray, u0: int, v0: int, name: str) -> Box | None:
        """Paint `mask` of a slice region whose corner is (u0, v0) as one step; returns the changed box."""
        hit = _bounds(mask)
        if hit is None:
            return None
        (a, b), (c, e) = hit
        box = self._plane_box(axis, index, u0 + c, u0 + e, v0 + a, v0 + b)
        before = self.data[box.slices()].copy()
        region[a:b, c:e][mask[a:b, c:e]] = colour
        return self._record(box, before, name)

    @staticmethod
    def _plane_box(axis: str, k: int, u0: int, u1: int, v0: int, v1: int) -> Box:
        if axis == "z":
            return Box(u0, v0, k, u1, v1, k + 1)
        if axis == "y":
            return Box(u0, k, v0, u1, k + 1, v1)
        return Box(k, u0, v0, k + 1, u1, v1)

    def _patch(self, box: Box, contents: np.ndarray, name: str) -> Box:
        """Write `contents` (broadcast) into `box` as one undo step."""
        view = self.data[box.slices()]
        before = view.copy()
        view[...] = contents
        return self._record(box, before, name)

    def _record(self, box: Box, before: np.ndarray, name: str) -> Box:
        if self._previewing:
            self._preview = _Patch(box, before)
            self._changed(box)
            return box
        patch = _Patch(box, before, name=name)
        if self.scalars is not None:  # the edit bakes the window in: its step keeps the scalars
            patch.scalars, patch.baked, self.scalars = self.scalars, self.scalars.nbytes, None
        self._push(patch)
        self._changed(box)
        return box

    def _recolour(self, transfer: TransferFunction) -> None:
        """Every voxel again from the scalars: the texture uploads the volume once."""
        self.scalars = Scalars(self.scalars.values, transfer)
        colour(self.scalars.values, transfer, self.data)
        self._changed(self.full_box())

    def _rotate(self, axis: str, turns: int) -> None:
        self.data = np.ascontiguousarray(np.rot90(self.data, turns, axes=_ROT90_AXES[axis]))
        if self.scalars is not None:
            values = np.ascontiguousarray(np.rot90(self.scalars.values, turns, axes=_ROT90_AXES[axis]))
            values.flags.writeable = False
            self.scalars = Scalars(values, self.scalars.transfer)
        self._changed(None)

    def _apply(self, step: _Step, undo: bool) -> None:
        if isinstance(step, _Patch):
            view = self.data[step.box.slices()]
            shown = view.copy()
            view[...] = step.other
            step.other = shown
            self.scalars, step.scalars = step.scalars, self.scalars
            self._changed(step.box)
        elif isinstance(step, _Rotate):
            self._rotate(step.axis, -step.turns if undo else step.turns)
        elif isinstance(step, _Group):
            for inner in reversed(step.steps) if undo else step.steps:
                self._apply(inner, undo)
        elif isinstance(step, _Window):
            shown = self.scalars.transfer
            self._recolour(step.transfer)
            step.transfer = shown
        else:
            self.data, step.other = step.other, self.data
            self.scalars, step.scalars = step.scalars, self.scalars
            self._changed(None)

    def _push(self, step: _Step) -> None:
        """Record an edit; clears redo and drops the oldest steps beyond the count and byte caps."""
        self._history_bytes -= sum(s.nbytes for s in self._redo)
        self._redo.clear()
        self._pushes += 1
        step.serial = self._pushes
        self._undo.append(step)
        self._history_bytes += step.nbytes
        # A step bigger than the byte cap drops too: that edit cannot be undone, but memory stays bounded.
        while self._undo and (len(self._undo) > self.max_undo_steps or self._history_bytes > self.max_undo_bytes):
            self._history_bytes -= self._undo.popleft().nbytes

    def _changed(self, box: Box | None) -> None:
        self.version += 1
        self._log.append((self.version, box))
        if len(self._log) > CHANGE_RECORDS:
            self._log_floor = self._log.popleft()[0]


class VolumeWatch:
    """One consumer's view of a volume's changes (a GPU texture, a distance field): what changed since
    it last looked. A different Volume object counts as changed everywhere."""

    def __init__(self) -> None:
        self.source: Volume | None = None
        self.seen = -1

    def changes(self, volume: Volume) -> Box | None:
        if self.source is not volume:
            self.source, self.seen = volume, -1  # changed_since(-1): the whole volume
        box = volume.changed_since(self.seen)
        self.seen = volume.version
        return box
