"""The box of a scalar volume that can change a mode's picture, from its bricks' greatest values
(scalar_modes.brick_maxima): the shader's rays sample only where they cross it (scalar_modes.shl `clip_steps`).

A mode that shows nothing of the values at or below a level (mip and attenuated_mip: the window's low, drawn as the
low's colour; iso: the iso value; translucent: clear_below, what the opacity curve reads as clear) draws the same
picture from the samples inside the box of the bricks whose greatest value is over that level: every sample outside
reads only voxels of the other bricks (each brick's maximum covers its rim), so it is at most the level. minip and
average read every sample: their box is the whole volume."""
from __future__ import annotations

import numpy as np

from app.model.volume.scalar_modes import BRICK

WHOLE = ((0.0, 0.0, 0.0), (1.0, 1.0, 1.0))
NOTHING = ((1.0, 1.0, 1.0), (0.0, 0.0, 0.0))  # lo over hi: every ray misses it
LEVEL_MODES = ("mip", "attenuated_mip", "iso", "translucent")


def box_over(maxima: np.ndarray, size: tuple[int, int, int], level: float, margin: float) -> tuple[tuple, tuple]:
    """(lo, hi) in texture space (x, y, z) of the bricks of `maxima` (down z, y, x) whose greatest value is over
    `level` less `margin` (what the GPU's filtering and scaling may round a value at the level up by), for a volume
    of `size` (w, h, d) voxels."""
    over = maxima > np.float64(level - margin)  # in float64: the level may be float32's least
    if not over.any():
        return NOTHING
    lo, hi = [], []
    for axes, n in (((0, 1), size[0]), ((0, 2), size[1]), ((1, 2), size[2])):  # x, y, z
        where = np.flatnonzero(over.any(axis=axes))
        lo.append(where[0] * BRICK / n)
        hi.append(min((where[-1] + 1) * BRICK, n) / n)
    return tuple(lo), tuple(hi)


class ClipBox:
    """The clip box's uniforms for a mode, recomputed only when the bricks or the level change."""

    def __init__(self) -> None:
        self.enabled = True  # False: the whole volume (what tests compare the clipped picture with)
        self._maxima: np.ndarray | None = None  # held: a new array's id may be an old one's
        self._key: tuple | None = None
        self._box = WHOLE

    def uniforms(self, mode: str, maxima: np.ndarray, size: tuple[int, int, int], level: float,
                 value_scale: float) -> dict:
        if not self.enabled or mode not in LEVEL_MODES:
            box = WHOLE
        else:
            # a value read back from an integer texture is off by a few of its units at most, a float by its rounding
            margin = value_scale / 4096.0 + 1e-5 * abs(level)
            key = (level, margin, size)
            if maxima is not self._maxima or key != self._key:
                self._maxima, self._key, self._box = maxima, key, box_over(maxima, size, level, margin)
            box = self._box
        return {"u_clip_lo": box[0], "u_clip_hi": box[1]}
