"""Painting a volume's voxels: single voxels, gap-free brush strokes along a slice, flood fills and a 3x3x3
smoothing, each written into the voxels and handed to the history as one undo step (a stroke in progress as
its preview). An RGBA volume is painted in colours; a scan (a scalar volume) in labels over its values, which stay
as loaded (app/model/volume/labels.py)."""
from __future__ import annotations

import math
import operator
from collections.abc import Iterator, Sequence
from functools import lru_cache

import numpy as np
from scipy import ndimage

from app.model.volume.history import VoxelHistory
from app.model.volume.labels import Labels, check_label
from app.model.volume.voxels import MAX_SIDE, Box, VolumeError, Voxels, whole

MAX_COORD = 1 << 24      # stroke points beyond this are no mouse position: refuse before the line maths overflows
_SMOOTH_TILE = 1 << 15   # voxels smoothed at once: their uint16 temporaries stay near 1 MiB


def _colour(rgba: Sequence[int]) -> np.ndarray:
    try:
        vals = [operator.index(c) for c in rgba]
    except TypeError:
        vals = []
    if len(vals) != 4 or not all(0 <= c <= 255 for c in vals):
        raise VolumeError(f"colour must be four whole numbers 0..255 (r, g, b, a), got {rgba!r}")
    return np.array(vals if vals[3] else [0, 0, 0, 0], dtype=np.uint8)  # alpha 0 erases


def _differs(region: np.ndarray, value: np.ndarray) -> np.ndarray:
    """Where a region of a slice (colours (v, u, 4), or labels (v, u)) is not `value`."""
    return (region != value).any(-1) if region.ndim == 3 else region != value


def _connected(mask: np.ndarray, u: int, v: int) -> np.ndarray:
    """The 4-connected part of `mask` (v, u) holding (u, v); nothing if (u, v) is outside it."""
    parts, _ = ndimage.label(mask)  # default structure: 4-connected
    return (parts == parts[v, u]) & mask


def _stroke_points(points: list[tuple[int, int]]) -> list[tuple[int, int]]:
    pts = []
    for p in points:
        try:
            u, v = p
        except (TypeError, ValueError):
            raise VolumeError(f"a stroke point must be (u, v), got {p!r}") from None
        u, v = whole("stroke u", u), whole("stroke v", v)
        if max(abs(u), abs(v)) > MAX_COORD:
            raise VolumeError(f"stroke point ({u}, {v}) is too far outside the slice")
        pts.append((u, v))
    return pts


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


def _plane_box(axis: str, k: int, u0: int, u1: int, v0: int, v1: int) -> Box:
    if axis == "z":
        return Box(u0, v0, k, u1, v1, k + 1)
    if axis == "y":
        return Box(u0, k, v0, u1, k + 1, v1)
    return Box(k, u0, v0, k + 1, u1, v1)


