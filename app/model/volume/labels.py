"""A scan's labels, as napari's Labels layer and 3D Slicer's segmentations paint them: one uint8 a voxel over a
scalar volume's values, 0 clear and 1..255 a label drawn in its colour over the scan (with the r_labelOpacity cvar's
opacity). The scan's values are never changed: painting, filling and erasing (painting label 0) write the labels.
They are allocated the first time a label is painted (a scan that is only viewed holds none) and count in the
volume's memory bound from the start (LABEL_BYTES a voxel, checked with the scan's size when it loads)."""
from __future__ import annotations

import colorsys
import operator
from collections.abc import Mapping, Sequence

import numpy as np

from app.model.volume.voxels import _ARRAY_AXIS, Box, ChangeRecord, VolumeError, check_axis, check_size

LABELS = 255        # labels 1..255; 0 is clear
LABEL_BYTES = 1     # a label a voxel
DEFAULT_OPACITY = 0.5
# The first labels' colours, distinct from one another and from grey (Sasha Trubetskoy's list of distinct
# colours); the others step round the hue circle by the golden ratio, so neighbours differ.
_FIRST = ((230, 25, 75), (60, 180, 75), (255, 225, 25), (0, 130, 200), (245, 130, 48), (145, 30, 180),
          (70, 240, 240), (240, 50, 230), (210, 245, 60), (250, 190, 212), (0, 128, 128), (220, 190, 255))
_GOLDEN = 0.6180339887498949


def _default_colours() -> np.ndarray:
    table = np.zeros((LABELS + 1, 3), np.uint8)
    table[1:len(_FIRST) + 1] = _FIRST
    for n in range(len(_FIRST) + 1, LABELS + 1):
        table[n] = [round(255 * c) for c in colorsys.hsv_to_rgb((n * _GOLDEN) % 1.0, 0.7, 0.95)]
    table.flags.writeable = False
    return table


DEFAULT_COLOURS = _default_colours()  # (256, 3): entry n is label n's colour; 0 (clear) is never drawn


def check_label(label: object, least: int = 0) -> int:
    """`label` as an int if it is a whole number least..255, else VolumeError."""
    try:
        n = operator.index(label)
    except TypeError:
        n = None
    if n is None or not least <= n <= LABELS:
        raise VolumeError(f"a label is a whole number {least}..{LABELS}{' (0: clear)' if least == 0 else ''}, "
                          f"got {label!r}")
    return n


def check_rgb(rgb: Sequence[int]) -> tuple[int, int, int]:
    try:
        values = tuple(operator.index(c) for c in rgb)
    except TypeError:
        values = ()
    if len(values) != 3 or not all(0 <= c <= 255 for c in values):
        raise VolumeError(f"a label's colour is three whole numbers 0..255 (r, g, b), got {rgb!r}")
    return values


class Labels(ChangeRecord):
    """The labels of a scan `size` (w, h, d) voxels: `data` (d, h, w) uint8 once painted (None before), and
    `colours` (256, 3) uint8, label n's at n. `version` and `changed_since` record where `data` changed (as Voxels
    does theirs); `colour_version` counts colour changes."""

    def __init__(self, size: tuple[int, int, int], data: np.ndarray | None = None,
                 colours: Mapping[int, Sequence[int]] | None = None) -> None:
        super().__init__()
        self.size = size
        self.data = data
        self.colours = DEFAULT_COLOURS.copy()
        for n, rgb in (colours or {}).items():
            self.colours[check_label(n, 1)] = check_rgb(rgb)
        self.colour_version = 0

    @classmethod
    def loaded(cls, data: np.ndarray, colours: Mapping[int, Sequence[int]] | None = None) -> Labels:
        """Labels read from a file: `data` (d, h, w) uint8 is kept as it is (a reader's fresh array); all clear
        holds none, as a scan never painted."""
        if not isinstance(data, np.ndarray) or data.dtype != np.uint8 or data.ndim != 3:
            raise VolumeError(f"labels must be a (depth, height, width) uint8 array, got "
                              f"{getattr(data, 'dtype', type(data).__name__)} of shape {getattr(data, 'shape', None)}")
        d, h, w = data.shape
        check_size(w, h, d)
        kept = np.ascontiguousarray(data) if data.any() else None
        return cls((w, h, d), kept, colours)

    def full_box(self) -> Box:
        w, h, d = self.size
        return Box(0, 0, 0, w, h, d)

    @property
    def nbytes(self) -> int:
        return 0 if self.data is None else self.data.nbytes

    def allocate(self) -> np.ndarray:
        """The labels, all clear the first time (the volume's size check made room for them). Whoever paints them
        marks what changed; a consumer that held no labels takes them whole."""
        if self.data is None:
            w, h, d = self.size
            self.data = np.zeros((d, h, w), np.uint8)
        return self.data

    def release(self) -> None:
        """Hold none again (the first label painted was undone: every label is clear)."""
        self.data = None
        self.changed(None)

    def plane(self, axis: str, index: int) -> np.ndarray:
        """The writable (v, u) view of a slice of allocated labels; the index is the caller's, checked."""
        return self.data[(slice(None),) * _ARRAY_AXIS[check_axis(axis)] + (index,)]

    def at(self, index: tuple[int, int, int]) -> int:
        """The label at a (z, y, x) index inside the volume."""
        return 0 if self.data is None else int(self.data[index])

    def counts(self) -> np.ndarray:
        """Voxels of each label, (256,) indexed by label."""
        if self.data is None:
            return np.bincount([], minlength=LABELS + 1)
        return np.bincount(self.data.reshape(-1), minlength=LABELS + 1)

    def set_colour(self, label: int, rgb: tuple[int, int, int]) -> tuple[int, int, int]:
        """Give a label another colour (checked by the caller); returns the one before."""
        before = tuple(int(c) for c in self.colours[label])
        self.colours[label] = rgb
        self.colour_version += 1
        return before

    def recoloured(self) -> dict[int, tuple[int, int, int]]:
        """The labels whose colour is not the default one, with their colours."""
        changed = np.flatnonzero((self.colours != DEFAULT_COLOURS).any(-1))
        return {int(n): tuple(int(c) for c in self.colours[n]) for n in changed}

    def turn(self, axes: tuple[int, int], turns: int) -> None:
        """Quarter turns in the plane of two array axes, as the scan's voxels turn."""
        if self.data is not None:
            self.data = np.ascontiguousarray(np.rot90(self.data, turns, axes=axes))
        shape = list(self.size[::-1])  # (d, h, w)
        if turns % 2:  # the two axes trade places
            shape[axes[0]], shape[axes[1]] = shape[axes[1]], shape[axes[0]]
        self.size = tuple(shape[::-1])
        self.changed(None)

    def hash_into(self, h) -> None:
        """Add the labels to a digest; nothing while none is painted or recoloured (a scan's digest as before)."""
        recoloured = self.recoloured()
        if self.data is None and not recoloured:
            return
        h.update(f";labels {sorted(recoloured.items())!r};".encode())
        if self.data is not None:
            h.update(self.data.data)
