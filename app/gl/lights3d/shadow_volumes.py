"""Shadow volumes as vertex arrays ready to upload (numpy, vectorised): the one-pass volume of caster triangles
(closed, of those turned from the light; or open at infinity, of every one, as seed 002 draws it), and Everitt &
Kilgard's silhouette volume, capped for z-fail.

A light is a homogeneous vec4 l: w = 1 for a point or spot light at l.xyz, w = 0 for a directional light shining
from direction l.xyz. A mesh vertex p goes to infinity, away from the light, as the w = 0 vertex
(l.w p - l.xyz, 0): p - l for a point light, -l.xyz for a directional one. A perspective projection maps it to a
point beyond the far plane, which depth clamping draws at depth 1 instead of clipping.

Meshes are world-space `positions` (V, 3) and `triangles` (T, 3), counter-clockwise seen from outside. A
triangle faces the light by app/model/lights3d/facing.py's rule, the light pass's: a light in its plane (on a
vertex, on an edge, level with a face) is behind it.

A point light on the mesh itself: a vertex at the light has no way away from it, so it stays where it is (w = 1)
instead of becoming (0, 0, 0, 0), which GL cannot place; a dark-cap triangle that holds the light (on a corner,
an edge or inside) is capped by a fan from the light (`_fans`). The volumes stay closed: every edge is drawn once
each way, the degenerate pieces that have no area left out in pairs."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from app.model.lights3d.facing import IN_PLANE, faces_light, in_plane
from app.model.lights3d.mesh import Adjacency, edge_adjacency

AT_LIGHT = 1e-12  # a vertex this close to a point light (times the light's largest coordinate, at least 1) is at it


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
    """Points (..., 3) pushed to infinity away from the light, as w = 0 vec4s; a point at a point light stays."""
    away = light[3] * points - light[:3]
    at_light = (light[3] != 0) & (np.abs(away).max(axis=-1) <= AT_LIGHT * max(1.0, np.abs(light[:3]).max()))
    return np.where(at_light[..., None], _homogeneous(points, 1.0), _homogeneous(away, 0.0))


def facing_light(positions, triangles, light) -> np.ndarray:
    """(T,) bool: the light is on each triangle's outer side (not in its plane)."""
    positions, triangles = _mesh(positions, triangles)
    return _facing(positions, triangles, light_vector(light))


def _as_drawn(values: np.ndarray) -> np.ndarray:
    return values.astype(np.float32).astype(np.float64)


def _planes(positions: np.ndarray, triangles: np.ndarray, light: np.ndarray):
    """Each triangle's unit normal and third corner, and the light, as the light pass gets them (float32, as
    app/gl/lights3d/meshes.py uploads them): the facing rule then reads the numbers the GPU reads."""
    c = positions[triangles]
    normals = np.cross(c[:, 1] - c[:, 0], c[:, 2] - c[:, 0])  # Mesh.face_normals
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    return _as_drawn(normals), _as_drawn(c[:, 2]), _as_drawn(light)


def _facing(positions: np.ndarray, triangles: np.ndarray, light: np.ndarray) -> np.ndarray:
    with np.errstate(invalid="ignore"):  # a triangle without area has no normal: it faces nothing
        return faces_light(*_planes(positions, triangles, light))


def _flat(positions: np.ndarray, triangles: np.ndarray, light: np.ndarray) -> np.ndarray:
    """(T,) bool: the light lies in each triangle's plane, so the volume behind the triangle has none."""
    with np.errstate(invalid="ignore"):
        return in_plane(*_planes(positions, triangles, light))


def _holding(positions: np.ndarray, triangles: np.ndarray, light: np.ndarray) -> np.ndarray:
    """(T,) bool: a point light lies on each triangle (in its plane, and on a corner, an edge or inside, within
    the in-plane margin: a fan where none was needed bounds the same flat volume)."""
    if light[3] == 0:
        return np.zeros(len(triangles), bool)
    c = positions[triangles]
    normals = np.cross(c[:, 1] - c[:, 0], c[:, 2] - c[:, 0])
    inside = _flat(positions, triangles, light)
    for k in range(3):
        edge, to_light = c[:, (k + 1) % 3] - c[:, k], light[:3] - c[:, k]
        turn = np.einsum("ij,ij->i", normals, np.cross(edge, to_light))  # >= 0: the light on the edge's inner side
        inside &= turn >= -IN_PLANE * np.linalg.norm(normals, axis=1) * np.linalg.norm(edge, axis=1) * \
            np.linalg.norm(to_light, axis=1)
    return inside


