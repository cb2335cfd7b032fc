"""The views a light's shadow map is drawn from, fitted to what the camera sees (numpy). Fitted to the whole
scene, one object far off (or a wide spot's cone) spread a map's texels so thin that no shadow kept a texel;
fitted to the receivers in view, the texels fall where the view needs them, wherever the rest of the scene lies.

Receivers are the objects a light reaches in view, each the convex region its bounding box, the view frustum and
the light's reach (a point light's range box; a spot's cone box and the square pyramid around its cone) hold in
common: half-spaces, whose corners convex_corners finds by meeting their planes three at a time.
- directional: cascades over the view depths the receivers span, split by the practical scheme (Zhang et al.
  2006: SPLIT_BLEND of the logarithmic split, the rest of the uniform one); each an orthographic box across the
  light fitted to its slice's receivers, its depth theirs alone: the casters nearer the light are drawn clamped to
  depth 0 (shadow_map.ORTHOGRAPHIC_DEPTH_STATE), so a caster far up the light's rays neither escapes the box nor
  stretches its depth (and the bias, a share of it). Its texel is a quantised size (steps of 2^(1/TEXEL_STEPS))
  and its corner lies on whole texels of a grid fixed in the light's frame, so the map's texels hold still while
  the camera moves (no shimmering edges). The light pass picks the cascade by the pixel's view depth.
- spot: one perspective view aimed at the receivers' mean direction, its window the box of their tangents, where
  they all lie within WIDE of that direction; else (a wide cone seen whole, a spot of 89.9 degrees) the point
  light's six faces.
- point: six cube faces, each window the box of the tangents of the receivers within it (clamped to the face's
  own 90 degrees); a face with none is not drawn. Radial depth runs from the nearest caster to the farthest
  receiver (within a point light's range), so the bias is a share of that span, not of the scene's.
Every window is a little wider than its receivers (PAD texels a side for the PCF kernel: shadow_map.widening).
"""
from __future__ import annotations

import itertools
import math
from functools import lru_cache

import numpy as np

from app.gl.lights3d.light_reach import frustum_planes, reach_box
from app.gl.lights3d.shadow_map import (CASCADES, CUBE, CUBE_FACES, NEAR_SHARE, NO_SPLIT, ONE, MapViews, pad,
                                        widening)
from app.model.lights3d.scene import Light3D
from app.model.transforms import frustum, look_at, orthographic

SPLIT_BLEND = 0.75     # lambda of the practical split: 1 logarithmic, 0 uniform
TEXEL_STEPS = 8        # a cascade's texel is a whole power of 2^(1/8) world units (at most 9 % of the texels spare)
WIDE = math.radians(60.0)  # a spot's receivers spread wider than this from their middle: the cube's faces instead
FRONT = 1e-6           # a cube face holds what lies this share of the far distance ahead of the light, or more
MARGIN = 1e-3          # of a depth span, kept beyond its ends against rounding


@lru_cache(maxsize=64)
def _triples(count: int, fresh: int) -> np.ndarray:
    """The triples of `count` planes that take one from `fresh` on."""
    return np.array([t for t in itertools.combinations(range(count), 3) if t[2] >= fresh], np.intp).reshape(-1, 3)


def _inside(points: np.ndarray, planes: np.ndarray) -> np.ndarray:
    """Which points (..., 3) no plane (k, 4) of `planes` (..., k, 4) leaves outside, but for rounding."""
    slack = 1e-9 * (1.0 + np.abs(points).max(axis=-1, initial=0.0))
    return (points @ np.swapaxes(planes[..., :3], -1, -2) + planes[..., None, :, 3] >= -slack[..., None]).all(-1)


def convex_corners(planes, fresh: int = 0) -> np.ndarray:
    """The corners (m, 3) of bounded convex regions, each where n . p + d >= 0 for every one of its planes (n, d)
    (n unit; `planes` (regions, k, 4), or (k, 4) for one): the points where three of a region's planes meet that
    none of them leaves outside, every region's together; none where the regions are empty. With `fresh`, only
    the corners on a plane from that one on (the others are the corners of the region its first planes bound)."""
    planes = np.asarray(planes, np.float64).reshape(-1, *np.shape(planes)[-2:])
    triples = _triples(planes.shape[1], fresh)
    n, d = planes[:, triples, :3], -planes[:, triples, 3]  # (regions, triples, 3, 3), (regions, triples, 3)
    a, b, c = n[..., 0, :], n[..., 1, :], n[..., 2, :]
    bc, ca, ab = np.cross(b, c), np.cross(c, a), np.cross(a, b)
    det = (a * bc).sum(axis=-1)
    ok = np.abs(det) > 1e-9  # three planes through one line, or two parallel ones, meet in no single point
    safe = np.where(ok, det, 1.0)[..., None]
    points = (d[..., :1] * bc + d[..., 1:2] * ca + d[..., 2:] * ab) / safe  # Cramer's rule
    return points[ok & _inside(points, planes)]


