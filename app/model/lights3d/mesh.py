"""Triangle meshes of the 3D lights workspace (seeds 002 and 004), numpy only.

Conventions: right-handed, +y up. Every vertex is stored once and shared by its triangles, so a closed mesh's
edges are shared too (the shadow volumes' silhouettes need that); triangles wind counter-clockwise seen from
outside. Normals are per triangle corner: flat on the box and prism faces, smooth on the sphere and torus.
Every generator centres its shape on the origin (the bounding box's centre); an object's position is that
centre in the world, so a shape resting on the ground y = 0 stands at y = half its height.
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

# A ring of 3 is the least that closes; 1024 around makes a sphere of a million triangles, far beyond the bench.
MIN_SEGMENTS, MAX_SEGMENTS = 3, 1024
BOX_TRIANGLES, LPRISM_TRIANGLES, PLANE_TRIANGLES = 12, 20, 2


class MeshError(ValueError):
    """A mesh that is not what it claims (a bad array, an edge not shared by exactly two triangles)."""


def _frozen(values, dtype, shape: tuple, what: str) -> np.ndarray:
    """`values` as a read-only array (copied unless it is one already), so meshes can share arrays safely."""
    a = np.asarray(values)
    if a.ndim != len(shape) or any(want is not None and got != want for got, want in zip(a.shape, shape)):
        raise MeshError(f"{what} must have shape {tuple('n' if s is None else s for s in shape)}, got {a.shape}")
    if a.dtype != dtype or a.flags.writeable or not a.flags.c_contiguous:
        a = np.array(a, dtype=dtype, order="C")
        a.flags.writeable = False
    return a


@dataclass(frozen=True, eq=False)
class Adjacency:
    """Each undirected edge once, with the triangles on its two sides (silhouettes: one faces the light, the
    other does not). Triangle faces[e, 0] holds the directed edge edges[e, 0] -> edges[e, 1]; faces[e, 1] holds
    it the other way round, or is -1 where the edge borders an open mesh."""
    edges: np.ndarray  # (E, 2) int32 vertex ids
    faces: np.ndarray  # (E, 2) int32 triangle ids


@dataclass(frozen=True, eq=False)
class Mesh:
    positions: np.ndarray  # (V, 3) float64, each vertex once (shared), so edges are shared between triangles
    triangles: np.ndarray  # (T, 3) int32, counter-clockwise seen from outside
    normals: np.ndarray    # (T, 3, 3) float64 unit shading normal at each triangle corner
    closed: bool           # a closed 2-manifold: every edge in exactly two triangles, in opposite directions

    def __post_init__(self) -> None:
        positions = _frozen(self.positions, np.float64, (None, 3), "positions")
        triangles = _frozen(self.triangles, np.int32, (None, 3), "triangles")
        normals = _frozen(self.normals, np.float64, (len(triangles), 3, 3), "normals")
        if not np.isfinite(positions).all() or not np.isfinite(normals).all():
            raise MeshError("positions and normals must be finite")
        if len(triangles) == 0:
            raise MeshError("a mesh needs at least one triangle")
        if not (0 <= triangles.min() and triangles.max() < len(positions)):
            raise MeshError(f"triangles must index the {len(positions)} positions")
        object.__setattr__(self, "positions", positions)
        object.__setattr__(self, "triangles", triangles)
        object.__setattr__(self, "normals", normals)
        object.__setattr__(self, "closed", bool(self.closed))

    def moved(self, offset) -> Mesh:
        """The mesh translated by `offset` (x, y, z); triangles, normals and the adjacency are shared (the
        adjacency is computed once for the mesh every move comes from, whichever move asks for it first)."""
        out = Mesh(self.positions + np.asarray(offset, dtype=np.float64), self.triangles, self.normals, self.closed)
        out.__dict__["_topology"] = self._topology
        return out

    def corners(self) -> np.ndarray:
        """(T, 3, 3): each triangle's three corner positions."""
        return self.positions[self.triangles]

    def face_normals(self) -> np.ndarray:
        """(T, 3) unit geometric normals, from the winding (outward on a closed mesh)."""
        c = self.corners()
        n = np.cross(c[:, 1] - c[:, 0], c[:, 2] - c[:, 0])
        return n / np.linalg.norm(n, axis=1, keepdims=True)

    def signed_volume(self) -> float:
        """The enclosed volume by the divergence theorem: positive when a closed mesh winds outward."""
        c = self.corners()
        return float(np.einsum("ij,ij->i", c[:, 0], np.cross(c[:, 1], c[:, 2])).sum() / 6.0)

    def adjacency(self) -> Adjacency:
        """The edge adjacency (computed once); MeshError if an edge has more than two triangles, two in the same
        direction, or (on a mesh that claims to be closed) only one."""
        return self._topology._adjacency

    @cached_property
    def _topology(self) -> Mesh:
        """The mesh holding the adjacency: itself, or the one it was moved from."""
        return self

    @cached_property
    def _adjacency(self) -> Adjacency:
        return edge_adjacency(self.triangles, self.closed)


