"""CPU reference of a scan's labels over its rendering (resources/shaders/labels.shl), numpy: the same walk voxel by
voxel through the box holding every label, in float64, in front of where each ray stopped; the first labelled
voxel's colour, lit by the face the ray entered it through, over the ray's colour with the label opacity."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

LABEL_AMBIENT = 0.35  # labels.shl's constants
LABEL_NUDGE = 1e-4


@dataclass(frozen=True)
class LabelLayer:
    """What the reference lays over a render: `labels` (d, h, w) uint8, `colours` (256, 3) uint8, `opacity`."""
    labels: np.ndarray
    colours: np.ndarray
    opacity: float


def _bounds(labels: np.ndarray) -> tuple[np.ndarray, np.ndarray] | None:
    """The box holding every label, in voxels (x, y, z): lo inclusive, hi exclusive."""
    lo, hi = [], []
    for axis in (2, 1, 0):
        hit = np.flatnonzero(labels.any(axis=tuple(a for a in range(3) if a != axis)))
        if not len(hit):
            return None
        lo.append(hit[0])
        hi.append(hit[-1] + 1)
    return np.array(lo, float), np.array(hi, float)


def over(layer: LabelLayer, colour: np.ndarray, a: np.ndarray, b: np.ndarray, at: np.ndarray,
         d: np.ndarray) -> np.ndarray:
    """`colour` (n, 3) of the rays a -> b (texture space, (n, 3)) along world directions d, which stopped at `at`
    (n,) of the way, with the labels in front of their stops laid over it."""
    labels = layer.labels
    box = _bounds(labels)
    if box is None or layer.opacity <= 0:
        return colour
    lo, hi = box
    size = np.array(labels.shape[::-1], float)
    p0 = a * size
    v = (a + (b - a) * at[:, None]) * size - p0
    moves = np.abs(v) >= 1e-9
    with np.errstate(divide="ignore", invalid="ignore"):
        t0, t1 = (lo - p0) / v, (hi - p0) / v
    inside = (p0 >= lo) & (p0 <= hi)
    lo_t = np.where(moves, np.minimum(t0, t1), np.where(inside, -np.inf, np.inf))
    hi_t = np.where(moves, np.maximum(t0, t1), np.where(inside, np.inf, -np.inf))
    enter = np.maximum(lo_t.max(-1), 0.0)
    leave = np.minimum(hi_t.min(-1), 1.0)
    live = np.flatnonzero(enter < leave)
    axis = lo_t.argmax(-1)
    step = np.sign(v).astype(np.int64)
    cell = np.clip(np.floor(p0 + v * enter[:, None] + np.sign(v) * LABEL_NUDGE), lo, hi - 1).astype(np.int64)
    with np.errstate(divide="ignore", invalid="ignore"):
        delta = np.where(moves, np.abs(1.0 / v), np.inf)
        nxt = np.where(moves, (cell + (v > 0) - p0) / v, np.inf)
    found = np.zeros(len(a), np.int64)
    for _ in range(int(size.sum()) + 3):
        if not len(live):
            break
        c = np.clip(cell[live], 0, size.astype(np.int64) - 1)
        label = labels[c[:, 2], c[:, 1], c[:, 0]]
        found[live] = label
        live = live[label == 0]
        ax = nxt[live].argmin(-1)
        keep = nxt[live, ax] <= leave[live]
        live, ax = live[keep], ax[keep]
        axis[live] = ax
        cell[live, ax] += step[live, ax]
        nxt[live, ax] += delta[live, ax]
    hit = np.flatnonzero(found)
    out = colour.copy()
    lit = LABEL_AMBIENT + (1.0 - LABEL_AMBIENT) * np.abs(d[hit, axis[hit]])
    rgb = layer.colours[found[hit]] / 255.0 * lit[:, None]
    out[hit] = colour[hit] + (rgb - colour[hit]) * layer.opacity
    return out
