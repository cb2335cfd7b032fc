"""The grid index answers exactly what a test of every box answers, and counts the work it did."""
import numpy as np
import pytest

from app.model.lighting2d.spatial import GridIndex


@pytest.mark.parametrize("n", [0, 1, 7, 2000])
def test_queries_match_testing_every_box(n):
    rng = np.random.default_rng(n)
    lo = rng.uniform(-1000, 1000, (n, 2))
    size = rng.exponential(30, (n, 2)) + (rng.random((n, 1)) < 0.1) * rng.exponential(800, (n, 2))  # a few big
    boxes = np.concatenate([lo, lo + size], axis=1)
    grid = GridIndex(boxes)
    for _ in range(200):
        a = rng.uniform(-1200, 1200, 2)
        b = a + rng.exponential(200, 2) + (rng.random() < 0.05) * 50_000  # now and then wider than everything
        want = np.flatnonzero((boxes[:, 0] <= b[0]) & (boxes[:, 2] >= a[0]) & (boxes[:, 1] <= b[1])
                              & (boxes[:, 3] >= a[1]))
        assert np.array_equal(grid.query(*a, *b), want)


def test_a_point_far_from_every_box_visits_one_cell_and_tests_no_box():
    rng = np.random.default_rng(0)
    corners = rng.uniform(5_000, 15_000, (10_000, 2))
    grid = GridIndex(np.concatenate([corners, corners + 12], axis=1))
    assert len(grid.query(0.0, 0.0, 0.0, 0.0)) == 0
    assert (grid.cells_visited, grid.boxes_tested) == (1, 0)
    assert len(grid.query(5_000, 5_000, 15_012, 15_012)) == 10_000 and grid.boxes_tested == 10_000