def _fans(far: np.ndarray, triangles: np.ndarray, light: np.ndarray) -> np.ndarray:
    """The far caps of triangles that hold a point light, as fans from it: (l, a', b'), (l, b', c'), (l, c', a').
    Their own caps (a', b', c') would pass through (0, 0, 0, 0) (two corners seen from the light in opposite
    directions, or a corner at it); a fan bounds the same flat volume (the triangle's plane, from the light
    outwards) with the same edges at infinity. Pieces without area (a corner at the light, two corners seen
    along one line) are left out: their twins in the neighbouring triangle's fan are too."""
    apex = np.array([*light[:3], 1.0])
    corners = far[triangles]                                          # (T, 3, 4)
    p, q = corners, np.roll(corners, -1, axis=1)
    pieces = np.stack([np.broadcast_to(apex, p.shape), p, q], axis=2)  # (T, 3 pieces, 3 vertices, 4)
    span = np.linalg.norm(np.cross(p[..., :3], q[..., :3]), axis=-1)
    flat = (p[..., 3] != 0) | (q[..., 3] != 0) | (
        span <= IN_PLANE * np.linalg.norm(p[..., :3], axis=-1) * np.linalg.norm(q[..., :3], axis=-1))
    return pieces[~flat].reshape(-1, 4)


def _sides(u: np.ndarray, v: np.ndarray, u_far: np.ndarray, v_far: np.ndarray) -> np.ndarray:
    """The quad extruded from edges u -> v (each (..., 4)) as two triangles (..., 6, 4): (v, u, u'), (v, u', v').
    It runs v -> u, against the edge, so it faces out of a volume whose cap holds u -> v in its winding."""
    return np.stack([v, u, u_far, v, u_far, v_far], axis=-2)


def onepass_volume(positions, triangles, light, closed: bool = True) -> VolumeGeometry:
    """Seed 002: caster triangles give their prisms away from the light, in caster order: the triangle itself
    (the seed's 7th triangle, which makes a caster's own pixels fail the depth test LESS once more) and the 6 of
    the 3 quads from its edges to infinity, for every caster triangle as the seed draws them (not `closed`).
    Open at the far end, a prism that a view ray runs to infinity inside counts the ray's entry and never its exit.

    `closed`: each prism also gets its far cap at infinity (8 triangles), so that a view ray that enters it
    leaves it too, and only the triangles turned from the light give one: a segment from the light to a point in
    the shadow of a closed caster leaves the caster through such a triangle, so their prisms' union is the
    shadow, at about half the triangles and the fill. A triangle with the light in its plane gives none (its
    prism is flat: nothing lies inside it).

    Orientation is whatever falls out (outward for light-facing casters, inward for the others): the method
    draws both faces alike. Keep each caster's triangles together when reordering: the seed's order freedom
    holds within them, not across casters."""
    positions, triangles = _mesh(positions, triangles)
    light = light_vector(light)
    if closed:
        triangles = triangles[~_facing(positions, triangles, light) & ~_flat(positions, triangles, light)]
    corners = positions[triangles]                       # (T, 3 corners, 3)
    near, far = _homogeneous(corners, 1.0), _extruded(corners, light)
    # edge k runs from corner k to corner k + 1
    sides = _sides(near, np.roll(near, -1, axis=1), far, np.roll(far, -1, axis=1))  # (T, 3 edges, 6, 4)
    parts = [near, sides.reshape(len(triangles), 18, 4)] + ([far[:, ::-1]] if closed else [])
    volume = np.concatenate(parts, axis=1)
    return VolumeGeometry(volume.reshape(-1, 4).astype(np.float32), 3 * len(triangles))


def silhouette_volume(positions, triangles, light, caps: bool, adjacency: Adjacency | None = None) -> VolumeGeometry:
    """Everitt & Kilgard: the quads from the silhouette edges (shared by a light-facing and a back-facing
    triangle) to infinity, plus with `caps` the light cap (the light-facing triangles) and the dark cap (the
    others, at infinity), which closes the volume for z-fail. A dark-cap triangle that holds a point light is
    capped by a fan from the light instead, which is not at infinity: z-pass draws it too, so a light on the
    mesh (which then has no silhouette) still shadows with either. Faces point out of the volume, so seen from
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
    dark = triangles[~facing]
    holding = _holding(positions, dark, light)
    # a fan's pieces are not at infinity: z-pass counts them too (where a point light lies on the mesh)
    parts = [_sides(near[u], near[v], far[u], far[v]).reshape(-1, 4), _fans(far, dark[holding], light)]
    if caps:
        parts += [near[triangles[facing]].reshape(-1, 4), far[dark[~holding]].reshape(-1, 4)]
    return VolumeGeometry(np.concatenate(parts).astype(np.float32), int(silhouette.sum()))
