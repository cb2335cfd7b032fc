"""Exact CPU Koch polyline (float64), the reference the geometry shader is measured against."""
from __future__ import annotations

import math

import numpy as np

from app.model.snowflake import split_level

BUMP = math.sqrt(3.0) / 6.0  # peak height over the segment length


def triangle(x: float, y: float, radius: float) -> np.ndarray:
    """Level-0 corners, counter-clockwise, first corner straight up; closed (4 points)."""
    angles = math.pi / 2 + np.arange(4) * 2.0 * math.pi / 3.0
    return np.stack([x + radius * np.cos(angles), y + radius * np.sin(angles)], axis=1)


def subdivide(points: np.ndarray, t: float) -> np.ndarray:
    """One Koch step on a closed CCW polyline; the new peaks at height t (1 = Koch)."""
    a, b = points[:-1], points[1:]
    d = b - a
    normal = np.stack([d[:, 1], -d[:, 0]], axis=1)  # outward for a CCW outline
    p1 = a + d / 3.0
    peak = a + d / 2.0 + normal * (BUMP * t)
    p3 = a + 2.0 * d / 3.0
    out = np.stack([a, p1, peak, p3], axis=1).reshape(-1, 2)
    return np.vstack([out, points[-1:]])


def polyline(x: float, y: float, radius: float, level: float) -> np.ndarray:
    """The closed outline at `level`: 3 * 4**ceil(level) + 1 points."""
    m, t = split_level(level)
    pts = triangle(x, y, radius)
    for i in range(m):
        pts = subdivide(pts, t if i == m - 1 else 1.0)
    return pts


def segments(flakes, level: float) -> np.ndarray:
    """All flakes' outlines as (n, 2, 2) segment end points, flake after flake."""
    parts = []
    for f in flakes:
        p = polyline(f.x, f.y, f.radius, level)
        parts.append(np.stack([p[:-1], p[1:]], axis=1))
    return np.concatenate(parts) if parts else np.zeros((0, 2, 2))
