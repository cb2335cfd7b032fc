"""Float64 CPU reference of the 3D lights workspace (seeds 004 and 002): an exact ray tracer, numpy only.

One primary ray per pixel centre, from the camera's own projection (OrbitCamera.ray's unprojection, near and
far planes included), so a GL rasterisation of the same camera covers the same pixels; then, per light, one
shadow ray from each surface point. The light formulas are app.model.lights3d.scene's (its docstring writes them out).

Every hit is an exact Moller-Trumbore test in float64, but no ray meets every triangle: rays and triangles are
binned into cells so that a ray can only hit the triangles binned in its own cell (conservative bounds, so the
result is what testing every pair would give):
- primary rays: one cell per pixel; a triangle goes to the pixels its projected bounding box covers, after
  clipping it at the near plane (the projection of a triangle in front of the eye is the triangle of its
  projected corners);
- shadow rays of point and spot lights: direction cells around the light, an n x n grid on each face of a
  cube map; a triangle goes to the cells its projection covers on each face it reaches (clipped at the face's
  depth 0, where the projection runs off to infinity);
- shadow rays of a directional light: a 2D grid across the light's direction; a shadow ray projects to a
  single point of it, a triangle to its bounding box.
Meant for small images (~160 x 90) of scenes up to ~100k triangles.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Iterator

import numpy as np

from app.model.lights3d import scene as lm
from app.model.lights3d.facing import faces_light, homogeneous
from app.model.camera3d import OrbitCamera
from app.model.lights3d.scene import Scene3D

CHUNK = 1 << 17          # ray-triangle pairs tested at once
BARY_TOL = 1e-10         # barycentric slack: a ray through a shared edge hits at least one of its triangles
PARALLEL = 1e-12         # |cos| between a ray and a triangle's plane below which the ray misses it (grazes)
SELF_EPS = 1e-7          # a shadow ray starts this far (x the scene's scale) off its surface point
PIXEL_MARGIN = 1e-6      # pixels added around a triangle's projected box
CELL_MARGIN = 1e-6       # cells added around a triangle's projected box on a cube face or grid


@dataclass(frozen=True)
class Result:
    rgb: np.ndarray          # (H, W, 3) float64 0..1, row 0 at the top
    object_id: np.ndarray    # (H, W) int32 index into scene.objects, -1 for the background
    position: np.ndarray     # (H, W, 3) world position of the surface point (NaN on the background)
    normal: np.ndarray       # (H, W, 3) unit shading normal (0 on the background)
    facing: np.ndarray       # (lights, H, W) bool: the surface's triangle faces the light (app/model/lights3d/
    #                          facing.py: its own plane, a light in it behind it), inside its range/cone
    visible: np.ndarray      # (lights, H, W) bool: the segment to the light (ray to a directional) hits no caster
    #                          (whatever the light's shadow method: with "none" the colour just ignores it)
    rays: int                # rays traced, primary and shadow
    pairs: int               # ray-triangle pairs tested: the work done, against rays x triangles


@dataclass(frozen=True)
class Triangles:
    """Every object's triangles in world space, one array each, in the scene's object order."""
    v0: np.ndarray           # (T, 3) first corner
    e1: np.ndarray           # (T, 3) second corner - first
    e2: np.ndarray           # (T, 3) third corner - first
    normals: np.ndarray      # (T, 3, 3) shading normals at the corners
    geometric: np.ndarray    # (T, 3) unit geometric normals
    third: np.ndarray        # (T, 3) third corner, as given (the facing rule's point of the plane)
    twice_area: np.ndarray   # (T,) |e1 x e2|
    owner: np.ndarray        # (T,) int32 object index
    casts: np.ndarray        # (T,) bool: part of a closed mesh (a shadow caster)

    @staticmethod
    def of(scene: Scene3D) -> Triangles:
        meshes = [o.mesh() for o in scene.objects]
        corners = np.concatenate([m.corners() for m in meshes]) if meshes else np.zeros((0, 3, 3))
        e1, e2 = corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]
        n = np.cross(e1, e2)
        area = np.linalg.norm(n, axis=1)
        counts = [len(m.triangles) for m in meshes]
        return Triangles(corners[:, 0], e1, e2,
                         np.concatenate([m.normals for m in meshes]) if meshes else np.zeros((0, 3, 3)),
                         n / np.maximum(area, 1e-300)[:, None], corners[:, 2], area,
                         np.repeat(np.arange(len(meshes), dtype=np.int32), counts),
                         np.repeat([m.closed for m in meshes], counts).astype(bool))

    def corners(self) -> np.ndarray:
        return np.stack([self.v0, self.v0 + self.e1, self.v0 + self.e2], axis=1)


# ---- ray-triangle pairs -----------------------------------------------------------------------------------


def _dot(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return a[:, 0] * b[:, 0] + a[:, 1] * b[:, 1] + a[:, 2] * b[:, 2]


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.stack([a[:, 1] * b[:, 2] - a[:, 2] * b[:, 1], a[:, 2] * b[:, 0] - a[:, 0] * b[:, 2],
                     a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]], axis=1)


def intersect(tris: Triangles, tri: np.ndarray, origin: np.ndarray, direction: np.ndarray
              ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Moller-Trumbore for pairs: (hit, t, u, v) of ray k (origin[k] + t direction[k]) against triangle
    tri[k]; u and v are the barycentric weights of the second and third corners. Inclusive edges (a ray
    through a shared edge or vertex hits), and a ray in the triangle's plane misses it."""
    e1, e2 = tris.e1[tri], tris.e2[tri]
    p = _cross(direction, e2)
    det = _dot(e1, p)
    ok = np.abs(det) > PARALLEL * tris.twice_area[tri] * np.linalg.norm(direction, axis=1)
    inv = 1.0 / np.where(ok, det, 1.0)
    s = origin - tris.v0[tri]
    u = _dot(s, p) * inv
    q = _cross(s, e1)
    v = _dot(direction, q) * inv
    t = _dot(e2, q) * inv
    return ok & (u >= -BARY_TOL) & (v >= -BARY_TOL) & (u + v <= 1.0 + BARY_TOL), t, u, v


