"""CPU reference of the F-modes (app/reference/volume.py) on a scan, as the GPU draws it (r_scalarMode colour): the
values interpolated, then looked up in the colour map's table (resources/shaders/scan_colour.shl), never the colours
interpolated. napari and vispy do the same: a value between two voxels gets the colour map's colour of that value,
not a blend of its neighbours' colours (which, across a sharp window, is a colour the map does not hold).

The values are sampled as the scalar modes sample them (trilinear in float64, clamped to the edge); the colour is
then weighted by the share of the trilinear filter inside the box, as an RGBA texture with a transparent border
filters it, so the box's faces stay surfaces as they are for an RGBA volume. A hit's material reads its 8 voxels'
colours; the dual view's nearest samples colour the nearest voxel's value."""
from __future__ import annotations

import numpy as np
from scipy.ndimage import map_coordinates

from app.model.camera3d import OrbitCamera
from app.model.volume import render_modes as rm
from app.model.volume.scalar_modes import colour_of, drawable, finite_span
from app.model.volume.scalars import TransferFunction
from app.model.volume.view import box_extents, voxel_extent
from app.model.volume.voxels import DEFAULT_SPACING, Spacing
from app.reference.volume import Scene, render_scene
from app.reference.volume_labels import LabelLayer


class ScanScene(Scene):
    """A scan's values (as the GPU holds them, float64) and its transfer function: its colours made as sampled."""

    def __init__(self, values: np.ndarray, transfer: TransferFunction, sample_range: float = 1.0,
                 shadow_offset: float = rm.SHADOW_OFFSET, spacing: Spacing = DEFAULT_SPACING) -> None:
        self.values = drawable(values, finite_span(values)).astype(np.float64)
        self.table, self.low, self.high = transfer.table(), transfer.low, transfer.high
        self.size = np.array(values.shape[::-1], dtype=np.float64)  # (w, h, d)
        voxels = tuple(int(s) for s in self.size)
        self.extent = np.array(box_extents(voxels, spacing))
        self.voxel = voxel_extent(voxels, spacing)
        self.sample_range, self.shadow_offset = sample_range, shadow_offset

    def colours(self, v: np.ndarray) -> np.ndarray:
        """RGBA 0..1 (..., 4) of values v: the colour map's at their window units."""
        return colour_of(self.table, (v - self.low) / (self.high - self.low))

    def sample(self, t: np.ndarray, nearest: bool = False) -> np.ndarray:
        coords = [t[..., 2] * self.size[2] - 0.5, t[..., 1] * self.size[1] - 0.5, t[..., 0] * self.size[0] - 0.5]
        if nearest:
            return self.colours(map_coordinates(self.values, [np.floor(c + 0.5) for c in coords], order=0,
                                                mode="nearest"))
        inside = np.clip(np.minimum(t, 1.0 - t) * self.size + 0.5, 0.0, 1.0).prod(-1)
        return self.colours(map_coordinates(self.values, coords, order=1, mode="nearest")) * inside[..., None]

    def texels(self, q: np.ndarray) -> np.ndarray:
        return self.colours(self.values[q[:, 2], q[:, 1], q[:, 0]])


def render(values: np.ndarray, transfer: TransferFunction, camera: OrbitCamera, size: tuple[int, int],
           mode: rm.Mode, steps: float, shadow_steps: int = 20, sample_range: float = 1.0,
           background=(0.0, 0.0, 0.0), lights=rm.LIGHTS, shadow_offset: float = rm.SHADOW_OFFSET,
           spacing: Spacing = DEFAULT_SPACING, labels: LabelLayer | None = None) -> np.ndarray:
    """The image (height, width, 3), floats 0..1, top row first, of the scan `values` (d, h, w) coloured through
    `transfer` in F-mode `mode`, as app/reference/volume.py's `render` draws an RGBA volume."""
    scene = ScanScene(values, transfer, sample_range, shadow_offset, spacing)
    return render_scene(scene, camera, size, mode, steps, shadow_steps, background, lights, labels)
