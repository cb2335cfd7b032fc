"""The exact 2D lightmap (seed 000): what every GPU shadow method is measured against.

A pixel receives a light's value times the visible fraction of the light's emitting disc: the share of
disc points Q for which the segment from Q to the pixel crosses no hull. Where no hull piece touches the
disc, that share is exact: seen from the pixel, each convex hull piece in front of the disc hides the
disc between two rays, and the hidden area between two rays at offsets u1 < u2 from the disc's centre is
G(u2) - G(u1) with G(u) = u sqrt(r^2 - u^2) + r^2 asin(u / r); the pieces' intervals are fused (their
union measured) before the area is taken, so two hulls hiding the same half hide half. Where a piece
touches the disc, the hidden share is the area of the disc clipped by the union of the pieces' shadows,
in closed form too (`lighting2d_disc.py`); `sampled` measures it by sampling the disc, and converges on it.

Hull semantics per light (shadow_type): solid hulls are dark inside; illuminated hulls are lit inside as
if nothing cast shadows; occluded hulls are lit inside by what the other hulls let through. A light whose
centre is inside (or on) a hull it does not ignore is not drawn (Penumbra's rule)."""
from __future__ import annotations

import math

import numpy as np

from app.model.lighting2d.scene import Light, Scene2D, inside_convex
from app.model.lighting2d.index import SceneIndex
from app.reference.lighting2d_disc import hidden_share
from app.reference.lighting2d_light import light_value, normal_factor, pixel_world, textures_for

CHUNK = 4096  # pixels per vectorised block


def render(scene: Scene2D, width: int, height: int, view=None, flip_y: bool = False) -> np.ndarray:
    """The lightmap (height, width, 3) float64, clamped to 0..1, row 0 at the top of the view."""
    world = pixel_world(view or scene.view, width, height, flip_y)
    textures = textures_for(scene)
    index = SceneIndex(scene)
    out = np.broadcast_to(np.asarray(scene.ambient, dtype=np.float64), (height * width, 3)).copy()
    for light in scene.lights:
        contribution = light_contribution(scene, light, world, textures, index)
        if contribution is not None:
            out += contribution
    return np.clip(out, 0.0, 1.0).reshape(height, width, 3)


def blockers(scene: Scene2D, light: Light, index: SceneIndex | None = None) -> list[tuple[int, np.ndarray]]:
    """(hull index, convex world piece) of every enabled, valid hull the light does not ignore that can
    reach its quad (the others cannot shadow anything it lights)."""
    index = index or SceneIndex(scene)
    return [(i, piece) for i in index.casters(light) for piece in scene.hulls[i].world_pieces()]


def light_contribution(scene, light, world, textures, index=None):
    """Added colour (n, 3) of one light at world points (n, 2), or None when it adds nothing."""
    index = index or SceneIndex(scene)
    if not light.enabled or index.centre_blocked(light):
        return None
    value = light_value(light, world, textures)
    lit = np.flatnonzero(value.max(axis=1) > 0)
    if lit.size == 0:
        return None
    if scene.normal_map and light.height > 0:
        value[lit] *= normal_factor(light, world[lit], textures[scene.normal_map])[:, None]
    if light.casts_shadows:
        value[lit] *= visibility(scene, light, world[lit], index)[:, None]
    return value


def visibility(scene: Scene2D, light: Light, points: np.ndarray, index=None) -> np.ndarray:
    """Visible fraction of the light's disc from each point (n,), with the hull semantics applied."""
    index = index or SceneIndex(scene)
    pieces = blockers(scene, light, index)
    touching = index.disc_touched(light)
    out = np.empty(len(points))
    for start in range(0, len(points), CHUNK):
        out[start:start + CHUNK] = _visibility_block(light, pieces, points[start:start + CHUNK], touching)
    return out


