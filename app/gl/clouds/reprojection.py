"""What the clouds' reprojection needs beyond the shaders (docs/clouds.md, "Upsampling and reprojection"): how far
the wind moved the clouds between two frames, which parts of a turned view the last frame never saw (traced at
full size there), and how much a frame changed the picture (a still view is drawn until that is small)."""
from __future__ import annotations

import math

import moderngl
import numpy as np

# The directions a turn brought into view are traced at full size where they are at most this share of the
# frame's own trace (a fast turn shows this frame's buffer there instead).
NEW_SHARE = 0.5


def cloud_motion(before: tuple, now: tuple) -> tuple[float, float, float]:
    """How far the clouds moved (metres) between two frames' clocks (wind_offset, weather_offset, ...). The density
    at p reads the noise at p + wind_offset and the weather map at p.xz + weather_offset, so what either showed at
    p shows at p minus its offset's change: the clouds' shapes go with the one, their coverage with the other, and
    the mean of the two moves leaves the least error."""
    noise = [b - a for a, b in zip(now[0], before[0])]
    weather = [before[1][0] - now[1][0], 0.0, before[1][1] - now[1][1]]
    return tuple(0.5 * float(n + w) for n, w in zip(noise, weather))


def _clip(polygon: list[tuple[float, float, float]]) -> list[tuple[float, float]]:
    """The part of a polygon (x, y, g) where g < 0, g affine along its edges: its vertices (x, y)."""
    out = []
    for (x0, y0, g0), (x1, y1, g1) in zip(polygon, polygon[1:] + polygon[:1]):
        if g0 < 0:
            out.append((x0, y0))
        if (g0 < 0) != (g1 < 0):
            s = g0 / (g0 - g1)
            out.append((x0 + s * (x1 - x0), y0 + s * (y1 - y0)))
    return out


def new_directions(before: tuple, now: tuple, tan_half_fov: float, size: tuple[int, int]
                   ) -> list[tuple[int, int, int, int]]:
    """Rectangles (x, y, width, height, in pixels from the bottom left) that cover the directions of view `now`
    (forward, right, up) outside the last frame's view `before`: the current image beyond each of its four
    edges, a straight line in it (a plane through the eye), with a pixel's margin."""
    w, h = size
    aspect = w / h
    f, r, u = (np.array(v, dtype=np.float64) for v in now)
    f0, r0, u0 = (np.array(v, dtype=np.float64) for v in before)
    corners = [(0.0, 0.0), (w, 0.0), (w, h), (0.0, h)]
    rects = []
    for edge, half in ((r0, aspect * tan_half_fov), (-r0, aspect * tan_half_fov), (u0, tan_half_fov),
                       (-u0, tan_half_fov)):
        def g(x: float, y: float) -> float:  # >= 0 inside the last frame's view along this edge
            d = f + (x / w * 2 - 1) * aspect * tan_half_fov * r + (y / h * 2 - 1) * tan_half_fov * u
            return half * float(d @ f0) - float(d @ edge)
        outside = _clip([(x, y, g(x, y)) for x, y in corners])
        if outside:
            xs, ys = [p[0] for p in outside], [p[1] for p in outside]
            x0, y0 = max(0, math.floor(min(xs)) - 1), max(0, math.floor(min(ys)) - 1)
            x1, y1 = min(w, math.ceil(max(xs)) + 1), min(h, math.ceil(max(ys)) + 1)
            if x1 > x0 and y1 > y0:
                rects.append((x0, y0, x1 - x0, y1 - y0))
    return rects


def buffer_change(before: moderngl.Texture, after: moderngl.Texture) -> float:
    """The mean absolute change of RGB per texel between two cloud buffers of one size, whatever their format."""
    def rgb(texture: moderngl.Texture) -> np.ndarray:
        dtype = {"f1": np.uint8, "f2": np.float16}.get(texture.dtype, np.float32)
        a = np.frombuffer(texture.read(), dtype=dtype).reshape(-1, texture.components)[:, :3].astype(np.float32)
        return a / 255.0 if dtype is np.uint8 else a
    return float(np.abs(rgb(after) - rgb(before)).mean())