class Painting:
    """The edits of a volume's voxels a box at a time: an RGBA volume's colours, a scan's labels (the `*_label`
    edits; label 0 erases). Each returns the box it changed (None: nothing changed, and no step); the previous
    contents there go to the history. A scan's first label allocates its labels, and that edit's step releases
    them when undone; an edit that paints nothing leaves none allocated."""

    def __init__(self, voxels: Voxels, history: VoxelHistory) -> None:
        self.voxels = voxels
        self.history = history

    def set_voxel(self, x: int, y: int, z: int, rgba: Sequence[int]) -> None:
        self.history.clear_preview()
        self.voxels.require_colours()
        painted = self._set(self.voxels, x, y, z, _colour(rgba))
        if painted is not None:
            self.history.record(*painted, "Paint Voxel")

    def set_label(self, x: int, y: int, z: int, label: int) -> Box | None:
        self.history.clear_preview()
        label = check_label(label)
        return self._labelled(label, lambda labels: self._set(labels, x, y, z, np.uint8(label)), "Label Voxel")

    def stroke(self, axis: str, index: int, size: int, rgba: Sequence[int], points: list[tuple[int, int]],
               round_brush: bool = True) -> Box | None:
        """Stamp the brush along the polyline through `points` (slice u, v); returns the changed box."""
        self.history.clear_preview()
        self.voxels.require_colours()
        painted = self._stroke(self.voxels, axis, index, size, _colour(rgba), points, round_brush)
        return None if painted is None else self.history.record(*painted, "Stroke")

    def preview_stroke(self, axis: str, index: int, size: int, rgba: Sequence[int], points: list[tuple[int, int]],
                       round_brush: bool = True) -> Box | None:
        """Paint a stroke that is shown (and marked changed) but not recorded: the next preview, any
        edit, undo or redo first puts the voxels back, so it can never mix with the history."""
        self.history.clear_preview()
        self.voxels.require_colours()
        painted = self._stroke(self.voxels, axis, index, size, _colour(rgba), points, round_brush)
        return None if painted is None else self.history.preview(*painted)

    def stroke_label(self, axis: str, index: int, size: int, label: int, points: list[tuple[int, int]],
                     round_brush: bool = True, preview: bool = False) -> Box | None:
        """A stroke of `label` over a scan (0 erases); with `preview`, shown but not recorded (preview_stroke)."""
        self.history.clear_preview()
        label = check_label(label)
        return self._labelled(label, lambda labels: self._stroke(labels, axis, index, size, np.uint8(label), points,
                                                                 round_brush), "Label Stroke", preview)

    def fill(self, axis: str, index: int, u: int, v: int, rgba: Sequence[int], tolerance: int = 0) -> Box | None:
        """Flood the 4-connected region of the slice around (u, v) whose every channel (r, g, b, a) is within
        `tolerance` (0..255) of the colour at (u, v); 0: exactly that colour."""
        self.history.clear_preview()
        self.voxels.require_colours()
        plane, similar, u, v = self._similar(axis, index, u, v, tolerance)
        painted = self._paint_plane(self.voxels, axis, index, plane, _connected(similar, u, v), _colour(rgba), 0, 0)
        return None if painted is None else self.history.record(*painted, "Fill")

    def fill_label(self, axis: str, index: int, u: int, v: int, label: int, tolerance: int = 0) -> Box | None:
        """Flood `label` over the 4-connected region of a scan's slice around (u, v) that has the label found
        there and whose window colours are within `tolerance` of those at (u, v), compared as `fill` compares
        (0: exactly that colour; 255: the labels alone bound it). The scan is read, never written."""
        self.history.clear_preview()
        label = check_label(label)
        _plane, similar, u, v = self._similar(axis, index, u, v, tolerance)

        def paint(labels: Labels) -> tuple[Box, np.ndarray] | None:
            plane = labels.plane(axis, index)
            region = _connected(similar & (plane == plane[v, u]), u, v)
            return self._paint_plane(labels, axis, index, plane, region, np.uint8(label), 0, 0)

        return self._labelled(label, paint, "Label Fill")

    def smooth(self, box: Box | None = None) -> Box | None:
        """3x3x3 box filter over `box` (default: all), reading neighbours beyond it, edge-clamped at the border.

        Memory: the volume, one copy of the box that changes (the undo step) and one tile's temporaries. A first
        pass finds that box without keeping results; the second writes it tile by tile, its neighbours coming
        from the undo copy where earlier tiles have already overwritten them.
        """
        self.history.clear_preview()
        self.voxels.require_colours()
        full = self.voxels.full_box()
        box = full if box is None else box.intersect(full)
        if box.empty:
            return None
        changed = self._smooth_changes(box)
        if changed is None:
            return None
        before = self.voxels.data[changed.slices()].copy()
        for tile, mean in self._smoothed_tiles(changed, before):
            self.voxels.data[tile.slices()] = mean
        return self.history.record(changed, before, "Smooth")

    def _labelled(self, label: int, paint, name: str, preview: bool = False) -> Box | None:
        """Run `paint(labels)` (which returns the changed box and its labels before, or None) on the scan's
        labels, allocated first if they were not, and keep the change as the step `name` (or its preview)."""
        labels = self.voxels.require_labels()
        fresh = labels.data is None
        if fresh and label == 0:
            return None  # erasing where no label was ever painted
        labels.allocate()
        try:
            painted = paint(labels)
        except Exception:
            if fresh:
                labels.release()
            raise
        if painted is None:
            if fresh:
                labels.release()
            return None
        if preview:
            return self.history.preview(*painted, labels=True, allocated=fresh)
        return self.history.record(*painted, name, labels=True, allocated=fresh)

    def _plane(self, layer: Voxels | Labels, axis: str, index: int) -> np.ndarray:
        """The writable slice of the colours or of the allocated labels; the axis and index checked."""
        plane = self.voxels.plane(axis, index)
        return plane if layer is self.voxels else layer.plane(axis, whole("slice index", index))

    def _set(self, layer: Voxels | Labels, x: int, y: int, z: int, value: np.ndarray) -> tuple[Box, np.ndarray] | None:
        """Set one voxel's colour or label: (its box, what it held), None if it held that."""
        z, y, x = self.voxels.array_index(x, y, z)
        if np.array_equal(layer.data[z, y, x], value):
            return None
        box = Box(x, y, z, x + 1, y + 1, z + 1)
        before = layer.data[box.slices()].copy()
        layer.data[z, y, x] = value
        return box, before

    def _similar(self, axis: str, index: int, u: int, v: int,
                 tolerance: int) -> tuple[np.ndarray, np.ndarray, int, int]:
        """(the slice's colours, where every channel is within `tolerance` of (u, v)'s, u, v), checked."""
        plane = self.voxels.plane(axis, index)
        u, v, tolerance = whole("u", u), whole("v", v), whole("fill tolerance", tolerance)
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
        return plane, similar, u, v

    def _stroke(self, layer: Voxels | Labels, axis: str, index: int, size: int, value: np.ndarray,
                points: list[tuple[int, int]], round_brush: bool) -> tuple[Box, np.ndarray] | None:
        """Paint the stroke; (the changed box, its voxels before), None if none changed."""
        plane = self._plane(layer, axis, index)
        size = whole("brush size", size)
        if not 1 <= size <= MAX_SIDE:
            raise VolumeError(f"brush size must be within 1..{MAX_SIDE}, got {size}")
        pts = _stroke_points(points)
        if not pts:
            return None
        du, lo, hi = _brush_rows(size, bool(round_brush))
        vs, us = plane.shape[:2]
        win_lo, win_hi = (-size, -size), (us - 1 + size, vs - 1 + size)  # centres whose stamp may touch
        lines = [_line(a, b, win_lo, win_hi) for a, b in zip(pts, pts[1:])] or [np.array(pts)]
        stamped = _stamp(np.unique(np.concatenate(lines), axis=0), du, lo, hi, us, vs)
        if stamped is None:
            return None
        cover, u0, v0 = stamped
        region = plane[v0:v0 + cover.shape[0], u0:u0 + cover.shape[1]]
        return self._paint_plane(layer, axis, index, region, cover, value, u0, v0)

    def _paint_plane(self, layer: Voxels | Labels, axis: str, index: int, region: np.ndarray, mask: np.ndarray,
                     value: np.ndarray, u0: int, v0: int) -> tuple[Box, np.ndarray] | None:
        """Paint `value` over `mask` of a slice region whose corner is (u0, v0), where it is not that already:
        (the changed box, what it held before)."""
        mask = mask & _differs(region, value)
        hit = _bounds(mask)
        if hit is None:
            return None
        (a, b), (c, e) = hit
        box = _plane_box(axis, index, u0 + c, u0 + e, v0 + a, v0 + b)
        before = layer.data[box.slices()].copy()
        region[a:b, c:e][mask[a:b, c:e]] = value
        return box, before

    def _smooth_changes(self, box: Box) -> Box | None:
        """The part of `box` that smoothing changes, None if nothing."""
        bw, bh, bd = box.shape
        z_hit, y_hit, x_hit = np.zeros(bd, bool), np.zeros(bh, bool), np.zeros(bw, bool)
        for tile, mean in self._smoothed_tiles(box):
            differs = (mean != self.voxels.data[tile.slices()]).any(-1)
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
        inside = around.intersect(self.voxels.full_box())
        region = self.voxels.data[inside.slices()]
        if before is not None:
            region = region.copy()
            restored = inside.intersect(box)
            region[_within(restored, inside)] = before[_within(restored, box)]
        w, h, d = self.voxels.size
        edges = [(int(lo == 0), int(hi == n)) for lo, hi, n in ((tile.z0, tile.z1, d), (tile.y0, tile.y1, h),
                                                                (tile.x0, tile.x1, w))]
        return np.pad(region, edges + [(0, 0)], mode="edge") if any(map(any, edges)) else region