def box_planes(lo, hi) -> np.ndarray:
    """(6, 4): the box lo..hi as the half-spaces x >= lo and x <= hi on each axis."""
    eye = np.identity(3)
    return np.vstack([np.c_[eye, -np.asarray(lo, np.float64)], np.c_[-eye, np.asarray(hi, np.float64)]])


def _cone_planes(light: Light3D) -> np.ndarray:
    """A spot's reach as half-spaces: ahead of it, and within the square pyramid around its cone."""
    apex = np.asarray(light.position, np.float64)
    frame = look_at(apex, light.direction)[:3, :3]
    right, up, ahead = frame[0], frame[1], -frame[2]
    spread = math.tan(math.radians(light.angle))
    normals = np.array([ahead, spread * ahead - right, spread * ahead + right, spread * ahead - up,
                        spread * ahead + up])
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    return np.c_[normals, -normals @ apex]


def receiver_regions(light: Light3D, receivers, view_proj) -> np.ndarray:
    """(regions, k, 4): per receiver (anything with lo and hi: its bounding box) within the light's reach, the
    planes of the part of it the view and the light may both see."""
    shared = frustum_planes(view_proj)
    if light.kind == "spot":
        shared = np.vstack([shared, _cone_planes(light)])
    regions = []
    for receiver in receivers:
        lo, hi = reach_box(light, receiver.lo, receiver.hi)
        if (lo <= hi).all():
            regions.append(np.vstack([box_planes(lo, hi), shared]))
    return np.array(regions).reshape(-1, 6 + len(shared), 4)


def _corners(regions: np.ndarray, corners: np.ndarray, *cuts) -> np.ndarray:
    """The corners of every region (`corners` theirs) cut by the planes `cuts` too: those of its own the cuts
    keep, and where a cut meets two of its planes or another cut."""
    cut = np.vstack(cuts)
    shared = np.broadcast_to(cut, (len(regions), *cut.shape))
    met = convex_corners(np.concatenate([regions, shared], axis=1), fresh=regions.shape[1])
    return np.concatenate([corners[_inside(corners, cut)], met])


def practical_splits(near: float, far: float, count: int, blend: float = SPLIT_BLEND) -> np.ndarray:
    """count + 1 view depths from near to far: blend x the logarithmic split + (1 - blend) x the uniform one."""
    share = np.arange(count + 1) / count
    splits = blend * near * (far / near) ** share + (1 - blend) * (near + (far - near) * share)
    splits[0], splits[-1] = near, far
    return splits


def fit_views(light: Light3D, receivers, casters, view_proj, size: int, pcf: int, cascades: int) -> MapViews:
    """The views of `light`'s map for the camera `view_proj` (row-major clip from world): `receivers` the
    objects it reaches in view, `casters` those that can shadow them (lo, hi, centre, radius: bounds)."""
    regions = receiver_regions(light, receivers, view_proj)
    if light.kind == "directional":
        return _cascades(light, regions, np.asarray(view_proj, np.float64), size, pcf, cascades)
    return _radial(light, regions, casters, size, pcf)


def _grid(count: int) -> tuple[int, int]:
    return (count, 1) if count <= 2 else (2, 2)


def _snapped(lo: float, hi: float, size: int, pcf: int) -> tuple[float, float]:
    """A cascade's extent on one axis holding lo..hi inside its pad: a quantised texel, the corner on the grid."""
    spare = pad(pcf)
    span = max(hi - lo, 1e-9 * (1.0 + abs(lo)))
    texel = 2.0 ** (math.ceil(math.log2(span / (size - 2 * spare - 1)) * TEXEL_STEPS) / TEXEL_STEPS)
    first = (math.floor(lo / texel) - spare) * texel  # snapping moves lo under a texel: the extent has one spare
    return first, first + size * texel


