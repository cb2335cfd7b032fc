"""Shadow volumes as vertex arrays ready to upload (numpy, vectorised): the seed's one-pass volume of every caster
triangle, and Everitt & Kilgard's silhouette volume, capped for z-fail.

A light is a homogeneous vec4 l: w = 1 for a point or spot light at l.xyz, w = 0 for a directional light shining
from direction l.xyz. A mesh vertex p goes to infinity, away from the light, as the w = 0 vertex
(l.w p - l.xyz, 0): p - l for a point light, -l.xyz for a directional one. A perspective projection maps it to a
point beyond the far plane, which depth clamping draws at depth 1 instead of clipping.

Meshes are world-space `positions` (V, 3) and `triangles` (T, 3), counter-clockwise seen from outside. A
triangle faces the light when the light is on its outer side (a directional light: its normal points at it)."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from app.model.lights3d.mesh import Adjacency, edge_adjacency


@dataclass(frozen=True)
class VolumeGeometry:
    vertices: np.ndarray  # float32 (3 n, 4): n triangles, three vertices each, w = 0 at infinity
    extruded_edges: int   # edges pushed to infinity: 3 per caster triangle (onepass), the silhouette's (else)

    @property
    def triangles(self) -> int:
        return len(self.vertices) // 3


def light_vector(light) -> np.ndarray:
    """The light as float64 (4,), or ValueError."""
    light = np.asarray(light, np.float64)
    if light.shape != (4,) or not np.isfinite(light).all() or light[3] not in (0.0, 1.0):
        raise ValueError(f"a light is a finite vec4 with w = 1 (point) or w = 0 (directional), got {light}")
    if light[3] == 0.0 and not light[:3].any():
        raise ValueError("a directional light needs a direction: its xyz is zero")
    return light


def _mesh(positions, triangles) -> tuple[np.ndarray, np.ndarray]:
    positions = np.asarray(positions, np.float64)
    triangles = np.asarray(triangles)
    if positions.ndim != 2 or positions.shape[1] != 3 or not np.isfinite(positions).all():
        raise ValueError(f"positions must be finite (V, 3), got shape {positions.shape}")
    if triangles.ndim != 2 or triangles.shape[1] != 3 or not np.issubdtype(triangles.dtype, np.integer):
        raise ValueError(f"triangles must be integer (T, 3), got {triangles.dtype} {triangles.shape}")
    if triangles.size and (triangles.min() < 0 or triangles.max() >= len(positions)):
        raise ValueError(f"triangles index outside the {len(positions)} positions")
    return positions, triangles.astype(np.int64)


def _homogeneous(points: np.ndarray, w: float) -> np.ndarray:
    return np.concatenate([points, np.full((*points.shape[:-1], 1), w)], axis=-1)


def _extruded(points: np.ndarray, light: np.ndarray) -> np.ndarray:
    """Points (..., 3) pushed to infinity away from the light, as w = 0 vec4s."""
    return _homogeneous(light[3] * points - light[:3], 0.0)


def facing_light(positions, triangles, light) -> np.ndarray:
    """(T,) bool: the light is strictly on each triangle's outer side."""
    positions, triangles = _mesh(positions, triangles)
    return _facing(positions, triangles, light_vector(light))


def _facing(positions: np.ndarray, triangles: np.ndarray, light: np.ndarray) -> np.ndarray:
    a, b, c = (positions[triangles[:, k]] for k in range(3))
    normals = np.cross(b - a, c - a)
    # the plane (n, -n.a) against the homogeneous light
    return normals @ light[:3] - light[3] * np.einsum("ij,ij->i", normals, a) > 0


def _sides(u: np.ndarray, v: np.ndarray, u_far: np.ndarray, v_far: np.ndarray) -> np.ndarray:
    """The quad extruded from edges u -> v (each (..., 4)) as two triangles (..., 6, 4): (v, u, u'), (v, u', v').
    It runs v -> u, against the edge, so it faces out of a volume whose cap holds u -> v in its winding."""
    return np.stack([v, u, u_far, v, u_far, v_far], axis=-2)


def onepass_volume(positions, triangles, light) -> VolumeGeometry:
    """Seed 002: every caster triangle gives 7 volume triangles, in caster order: the triangle itself (the
    7th of the seed, which makes a caster's own pixels fail the depth test LESS once more) and the 6 of the
    3 quads from its edges to infinity. The far end stays open. Orientation is whatever falls out (outward
    for light-facing casters, inward for the others): the method draws both faces alike. Keep each caster's 7
    together when reordering: the seed's order freedom holds within them, not across casters."""
    positions, triangles = _mesh(positions, triangles)
    light = light_vector(light)
    corners = positions[triangles]                       # (T, 3 corners, 3)
    near, far = _homogeneous(corners, 1.0), _extruded(corners, light)
    # edge k runs from corner k to corner k + 1
    sides = _sides(near, np.roll(near, -1, axis=1), far, np.roll(far, -1, axis=1))  # (T, 3 edges, 6, 4)
    volume = np.concatenate([near, sides.reshape(len(triangles), 18, 4)], axis=1)
    return VolumeGeometry(volume.reshape(-1, 4).astype(np.float32), 3 * len(triangles))


def silhouette_volume(positions, triangles, light, caps: bool, adjacency: Adjacency | None = None) -> VolumeGeometry:
    """Everitt & Kilgard: the quads from the silhouette edges (shared by a light-facing and a back-facing
    triangle) to infinity, plus with `caps` the light cap (the light-facing triangles) and the dark cap (the
    others, at infinity), which closes the volume for z-fail. Faces point out of the volume, so seen from
    outside its front faces enter it. The mesh must be closed and consistently wound (else ValueError).
    `adjacency`: the triangles' (Mesh.adjacency(), kept with the mesh), else paired here."""
    positions, triangles = _mesh(positions, triangles)
    light = light_vector(light)
    facing = _facing(positions, triangles, light)
    if adjacency is None:
        adjacency = edge_adjacency(triangles, closed=True)
    ends = facing[adjacency.faces]  # (E, 2): whether the triangle on each side faces the light
    silhouette = ends[:, 0] != ends[:, 1]
    # each silhouette edge as its light-facing triangle runs it: faces[e, 0] runs edges[e], faces[e, 1] reversed
    u, v = np.where(ends[silhouette, :1], adjacency.edges[silhouette], adjacency.edges[silhouette, ::-1]).T
    near, far = _homogeneous(positions, 1.0), _extruded(positions, light)
    parts = [_sides(near[u], near[v], far[u], far[v]).reshape(-1, 4)]
    if caps:
        parts += [near[triangles[facing]].reshape(-1, 4), far[triangles[~facing]].reshape(-1, 4)]
    return VolumeGeometry(np.concatenate(parts).astype(np.float32), int(silhouette.sum()))
