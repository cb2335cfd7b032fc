"""What the clouds' reprojection needs beyond the shaders (docs/clouds.md, "Upsampling and reprojection"): how far
the wind moved the clouds between two frames, which parts of a turned view the last frame never saw (traced at
full size there), and how much a frame changed the picture (a still view is drawn until that is small)."""
from __future__ import annotations

import math

import moderngl
import numpy as np

# The directions a turn brought into view are traced at full size where they are at most this share of the picture
# (half a quarter buffer's rays: a turn of some 2 degrees a frame at the editor's default view); a faster turn
# shows this frame's buffer there instead.
NEW_SHARE = 1 / 32


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
    """Rectangles (x, y, width, height, in pixels from the bottom left) holding every pixel of view `now` (forward,
    right, up) whose centre looks outside the last frame's picture `before`, or within a quarter pixel of its edge:
    beyond each edge of that picture, a straight line in this one (a plane through the eye)."""
    w, h = size
    aspect = w / h
    f, r, u = (np.array(v, dtype=np.float64) for v in now)
    f0, r0, u0 = (np.array(v, dtype=np.float64) for v in before)
    centres = [(0.5, 0.5), (w - 0.5, 0.5), (w - 0.5, h - 0.5), (0.5, h - 0.5)]
    half_x, half_y = aspect * tan_half_fov * (1 - 0.5 / w), tan_half_fov * (1 - 0.5 / h)
    rects = []
    for edge, half in ((r0, half_x), (-r0, half_x), (u0, half_y), (-u0, half_y)):
        def g(x: float, y: float) -> float:  # >= 0 inside the last frame's picture along this edge
            d = f + (x / w * 2 - 1) * aspect * tan_half_fov * r + (y / h * 2 - 1) * tan_half_fov * u
            return half * float(d @ f0) - float(d @ edge)
        outside = _clip([(x, y, g(x, y)) for x, y in centres])
        if outside:  # the pixels whose centres lie in it
            xs, ys = [p[0] for p in outside], [p[1] for p in outside]
            x0, x1 = math.ceil(min(xs) - 0.5), math.floor(max(xs) - 0.5) + 1
            y0, y1 = math.ceil(min(ys) - 0.5), math.floor(max(ys) - 0.5) + 1
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
