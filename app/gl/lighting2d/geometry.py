"""A light's shadow-casting geometry, relative to its centre (subtracted in double): edge quads for
the geometric methods, hull triangles for the hull pass, packed convex pieces for the exact method."""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from app.model.lighting2d.scene import Light, Scene2D, outlines_overlap
from app.model.lighting2d.index import SceneIndex

ORDERED_PIECES = 16  # light2d_disc_order.shl holds 32 intervals a pixel, two a piece at most
# each edge becomes two triangles over the corners (end, projected): A, B, A', B, B', A'
QUAD = np.array([(0, 0), (1, 0), (0, 1), (1, 0), (1, 1), (0, 1)], "f8")


def disc_samples(radius: float, n: int) -> np.ndarray:
    """n points spread evenly over the disc (Vogel's spiral: area-uniform, golden-angle steps)."""
    k = np.arange(n) + 0.5
    r = radius * np.sqrt(k / n)
    a = np.arange(n) * math.pi * (3.0 - math.sqrt(5.0))
    return np.stack([r * np.cos(a), r * np.sin(a)], axis=1)


@dataclass
class LightGeometry:
    edges: np.ndarray       # (6 * edges, 6): in_a, in_b, in_s per vertex
    triangles: np.ndarray   # (3 * triangles, 2)
    pieces: np.ndarray      # (texels, 4) for light2d_exact_FS.glsl
    heads: np.ndarray       # (pieces,) int32: each piece's header texel in `pieces`
    touching: bool          # a piece meets the emitting disc
    hull_count: int
    ordered: bool = False   # touching, its hulls apart and few pieces: light2d_disc_order.shl (else light2d_disc.shl)

    @classmethod
    def build(cls, scene: Scene2D, index: SceneIndex, light: Light) -> "LightGeometry":
        centre = np.asarray(light.position, dtype=np.float64)
        edges, triangles, texels, heads = [], [], [], []
        texel_count = 0
        hulls = index.casters(light)
        if len(hulls) >= 4096:
            raise ValueError("a light can take at most 4,095 hulls in reach")  # the packing below
        for local, h in enumerate(hulls):
            outline = scene.hulls[h].world() - centre
            a, b = outline, np.roll(outline, -1, axis=0)
            per_edge = np.concatenate([a, b], axis=1)                          # (k, 4)
            edges.append(np.concatenate([np.repeat(per_edge, 6, axis=0), np.tile(QUAD, (len(a), 1))], axis=1))
            for piece in scene.hulls[h].world_pieces():
                rel = piece - centre
                n = len(rel)
                fan = np.stack([np.repeat(rel[:1], n - 2, axis=0), rel[1:-1], rel[2:]], axis=1).reshape(-1, 2)
                triangles.append(fan)
                mid = rel.mean(axis=0)
                # one header texel: centre, bounding radius, and n with the hull's ordinal in this light
                head = np.array([[mid[0], mid[1], np.linalg.norm(rel - mid, axis=1).max(), n + 4096 * local]])
                verts = rel if n % 2 == 0 else np.concatenate([rel, rel[:1]])
                heads.append(texel_count)
                texels.append(np.concatenate([head, verts.reshape(-1, 4)]))
                texel_count += len(texels[-1])
        def cat(parts: list[np.ndarray], width: int) -> np.ndarray:
            return np.concatenate(parts).astype("f4") if parts else np.zeros((0, width), "f4")

        touching = index.disc_touched(light)
        # asked only where it picks the program: a union of every hull in reach takes 231 ms for 4,000
        ordered = (touching and len(heads) <= ORDERED_PIECES
                   and not outlines_overlap([scene.hulls[h].world() for h in hulls]))
        return cls(cat(edges, 6), cat(triangles, 2), cat(texels, 4), np.array(heads, "i4"), touching, len(hulls),
                   ordered)