def _visibility_block(light, pieces, points, touching):
    centre = np.asarray(light.position, dtype=np.float64)
    rel = points - centre  # light at the origin: keeps precision for coordinates near 1e6
    rel_pieces = [(h, p - centre) for h, p in pieces]
    owner = np.full(len(rel), -1)
    for h, piece in rel_pieces:
        owner[inside_convex(rel, piece)] = h
    inside = owner >= 0
    vis = np.ones(len(rel))
    if light.shadow_type == "solid":
        vis[inside] = 0.0
    todo = ~inside if light.shadow_type != "occluded" else np.ones(len(rel), bool)
    r = light.radius
    for hull_id in np.unique(owner[todo]):
        group = todo & (owner == hull_id)  # occluded hulls ignore themselves: group by containing hull
        active = [p for h, p in rel_pieces if h != hull_id or hull_id < 0]
        if touching:  # a piece meets the disc: the disc clipped by the pieces' shadows
            vis[group] = 1.0 - hidden_share(rel[group], active, r)
        else:
            vis[group] = _exact(rel[group], active, r)
    return vis


def hidden_area(lo, hi):
    """Share of the unit disc between offsets lo <= hi (in radii): (G(hi) - G(lo)) / (pi r^2)."""
    def g(x):
        x = np.clip(x, -1.0, 1.0)
        return (x * np.sqrt(1.0 - x * x) + np.arcsin(x)) / math.pi
    return g(hi) - g(lo)


def _exact(points, pieces, r):
    """Visible fraction where no piece touches the disc (or r = 0): fused angular intervals."""
    n = len(points)
    if not pieces or n == 0:
        return np.ones(n)
    dist = np.hypot(points[:, 0], points[:, 1])
    if r == 0:
        blocked = np.zeros(n, bool)
        for piece in pieces:
            blocked |= _ray_enters_before(points, piece, -points / np.maximum(dist, 1e-300)[:, None], dist)
        return np.where(blocked, 0.0, 1.0)
    enclosed = np.zeros(n, bool)
    for piece in pieces:
        enclosed |= inside_convex(points, piece)
    outside = (dist > r) & ~enclosed  # inside the disc all of it is seen: no piece touches the disc
    p, d = points[outside], dist[outside]
    to_centre = -p / d[:, None]
    beta = np.arcsin(r / d)
    los, his = [], []
    for piece in pieces:
        lo, hi = _clip_to_cone(*_angular_interval(p, to_centre, piece), beta)
        mid = 0.5 * (lo + hi)
        c, s = np.cos(mid), np.sin(mid)
        ray = np.stack([to_centre[:, 0] * c - to_centre[:, 1] * s, to_centre[:, 0] * s + to_centre[:, 1] * c], axis=1)
        t_disc = d * c - np.sqrt(np.maximum(r * r - (d * s) ** 2, 0.0))
        front = (lo < hi) & _ray_enters_before(p, piece, ray, t_disc)
        los.append(np.where(front, d * np.sin(lo) / r, 0.0))
        his.append(np.where(front, d * np.sin(hi) / r, 0.0))
    vis = np.where(enclosed, 0.0, 1.0)
    vis[outside] = 1.0 - union_measure(np.stack(los, axis=1), np.stack(his, axis=1))
    return vis


