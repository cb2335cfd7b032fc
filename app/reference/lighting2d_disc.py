"""The share of a light's disc hidden from points where hull pieces enter the disc, in closed form.

Seen from a point p outside a convex piece, the disc points q whose segment pq meets the piece form its
shadow: the piece's near chain (the edges facing p, from vertex a to vertex b) and the rays from b and
from a away from p, a convex region. The hidden part of the disc is the disc clipped by the union of the
shadows. Its area follows from Green's theorem over that part's boundary, the disc's centre at the
origin: each stretch of a shadow's edge inside the disc that no other shadow covers adds
cross(start, end) / 2, and each arc of the circle inside the union adds r^2 (its angle) / 2. The arcs are
found by splitting the circle where the shadows' uncovered edges cross it and testing each arc's midpoint,
so an edge grazing the circle, or a vertex on it, only splits an arc. Where two shadows share a ray
(pieces of one hull meeting at a vertex that both see from p as their end) the first piece keeps it.

`light2d_disc.shl` does the same per pixel on the GPU; `lighting2d.sampled` (the disc sampled) checks both."""
from __future__ import annotations

import math
from typing import Iterator

import numpy as np

CHAIN, OUT_RAY, IN_RAY = 0, 1, 2


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


class _Shadow:
    """One convex counter-clockwise piece's shadow from each of m points."""

    def __init__(self, points: np.ndarray, piece: np.ndarray, order: int) -> None:
        self.p, self.piece, self.order = points, piece, order
        edge = np.roll(piece, -1, axis=0) - piece
        self.front = _cross(edge[None], points[:, None, :] - piece[None]) < 0      # (m, n): edges facing p
        self.inside = ~self.front.any(axis=1)
        starts = self.front & ~np.roll(self.front, 1, axis=1)
        ends = self.front & ~np.roll(self.front, -1, axis=1)
        self.a = piece[np.argmax(starts, axis=1)]
        self.b = piece[(np.argmax(ends, axis=1) + 1) % len(piece)]

    def _chain(self) -> Iterator[tuple[np.ndarray, np.ndarray, np.ndarray]]:
        m = len(self.p)
        for k, (v, w) in enumerate(zip(self.piece, np.roll(self.piece, -1, axis=0))):
            yield np.broadcast_to(v, (m, 2)), np.broadcast_to(w - v, (m, 2)), self.front[:, k]

    def edges(self):
        """(origin, direction, t from, t to, where, kind, end vertex) of the boundary, the shadow on the left."""
        m, zero, outside = len(self.p), np.zeros(len(self.p)), ~self.inside
        for origin, direction, where in self._chain():
            yield origin, direction, zero, np.ones(m), where, CHAIN, None
        yield self.b, self.b - self.p, zero, np.full(m, np.inf), outside, OUT_RAY, self.b
        yield self.a, self.p - self.a, np.full(m, -np.inf), zero, outside, IN_RAY, self.a

    def span(self, c, u, lo, hi, kind=CHAIN, end=None, owner=-1):
        """Where c + s u (s in [lo, hi]) lies in this shadow: (lo, hi), empty as lo >= hi. The edge's own
        ray (`kind` from `end`), when this shadow has it too, is covered here only if this piece comes first."""
        lines = [(a, d, w, CHAIN) for a, d, w in self._chain()]
        lines += [(self.p, self.b - self.p, True, OUT_RAY), (self.p, self.p - self.a, True, IN_RAY)]
        for at, along, where, line_kind in lines:
            g0, g1 = _cross(along, c - at), _cross(along, u)
            with np.errstate(divide="ignore", invalid="ignore"):
                root = -g0 / g1
            new_lo = np.where(g1 > 0, np.maximum(lo, root), lo)
            new_hi = np.where(g1 < 0, np.minimum(hi, root), np.where((g1 == 0) & (g0 < 0), -np.inf, hi))
            if kind != CHAIN and line_kind == kind:
                shared = np.all(end == (self.b if kind == OUT_RAY else self.a), axis=1)
                new_lo = np.where(shared, lo, new_lo)
                new_hi = np.where(shared, hi if self.order < owner else -np.inf, new_hi)
            lo, hi = np.where(where, new_lo, lo), np.where(where, new_hi, hi)
        return lo, np.where(self.inside, -np.inf, hi)

    def contains(self, q: np.ndarray) -> np.ndarray:
        """Which of the points q (m, k, 2) lie in this shadow (m, k)."""
        m, k = q.shape[:2]
        c = q.reshape(-1, 2)
        rows = np.repeat(np.arange(m), k)
        lo, hi = self._at(rows).span(c, np.tile([1.0, 0.0], (len(c), 1)), np.zeros(len(c)), np.zeros(len(c)))
        return (lo <= hi).reshape(m, k)

    def _at(self, rows: np.ndarray) -> "_Shadow":
        """The same shadow for the points at `rows` (repeated as needed)."""
        other = object.__new__(_Shadow)
        other.p, other.piece, other.order = self.p[rows], self.piece, self.order
        other.front, other.inside, other.a, other.b = self.front[rows], self.inside[rows], self.a[rows], self.b[rows]
        return other