def edge_adjacency(triangles: np.ndarray, closed: bool) -> Adjacency:
    """Pair every directed edge a -> b with its twin b -> a by sorting undirected edge keys."""
    directed = triangles[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2).astype(np.int64)
    face = np.repeat(np.arange(len(triangles), dtype=np.int32), 3)
    key = directed.min(axis=1) * (int(triangles.max(initial=0)) + 1) + directed.max(axis=1)
    order = np.argsort(key, kind="stable")
    key, directed, face = key[order], directed[order], face[order]
    starts = np.flatnonzero(np.r_[True, key[1:] != key[:-1]])
    counts = np.diff(np.r_[starts, len(key)])
    if (counts > 2).any():
        a, b = directed[starts[np.argmax(counts > 2)]]
        raise MeshError(f"edge {a}-{b} is shared by more than two triangles")
    pairs = starts[counts == 2]
    same = (directed[pairs] == directed[pairs + 1]).all(axis=1)
    if same.any():
        a, b = directed[pairs[np.argmax(same)]]
        raise MeshError(f"edge {a}-{b} runs the same way in both its triangles (inconsistent winding)")
    if closed and (counts == 1).any():
        a, b = directed[starts[np.argmax(counts == 1)]]
        raise MeshError(f"edge {a}-{b} has only one triangle: the mesh is not closed")
    other = np.where(counts == 2, face[np.minimum(starts + 1, len(face) - 1)], -1)
    return Adjacency(directed[starts].astype(np.int32), np.stack([face[starts], other], axis=1).astype(np.int32))


def _flat(positions: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    """Each triangle's geometric normal at its three corners."""
    c = positions[triangles]
    n = np.cross(c[:, 1] - c[:, 0], c[:, 2] - c[:, 0])
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    return np.repeat(n[:, None, :], 3, axis=1)


def _quads(a, b, c, d) -> np.ndarray:
    """Quads a b c d (counter-clockwise from outside) as the triangles a b c and a c d."""
    return np.concatenate([np.stack([a, b, c], -1), np.stack([a, c, d], -1)]).reshape(-1, 3)


def box(sx: float, sy: float, sz: float) -> Mesh:
    """An axis-aligned box spanning -s/2..s/2 on each axis: 8 vertices, 12 triangles."""
    signs = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], dtype=np.float64)
    positions = signs * (np.array([sx, sy, sz]) / 2)
    # vertex index = 4 x + 2 y + z with x, y, z in {0, 1}; each face counter-clockwise from outside
    faces = np.array([[0, 1, 3, 2], [4, 6, 7, 5], [0, 4, 5, 1], [2, 3, 7, 6], [0, 2, 6, 4], [1, 5, 7, 3]])
    triangles = _quads(*faces.T)
    return Mesh(positions, triangles, _flat(positions, triangles), closed=True)