def _cascades(light: Light3D, regions, view_proj: np.ndarray, size: int, pcf: int, count: int) -> MapViews:
    """A directional light's cascades over the view depths the receivers' regions span."""
    row = view_proj[3]  # a perspective camera's clip w: the view depth of a world point
    grid = _grid(count)
    everything = convex_corners(regions)
    if not len(everything):
        return MapViews(CASCADES, (np.identity(4),) * count, (False,) * count, grid, depth_row=tuple(row),
                        splits=(NO_SPLIT,) * (count - 1))
    depth = everything @ row[:3] + row[3]
    splits = practical_splits(max(depth.min(), 1e-9), depth.max(), count)
    rotation = look_at(np.zeros(3), light.direction)  # a frame fixed in the world: the texel grids' origin
    turn = rotation[:3, :3]
    unit = np.linalg.norm(row[:3])
    views, drawn = [], []
    for first, last in zip(splits[:-1], splits[1:]):
        slab = np.array([[*row[:3], row[3] - first], [*-row[:3], last - row[3]]]) / unit
        points = _corners(regions, everything, slab)
        if not len(points):
            views.append(np.identity(4))
            drawn.append(False)
            continue
        local = points @ turn.T
        lo, hi = local[:, :2].min(0), local[:, :2].max(0)
        near, far = -local[:, 2].max(), -local[:, 2].min()  # casters nearer the light: clamped to depth 0
        margin = MARGIN * (far - near) + 1e-9 * (1.0 + abs(far))
        (x0, x1), (y0, y1) = _snapped(lo[0], hi[0], size, pcf), _snapped(lo[1], hi[1], size, pcf)
        views.append(orthographic((x0, y0, near - margin), (x1, y1, far + margin)) @ rotation)
        drawn.append(True)
    return MapViews(CASCADES, tuple(views), tuple(drawn), grid, depth_row=tuple(row),
                    splits=tuple(splits[1:-1]))


def _window(view: np.ndarray, tangents: np.ndarray, near: float, far: float, wider: float,
            lo=None, hi=None) -> np.ndarray:
    """A perspective view whose window holds `tangents` (clamped to lo..hi), widened for the PCF pad."""
    t_lo, t_hi = tangents.min(0), tangents.max(0)
    if lo is not None:
        t_lo, t_hi = np.maximum(t_lo, lo), np.minimum(t_hi, hi)
    centre, half = (t_lo + t_hi) / 2, np.maximum((t_hi - t_lo) / 2, 1e-9) * wider
    w_lo, w_hi = centre - half, centre + half
    slope = np.maximum(np.abs(w_lo), np.abs(w_hi))
    near_plane = near / math.sqrt(1.0 + slope @ slope)  # a caster at distance `near` anywhere in the window
    return frustum(w_lo, w_hi, near_plane, far) @ view


def _tangents(view: np.ndarray, points: np.ndarray) -> np.ndarray:
    local = points @ view[:3, :3].T + view[:3, 3]
    return local[:, :2] / -local[:, 2:]


def _radial(light: Light3D, regions, casters, size: int, pcf: int) -> MapViews:
    """A spot's one view, or six cube faces, each fitted to the receivers' regions it holds."""
    apex = np.asarray(light.position, np.float64)
    everything = convex_corners(regions)
    if not len(everything):
        return MapViews(CUBE, (np.identity(4),) * 6, (False,) * 6, (3, 2), 0.0, 1.0)
    distance = np.linalg.norm(everything - apex, axis=1)
    far = distance.max() if light.kind == "spot" else min(distance.max(), light.range)
    far = max(far * (1 + MARGIN), 1e-9)
    nearest = min((float(np.linalg.norm(c.centre - apex)) - c.radius for c in casters), default=far)
    near = min(max(nearest, NEAR_SHARE * far), far * (1 - MARGIN))  # a caster nearer than NEAR_SHARE of far: clipped
    wider = widening(size, pcf)
    if light.kind == "spot" and distance.min() > FRONT * far:
        directions = (everything - apex) / distance[:, None]
        middle = directions.sum(0)
        length = np.linalg.norm(middle)
        if length > 0 and (directions @ (middle / length)).min() >= math.cos(WIDE):
            view = look_at(apex, middle / length)
            return MapViews(ONE, (_window(view, _tangents(view, everything), near, far, wider),), (True,),
                            (1, 1), near, far)
    views, drawn = [], []
    for axis in CUBE_FACES:
        view = look_at(apex, axis)
        ahead = np.array([[*axis, -np.dot(axis, apex) - FRONT * far]])
        points = _corners(regions, everything, ahead)
        tangents = _tangents(view, points) if len(points) else np.zeros((0, 2))
        inside = len(tangents) and (tangents.min(0) <= 1).all() and (tangents.max(0) >= -1).all()
        views.append(_window(view, tangents, near, far, wider, -1.0, 1.0) if inside else np.identity(4))
        drawn.append(bool(inside))
    return MapViews(CUBE, tuple(views), tuple(drawn), (3, 2), near, far)
