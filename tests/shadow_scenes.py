"""Scenes for the shadow volume tests, built inline with numpy, and the CPU's answer per pixel: a ray through
each pixel's centre, the nearest triangle it hits, and whether that point sees the light."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from app.model.camera3d import OrbitCamera
from app.model.transforms import look_at

# A box's 6 faces as quads of corner indices (corner = 4 x + 2 y + z), counter-clockwise seen from outside.
_BOX_QUADS = ((0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3))


def box(lo, hi) -> tuple[np.ndarray, np.ndarray]:
    """A closed box: 8 shared corners, 12 triangles."""
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    bits = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)], float)
    triangles = [t for a, b, c, d in _BOX_QUADS for t in ((a, b, c), (a, c, d))]
    return lo + bits * (hi - lo), np.array(triangles, np.int32)


def ground(half: float = 4.0, y: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """An open square facing +y: the receiver."""
    positions = np.array([[-half, y, -half], [-half, y, half], [half, y, half], [half, y, -half]], float)
    return positions, np.array([[0, 1, 2], [0, 2, 3]], np.int32)


def view_proj(eye, target, size, near=0.1, far=50.0, fov=50.0) -> np.ndarray:
    """The app's perspective (OrbitCamera's projection) times a view from `eye` towards the point `target`."""
    eye, target = np.asarray(eye, float), np.asarray(target, float)
    view = look_at(eye, (target - eye) / np.linalg.norm(target - eye), (0.0, 1.0, 0.0))
    return OrbitCamera(fov=fov).projection(size[0] / size[1], near, far) @ view


def soup(meshes) -> np.ndarray:
    """Triangles of all meshes as float32 (3 n, 4) vertices with w = 1, for the depth pass."""
    return np.concatenate([np.c_[p[t].reshape(-1, 3), np.ones(3 * len(t))] for p, t in meshes]).astype(np.float32)


def _hits(origins, directions, corners):
    """Moller-Trumbore, both faces: t (rays, triangles) with inf where a ray misses."""
    a, e1, e2 = corners[:, 0], corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]
    p = np.cross(directions[:, None], e2[None])
    det = np.einsum("rtk,tk->rt", p, e1)
    with np.errstate(divide="ignore", invalid="ignore"):
        inv = 1.0 / det
        s = origins[:, None] - a[None]
        u = np.einsum("rtk,rtk->rt", s, p) * inv
        q = np.cross(s, e1[None])
        v = np.einsum("rtk,rk->rt", q, directions) * inv
        t = np.einsum("rtk,tk->rt", q, e2) * inv
        ok = (np.abs(det) > 1e-12) & (u >= 0) & (v >= 0) & (u + v <= 1)
    return np.where(ok, t, np.inf)


def pixel_rays(view_proj_matrix, size):
    """Each pixel centre's ray from the near plane to the far plane (top row first): origins, directions."""
    w, h = size
    x = (np.arange(w) + 0.5) / w * 2 - 1
    y = 1 - (np.arange(h) + 0.5) / h * 2
    ndc_x, ndc_y = np.meshgrid(x, y)
    inv = np.linalg.inv(view_proj_matrix)
    ends = []
    for z in (-1.0, 1.0):
        clip = np.stack([ndc_x.ravel(), ndc_y.ravel(), np.full(w * h, z), np.ones(w * h)], axis=1) @ inv.T
        ends.append(clip[:, :3] / clip[:, 3:])
    return ends[0], ends[1] - ends[0]


def in_shadow(points, casters, light, normals=None):
    """Points that do not see the light: a caster triangle in between, or (with normals, nan for none) their own
    surface not facing it."""
    corners = np.concatenate([p[t] for p, t in casters])
    light = np.asarray(light, float)
    to_light = light[:3] - light[3] * points  # a point light: up to it (t < 1); a directional one: forever
    t = _hits(points, to_light, corners)
    blocked = ((t > 1e-6) & (t < (1.0 if light[3] else np.inf))).any(axis=1)
    if normals is not None:
        blocked |= np.einsum("ij,ij->i", normals, to_light) <= 0  # nan compares False: receivers
    return blocked


@dataclass
class CpuShadow:
    covered: np.ndarray   # bool (h, w), top row first: the pixel's ray hits a triangle
    shadow: np.ndarray    # ... and that point does not see the light
    edge_on: np.ndarray   # ... and it lies on a caster face edge-on to the light: N.L = 0, lit or not alike


def cpu_shadow(size, view_proj_matrix, receivers, casters, light) -> CpuShadow:
    """Casters are closed meshes whose faces turned from the light are in shadow; receivers only receive."""
    origins, directions = pixel_rays(view_proj_matrix, size)
    meshes = [*receivers, *casters]
    corners = np.concatenate([p[t] for p, t in meshes])
    is_caster = np.concatenate([np.full(len(t), i >= len(receivers)) for i, (_, t) in enumerate(meshes)])
    t = _hits(origins, directions, corners)
    t[(t < 0) | (t > 1)] = np.inf
    nearest, hit = t.argmin(axis=1), t.min(axis=1)
    covered = np.isfinite(hit)
    points = origins[covered] + hit[covered, None] * directions[covered]
    tri = corners[nearest[covered]]
    normals = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    normals[~is_caster[nearest[covered]]] = np.nan
    light = np.asarray(light, float)
    shadow, edge_on = np.zeros(len(origins), bool), np.zeros(len(origins), bool)
    shadow[covered] = in_shadow(points, casters, light, normals)
    to_light = light[:3] - light[3] * points
    lengths = np.linalg.norm(normals, axis=1) * np.linalg.norm(to_light, axis=1)
    cosine = np.einsum("ij,ij->i", normals, to_light) / lengths
    edge_on[covered] = np.abs(cosine) < 1e-9  # nan (receivers) compares False
    h = size[1]
    return CpuShadow(covered.reshape(h, -1), shadow.reshape(h, -1), edge_on.reshape(h, -1))