def _rect_cells(x0, x1, y0, y1, nx: int, base: int) -> tuple[np.ndarray, np.ndarray]:
    """(cell, triangle) for every cell of each triangle's inclusive rectangle x0..x1, y0..y1 (empty where
    x0 > x1 or y0 > y1) in a grid nx wide, its cells numbered from base."""
    w, h = np.maximum(x1 - x0 + 1, 0), np.maximum(y1 - y0 + 1, 0)
    counts = w * h
    tri = np.repeat(np.arange(len(counts)), counts)
    k = np.arange(int(counts.sum())) - np.repeat(np.cumsum(counts) - counts, counts)
    cw = w[tri]
    return base + (y0[tri] + k // cw) * nx + x0[tri] + k % cw, tri


def _pairs(cells: np.ndarray, cell_tris: np.ndarray, ray_cells: np.ndarray, n_cells: int
           ) -> Iterator[tuple[np.ndarray, np.ndarray]]:
    """(ray, triangle) candidate pairs, CHUNK at a time, each ray's pairs in one chunk; ray_cells -1: none."""
    order = np.argsort(cells, kind="stable")
    sorted_tris = cell_tris[order]
    per_cell = np.bincount(cells, minlength=n_cells)
    first = np.cumsum(per_cell) - per_cell
    counts = np.where(ray_cells >= 0, per_cell[np.maximum(ray_cells, 0)], 0)
    starts = first[np.maximum(ray_cells, 0)]
    ends = np.cumsum(counts)
    cuts = np.searchsorted(ends, np.arange(CHUNK, int(ends[-1]) if len(ends) else 0, CHUNK), side="right")
    for r0, r1 in zip(np.r_[0, cuts], np.r_[cuts, len(counts)]):
        c = counts[r0:r1]
        total = int(c.sum())
        if total == 0:
            continue
        ray = np.repeat(np.arange(r0, r1), c)
        offset = np.arange(total) - np.repeat(np.cumsum(c) - c, c)
        yield ray, sorted_tris[np.repeat(starts[r0:r1], c) + offset]


# ---- binning ------------------------------------------------------------------------------------------------


def _pixel_rects(tris: Triangles, clip_from_world: np.ndarray, near: float, width: int, height: int):
    """Each triangle's pixel rectangle (x0, x1, y0, y1): the pixels whose centres its projection, clipped at
    the near plane (clip w >= near), may cover."""
    corners = tris.corners()
    clip = np.einsum("ij,tkj->tki", clip_from_world[:, :3], corners) + clip_from_world[:, 3]
    w = clip[..., 3] - near
    points, valid = [clip], [w >= 0]
    for i, j in ((0, 1), (1, 2), (2, 0)):  # where an edge crosses the near plane
        s = w[:, i] / np.where(w[:, i] == w[:, j], 1.0, w[:, i] - w[:, j])
        points.append((clip[:, i] + s[:, None] * (clip[:, j] - clip[:, i]))[:, None])
        valid.append((w[:, i] * w[:, j] < 0)[:, None])
    p, ok = np.concatenate(points, axis=1), np.concatenate(valid, axis=1)
    pw = np.where(ok, p[..., 3], 1.0)
    x = (p[..., 0] / pw + 1.0) * width / 2
    y = (1.0 - p[..., 1] / pw) * height / 2
    lo_x, hi_x = np.where(ok, x, np.inf).min(1), np.where(ok, x, -np.inf).max(1)
    lo_y, hi_y = np.where(ok, y, np.inf).min(1), np.where(ok, y, -np.inf).max(1)
    # pixel i's centre is i + 0.5
    x0 = np.ceil(np.clip(lo_x, -2, width + 2) - 0.5 - PIXEL_MARGIN)
    x1 = np.floor(np.clip(hi_x, -2, width + 2) - 0.5 + PIXEL_MARGIN)
    y0 = np.ceil(np.clip(lo_y, -2, height + 2) - 0.5 - PIXEL_MARGIN)
    y1 = np.floor(np.clip(hi_y, -2, height + 2) - 0.5 + PIXEL_MARGIN)
    return (np.maximum(x0, 0).astype(np.int64), np.minimum(x1, width - 1).astype(np.int64),
            np.maximum(y0, 0).astype(np.int64), np.minimum(y1, height - 1).astype(np.int64))


def _cells(lo, hi, n: int):
    """Inclusive cell range of each interval lo..hi of -1..1 split into n cells (empty: first > last)."""
    first = np.floor((np.clip(lo, -2, 2) + 1) / 2 * n - CELL_MARGIN)
    last = np.floor((np.clip(hi, -2, 2) + 1) / 2 * n + CELL_MARGIN)
    return np.maximum(first, 0).astype(np.int64), np.minimum(last, n - 1).astype(np.int64)


def _face_axes(face: int) -> tuple[int, float, int, int]:
    """Cube face 0..5 = +x, -x, +y, -y, +z, -z: (depth axis, its sign, u axis, v axis)."""
    a = face // 2
    return a, (1.0 if face % 2 == 0 else -1.0), (a + 1) % 3, (a + 2) % 3


def _cube_cells(d: np.ndarray, n: int) -> np.ndarray:
    """The cube-map cell of each direction d (R, 3) from the light (none may be 0)."""
    a = np.argmax(np.abs(d), axis=1)
    rows = np.arange(len(d))
    depth = np.abs(d[rows, a])
    face = 2 * a + (d[rows, a] < 0)
    u, v = d[rows, (a + 1) % 3] / depth, d[rows, (a + 2) % 3] / depth
    i = np.minimum(np.floor((u + 1) / 2 * n), n - 1).astype(np.int64)
    j = np.minimum(np.floor((v + 1) / 2 * n), n - 1).astype(np.int64)
    return face * n * n + j * n + i


def _cube_bins(rel: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray]:
    """(cell, triangle) for the cube-map cells of the triangles rel (T, 3 corners, 3) around the light.

    On a face, the part of a triangle at depth > 0 projects (u, v) = (x_u, x_v) / depth: the bounding box of
    its corners in front, widened to infinity towards the (x_u, x_v) of each point where it meets depth 0
    (a corner there, or an edge crossing it). A triangle reaching the face only at depth ~0 gets the whole
    face if it passes within the tolerance of the light, else none."""
    scale = np.abs(rel).max(axis=(1, 2))
    tol = 1e-9 * scale
    cells, owners = [], []
    for face in range(6):
        a, sign, bu, bv = _face_axes(face)
        depth, xu, xv = sign * rel[..., a], rel[..., bu], rel[..., bv]
        front = depth > tol[:, None]
        safe = np.where(front, depth, 1.0)
        u, v = xu / safe, xv / safe
        lo_u, hi_u = np.where(front, u, np.inf).min(1), np.where(front, u, -np.inf).max(1)
        lo_v, hi_v = np.where(front, v, np.inf).min(1), np.where(front, v, -np.inf).max(1)
        # points at depth 0: corners there, and edges from the front to behind
        edge_points = [(np.abs(depth) <= tol[:, None], xu, xv)]
        for i, j in ((0, 1), (1, 2), (2, 0)):
            crosses = (front[:, i] & (depth[:, j] < -tol)) | (front[:, j] & (depth[:, i] < -tol))
            s = depth[:, i] / np.where(crosses, depth[:, i] - depth[:, j], 1.0)
            edge_points.append((crosses[:, None], (xu[:, i] + s * (xu[:, j] - xu[:, i]))[:, None],
                                (xv[:, i] + s * (xv[:, j] - xv[:, i]))[:, None]))
        at_zero = np.zeros(len(rel), bool)
        for where, pu, pv in edge_points:
            at_zero |= where.any(1)
            lo_u = np.where((where & (pu < tol[:, None])).any(1), -np.inf, lo_u)
            hi_u = np.where((where & (pu > -tol[:, None])).any(1), np.inf, hi_u)
            lo_v = np.where((where & (pv < tol[:, None])).any(1), -np.inf, lo_v)
            hi_v = np.where((where & (pv > -tol[:, None])).any(1), np.inf, hi_v)
        # No corner in front: a ray of this face (|x_u|, |x_v| <= depth) can meet it only within tol of the light.
        near = ((xu.min(1) <= tol) & (xu.max(1) >= -tol) & (xv.min(1) <= tol) & (xv.max(1) >= -tol))
        whole = at_zero & ~front.any(1) & near
        lo_u, lo_v = np.where(whole, -np.inf, lo_u), np.where(whole, -np.inf, lo_v)
        hi_u, hi_v = np.where(whole, np.inf, hi_u), np.where(whole, np.inf, hi_v)
        reached = front.any(1) | whole
        x0, x1 = _cells(lo_u, hi_u, n)
        y0, y1 = _cells(lo_v, hi_v, n)
        x1, y1 = np.where(reached, x1, -1), np.where(reached, y1, -1)
        c, t = _rect_cells(x0, x1, y0, y1, n, face * n * n)
        cells.append(c)
        owners.append(t)
    return np.concatenate(cells), np.concatenate(owners)


def _cube_size(triangles: int) -> int:
    """Cells along a cube face's side: finer for more triangles, so each cell holds a few."""
    return int(np.clip(2 * math.sqrt(triangles), 8, 256))


# ---- rendering ----------------------------------------------------------------------------------------------


def primary_rays(camera: OrbitCamera, width: int, height: int) -> tuple[np.ndarray, np.ndarray]:
    """(origin (3,), unit directions (H*W, 3)) through the pixel centres, row 0 at the top: OrbitCamera.ray's
    unprojection, for every pixel at once."""
    inv = np.linalg.inv(camera.clip_from_world((width, height)))
    py, px = np.mgrid[0:height, 0:width] + 0.5
    ndc = np.stack([2 * px / width - 1, 1 - 2 * py / height, np.ones_like(px), np.ones_like(px)], -1)
    far = ndc.reshape(-1, 4) @ inv.T
    origin = camera.position()
    d = far[:, :3] / far[:, 3:] - origin
    return origin, d / np.linalg.norm(d, axis=1, keepdims=True)


def _primary(tris: Triangles, camera: OrbitCamera, width: int, height: int):
    """(each pixel's triangle or -1, its (t, u, v), the eye, pairs tested): the nearest hit within the clip
    planes."""
    origin, dirs = primary_rays(camera, width, height)
    forward = -camera.view()[2, :3]
    clip_from_world = camera.clip_from_world((width, height))
    x0, x1, y0, y1 = _pixel_rects(tris, clip_from_world, camera.NEAR, width, height)
    cells, cell_tris = _rect_cells(x0, x1, y0, y1, width, 0)
    count = width * height
    best_tri, best = np.full(count, -1), np.zeros((count, 3))
    pairs = 0
    for ray, tri in _pairs(cells, cell_tris, np.arange(count), count):
        pairs += len(ray)
        hit, t, u, v = intersect(tris, tri, np.broadcast_to(origin, (len(ray), 3)), dirs[ray])
        depth = t * (dirs[ray] @ forward)
        hit &= (depth >= camera.NEAR) & (depth <= camera.FAR)  # what GL's clipping keeps
        ray, tri, t, u, v = ray[hit], tri[hit], t[hit], u[hit], v[hit]
        order = np.lexsort((tri, t, ray))  # the nearest hit of each ray (ties: the first triangle)
        _, first = np.unique(ray[order], return_index=True)
        pick = order[first]
        best_tri[ray[pick]] = tri[pick]
        best[ray[pick]] = np.stack([t[pick], u[pick], v[pick]], 1)
    return best_tri, best, origin, pairs


def _sun_bins(corners: np.ndarray, points: np.ndarray, toward: np.ndarray, scale: float):
    """(cells, their triangles, each point's cell or -1, cell count) on a grid across a directional light: a
    ray towards the light projects to one point, a triangle to its box; the grid spans the casters."""
    e1 = np.cross(toward, np.eye(3)[np.argmin(np.abs(toward))])
    e1 /= np.linalg.norm(e1)
    basis = np.stack([e1, np.cross(toward, e1)], 1)
    flat, at = corners @ basis, points @ basis
    lo, hi = flat.reshape(-1, 2).min(0), flat.reshape(-1, 2).max(0)
    n = _cube_size(len(corners))
    cell = np.maximum(hi - lo, 1e-9 * scale) / n
    x0, y0 = np.floor((flat.min(1) - lo) / cell - CELL_MARGIN).astype(np.int64).T
    x1, y1 = np.minimum(np.floor((flat.max(1) - lo) / cell + CELL_MARGIN), n - 1).astype(np.int64).T
    cells, cell_tris = _rect_cells(np.maximum(x0, 0), x1, np.maximum(y0, 0), y1, n, 0)
    ij = np.minimum(np.floor((at - lo) / cell), n - 1).astype(np.int64)
    inside = ((at >= lo) & (at <= hi)).all(1)  # outside, a ray passes every caster by
    return cells, cell_tris, np.where(inside, ij[:, 1] * n + ij[:, 0], -1), n * n


def _cube_map_bins(corners: np.ndarray, points: np.ndarray, position: np.ndarray):
    """(cells, their triangles, each point's cell or -1, cell count) on a cube map around a point or spot
    light: a segment from the light has one direction, a triangle covers the cells of its projection."""
    n = _cube_size(len(corners))
    cells, cell_tris = _cube_bins(corners - position, n)
    away = points - position
    at_light = (away == 0).all(1)  # a zero-length segment: nothing in between
    ray_cells = np.where(at_light, -1, _cube_cells(np.where(at_light[:, None], 1.0, away), n))
    return cells, cell_tris, ray_cells, 6 * n * n


def _shadow_rays(tris: Triangles, light: lm.Light3D, points: np.ndarray, own: np.ndarray, scale: float
                 ) -> tuple[np.ndarray, int]:
    """(blocked (R,), pairs tested): whether the segment from each point to the light (the ray towards a
    directional light) hits a caster's triangle other than the point's own, SELF_EPS x scale off both ends."""
    blocked = np.zeros(len(points), bool)
    casters = np.flatnonzero(tris.casts)
    if len(casters) == 0 or len(points) == 0:
        return blocked, 0
    corners = tris.corners()[casters]
    if light.kind == "directional":
        toward = -np.asarray(light.direction)
        cells, cell_tris, ray_cells, n_cells = _sun_bins(corners, points, toward, scale)
        directions = np.broadcast_to(toward, points.shape)
        t_lo, t_hi = np.full(len(points), SELF_EPS * scale), np.full(len(points), np.inf)
    else:
        cells, cell_tris, ray_cells, n_cells = _cube_map_bins(corners, points, np.asarray(light.position))
        directions = np.asarray(light.position) - points  # t = 1 at the light
        t_lo = SELF_EPS * scale / np.maximum(np.linalg.norm(directions, axis=1), 1e-300)
        t_hi = 1.0 - t_lo
    pairs = 0
    for ray, k in _pairs(cells, cell_tris, ray_cells, n_cells):
        tri = casters[k]
        other = tri != own[ray]  # a point never shadows itself on its own triangle
        ray, tri = ray[other], tri[other]
        pairs += len(ray)
        hit, t, _, _ = intersect(tris, tri, points[ray], directions[ray])
        blocked[ray[hit & (t > t_lo[ray]) & (t < t_hi[ray])]] = True
    return blocked, pairs


def world_scale(tris: Triangles, eye: np.ndarray, lights) -> float:
    """The largest coordinate in play (at least 1): shadow rays start SELF_EPS times this off their surface."""
    return max(1.0, float(np.abs(tris.v0).max(initial=0.0)), float(np.abs(eye).max()),
               *(abs(c) for light in lights for c in light.position))


def render(scene: Scene3D, camera: OrbitCamera, size: tuple[int, int]) -> Result:
    """The scene seen by `camera` at size (width, height)."""
    width, height = size
    tris = Triangles.of(scene)
    tri, tuv, origin, pairs = _primary(tris, camera, width, height)
    hit = tri >= 0
    k = tri[hit]
    u, v = tuv[hit, 1:2], tuv[hit, 2:3]
    points = tris.v0[k] + u * tris.e1[k] + v * tris.e2[k]  # on the triangle's plane, for the shadow rays
    shading = (1 - u - v) * tris.normals[k, 0] + u * tris.normals[k, 1] + v * tris.normals[k, 2]
    shading /= np.linalg.norm(shading, axis=1, keepdims=True)
    scale = world_scale(tris, origin, scene.lights)
    count, lights = width * height, len(scene.lights)
    facing, visible = np.zeros((lights, count), bool), np.zeros((lights, count), bool)
    rays = count
    for i, light in enumerate(scene.lights):
        faces = faces_light(tris.geometric, tris.third, homogeneous(light))
        facing[i, hit] = faces[k] & lm.in_reach(light, points)
        blocked, tested = _shadow_rays(tris, light, points, k, scale)
        visible[i, hit] = ~blocked
        rays += len(points)
        pairs += tested
    lit = np.ones((lights, len(points)), bool)  # a light without shadows: the formulas alone
    for i, light in enumerate(scene.lights):
        if light.shadow != "none":
            lit[i] = facing[i, hit] & visible[i, hit]
    albedo = np.array([o.colour for o in scene.objects]).reshape(-1, 3)[tris.owner[k]]
    rgb = np.tile(np.asarray(lm.BACKGROUND), (count, 1))
    rgb[hit] = lm.shade(scene, albedo, points, shading, origin, lit)
    object_id = np.full(count, -1, np.int32)
    object_id[hit] = tris.owner[k]
    position = np.full((count, 3), np.nan)
    position[hit] = points
    normal = np.zeros((count, 3))
    normal[hit] = shading
    return Result(rgb.reshape(height, width, 3), object_id.reshape(height, width),
                  position.reshape(height, width, 3), normal.reshape(height, width, 3),
                  facing.reshape(lights, height, width), visible.reshape(lights, height, width), rays, pairs)
