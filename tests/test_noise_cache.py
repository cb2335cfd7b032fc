"""The noise cache: built once then loaded; damaged files, folders and FIFOs rebuilt; atomic writes."""
from __future__ import annotations

import hashlib
import io
import os

import numpy as np
import pytest

from app.io.clouds import noise_cache
from app.io.clouds.noise_cache import cache_path, load_or_build

SHAPE = (4, 4, 4)


class Builder:
    def __init__(self, value: float = 0.5) -> None:
        self.calls = 0
        self.value = value

    def __call__(self) -> np.ndarray:
        self.calls += 1
        return np.arange(64, dtype=np.float32).reshape(SHAPE) * np.float32(self.value)


def load(cache_dir, build, version=1, **kw):
    kw.setdefault("shape", SHAPE)
    return load_or_build("shape", build, cache_dir, version, **kw)


def test_builds_once_then_loads_without_building(tmp_path):
    build = Builder()
    first = load(tmp_path / "a" / "noise", build)  # the missing folder is made
    second = load(tmp_path / "a" / "noise", build)
    assert build.calls == 1
    assert np.array_equal(first, second) and second.dtype == np.float32 and second.shape == SHAPE
    assert [p.name for p in (tmp_path / "a" / "noise").iterdir()] == ["shape-v1.noise"]


def test_a_new_version_builds_a_new_file(tmp_path):
    build = Builder()
    load(tmp_path, build, version=1)
    load(tmp_path, build, version=2)
    load(tmp_path, build, version=2)
    assert build.calls == 2
    assert sorted(p.name for p in tmp_path.iterdir()) == ["shape-v1.noise", "shape-v2.noise"]


def damage_truncate(path):
    data = path.read_bytes()
    path.write_bytes(data[: len(data) - 7])


def damage_flip_a_data_byte(path):
    data = bytearray(path.read_bytes())
    data[-5] ^= 0x40
    path.write_bytes(bytes(data))


def damage_flip_a_digest_byte(path):
    data = bytearray(path.read_bytes())
    data[len(noise_cache.MAGIC) + 3] ^= 0x01
    path.write_bytes(bytes(data))


def damage_empty(path):
    path.write_bytes(b"")


def damage_garbage(path):
    path.write_bytes(b"\x93NUMPY not really")


def damage_wrong_shape(path):
    path.write_bytes(noise_cache.encode(np.zeros((4, 4, 2), np.float32)))


def damage_wrong_dtype(path):
    path.write_bytes(noise_cache.encode(np.zeros(SHAPE, np.float64)))


def damage_object_array(path):
    """A pickled object array with a valid header and digest: loading it must not unpickle anything."""
    buf = io.BytesIO()
    np.save(buf, np.array([None] * 64, dtype=object).reshape(SHAPE), allow_pickle=True)
    body = buf.getvalue()
    path.write_bytes(noise_cache.MAGIC + hashlib.sha256(body).hexdigest().encode() + b"\n" + body)


def damage_too_big(path):
    path.write_bytes(path.read_bytes() + b"\0" * (noise_cache.NPY_HEADER_MAX + 64 * 4))


def damage_directory(path):
    path.unlink()
    path.mkdir()


def damage_fifo(path):
    path.unlink()
    os.mkfifo(path)


DAMAGE = [damage_truncate, damage_flip_a_data_byte, damage_flip_a_digest_byte, damage_empty, damage_garbage,
          damage_wrong_shape, damage_wrong_dtype, damage_object_array, damage_too_big, damage_directory, damage_fifo]


@pytest.mark.parametrize("damage", DAMAGE, ids=lambda f: f.__name__.removeprefix("damage_"))
def test_a_damaged_file_is_rebuilt_and_overwritten(tmp_path, damage):
    load(tmp_path, Builder())
    damage(cache_path("shape", tmp_path, 1))
    build = Builder(value=2.0)  # a different array, so what comes back is the rebuilt one
    got = load(tmp_path, build)
    assert build.calls == 1
    assert np.array_equal(got, Builder(2.0)())
    again = Builder()
    assert np.array_equal(load(tmp_path, again), got)  # the rebuilt file was written over the damaged one
    assert again.calls == 0


