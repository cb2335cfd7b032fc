"""Frame All (`view.frame`): the view that shows a whole scene, for a 2D camera and for an orbit camera."""
from __future__ import annotations

from dataclasses import replace

import numpy as np

from app.model.camera3d import OrbitCamera

MARGIN = 1.1  # a 2D scene's bounds take 1 / MARGIN of the view's height or width, whichever binds
FILL = 0.8    # a 3D scene's box reaches this share of the view, from its middle to the nearer edge
EDGE = 0.95   # ... a volume's box spans FILL of the view across and keeps within this share of it from the middle


def view_2d(lo, hi, aspect: float) -> tuple[float, float, float]:
    """(centre x, centre y, world height shown) of a view of width/height `aspect` around the box lo..hi."""
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    width, height = np.maximum(hi - lo, 1e-6)
    shown = MARGIN * max(height, width / max(aspect, 1e-3))
    cx, cy = (lo + hi) / 2
    return float(cx), float(cy), float(shown)


def in_view_2d(view: tuple[float, float, float], lo, hi, aspect: float) -> bool:
    """Whether the box lo..hi lies whole in the 2D view (centre x, centre y, height) `aspect` wide per height."""
    cx, cy, height = view
    half = np.array([height * aspect / 2, height / 2])
    return bool((np.asarray(lo) >= (cx, cy) - half).all() and (np.asarray(hi) <= (cx, cy) + half).all())


def _corners_clip(camera: OrbitCamera, lo, hi, aspect: float) -> np.ndarray:
    """The box lo..hi's 8 corners in `camera`'s clip space, for a view `aspect` wide per unit of height."""
    x0, y0, z0 = lo
    x1, y1, z1 = hi
    corners = np.array([(x, y, z, 1.0) for x in (x0, x1) for y in (y0, y1) for z in (z0, z1)])
    return corners @ camera.clip_from_world((max(1, round(1000 * aspect)), 1000)).T


def box_in_view(camera: OrbitCamera, lo, hi, aspect: float, fill: float = 1.0) -> bool:
    """Whether every corner of the box lo..hi lies in front of `camera` and within `fill` of its view (a view
    `aspect` wide per unit of height) on both axes."""
    clip = _corners_clip(camera, lo, hi, aspect)
    w = clip[:, 3]
    return bool((w > camera.NEAR).all() and (np.abs(clip[:, :2]) <= fill * w[:, None]).all())


def box_span(camera: OrbitCamera, lo, hi, aspect: float) -> np.ndarray:
    """The share (x, y) of the view's width and height the box lo..hi's picture spans; inf where a corner lies
    behind the near plane."""
    clip = _corners_clip(camera, lo, hi, aspect)
    if (clip[:, 3] <= camera.NEAR).any():
        return np.array([np.inf, np.inf])
    ndc = clip[:, :2] / clip[:, 3:]
    return (ndc.max(0) - ndc.min(0)) / 2


def orbit_distance(camera: OrbitCamera, lo, hi, aspect: float) -> float:
    """The distance at which `camera` (its yaw, pitch and centre kept) shows the box lo..hi whole, its corners
    within FILL of the view on both axes, for a view `aspect` wide per unit of height; within the camera's limits.
    Found by bisection: the corners' reach on screen only shrinks as the camera backs away."""
    def fits(distance: float) -> bool:
        return box_in_view(replace(camera, distance=distance), lo, hi, aspect, FILL)

    near, far = camera.MIN_DISTANCE, camera.MAX_DISTANCE
    if fits(near) or not fits(far):
        return near if fits(near) else far
    return _bisect(camera, fits)


def filling_distance(camera: OrbitCamera, lo, hi, aspect: float) -> float:
    """The distance at which `camera` (its yaw, pitch and centre kept) sees the box lo..hi span FILL of the view's
    height or width, whichever binds, its corners within EDGE of the view: as orbit_distance, but measured across
    the picture rather than from its middle, so a box seen from above (its picture below the middle, its near
    corners larger) fills about FILL of the view, not FILL less twice that offset."""
    def fits(distance: float) -> bool:
        moved = replace(camera, distance=distance)
        return bool((box_span(moved, lo, hi, aspect) <= FILL).all()) and box_in_view(moved, lo, hi, aspect, EDGE)

    return _bisect(camera, fits)


def _bisect(camera: OrbitCamera, fits) -> float:
    """The least distance within the camera's limits at which `fits` (false nearer, true farther) holds."""
    near, far = camera.MIN_DISTANCE, camera.MAX_DISTANCE
    if fits(near) or not fits(far):
        return near if fits(near) else far
    for _ in range(48):
        middle = (near + far) / 2
        near, far = (near, middle) if fits(middle) else (middle, far)
    return far
