"""Weather maps, their blend, blue noise, cirrus and weather PNGs: tileable, deterministic per seed, in range; the
blend linear and without jumps; bad files refused with a WeatherError and nothing else."""
from __future__ import annotations

import numpy as np
import pytest

from app.model import cloud_noise as cn


def seam_ratio(a: np.ndarray, axis: int) -> float:
    """Mean |difference| across the wrap seam (last texel to first) over the mean between interior neighbours."""
    n = a.shape[axis]
    seam = np.abs(np.take(a, 0, axis) - np.take(a, n - 1, axis)).mean()
    inner = np.abs(np.diff(a, axis=axis)).mean()
    return float(seam / inner) if inner > 0 else float(seam > 0) * np.inf


# The noises it is made of


@pytest.mark.parametrize("frequency", [1, 2, 5, (3, 7)])
def test_simplex_wraps_and_stays_about_within_one(frequency):
    a = cn.simplex(48, frequency, np.random.default_rng(2))  # any size: no blocked lattice
    assert a.shape == (48, 48) and a.dtype == np.float32
    assert np.abs(a).max() <= 1.05 and a.std() > 0.1
    for axis in range(2):
        assert seam_ratio(a, axis) < 1.5, axis


def test_simplex_is_one_function_sampled_at_texel_centres():
    """Texel j of 16 and texel 3j + 1 of 48 share a centre, (2j + 1) / 32 of the tile: the same value there."""
    small, large = (cn.simplex(n, (2, 3), np.random.default_rng(0)) for n in (16, 48))
    np.testing.assert_allclose(large[1::3, 1::3], small, atol=1e-6)


def brute_force_worley_2d(size: int, frequency: int, seed: int) -> np.ndarray:
    points = np.random.default_rng(seed).random((frequency, frequency, 2), dtype=np.float32).astype(np.float64)
    cells = np.stack(np.meshgrid(np.arange(frequency), np.arange(frequency), indexing="ij"), axis=-1)
    features = (cells + points).reshape(-1, 2)
    centres = (np.stack(np.meshgrid(np.arange(size), np.arange(size), indexing="ij"), axis=-1) + 0.5)
    d = (centres * frequency / size).reshape(-1, 1, 2) - features[None]
    d -= frequency * np.round(d / frequency)
    return np.minimum(np.sqrt((d ** 2).sum(-1)).min(1), 1.0).reshape(size, size)


@pytest.mark.parametrize("frequency", [1, 2, 4, 8])
def test_2d_worley_equals_a_brute_force_search(frequency):
    got = cn.worley(16, frequency, np.random.default_rng(5), dim=2)
    np.testing.assert_allclose(got, brute_force_worley_2d(16, frequency, 5), atol=1e-5)


def test_stretched_perlin_wraps_with_its_own_period_per_axis():
    a = cn.perlin(64, (16, 2), np.random.default_rng(0), dim=2)
    for axis in range(2):
        assert seam_ratio(a, axis) < 1.5
    assert np.abs(np.diff(a, axis=0)).mean() > 4 * np.abs(np.diff(a, axis=1)).mean()  # finer across y
