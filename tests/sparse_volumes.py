"""Seeded random sparse volumes, cameras and ray settings: the scenes where empty-space skipping skips the most
and a sample near the surface threshold decides a pixel (issue 13)."""
from __future__ import annotations

import numpy as np

from app.model.camera3d import OrbitCamera

KINDS = ("voxels", "lines", "planes", "shell", "noise")


def _rgba(rng: np.random.Generator, n: int) -> np.ndarray:
    """Random colours with alpha 1..255, so some samples land near the threshold and some far over it."""
    colour = rng.integers(0, 256, (n, 4))
    colour[:, 3] = rng.integers(1, 256, n)
    return colour.astype(np.uint8)


def _points_on_lines(rng, shape, count: int) -> np.ndarray:
    """Voxels along `count` random lines through the volume, one voxel wide."""
    size = np.array(shape[::-1], float)  # (w, h, d)
    out = []
    for _ in range(count):
        origin = rng.uniform(0, size)
        direction = rng.normal(size=3)
        direction /= np.linalg.norm(direction)
        span = np.linalg.norm(size)
        out.append(origin + np.arange(-span, span, 0.5)[:, None] * direction)
    return np.concatenate(out)


def sparse_volume(rng: np.random.Generator, kind: str, shape: tuple[int, int, int]) -> np.ndarray:
    """A (d, h, w, 4) uint8 volume of one of KINDS; `shape` is (w, h, d)."""
    w, h, d = shape
    data = np.zeros((d, h, w, 4), np.uint8)
    zyx = np.stack(np.meshgrid(np.arange(d), np.arange(h), np.arange(w), indexing="ij"), -1).reshape(-1, 3)
    centre = np.array([d, h, w]) / 2
    if kind == "voxels":
        picked = zyx[rng.choice(len(zyx), size=int(rng.integers(1, 40)), replace=False)]
    elif kind == "lines":
        xyz = np.rint(_points_on_lines(rng, (d, h, w), int(rng.integers(1, 6)))).astype(int)
        inside = ((xyz >= 0) & (xyz < [w, h, d])).all(-1)
        picked = xyz[inside][:, ::-1]
    elif kind == "planes":
        normal = rng.normal(size=3)
        normal /= np.linalg.norm(normal)
        offset = (zyx - centre - rng.uniform(-0.3, 0.3, 3) * [d, h, w]) @ normal
        picked = zyx[np.abs(offset) < 0.5]
    elif kind == "shell":
        radius = rng.uniform(0.15, 0.45) * min(w, h, d)
        picked = zyx[np.abs(np.linalg.norm(zyx - centre, axis=-1) - radius) < rng.uniform(0.4, 1.0)]
    else:  # noise: 0.1 .. 5 % of the voxels
        picked = zyx[rng.random(len(zyx)) < rng.uniform(0.001, 0.05)]
    if len(picked):
        data[picked[:, 0], picked[:, 1], picked[:, 2]] = _rgba(rng, len(picked))
    return data


def random_camera(rng: np.random.Generator) -> OrbitCamera:
    """Any side, from inside the box (distance under ~1) to well outside it."""
    return OrbitCamera(yaw=float(rng.uniform(0, 360)), pitch=float(rng.uniform(-80, 80)),
                       distance=float(rng.uniform(0.6, 6.0)))


def random_steps(rng: np.random.Generator) -> dict:
    return {"steps": float(rng.integers(39, 242)), "shadow_steps": int(rng.integers(5, 61))}


def random_edit(rng: np.random.Generator, volume) -> None:
    """A stroke of a random colour, or an erasure (alpha 0) through a voxel that holds something."""
    axis = str(rng.choice(["x", "y", "z"]))
    us, vs = volume.voxels.slice_size(axis)
    held = np.argwhere(volume.voxels.data[..., 3] > 0)
    erase = len(held) and rng.random() < 0.5
    if erase:
        z, y, x = held[rng.integers(len(held))]
        index, u, v = {"z": (z, x, y), "y": (y, x, z), "x": (x, y, z)}[axis]
        points = [(int(u), int(v)), (int(u + rng.integers(-3, 4)), int(v + rng.integers(-3, 4)))]
        colour = (0, 0, 0, 0)
    else:
        index = int(rng.integers(volume.voxels.depth(axis)))
        points = [(int(rng.integers(us)), int(rng.integers(vs))) for _ in range(int(rng.integers(1, 4)))]
        colour = tuple(int(c) for c in _rgba(rng, 1)[0])
    volume.paint.stroke(axis, int(index), int(rng.integers(1, 4)), colour, points)