def sphere_rings(segments: int) -> int:
    """The rings of latitude bands of a UV sphere with `segments` around: about as tall as wide."""
    return max(2, segments // 2)


def sphere_triangles(segments: int) -> int:
    return 2 * segments * (sphere_rings(segments) - 1)


def sphere_segments(triangles: int) -> int:
    """The fewest segments whose sphere has at least `triangles` triangles (a bench's size knob)."""
    n = MIN_SEGMENTS
    while sphere_triangles(n) < triangles and n < MAX_SEGMENTS:
        n += 1
    return n


def sphere(radius: float, segments: int) -> Mesh:
    """A UV sphere: `segments` around the y axis, sphere_rings(segments) bands from pole to pole; each pole
    is one shared vertex (so the mesh is closed), vertex 0 at +y and the last at -y; smooth normals."""
    n, m = segments, sphere_rings(segments)
    polar = np.pi * np.arange(1, m) / m
    azimuth = 2 * np.pi * np.arange(n) / n
    s, c = np.sin(polar)[:, None], np.cos(polar)[:, None]
    ring = np.stack([s * np.cos(azimuth), np.broadcast_to(c, (m - 1, n)), -s * np.sin(azimuth)], -1).reshape(-1, 3)
    unit = np.concatenate([[[0.0, 1.0, 0.0]], ring, [[0.0, -1.0, 0.0]]])
    south = len(unit) - 1
    j = np.arange(n)

    def at(i, j):  # the vertex of ring i (0 nearest +y) at azimuth step j
        return 1 + i * n + j % n

    top = np.stack([np.zeros(n, int), at(0, j), at(0, j + 1)], -1)
    bottom = np.stack([np.full(n, south), at(m - 2, j + 1), at(m - 2, j)], -1)
    i, jj = np.meshgrid(np.arange(m - 2), j, indexing="ij")
    bands = _quads(at(i, jj), at(i + 1, jj), at(i + 1, jj + 1), at(i, jj + 1))
    triangles = np.concatenate([top, bands, bottom])
    return Mesh(unit * radius, triangles, unit[triangles], closed=True)


def torus_triangles(segments: int, sides: int) -> int:
    return 2 * segments * sides


def torus(major: float, minor: float, segments: int, sides: int) -> Mesh:
    """A ring torus around the y axis, lying in the xz plane: a tube of radius `minor` whose centre circles
    at radius `major` (> minor); `segments` around the ring, `sides` around the tube; smooth normals."""
    phi = 2 * np.pi * np.arange(segments) / segments
    psi = 2 * np.pi * np.arange(sides) / sides
    p, q = np.meshgrid(phi, psi, indexing="ij")
    normals = np.stack([np.cos(q) * np.cos(p), np.sin(q), -np.cos(q) * np.sin(p)], -1).reshape(-1, 3)
    centres = major * np.stack([np.cos(p), np.zeros_like(p), -np.sin(p)], -1).reshape(-1, 3)
    j, k = np.meshgrid(np.arange(segments), np.arange(sides), indexing="ij")

    def at(j, k):  # the vertex at ring step j, tube step k
        return (j % segments) * sides + k % sides

    triangles = _quads(at(j, k), at(j + 1, k), at(j + 1, k + 1), at(j, k + 1))
    return Mesh(centres + minor * normals, triangles, normals[triangles], closed=True)


def l_prism(sx: float, sy: float, sz: float, thickness: float) -> Mesh:
    """An L-shaped prism (not convex): the L in the xy plane, a foot `thickness` tall along x and a column
    `thickness` wide up the -x side, in a sx by sy box, extruded sz along z; 12 vertices, 20 triangles."""
    t = thickness
    outline = np.array([[0, 0], [sx, 0], [sx, t], [t, t], [t, sy], [0, sy]], dtype=np.float64) - [sx / 2, sy / 2]
    front = np.column_stack([outline, np.full(6, sz / 2)])   # vertices 0..5, counter-clockwise seen from +z
    back = np.column_stack([outline, np.full(6, -sz / 2)])   # vertices 6..11
    fan = np.array([[0, 1, 2], [0, 2, 3], [0, 3, 4], [0, 4, 5]])  # the L is star-shaped from its corner 0
    i = np.arange(6)
    sides = _quads(i, i + 6, (i + 1) % 6 + 6, (i + 1) % 6)
    positions = np.concatenate([front, back])
    triangles = np.concatenate([fan, fan[:, ::-1] + 6, sides])
    return Mesh(positions, triangles, _flat(positions, triangles), closed=True)


def plane(size: float) -> Mesh:
    """The ground: a size by size quad in the xz plane facing +y, open (it receives shadows, casts none)."""
    h = size / 2
    positions = np.array([[-h, 0, -h], [-h, 0, h], [h, 0, h], [h, 0, -h]], dtype=np.float64)
    triangles = np.array([[0, 1, 2], [0, 2, 3]])
    return Mesh(positions, triangles, np.tile([0.0, 1.0, 0.0], (2, 3, 1)), closed=False)

