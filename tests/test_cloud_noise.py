"""Cloud noise textures: tileable, in range, deterministic per seed, a divergence-free curl, progress to 1.0."""
from __future__ import annotations

import itertools

import numpy as np
import pytest

from app.model.clouds import noise as cn


def seam_ratio(a: np.ndarray, axis: int) -> float:
    """Mean |difference| across the wrap seam (last texel to first) over the mean between interior neighbours."""
    n = a.shape[axis]
    seam = np.abs(np.take(a, 0, axis) - np.take(a, n - 1, axis)).mean()
    inner = np.abs(np.diff(a, axis=axis)).mean()
    return float(seam / inner)


@pytest.fixture(scope="module")
def shape16():
    return cn.shape_noise(16, seed=3)


@pytest.fixture(scope="module")
def detail16():
    return cn.detail_noise(16, seed=3)


@pytest.fixture(scope="module")
def curl32():
    return cn.curl_noise(32, seed=3)


def test_shapes_dtypes_and_ranges(shape16, detail16, curl32):
    for a in (shape16, detail16):
        assert a.shape == (16, 16, 16) and a.dtype == np.float32
        assert a.min() == 0.0 and a.max() == 1.0
        assert 0.1 < a.std()
    assert curl32.shape == (32, 32, 2) and curl32.dtype == np.float32
    assert np.isfinite(curl32).all()
    assert np.abs(curl32).max() == pytest.approx(1.0)


@pytest.mark.parametrize("name", ["shape16", "detail16"])
def test_3d_textures_wrap(name, request):
    a = request.getfixturevalue(name)
    for axis in range(3):
        assert seam_ratio(a, axis) < 1.5, axis


def test_the_seam_ratio_catches_a_texture_that_does_not_wrap():
    ramp = np.linspace(0, 1, 16, dtype=np.float32)[None, None, :] * np.ones((16, 16, 1), np.float32)
    assert seam_ratio(ramp, 2) > 10
    half = cn.shape_noise(32, seed=3)[:16, :16, :16]  # a piece of a tiling texture does not tile
    assert max(seam_ratio(half, axis) for axis in range(3)) > 2


@pytest.mark.parametrize("frequency", [2, 4, 8])  # at 1 the seam is the only lattice crossing: nothing to compare
def test_perlin_wraps_and_is_smooth(frequency):
    a = cn.perlin(32, frequency, np.random.default_rng(0))
    for axis in range(3):
        assert seam_ratio(a, axis) < 1.5
    assert np.abs(a).max() <= 1.0


def test_2d_perlin_and_curl_wrap(curl32):
    p = cn.perlin(32, 4, np.random.default_rng(1), dim=2)
    assert p.shape == (32, 32)
    for axis in range(2):
        assert seam_ratio(p, axis) < 1.5
        for c in range(2):
            assert seam_ratio(curl32[..., c], axis) < 1.5


def brute_force_worley(size: int, frequency: int, seed: int) -> np.ndarray:
    """The nearest of every feature point, with periodic distances: what the 27-cell search must equal."""
    points = np.random.default_rng(seed).random((frequency,) * 3 + (3,), dtype=np.float32).astype(np.float64)
    cells = np.stack(np.meshgrid(*[np.arange(frequency)] * 3, indexing="ij"), axis=-1)
    features = (cells + points).reshape(-1, 3)  # in cell units
    centres = (np.stack(np.meshgrid(*[np.arange(size)] * 3, indexing="ij"), axis=-1) + 0.5) * frequency / size
    d = centres.reshape(-1, 1, 3) - features[None]
    d -= frequency * np.round(d / frequency)  # the nearest periodic image
    return np.minimum(np.sqrt((d ** 2).sum(-1)).min(1), 1.0).reshape((size,) * 3)


@pytest.mark.parametrize("frequency", [1, 2, 4, 8])
def test_worley_equals_a_brute_force_search_over_all_points(frequency):
    got = cn.worley(8, frequency, np.random.default_rng(5))
    np.testing.assert_allclose(got, brute_force_worley(8, frequency, 5), atol=1e-5)


def test_worley_wraps():
    a = cn.worley(16, 4, np.random.default_rng(2))
    assert 0.0 <= a.min() and a.max() <= 1.0
    for axis in range(3):
        assert seam_ratio(a, axis) < 1.5


@pytest.mark.parametrize("make", [cn.shape_noise, cn.detail_noise, cn.curl_noise])
def test_same_seed_same_texture_other_seed_other_texture(make):
    a, b, c = make(16, seed=7), make(16, seed=7), make(16, seed=8)
    assert np.array_equal(a, b)
    assert not np.allclose(a, c)


def test_the_curl_field_has_no_divergence(curl32):
    u, v = curl32[..., 0].astype(np.float64), curl32[..., 1].astype(np.float64)
    du_dx = (np.roll(u, -1, axis=1) - np.roll(u, 1, axis=1)) / 2
    dv_dy = (np.roll(v, -1, axis=0) - np.roll(v, 1, axis=0)) / 2
    du_dy = (np.roll(u, -1, axis=0) - np.roll(u, 1, axis=0)) / 2
    divergence, vorticity = du_dx + dv_dy, np.abs(du_dy).mean()
    assert np.abs(divergence).max() < 1e-5 * vorticity * 100  # rounding only, next to a clearly non-zero rotation
    assert vorticity > 1e-3


@pytest.mark.parametrize("make", [cn.shape_noise, cn.detail_noise, cn.curl_noise])
def test_progress_rises_to_exactly_one(make):
    seen: list[float] = []
    make(16, seed=0, progress=seen.append)
    assert len(seen) >= 3
    assert all(0 < a <= b for a, b in itertools.pairwise(seen))
    assert seen[-1] == 1.0


@pytest.mark.parametrize("size", [0, 1, 12, 48])
def test_sizes_must_be_powers_of_two(size):
    with pytest.raises(ValueError, match="power of two"):
        cn.shape_noise(size)
