"""Noise textures cached on disk: built once, then loaded, with any damaged file rebuilt.

One file per texture, `<name>-v<version>.noise` in the cache folder (the product's is
`default_cache_dir().parent / "noise"`, passed in by the caller: io does not import gl). Its layout:

    b"SHADELAB-NOISE 1\\n" + 64 hex digits (SHA-256 of the rest) + b"\\n" + the array as a .npy file

The file is written atomically (app.io.atomic) and read through app.io.regular_file with a size bound from the
expected shape, so a FIFO, a device or a folder in its place is refused rather than waited on or read for ever.
A missing, truncated, corrupt (digest), wrong-shape or wrong-dtype file is rebuilt and overwritten, and so is one
whose values are not all finite and within the range the recipe makes: the digest only shows the file is whole,
and anyone who can write the cache can write a matching one. Bumping `version` (the recipe changed) leaves the
old file where it is and builds a new one.
"""
from __future__ import annotations

import errno
import hashlib
import io
import logging
import math
import os
import re
from pathlib import Path
from typing import Callable

import numpy as np

from app.io import atomic
from app.io.regular_file import read_regular_bytes

log = logging.getLogger(__name__)

MAGIC = b"SHADELAB-NOISE 1\n"
_DIGEST_LEN = 64
_HEADER_LEN = len(MAGIC) + _DIGEST_LEN + 1
NPY_HEADER_MAX = 4096  # a .npy header is a few hundred bytes at most for a plain array
MAX_BYTES_ANY_SHAPE = 256 << 20  # the bound when no shape is given
_NAME = re.compile(r"[A-Za-z0-9_.-]+")


class CacheError(ValueError):
    """A cached file that cannot be used; the message says why."""


def cache_path(name: str, cache_dir: Path, version: int) -> Path:
    if not _NAME.fullmatch(name) or name.startswith("."):
        raise ValueError(f"a noise cache name is letters, digits, '_', '.' and '-': {name!r}")
    return Path(cache_dir) / f"{name}-v{int(version)}.noise"


def encode(array: np.ndarray) -> bytes:
    buf = io.BytesIO()
    np.save(buf, np.ascontiguousarray(array), allow_pickle=False)
    body = buf.getvalue()
    return MAGIC + hashlib.sha256(body).hexdigest().encode("ascii") + b"\n" + body


def decode(data: bytes, shape: tuple[int, ...] | None, dtype: np.dtype,
           within: tuple[float, float] | None = None) -> np.ndarray:
    """The array in a cache file's bytes; CacheError if it is not exactly what was expected, or (`within`) holds
    a value that is not finite or outside lo..hi."""
    if not data.startswith(MAGIC) or len(data) < _HEADER_LEN or data[_HEADER_LEN - 1:_HEADER_LEN] != b"\n":
        raise CacheError("not a noise cache file (no header)")
    body = data[_HEADER_LEN:]
    if hashlib.sha256(body).hexdigest().encode("ascii") != data[len(MAGIC):_HEADER_LEN - 1]:
        raise CacheError("the SHA-256 digest does not match (truncated or corrupt)")
    try:
        array = np.load(io.BytesIO(body), allow_pickle=False)
    except (ValueError, OSError, EOFError) as exc:
        raise CacheError(f"not a readable .npy array: {exc}") from exc
    if not isinstance(array, np.ndarray):
        raise CacheError("not a single array")
    if array.dtype != dtype:
        raise CacheError(f"dtype {array.dtype}, expected {dtype}")
    if shape is not None and array.shape != tuple(shape):
        raise CacheError(f"shape {array.shape}, expected {tuple(shape)}")
    if within is not None and array.size:
        lo, hi = within
        if not np.isfinite(array).all():
            raise CacheError(f"{np.count_nonzero(~np.isfinite(array))} values are NaN or infinite")
        if array.min() < lo or array.max() > hi:
            raise CacheError(f"values {array.min():g}..{array.max():g}, expected within {lo:g}..{hi:g}")
    return array


def _max_bytes(shape: tuple[int, ...] | None, dtype: np.dtype) -> int:
    if shape is None:
        return MAX_BYTES_ANY_SHAPE
    return _HEADER_LEN + NPY_HEADER_MAX + math.prod(shape) * dtype.itemsize


def _clear_for_write(path: Path) -> bool:
    """Make room for a new file at path: an empty folder or a symlink there goes (the file is written in the
    cache folder, never through a link); False when something else is in the way (a folder with files)."""
    if path.is_symlink():
        path.unlink()
    elif path.is_dir():
        try:
            path.rmdir()
        except OSError:
            return False
    return True


def load_or_build(name: str, build: Callable[[], np.ndarray], cache_dir: Path, version: int, *,
                  shape: tuple[int, ...] | None = None, dtype: np.dtype | type = np.float32,
                  within: tuple[float, float] | None = None, warn: Callable[[str], None] | None = None) -> np.ndarray:
    """The cached array `name` (recipe `version`), or build()'s result, saved for next time.

    shape: the expected shape (it also bounds the bytes read); None accepts any shape up to
    MAX_BYTES_ANY_SHAPE. dtype: the expected dtype, which build() must return. within: (lo, hi) every value
    must lie in, finite (None: any). A file that cannot be used is rebuilt and overwritten; a cache that cannot be
    written (a read-only folder, a full disk) is left and the built array returned all the same. Either is said
    to `warn` (a host's console), else logged.
    """
    say = warn or log.warning
    dtype = np.dtype(dtype)
    path = cache_path(name, cache_dir, version)
    try:
        return decode(read_regular_bytes(path, _max_bytes(shape, dtype)), shape, dtype, within)
    except FileNotFoundError:
        pass
    except (OSError, CacheError) as exc:
        reason = exc.strerror if isinstance(exc, OSError) and exc.strerror else str(exc)
        say(f"rebuilding the noise cache {path}: {reason}")

    array = np.asarray(build())
    if array.dtype != dtype or (shape is not None and array.shape != tuple(shape)):
        raise ValueError(f"{name}: build() gave {array.dtype} {array.shape}, expected {dtype} {shape}")
    try:
        if not _clear_for_write(path):
            raise OSError(errno.EEXIST, "a folder with files is in the way", os.fspath(path))
        atomic.write_bytes(path, encode(array))
    except OSError as exc:
        say(f"cannot write the noise cache {path}: {exc.strerror or exc}")
    return array
