"""PNG output through QtGui's QImage (no widgets, no display needed)."""
from __future__ import annotations

import os

import numpy as np
from PySide6.QtCore import QBuffer, QByteArray, QIODevice
from PySide6.QtGui import QImage

from app.io.atomic import write_bytes


def encode_png(rgba: np.ndarray) -> bytes:
    """RGBA uint8 (height, width, 4), top row first."""
    rgba = np.ascontiguousarray(rgba, dtype=np.uint8)
    h, w = rgba.shape[:2]
    image = QImage(rgba.data, w, h, 4 * w, QImage.Format.Format_RGBA8888)
    data = QByteArray()
    buffer = QBuffer(data)
    buffer.open(QIODevice.OpenModeFlag.WriteOnly)
    if not image.save(buffer, "PNG"):
        raise OSError("PNG encoding failed")
    return bytes(data.data())


def write_png(path: str | os.PathLike, rgba: np.ndarray) -> None:
    write_bytes(path, encode_png(rgba))


def read_png(path: str | os.PathLike) -> np.ndarray:
    image = QImage(os.fspath(path))
    if image.isNull():
        raise OSError(f"cannot read image {path}")
    return _rgba(image)


def decode_png(data: bytes) -> np.ndarray:
    """An image file's bytes (PNG, or another format Qt reads) as RGBA uint8; OSError if they are none."""
    image = QImage.fromData(data)
    if image.isNull():
        raise OSError("not an image Qt can read")
    return _rgba(image)


def _rgba(image: QImage) -> np.ndarray:
    image = image.convertToFormat(QImage.Format.Format_RGBA8888)
    w, h = image.width(), image.height()
    return np.frombuffer(image.constBits(), np.uint8, count=h * image.bytesPerLine()).reshape(h, -1)[:, : 4 * w].reshape(h, w, 4).copy()