def union_measure(lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """Hidden share of the disc covered by the union of intervals (n, k) in radii; empty ones lo == hi."""
    order = np.argsort(lo, axis=1)
    lo, hi = np.take_along_axis(lo, order, 1), np.take_along_axis(hi, order, 1)
    reach = np.maximum.accumulate(hi, axis=1)
    start = np.maximum(lo, np.concatenate([np.full((len(lo), 1), -1.0), reach[:, :-1]], axis=1))
    return np.clip(np.sum(np.maximum(hidden_area(start, np.maximum(hi, start)), 0.0), axis=1), 0.0, 1.0)


def _angular_interval(points, axis, piece):
    """The angles (relative to `axis`) between which a convex piece is seen from each point."""
    rel = piece[None, :, :] - points[:, None, :]
    centroid = rel.mean(axis=1)
    ref = np.arctan2(axis[:, 0] * centroid[:, 1] - axis[:, 1] * centroid[:, 0], np.einsum("pd,pd->p", axis, centroid))
    cx, cy = centroid[:, 0:1], centroid[:, 1:2]
    ang = np.arctan2(cx * rel[..., 1] - cy * rel[..., 0], cx * rel[..., 0] + cy * rel[..., 1])
    lo, hi = ref + ang.min(axis=1), ref + ang.max(axis=1)
    return lo, hi


def _clip_to_cone(lo, hi, beta):
    """The interval is shorter than pi: shift it by a turn if that brings it onto the disc's cone."""
    shift = np.where(lo > beta, -2 * math.pi, np.where(hi < -beta, 2 * math.pi, 0.0))
    return np.maximum(lo + shift, -beta), np.minimum(hi + shift, beta)


def _ray_enters_before(points, piece, direction, limit):
    """Does the ray from each point along `direction` enter the convex piece before distance `limit`?"""
    a, e = piece, np.roll(piece, -1, axis=0) - piece
    normal = np.stack([e[:, 1], -e[:, 0]], axis=1)  # outward for counter-clockwise pieces
    denom = direction @ normal.T                       # (n, k)
    num = np.einsum("pkd,kd->pk", a[None] - points[:, None, :], normal)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = num / denom
    enter = np.max(np.where(denom < 0, t, -np.inf), axis=1)
    leave = np.min(np.where(denom > 0, t, np.inf), axis=1)
    parallel_out = np.any((denom == 0) & (num < 0), axis=1)
    enter = np.maximum(enter, 0.0)
    return (enter <= leave) & ~parallel_out & (enter < limit)


def sampled(points, pieces, r, samples):
    """Visible fraction of the disc (radius r at the origin) from points relative to its centre, by
    stratified samples (samples x samples strata, area-uniform) and the pieces' segment tests: it
    converges as `samples` grows, and checks the closed form used where a piece touches the disc."""
    rng = np.random.default_rng(12345)
    i, j = np.meshgrid(np.arange(samples), np.arange(samples), indexing="ij")
    rad = r * np.sqrt((i + rng.random(i.shape)) / samples)
    ang = 2 * math.pi * (j + rng.random(j.shape)) / samples
    q = np.stack([rad * np.cos(ang), rad * np.sin(ang)], axis=-1).reshape(-1, 2)
    vis = np.empty(len(points))
    step = max(1, 2_000_000 // (len(q) * 8))
    for start in range(0, len(points), step):
        p = points[start:start + step]
        blocked = np.zeros((len(p), len(q)), bool)
        for piece in pieces:
            blocked |= _segments_hit(p, q, piece)
        vis[start:start + step] = 1.0 - blocked.mean(axis=1)
    return vis


def _segments_hit(p, q, piece):
    """Do segments from each point p (n) to each sample q (m) pass through the convex piece? (n, m)"""
    a, e = piece, np.roll(piece, -1, axis=0) - piece
    normal = np.stack([e[:, 1], -e[:, 0]], axis=1)
    d = q[None, :, :] - p[:, None, :]                            # (n, m, 2)
    denom = np.einsum("nmd,kd->nmk", d, normal)
    num = (a @ normal.T).diagonal()[None, None, :] - (p @ normal.T)[:, None, :]
    with np.errstate(divide="ignore", invalid="ignore"):
        t = num / denom
    enter = np.maximum(np.max(np.where(denom < 0, t, -np.inf), axis=2), 0.0)
    leave = np.minimum(np.min(np.where(denom > 0, t, np.inf), axis=2), 1.0)
    outside_parallel = np.any((denom == 0) & (num < 0), axis=2)
    return (enter < leave) & ~outside_parallel
