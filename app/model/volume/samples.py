"""The seed's sample volumes, made by code: coords3d, a Cornell box, and a Cornell box with a name."""
from __future__ import annotations

import numpy as np

SAMPLES = ("coords3d", "cornell_box", "cornell_name")
NAME = "SHADELAB"

# 5x7 glyphs of the letters in NAME ('#' = set), enough to write it on the back wall.
GLYPHS = {
    "S": (" ####", "#    ", "#    ", " ### ", "    #", "    #", "#### "),
    "H": ("#   #", "#   #", "#   #", "#####", "#   #", "#   #", "#   #"),
    "A": (" ### ", "#   #", "#   #", "#####", "#   #", "#   #", "#   #"),
    "D": ("#### ", "#   #", "#   #", "#   #", "#   #", "#   #", "#### "),
    "E": ("#####", "#    ", "#    ", "#### ", "#    ", "#    ", "#####"),
    "L": ("#    ", "#    ", "#    ", "#    ", "#    ", "#    ", "#####"),
    "B": ("#### ", "#   #", "#   #", "#### ", "#   #", "#   #", "#### "),
}

WHITE = (220, 220, 215, 255)
RED = (200, 40, 35, 255)
GREEN = (40, 170, 60, 255)
LIGHT = (255, 244, 200, 255)


def coords3d(n: int = 64) -> np.ndarray:
    """Colour = normalised coordinates (r = x, g = y, b = z), opaque: Tex3Dtrace's coords3d_%i."""
    ramp = np.linspace(0, 255, n).round().astype(np.uint8)
    data = np.empty((n, n, n, 4), np.uint8)
    data[..., 0] = ramp[None, None, :]
    data[..., 1] = ramp[None, :, None]
    data[..., 2] = ramp[:, None, None]
    data[..., 3] = 255
    return data


def cornell_box(n: int = 64) -> np.ndarray:
    """Red left wall, green right wall, white floor, ceiling and back, open at the front (z = 0),
    a light in the ceiling and a tall and a short block. Index space: x right, y down, z away."""
    data = np.zeros((n, n, n, 4), np.uint8)
    t = max(1, n // 32)  # wall thickness
    data[:, :, :t] = RED
    data[:, :, n - t:] = GREEN
    data[:, :t, :] = WHITE
    data[:, n - t:, :] = WHITE
    data[n - t:, :, :] = WHITE
    q = n // 4
    data[q + q // 2:n - q, :t, q + q // 2:n - q - q // 2] = LIGHT
    tall, short = (slice(n // 2, n // 2 + q), slice(n // 3, n - t), slice(n // 5, n // 5 + q)), \
        (slice(n // 5, n // 5 + q), slice(n - t - q, n - t), slice(n - n // 5 - q, n - n // 5))
    for z, y, x in (tall, short):
        data[z, y, x] = WHITE
    return data


def cornell_name(n: int = 64, text: str = NAME) -> np.ndarray:
    """The Cornell box with a name written across its back wall, in relief."""
    data = cornell_box(n)
    t = max(1, n // 32)
    scale = max(1, (n - 4 * t) // (6 * len(text)))
    x = (n - 6 * scale * len(text)) // 2
    y = n // 6
    for ch in text:
        for row, bits in enumerate(GLYPHS[ch]):
            for col, bit in enumerate(bits):
                y0, x0 = y + row * scale, x + col * scale
                if bit == "#" and t <= x0 and x0 + scale <= n - t:  # a small box shows only what fits
                    data[n - 2 * t:n - t, y0:y0 + scale, x0:x0 + scale] = (30, 60, 200, 255)
        x += 6 * scale
    return data


def make(name: str, n: int = 64) -> np.ndarray:
    return {"coords3d": coords3d, "cornell_box": cornell_box, "cornell_name": cornell_name}[name](n)