def test_a_folder_with_files_in_the_way_still_returns_the_array(tmp_path):
    path = cache_path("shape", tmp_path, 1)
    path.mkdir()
    (path / "keep").write_text("someone's")
    build = Builder()
    assert np.array_equal(load(tmp_path, build), Builder()())
    assert (path / "keep").read_text() == "someone's"
    load(tmp_path, build)
    assert build.calls == 2  # nothing could be cached


def test_a_symlink_in_place_of_the_file_is_replaced_not_written_through(tmp_path):
    outside = tmp_path / "outside.txt"
    outside.write_text("not yours")
    cache = tmp_path / "cache"
    cache.mkdir()
    cache_path("shape", cache, 1).symlink_to(outside)
    build = Builder()
    load(cache, build)
    assert outside.read_text() == "not yours"
    assert not cache_path("shape", cache, 1).is_symlink()
    load(cache, build)
    assert build.calls == 1


def test_the_write_is_atomic_and_leaves_no_temporary_files(tmp_path, monkeypatch):
    load(tmp_path, Builder())
    damage_flip_a_data_byte(cache_path("shape", tmp_path, 1))
    load(tmp_path, Builder())
    assert [p.name for p in tmp_path.iterdir()] == ["shape-v1.noise"]
    calls = []
    real = noise_cache.atomic.write_bytes
    monkeypatch.setattr(noise_cache.atomic, "write_bytes", lambda path, data: calls.append(path) or real(path, data))
    load_or_build("detail", Builder(), tmp_path, 1, shape=SHAPE)
    assert calls == [cache_path("detail", tmp_path, 1)]


def test_an_unwritable_cache_still_returns_the_array(tmp_path, monkeypatch):
    def fail(path, data):
        raise OSError(28, "No space left on device", str(path))

    monkeypatch.setattr(noise_cache.atomic, "write_bytes", fail)
    assert np.array_equal(load(tmp_path, Builder()), Builder()())


def test_a_build_of_the_wrong_shape_or_dtype_is_a_programming_error(tmp_path):
    with pytest.raises(ValueError, match="expected"):
        load(tmp_path, lambda: np.zeros((2, 2), np.float32))
    with pytest.raises(ValueError, match="expected"):
        load(tmp_path, lambda: np.zeros(SHAPE, np.float64))


def test_without_a_shape_any_shape_is_accepted(tmp_path):
    build = Builder()
    load(tmp_path, build, shape=None)
    assert load(tmp_path, build, shape=None).shape == SHAPE
    assert build.calls == 1


@pytest.mark.parametrize("name", ["", "../up", ".hidden", "a/b", "sp ace"])
def test_names_stay_inside_the_cache_folder(tmp_path, name):
    with pytest.raises(ValueError):
        cache_path(name, tmp_path, 1)


@pytest.mark.parametrize("values, reason", [
    (np.nan, "64 values are NaN or infinite"),
    (np.inf, "64 values are NaN or infinite"),
    (2.0, "values 2..2, expected within 0..1"),
])
def test_values_not_finite_or_out_of_range_are_rebuilt_with_a_message(tmp_path, values, reason):
    """The digest only shows the file is whole: anyone who can write the cache can write a matching one."""
    path = cache_path("shape", tmp_path, 1)
    path.write_bytes(noise_cache.encode(np.full(SHAPE, values, dtype=np.float32)))  # a good digest of bad values
    said = []
    got = load(tmp_path, Builder(1 / 64), within=(0.0, 1.0), warn=said.append)
    assert np.isfinite(got).all() and got.max() <= 1.0
    assert said == [f"rebuilding the noise cache {path}: {reason}"]
    assert np.array_equal(noise_cache.decode(path.read_bytes(), SHAPE, np.dtype(np.float32), (0.0, 1.0)), got)
