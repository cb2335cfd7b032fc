"""Images the 2D lighting scene names: built-in ones (generated, no files) or PNG paths.

Every image is RGBA uint8 (height, width, 4), row 0 at the top. The renderer uploads exactly these
bytes and the reference samples them the same way, so both see the same texels."""
from __future__ import annotations

import functools
import os

import numpy as np

from app.io.regular_file import read_regular_bytes
from app.io.png import decode_png
from app.model.lighting2d.scene import Lighting2DError

BUILTIN = "builtin:"
MAX_IMAGE_BYTES = 64 << 20  # a file, before decoding; app.io.png caps the decoded image at MAX_PIXELS (256 MiB)


def _grid(n: int) -> tuple[np.ndarray, np.ndarray]:
    y, x = np.mgrid[0:n, 0:n]
    return (x + 0.5) / n, (y + 0.5) / n


def _tiles() -> np.ndarray:
    """Diffuse floor: warm stone tiles with grout, 128 texels = 2 tiles each way."""
    u, v = _grid(128)
    fu, fv = (u * 2) % 1, (v * 2) % 1
    grout = (np.minimum(np.minimum(fu, 1 - fu), np.minimum(fv, 1 - fv)) < 0.04)
    checker = ((np.floor(u * 2) + np.floor(v * 2)) % 2)[..., None]
    stone = np.array([0.86, 0.82, 0.74]) * (1 - 0.08 * checker)
    rgb = np.where(grout[..., None], np.array([0.45, 0.43, 0.40]), stone)
    return _rgba(rgb)


def _white() -> np.ndarray:
    return np.full((4, 4, 4), 255, np.uint8)


def _bumps() -> np.ndarray:
    """Normal map of the tiles: each tile a low dome, so height-lit lights show relief."""
    u, v = _grid(128)
    fu, fv = (u * 2) % 1 - 0.5, (v * 2) % 1 - 0.5
    nx, ny = -fu * 0.9, fv * 0.9  # rows go down the image, world y goes up
    n = np.stack([nx, ny, np.ones_like(nx)], axis=-1)
    n /= np.linalg.norm(n, axis=-1, keepdims=True)
    return _rgba(n * 0.5 + 0.5)


def _window() -> np.ndarray:
    """A four-pane window for textured lights (the seed's cookie example)."""
    u, v = _grid(64)
    frame = (np.abs(u - 0.5) < 0.05) | (np.abs(v - 0.5) < 0.05) | (u < 0.06) | (u > 0.94) | (v < 0.06) | (v > 0.94)
    falloff = np.clip(1.0 - 1.6 * np.hypot(u - 0.5, v - 0.5), 0.0, 1.0)
    return _rgba(np.repeat(np.where(frame, 0.0, falloff)[..., None], 3, axis=-1))


def _flame() -> np.ndarray:
    u, v = _grid(64)
    r = np.hypot((u - 0.5) * 1.0, (v - 0.55) * 0.8)
    flicker = 0.85 + 0.15 * np.cos(9 * u)
    return _rgba(np.repeat(np.clip(1.0 - 2.2 * r, 0, 1)[..., None] * flicker[..., None], 3, axis=-1))


def _rgba(rgb: np.ndarray) -> np.ndarray:
    out = np.empty(rgb.shape[:2] + (4,), np.uint8)
    out[..., :3] = np.clip(np.rint(rgb * 255), 0, 255)
    out[..., 3] = 255
    return out


BUILTINS = {"tiles": _tiles, "white": _white, "bumps": _bumps, "window": _window, "flame": _flame}


@functools.lru_cache(maxsize=32)
def _load(name: str, mtime: float) -> np.ndarray:
    if name.startswith(BUILTIN):
        key = name[len(BUILTIN):]
        if key not in BUILTINS:
            raise Lighting2DError(f"no built-in image {key!r}; there are {', '.join(BUILTINS)}")
        image = BUILTINS[key]()
    else:
        try:
            image = decode_png(read_regular_bytes(name, MAX_IMAGE_BYTES))
        except OSError as exc:
            raise Lighting2DError(f"cannot read image {name}: {exc.strerror or exc}") from None
    image.setflags(write=False)
    return image


def image(name: str) -> np.ndarray:
    """The RGBA uint8 image a scene names; refused with a message when it cannot be read."""
    mtime = 0.0 if name.startswith(BUILTIN) else (os.path.getmtime(name) if os.path.exists(name) else -1.0)
    return _load(name, mtime)
