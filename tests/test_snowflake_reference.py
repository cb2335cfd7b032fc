"""The CPU Koch polyline: counts, geometry, and fractional levels between integers."""
import math

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from app.model.snowflake import Flake, split_level
from app.reference.snowflake import polyline, segments


@pytest.mark.parametrize("level", range(0, 7))
def test_vertex_count_and_closed(level):
    p = polyline(0.0, 0.0, 1.0, level)
    assert len(p) == 3 * 4 ** level + 1  # the seed's count
    np.testing.assert_allclose(p[0], p[-1], atol=1e-12)


@pytest.mark.parametrize("level", range(0, 6))
def test_perimeter_grows_by_four_thirds(level):
    p = polyline(0.0, 0.0, 1.0, level)
    perimeter = np.linalg.norm(np.diff(p, axis=0), axis=1).sum()
    assert perimeter == pytest.approx(3 * math.sqrt(3) * (4 / 3) ** level, rel=1e-12)


def test_level_one_is_the_hexagram():
    p = polyline(0.0, 0.0, 1.0, 1)
    radii = np.linalg.norm(p[:-1], axis=1)
    # tips on the circumcircle, inner corners at 1/sqrt(3) of it
    np.testing.assert_allclose(sorted(radii)[-6:], 1.0, rtol=1e-12)
    np.testing.assert_allclose(sorted(radii)[:6], 1 / math.sqrt(3), rtol=1e-12)


def test_split_level():
    assert split_level(0) == (0, 1.0)
    assert split_level(3) == (3, 1.0)
    assert split_level(2.25) == (3, pytest.approx(0.25))


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 4), st.floats(0.0, 1.0))
def test_fractional_level_interpolates_linearly(n, t):
    """Level n + t is the vertex-wise blend of level n (upsampled) and level n + 1."""
    lo = polyline(0.3, -0.2, 0.7, n + 1e-12 if n else 1e-12)  # the level n+1 outline with flat peaks
    hi = polyline(0.3, -0.2, 0.7, n + 1)
    mid = polyline(0.3, -0.2, 0.7, n + max(t, 1e-12))
    np.testing.assert_allclose(mid, lo + (hi - lo) * max(t, 1e-12), atol=1e-9)


def test_level_n_vertices_stay_on_level_n_plus_one():
    a, b = polyline(0, 0, 1, 3), polyline(0, 0, 1, 4)
    np.testing.assert_allclose(b[::4], a, atol=1e-12)


def test_segments_concatenate_flakes_in_order():
    flakes = [Flake(0, 0, 1), Flake(5, 0, 0.5)]
    s = segments(flakes, 2)
    assert s.shape == (2 * 48, 2, 2)
    np.testing.assert_allclose(s[48:].mean(axis=(0, 1)), (5, 0), atol=1e-9)
