"""Which voxel a ray from the 3D view meets first: for the slice picker's hover."""
from __future__ import annotations

import numpy as np

from app.model.volume.view import box_extents, world_to_texture
from app.model.volume.voxels import Voxels



def first_hit(voxels: Voxels, origin: np.ndarray, direction: np.ndarray) -> tuple[int, int, int] | None:
    """The first voxel with alpha > 0 along the ray, else the voxel where the ray enters the box,
    else None when the ray misses the box."""
    extent = np.array(box_extents(voxels.size, voxels.spacing))
    with np.errstate(divide="ignore", invalid="ignore"):
        t0, t1 = (-extent - origin) / direction, (extent - origin) / direction
    t_near = max(np.nanmax(np.minimum(t0, t1)), 0.0)
    t_far = np.nanmin(np.maximum(t0, t1))
    if not t_near < t_far:
        return None
    size = np.array(voxels.size)
    to_index = lambda t: world_to_texture(origin + direction * t, extent) * size  # noqa: E731
    steps = int(np.ceil(np.linalg.norm(to_index(t_far) - to_index(t_near)) * 2)) + 1  # half-voxel steps
    ts = np.linspace(t_near, t_far, steps)
    idx = np.clip(np.floor(to_index(ts[:, None])).astype(int), 0, size - 1)
    alpha = voxels.data[idx[:, 2], idx[:, 1], idx[:, 0], 3]
    hit = np.flatnonzero(alpha > 0)
    x, y, z = idx[hit[0] if hit.size else 0]
    return int(x), int(y), int(z)
