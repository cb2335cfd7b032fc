"""A 3D RGBA raster being edited: its voxels, their undo history, their painting, and the edits of the whole
image (a rotation, another image, a window, a label's colour, a spacing), each one undo step."""
from __future__ import annotations

import numpy as np

from app.model.volume.history import (UNDO_BYTES, UNDO_STEPS, LabelColour, Respace, Swap, Turn, VoxelHistory,
                                     Window)
from app.model.volume.labels import LABEL_BYTES, Labels, check_label, check_rgb
from app.model.volume.painting import Painting
from app.model.volume.scalars import Scalars, TransferFunction, check_values, colour, default_window, own_values
from app.model.volume.voxels import (DEFAULT_SPACING, Spacing, VolumeError, Voxels, check_axis, check_size,
                                     check_spacing, own_rgba, transparent, whole)


class Volume:
    """`voxels` (what renderers and views read), their `history` (undo, redo) and their `paint` (strokes, fills,
    smoothing), made together: the history and the painting act on these voxels.

    A volume loaded from scalars (`replace_scalars`) keeps them in `voxels.scalars`: its voxels are their colours
    through the transfer function, made again whenever that changes (`set_transfer`). Such a scan is painted in
    labels (`voxels.labels`), never in colours: its values stay as loaded. Rotations turn the scalars and labels
    with the voxels."""

    def __init__(self, data: np.ndarray, *, max_undo_steps: int = UNDO_STEPS,
                 max_undo_bytes: int = UNDO_BYTES) -> None:
        self.voxels = Voxels(data)
        self.history = VoxelHistory(self.voxels, max_undo_steps, max_undo_bytes)
        self.paint = Painting(self.voxels, self.history)

    @classmethod
    def new(cls, w: int, h: int, d: int, **history: int) -> Volume:
        """A fully transparent volume; the size is checked before anything is allocated."""
        return cls(transparent(w, h, d), **history)

    def rotate(self, axis: str, turns: int = 1) -> None:
        """Quarter turns about an axis, counter-clockwise looking from +axis towards the origin."""
        self.history.clear_preview()
        turns = whole("turns", turns) % 4
        check_axis(axis)
        if turns:
            self.voxels.turn(axis, turns)
            self.history.push(Turn(axis, turns))

    def replace(self, data: np.ndarray, name: str = "Replace Volume", spacing: Spacing = DEFAULT_SPACING) -> None:
        """Swap in a whole new image (a loaded file) as one undo step called `name`."""
        self.history.clear_preview()
        spacing = check_spacing(*spacing)
        new = own_rgba(data)
        self.history.push(Swap.of(self.voxels, name))
        self.voxels.swap(new, None, spacing)
        self.voxels.labels = None  # an RGBA volume is painted in colours

    def replace_scalars(self, values: np.ndarray, transfer: TransferFunction | None = None,
                        name: str = "Replace Volume", copy: bool = True, spacing: Spacing = DEFAULT_SPACING,
                        labels: Labels | None = None) -> None:
        """Swap in a scalar volume (a loaded 16-bit or float file) as one undo step called `name`, coloured through
        `transfer` (by default the window from the values' percentiles, grey), with `labels` painted over it (a
        labels file's, of the same size; by default none yet). The size, labels included, is checked before
        anything is allocated; the values are copied, unless `copy` is False: then the volume keeps `values`
        itself (made read-only), which its caller hands over (a reader's fresh array, not a second copy of it)."""
        self.history.clear_preview()
        spacing = check_spacing(*spacing)
        d, h, w = check_values(values)
        check_size(w, h, d, values.itemsize + LABEL_BYTES)
        if labels is not None and labels.size != (w, h, d):
            raise VolumeError("the labels are {} x {} x {} voxels, the scan {} x {} x {}".format(*labels.size, w, h, d))
        values = own_values(values, copy)
        scalars = Scalars(values, transfer or TransferFunction(*default_window(values)))
        data = np.empty(values.shape + (4,), np.uint8)
        colour(values, scalars.transfer, data)
        self.history.push(Swap.of(self.voxels, name))
        self.voxels.swap(data, scalars, spacing)
        self.voxels.labels = labels or Labels((w, h, d))

    def set_spacing(self, spacing: Spacing) -> bool:
        """The voxels' sides (x, y, z) as one undo step; False if they are the same. The voxels stay as they are."""
        self.history.clear_preview()
        spacing = check_spacing(*spacing)
        if spacing == self.voxels.spacing:
            return False
        self.history.push(Respace(self.voxels.respace(spacing)))
        return True

    def set_transfer(self, transfer: TransferFunction, name: str = "Set Window") -> bool:
        """Colour the scalars through another window, colour map or opacity curve, as one undo step called `name`;
        False if it is the same."""
        self.history.clear_preview()
        scalars = self.voxels.require_scalars()
        if transfer == scalars.transfer:
            return False
        self.history.push(Window(scalars.transfer, name=name))
        self.voxels.recolour(transfer)
        return True

    def set_label_colour(self, label: int, rgb: tuple[int, int, int]) -> bool:
        """Give a scan's label another colour, as one undo step; False if it has that one."""
        self.history.clear_preview()
        labels = self.voxels.require_labels()
        label, rgb = check_label(label, least=1), check_rgb(rgb)
        if rgb == tuple(int(c) for c in labels.colours[label]):
            return False
        self.history.push(LabelColour(label, labels.set_colour(label, rgb)))
        return True

    def preview_transfer(self, transfer: TransferFunction) -> None:
        """Show another transfer function until the next edit (a drag in the transfer-function editor), unrecorded."""
        self.voxels.require_scalars()
        self.history.preview_transfer(transfer)
