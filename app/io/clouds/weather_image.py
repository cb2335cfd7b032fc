"""Weather maps as PNG files: R coverage, G cloud type, B precipitation, 0..255 for 0..1.

Loading takes an RGB or RGBA PNG (8 or 16 bits a sample; alpha is ignored) that is square with a side of MIN_SIDE
.. MAX_SIDE; its header is checked before anything is decoded, and every failure, a missing file included, is a
WeatherError that says why. Pixels go through app.io.png, which gives 8 bits a sample (of a 16-bit RGB sample
Pillow keeps the high byte). Saving writes an 8-bit RGB PNG atomically.
"""
from __future__ import annotations

import io
import os
import struct

import numpy as np
from PIL import Image

from app.io.atomic import write_bytes
from app.io.png import decode_png
from app.io.regular_file import read_regular_bytes

MIN_SIDE = 16
MAX_SIDE = 2048
# A 2048^2 RGBA PNG of 16-bit samples is 32 MiB uncompressed; stored (uncompressed) deflate adds a little.
MAX_BYTES = 40 << 20
_SIGNATURE = b"\x89PNG\r\n\x1a\n"
_IHDR = struct.Struct(">I4sIIBB")  # length, type, width, height, bit depth, colour type
_RGB, _RGBA = 2, 6  # PNG colour types
_COLOUR_NAMES = {0: "greyscale", 3: "palette", 4: "greyscale with alpha"}


class WeatherError(ValueError):
    """A weather image that cannot be used; the message says why."""


def _check_header(data: bytes) -> None:
    if not data.startswith(_SIGNATURE):
        raise WeatherError("not a PNG file")
    try:
        length, kind, width, height, depth, colour = _IHDR.unpack_from(data, len(_SIGNATURE))
    except struct.error:
        raise WeatherError("a truncated PNG (no complete header)") from None
    if kind != b"IHDR" or length != 13:
        raise WeatherError("a damaged PNG (its first chunk is not a header)")
    if colour not in (_RGB, _RGBA):
        what = _COLOUR_NAMES.get(colour, f"colour type {colour}")
        raise WeatherError(f"a weather map is an RGB or RGBA PNG, not {what}")
    if depth not in (8, 16):
        raise WeatherError(f"a weather map has 8 or 16 bits a sample, not {depth}")
    if width != height:
        raise WeatherError(f"a weather map is square, not {width}x{height}")
    if not MIN_SIDE <= width <= MAX_SIDE:
        raise WeatherError(f"a weather map's side is {MIN_SIDE} .. {MAX_SIDE} pixels, not {width}")


def load_weather(path: str | os.PathLike) -> np.ndarray:
    """The weather map in the PNG at path, (n, n, 3) float32 in 0..1 ([y, x], top row first); WeatherError for
    anything else."""
    try:
        data = read_regular_bytes(path, MAX_BYTES)
    except OSError as exc:
        raise WeatherError(f"cannot read {os.fspath(path)}: {exc.strerror or exc}") from None
    _check_header(data)
    try:
        rgba = decode_png(data)
    except OSError as exc:
        raise WeatherError(f"cannot decode {os.fspath(path)}: {exc}") from None
    side = _IHDR.unpack_from(data, len(_SIGNATURE))[2]
    if rgba.shape[:2] != (side, side):  # what the header promised is what was checked
        raise WeatherError(f"{os.fspath(path)} decodes to {rgba.shape[1]}x{rgba.shape[0]}, not its header's size")
    return rgba[..., :3].astype(np.float32) / np.float32(255)


def save_weather(path: str | os.PathLike, weather: np.ndarray) -> None:
    """weather, (n, n, 3) in 0..1 (clamped), as an 8-bit RGB PNG written atomically."""
    a = np.asarray(weather, dtype=np.float64)
    if a.ndim != 3 or a.shape[0] != a.shape[1] or a.shape[2] != 3 or not MIN_SIDE <= a.shape[0] <= MAX_SIDE:
        raise WeatherError(f"a weather map is (n, n, 3) with n in {MIN_SIDE} .. {MAX_SIDE}, not {a.shape}")
    if not np.isfinite(a).all():
        raise WeatherError("a weather map's values must be finite")
    rgb = np.round(np.clip(a, 0, 1) * 255).astype(np.uint8)
    buffer = io.BytesIO()
    Image.fromarray(rgb).save(buffer, "PNG")
    write_bytes(path, buffer.getvalue())
