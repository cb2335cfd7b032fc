"""PNG output and image input through Pillow (no Qt, no display needed).

Every image comes back as RGBA uint8 (height, width, 4), row 0 at the top, whatever the file holds: palette,
greyscale and alpha-less images gain an opaque alpha channel (or the one their transparency key gives), and
16-bit samples are rounded to 8 bits. An image over MAX_PIXELS is refused from its header, before its pixels
are decoded.
"""
from __future__ import annotations

import io
import os
import warnings
from typing import BinaryIO

import numpy as np
from PIL import Image, UnidentifiedImageError

from app.io.atomic import write_bytes

# The formats read, about those Qt's image plugins read; Pillow's others (EPS through Ghostscript, PSD, FITS...)
# are not images a scene names.
FORMATS = ("PNG", "BMP", "JPEG", "GIF", "TGA", "TIFF", "WEBP", "PPM", "XBM", "XPM", "ICO", "ICNS")
# 8192 x 8192: 256 MiB as RGBA, the decoded size Qt's image reader allowed by default. Below Pillow's own
# decompression bomb bound (Image.MAX_IMAGE_PIXELS), so this is the one that refuses.
MAX_PIXELS = 1 << 26
_SIXTEEN_BIT = ("I", "I;16", "I;16L", "I;16B", "I;16N")  # Pillow's modes for 16-bit greyscale


def encode_png(rgba: np.ndarray) -> bytes:
    """RGBA uint8 (height, width, 4), top row first."""
    rgba = np.ascontiguousarray(rgba, dtype=np.uint8)
    if rgba.ndim != 3 or rgba.shape[2] != 4:
        raise ValueError(f"an RGBA image is (height, width, 4), not {rgba.shape}")
    buffer = io.BytesIO()
    try:
        Image.fromarray(rgba).save(buffer, "PNG")
    except (ValueError, OSError) as exc:
        raise OSError(f"PNG encoding failed: {exc}") from exc
    return buffer.getvalue()


def write_png(path: str | os.PathLike, rgba: np.ndarray) -> None:
    write_bytes(path, encode_png(rgba))


def read_png(path: str | os.PathLike) -> np.ndarray:
    """The image file at path (PNG, or another of FORMATS) as RGBA uint8; OSError if it cannot be read."""
    try:
        with open(path, "rb") as f:
            return _decode(f)
    except OSError as exc:
        raise OSError(f"cannot read image {os.fspath(path)}: {exc.strerror or exc}") from None


def decode_png(data: bytes) -> np.ndarray:
    """An image file's bytes (PNG, or another of FORMATS) as RGBA uint8; OSError if they are none."""
    return _decode(io.BytesIO(data))


def _decode(f: BinaryIO) -> np.ndarray:
    """OSError, with a message that says why, for anything but a readable image of at most MAX_PIXELS."""
    try:
        with warnings.catch_warnings():  # Pillow's warning of a big image: MAX_PIXELS below refuses it anyway
            warnings.simplefilter("ignore", Image.DecompressionBombWarning)
            image = Image.open(f, formats=FORMATS)  # the header only: load() decodes the pixels
    except UnidentifiedImageError:  # its message shows the file object's repr
        raise OSError("not an image Pillow can read") from None
    except (Image.DecompressionBombError, Image.DecompressionBombWarning) as exc:  # the warning under -W error
        raise OSError(f"an image over Pillow's decompression bomb bound: {exc}") from None
    except MemoryError:
        raise
    except Exception as exc:  # decoders raise anything (SyntaxError, ValueError, struct.error...) on a bad file
        raise OSError(_damaged(exc)) from None
    with image:
        width, height = image.size
        if width * height > MAX_PIXELS:
            side = int(MAX_PIXELS**0.5)
            raise OSError(f"a {width}x{height} image is over the limit of {MAX_PIXELS} pixels ({side}x{side})")
        try:
            image.load()
            return _rgba(image)
        except MemoryError:
            raise
        except Exception as exc:
            raise OSError(_damaged(exc)) from None


def _damaged(exc: Exception) -> str:
    return f"a damaged or unsupported image: {exc or type(exc).__name__}"


def _rgba(image: Image.Image) -> np.ndarray:
    if image.mode in _SIXTEEN_BIT:  # convert() would clip 16-bit samples to 255, not scale them
        grey = np.clip(np.asarray(image).astype(np.int64), 0, 0xFFFF)
        out = np.empty(grey.shape + (4,), np.uint8)
        out[..., :3] = ((grey * 255 + 0x7FFF) // 0xFFFF)[..., None]  # x / 257, rounded
        key = image.info.get("transparency")
        out[..., 3] = np.where(grey == key, 0, 255) if isinstance(key, int) else 255
        return out
    return np.array(image.convert("RGBA"), np.uint8)