def _uncovered(s0: np.ndarray, s1: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """Length of [s0, s1] outside the intervals (m, k) (empty ones have lo >= hi)."""
    empty = hi <= lo
    lo, hi = np.where(empty, s1[:, None], lo), np.where(empty, s1[:, None], hi)
    order = np.argsort(lo, axis=1)
    lo, hi = np.take_along_axis(lo, order, 1), np.take_along_axis(hi, order, 1)
    free, reach = np.zeros(len(s0)), s0.copy()
    for k in range(lo.shape[1]):
        free += np.maximum(np.minimum(lo[:, k], s1) - reach, 0.0)
        reach = np.maximum(reach, hi[:, k])
    return free + np.maximum(s1 - reach, 0.0)


def _covered_at(s: np.ndarray, lo: np.ndarray, hi: np.ndarray, margin: float) -> np.ndarray:
    return np.any((lo < s[:, None] - margin) & (hi > s[:, None] + margin), axis=1)


def hidden_share(points: np.ndarray, pieces: list[np.ndarray], r: float) -> np.ndarray:
    """Share of the disc of radius r > 0 at the origin hidden from each point (m, 2) by the convex
    counter-clockwise pieces (m,): 1 where a point is inside a piece."""
    m, eps = len(points), 1e-6 * r
    shadows = [_Shadow(points, piece, k) for k, piece in enumerate(pieces)]
    twice = np.zeros(m)  # twice the hidden area
    angles = []
    for j, shadow in enumerate(shadows):
        for origin, direction, t0, t1, where, kind, end in shadow.edges():
            length = np.maximum(np.hypot(direction[:, 0], direction[:, 1]), 1e-300)
            u = direction / length[:, None]
            tc = -np.einsum("md,md->m", origin, u)
            c = origin + tc[:, None] * u             # the line's point nearest the centre; s measures from it
            h2 = r * r - np.einsum("md,md->m", c, c)
            h = np.sqrt(np.maximum(h2, 0.0))
            with np.errstate(invalid="ignore"):
                s_lo, s_hi = t0 * length - tc, t1 * length - tc
            near = where & (h2 > -2 * eps * r)        # grazing lines split the circle too
            cuts = [near & (s >= s_lo - eps) & (s <= s_hi + eps) for s in (-h, h)]
            s0, s1 = np.maximum(s_lo, -h), np.minimum(s_hi, h)
            chord = near & (s1 > s0)
            if chord.any():
                s0, s1 = np.where(chord, s0, 0.0), np.where(chord, s1, 0.0)
                spans = [other.span(c, u, s0 - 2 * eps, s1 + 2 * eps, kind, end, j)
                         for k, other in enumerate(shadows) if k != j]
                lo = np.stack([a for a, _ in spans], axis=1) if spans else np.zeros((m, 0))
                hi = np.stack([b for _, b in spans], axis=1) if spans else np.zeros((m, 0))
                twice += np.where(chord, _uncovered(s0, s1, lo, hi) * _cross(c, u), 0.0)
                cuts = [cut & ~(chord & _covered_at(s, lo, hi, eps)) for cut, s in zip(cuts, (-h, h))]
            for cut, s in zip(cuts, (-h, h)):
                x = c + s[:, None] * u
                angles.append(np.where(cut, np.arctan2(x[:, 1], x[:, 0]), np.nan))
    twice += r * r * _arcs_inside(np.stack(angles, axis=1), shadows, r)
    inside = np.any([s.inside for s in shadows], axis=0) if shadows else np.zeros(m, bool)
    return np.where(inside, 1.0, np.clip(twice / (2 * math.pi * r * r), 0.0, 1.0))


def _arcs_inside(angles: np.ndarray, shadows: list[_Shadow], r: float) -> np.ndarray:
    """Total angle of the circle inside the shadows' union, given where their boundary may cross it
    (m, k; NaN for none): between two neighbouring crossings one midpoint decides."""
    count = np.sum(~np.isnan(angles), axis=1)
    phi = np.sort(angles, axis=1)[:, :max(int(count.max(initial=0)), 1)]  # NaN last
    column = np.arange(phi.shape[1])[None]
    following = np.where(column == (count - 1)[:, None], phi[:, :1] + 2 * math.pi, np.roll(phi, -1, axis=1))
    arc = np.where(column < count[:, None], following - phi, 0.0)
    mid = np.where(column < count[:, None], 0.5 * (phi + following), 0.0)
    whole = (count == 0)[:, None] & (column == 0)  # no crossing: the circle is all in or all out
    arc = np.where(whole, 2 * math.pi, arc)
    q = r * np.stack([np.cos(mid), np.sin(mid)], axis=-1)
    covered = np.zeros(mid.shape, bool)
    for shadow in shadows:
        covered |= shadow.contains(q)
    return np.sum(np.where(covered, arc, 0.0), axis=1)
