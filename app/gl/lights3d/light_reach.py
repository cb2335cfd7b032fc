"""Where a 3D light can reach, against the view and the objects (numpy): the renderer skips a light whose reach
the view does not see, and builds shadows and lights only the objects a light reaches.

Reach: a point light's range sphere (katt is 0 from its range on), a spot's cone (0 outside it; the spot has no
range), everywhere for a directional light. Objects are bounding spheres. Every test is conservative: it may
keep what is in fact out of reach, never drop what is in it. A caster out of a light's reach shadows nothing in
it: the segment from a lit point to a point or spot light lies inside the sphere or cone (both convex, holding
the light), so whatever blocks it does too."""
from __future__ import annotations

import itertools
import math

import numpy as np

from app.model.lights3d.scene import Light3D


def box_corners(lo, hi) -> np.ndarray:
    """(8, 3): corner i takes hi on x where bit 2 of i is set, on y bit 1, on z bit 0."""
    return np.array(list(itertools.product(*zip(lo, hi))), np.float64)


def frustum_planes(clip_from_world: np.ndarray) -> np.ndarray:
    """(6, 4) unit planes (n, d), n . p + d >= 0 inside, of the clip volume of a row-major view-projection
    (Gribb and Hartmann)."""
    m = np.asarray(clip_from_world, np.float64)
    planes = np.array([m[3] + m[0], m[3] - m[0], m[3] + m[1], m[3] - m[1], m[3] + m[2], m[3] - m[2]])
    return planes / np.linalg.norm(planes[:, :3], axis=1, keepdims=True)


def sphere_in_view(planes: np.ndarray, centre, radius: float) -> bool:
    return bool((planes[:, :3] @ np.asarray(centre, np.float64) + planes[:, 3] >= -radius).all())


def _cone_outside(n: np.ndarray, d: float, apex: np.ndarray, axis: np.ndarray, half_angle: float) -> bool:
    """The infinite cone lies wholly behind plane (n, d): its apex does, and no direction within it turns to
    the plane's front (the nearest is the angle between n and the axis less the half-angle)."""
    if n @ apex + d >= 0:
        return False
    between = math.acos(float(np.clip(n @ axis, -1.0, 1.0)))
    return between - half_angle >= math.pi / 2


def light_in_view(light: Light3D, planes: np.ndarray) -> bool:
    """Whether any of the light's reach may be seen."""
    if light.kind == "point":
        return sphere_in_view(planes, light.position, light.range)
    if light.kind == "spot":
        apex, axis = np.asarray(light.position), np.asarray(light.direction)
        half = math.radians(light.angle)
        return not any(_cone_outside(p[:3], p[3], apex, axis, half) for p in planes)
    return True


def reaches(light: Light3D, centre, radius: float) -> bool:
    """Whether the light's reach meets the sphere (centre, radius)."""
    if light.kind == "directional":
        return True
    to_centre = np.asarray(centre, np.float64) - np.asarray(light.position)
    distance = float(np.linalg.norm(to_centre))
    if light.kind == "point":
        return distance < light.range + radius
    if distance <= radius:
        return True
    off_axis = math.acos(float(np.clip(to_centre @ np.asarray(light.direction) / distance, -1.0, 1.0)))
    return off_axis <= math.radians(light.angle) + math.asin(radius / distance)


def reach_box(light: Light3D, lo, hi) -> tuple[np.ndarray, np.ndarray]:
    """The part of box lo..hi the light may reach, boxed (lo > hi on some axis where it reaches none of it).
    A spot's cone is cut where it leaves the box: its apex and the cap at the farthest corner's distance
    bound it (nothing of the cone within that distance lies outside their hull)."""
    lo, hi = np.asarray(lo, np.float64), np.asarray(hi, np.float64)
    if light.kind == "point":
        return np.maximum(lo, np.subtract(light.position, light.range)), np.minimum(hi, np.add(light.position,
                                                                                           light.range))
    if light.kind == "spot":
        apex, axis = np.asarray(light.position), np.asarray(light.direction)
        far = float(np.linalg.norm(box_corners(lo, hi) - apex, axis=1).max())
        cap = apex + far * axis
        spread = far * math.tan(math.radians(light.angle)) * np.sqrt(np.maximum(0.0, 1.0 - axis * axis))
        return np.maximum(lo, np.minimum(apex, cap - spread)), np.minimum(hi, np.maximum(apex, cap + spread))
    return lo, hi


def screen_rect(clip_from_world: np.ndarray, near: float, lo, hi, size: tuple[int, int]
                ) -> tuple[int, int, int, int] | None:
    """The pixels (x, y, width, height; GL's origin bottom left) box lo..hi may cover, a pixel to spare; the
    whole view where part of it lies behind the near plane; None where it is empty or off the view."""
    lo, hi = np.asarray(lo, np.float64), np.asarray(hi, np.float64)
    if (lo > hi).any():
        return None
    width, height = size
    clip = np.c_[box_corners(lo, hi), np.ones(8)] @ np.asarray(clip_from_world, np.float64).T
    if (clip[:, 3] < near).any():
        return 0, 0, width, height
    ndc = clip[:, :2] / clip[:, 3:]
    x0, y0 = np.floor((ndc.min(0) + 1) / 2 * size) - 1
    x1, y1 = np.ceil((ndc.max(0) + 1) / 2 * size) + 1
    x0, y0, x1, y1 = max(0, int(x0)), max(0, int(y0)), min(width, int(x1)), min(height, int(y1))
    if x0 >= x1 or y0 >= y1:
        return None
    return x0, y0, x1 - x0, y1 - y0


def union(rects) -> tuple[int, int, int, int] | None:
    rects = [r for r in rects if r is not None]
    if not rects:
        return None
    x0, y0 = min(r[0] for r in rects), min(r[1] for r in rects)
    x1, y1 = max(r[0] + r[2] for r in rects), max(r[1] + r[3] for r in rects)
    return x0, y0, x1 - x0, y1 - y0


DEPTH_MARGIN = 1e-5  # window depth around a depth range: the stored depths are rounded (24 bits) and rasterised


def depth_range(clip_from_world: np.ndarray, near: float, lo, hi) -> tuple[float, float] | None:
    """The window depths (GL's default range 0..1) box lo..hi may hold in view, a margin to spare: from its
    nearest corner's (0 where part of it lies before the near plane) to its farthest's (a perspective's depth
    grows with the distance along the view, which is linear: a box's extremes are at corners); None where the box
    is empty or wholly before the near plane."""
    lo, hi = np.asarray(lo, np.float64), np.asarray(hi, np.float64)
    if (lo > hi).any():
        return None
    clip = np.c_[box_corners(lo, hi), np.ones(8)] @ np.asarray(clip_from_world, np.float64).T
    ahead = clip[:, 3] >= near
    if not ahead.any():
        return None
    depth = (clip[ahead, 2] / clip[ahead, 3] + 1.0) / 2.0
    nearest = 0.0 if not ahead.all() else float(depth.min())
    return max(0.0, nearest - DEPTH_MARGIN), min(1.0, float(depth.max()) + DEPTH_MARGIN)


def span(ranges) -> tuple[float, float] | None:
    """The depth range holding all of `ranges` (None ones left out)."""
    ranges = [r for r in ranges if r is not None]
    if not ranges:
        return None
    return min(r[0] for r in ranges), max(r[1] for r in ranges)
