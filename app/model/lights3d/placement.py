"""Where a new object goes when object.add is given no position: standing on the ground in front of the camera,
clear of the other objects. numpy only.

The search starts below the point the camera looks at and goes outward along the ground in DIRECTIONS directions
(the first the one the camera faces); along each it takes the nearest spot where the object's bounding box,
GAP wider on every side, meets no other's (exact: each other box blocks one interval of the way). Of those spots
it takes one whose whole box is in view, else one whose centre is, else any: the nearest, then the earliest
direction. "In view" is the square frustum of the camera's field of view, which every view's aspect contains.
The spot is a function of the scene and the camera alone, so the same scene and camera give the same spot; the
command records the spot it took, so a replay does not depend on the camera either."""
from __future__ import annotations

import itertools
import math

import numpy as np

from app.model.camera3d import OrbitCamera
from app.model.lights3d.scene import MAX_COORD, Object3D, Scene3D

GAP = 2.0          # world units kept clear around the new object's bounding box, also what rounding may take
DIRECTIONS = 16    # directions searched along the ground, evenly around


def ground_spot(scene: Scene3D, camera: OrbitCamera, obj: Object3D) -> tuple[float, float, float]:
    """The position for `obj` (standing as it should: its y is kept) on a clear spot of the ground in front of
    `camera`, x and z whole units."""
    position = np.asarray(obj.position)
    lo, hi = (corner - position for corner in obj.bounds)       # the box about the object's position
    blocks = _blocking(scene, obj.bounds[0][1], obj.bounds[1][1])  # the others' boxes its height meets
    start = np.array(camera.centre(), dtype=np.float64)[[0, 2]]
    yaw = math.radians(camera.yaw)
    ahead, right = np.array([-math.sin(yaw), -math.cos(yaw)]), np.array([math.cos(yaw), -math.sin(yaw)])
    best = None
    for k in range(DIRECTIONS):
        angle = 2 * math.pi * k / DIRECTIONS
        way = math.cos(angle) * ahead + math.sin(angle) * right
        t = _first_clear(blocks, lo[[0, 2]], hi[[0, 2]], start, way)
        x, z = np.round(start + t * way)
        spot = np.array([x, position[1], z])
        # a spot whose box passes the model's coordinates is a last resort, which the model then refuses
        beyond = not (np.abs([spot + lo, spot + hi]) <= MAX_COORD).all()
        key = (beyond, _view_tier(camera, spot, lo, hi), t, k)
        if best is None or key < best[0]:
            best = (key, spot)
    return tuple(float(v) for v in best[1])


def _blocking(scene: Scene3D, bottom: float, top: float) -> np.ndarray:
    """The x and z ranges (N, 2, 2: [object][lowest, highest][x, z]) of the objects whose height range meets
    bottom..top inside both: an object standing on the ground plane does not meet it, a plane at a height within
    it does, two planes at one height meet."""
    boxes = []
    for other in scene.objects:
        olo, ohi = other.bounds
        if _heights_meet(bottom, top, olo[1], ohi[1]):
            boxes.append([olo[[0, 2]], ohi[[0, 2]]])
    return np.array(boxes, dtype=np.float64).reshape(-1, 2, 2)


def _heights_meet(lo_a: float, hi_a: float, lo_b: float, hi_b: float) -> bool:
    """Whether the insides of two ranges share a point; a range of no height is its one point."""
    if lo_a == hi_a and lo_b == hi_b:
        return lo_a == lo_b
    if lo_a == hi_a:
        return lo_b < lo_a < hi_b
    if lo_b == hi_b:
        return lo_a < lo_b < hi_a
    return max(lo_a, lo_b) < min(hi_a, hi_b)


def _first_clear(blocks: np.ndarray, lo: np.ndarray, hi: np.ndarray, start: np.ndarray, way: np.ndarray) -> float:
    """The smallest t >= 0 where the box lo..hi about start + t way keeps GAP from every block. A block keeps the
    centre out of the open rectangle (block lowest - GAP - hi, block highest + GAP - lo), which the way crosses
    in one open interval of t."""
    inner, outer = blocks[:, 0] - GAP - hi, blocks[:, 1] + GAP - lo
    with np.errstate(divide="ignore", invalid="ignore"):
        a, b = (inner - start) / way, (outer - start) / way
    first, last = np.minimum(a, b), np.maximum(a, b)
    # along an axis the way does not move on, the centre is inside that range always or never
    still, inside = np.abs(way) < 1e-12, (inner < start) & (start < outer)
    first = np.where(still, np.where(inside, -np.inf, np.inf), first)
    last = np.where(still, np.where(inside, np.inf, -np.inf), last)
    enter, leave = first.max(axis=1), last.min(axis=1)
    t = 0.0
    while True:
        across = (enter < t) & (t < leave)
        if not across.any():
            return t
        t = float(leave[across].max())


def _view_tier(camera: OrbitCamera, spot: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> int:
    """0 where the whole box about `spot` is in the camera's square frustum, 1 where its centre is, else 2."""
    corners = spot + np.array(list(itertools.product(*zip(lo, hi))))
    clip = np.concatenate([np.vstack([corners, spot]), np.ones((9, 1))], axis=1) @ camera.clip_from_world((1, 1)).T
    seen = (clip[:, 3] > camera.NEAR) & (np.abs(clip[:, :2]) <= clip[:, 3:]).all(axis=1)
    return 0 if seen[:8].all() else 1 if seen[8] else 2
