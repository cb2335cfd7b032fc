"""What the volume workspace shows besides the voxels: the camera, background, edited and highlighted slice."""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from app.model.camera3d import OrbitCamera
from app.model.volume.voxels import AXES, DEFAULT_SPACING, Spacing

AXIS_INDEX = {axis: i for i, axis in enumerate(AXES)}
# World -> voxel-index axes: the index space has y down and z away from the viewer (an image stack),
# the world is right-handed with y up. The shaders use the same flip.
FLIP = np.array([1.0, -1.0, -1.0])


@dataclass
class VolumeView:
    camera: OrbitCamera = field(default_factory=OrbitCamera)
    background: tuple[int, int, int] = (24, 26, 34)
    axis: str = "z"               # the slice the painter edits
    index: int = 0
    highlight: tuple[str, int] | None = None  # the slice picker's hovered slice
    brush: tuple[int, int, int, int] = (255, 140, 40, 255)  # the painter's colour
    mode: int = 5                 # Tex3Dtrace's F-key mode (app/model/volume/render_modes.py)
    shadows: bool = True          # key l
    light: tuple[float, float, float] = (0.4, 0.7, 2.6)  # the first light; key z moves it
    stereo: bool = False          # key t: red from the left eye, green and blue from the right
    magnify: bool = False         # key x: twice the magnification
    wireframe: bool = False       # key f: the box's edges
    iso: float | None = None      # a scalar volume's iso value (vol.iso, data units); None: the window's middle

    def key(self) -> tuple:
        c = self.camera
        key = (c.yaw, c.pitch, c.distance, self.background, self.axis, self.index, self.highlight, self.brush,
               self.mode, self.shadows, self.light, self.stereo, self.magnify, self.wireframe)
        return key if self.iso is None else (*key, self.iso)  # unset, the digests recorded before it stay


def box_extents(size: tuple[int, int, int], spacing: Spacing = DEFAULT_SPACING) -> tuple[float, float, float]:
    """Half extents of the volume's box, `size` voxels (w, h, d) of `spacing` (x, y, z): the physically longest
    side spans [-1, 1], the others in proportion (a CT of 0.5 mm pixels and 2 mm slices is not squashed)."""
    sides = [n * s for n, s in zip(size, spacing)]
    longest = max(sides)
    return tuple(s / longest for s in sides)


def voxel_extent(size: tuple[int, int, int], spacing: Spacing = DEFAULT_SPACING) -> float:
    """The world length of a voxel's shortest side, in box_extents' world (2 / the longest side in voxels when the
    voxels are cubes)."""
    return 2.0 * min(spacing) / max(n * s for n, s in zip(size, spacing))


def world_to_texture(p: np.ndarray, extent) -> np.ndarray:
    """World points to texture coordinates 0..1 across the box (x right, y down, z away)."""
    return (p * FLIP / np.asarray(extent) + 1.0) * 0.5
