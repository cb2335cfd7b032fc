"""A tileable blue-noise dither matrix by void-and-cluster (Ulichney 1993), for the cloud march's per-pixel jitter.

Every pixel gets a rank, the order in which it would be switched on in a binary pattern that stays as evenly
spread as possible at every density; the even spread is judged by an energy, each "on" pixel's Gaussian summed
over the torus, so the matrix tiles with no seam. Keeping the energy up to date costs one slice-add of the
precomputed kernel per pixel switched, O(size^2) numpy work a step.
"""
from __future__ import annotations

import numpy as np

SIGMA = 1.5  # Ulichney's Gaussian, in pixels
INITIAL_FRACTION = 0.1  # the share of pixels in the first random pattern


class _Pattern:
    """A binary pattern on the torus and its energy: each "on" pixel's Gaussian, summed."""

    def __init__(self, size: int) -> None:
        self.size = size
        d = np.arange(size)
        d = np.minimum(d, size - d)  # the toroidal distance from pixel 0
        g = np.exp(-(d * d) / (2 * SIGMA * SIGMA))
        # The kernel around pixel 0, tiled 2 x 2: the kernel around (y, x) is then one slice of it.
        self._tiled = np.tile(np.outer(g, g), (2, 2))
        self.on = np.zeros((size, size), bool)
        self.energy = np.zeros((size, size))

    def kernel_at(self, flat: int) -> np.ndarray:
        y, x = divmod(int(flat), self.size)
        n = self.size
        return self._tiled[n - y:2 * n - y, n - x:2 * n - x]

    def switch(self, flat: int, on: bool) -> None:
        if on:
            self.energy += self.kernel_at(flat)
        else:
            self.energy -= self.kernel_at(flat)
        self.on.flat[flat] = on

    def tightest_cluster(self) -> int:
        """The "on" pixel with the most energy."""
        return int(np.argmax(np.where(self.on, self.energy, -np.inf)))

    def largest_void(self) -> int:
        """The "off" pixel with the least energy."""
        return int(np.argmin(np.where(self.on, np.inf, self.energy)))


def blue_noise(size: int = 64, seed: int = 0) -> np.ndarray:
    """(size, size) float32: every rank 0 .. size^2 - 1 once, as (rank + 0.5) / size^2 in (0, 1); tileable; the
    same for the same seed."""
    if size < 2:
        raise ValueError(f"a blue-noise size is at least 2, not {size}")
    n = size * size
    pattern = _Pattern(size)
    count = max(1, round(INITIAL_FRACTION * n))
    for flat in np.random.default_rng(seed).choice(n, count, replace=False):
        pattern.switch(flat, True)
    # The initial pattern: move the tightest cluster into the largest void until it would come straight back
    # (bounded: a cycle of moves, never seen, would otherwise never end).
    for _ in range(n):
        cluster = pattern.tightest_cluster()
        pattern.switch(cluster, False)
        void = pattern.largest_void()
        pattern.switch(void, True)
        if void == cluster:
            break
    # The initial pattern's "off" pixels and their energy, "on" ones out of the running, for the second phase.
    void_energy = np.where(pattern.on, np.inf, pattern.energy).ravel()

    ranks = np.empty(n, np.int64)
    # Ranks below count: take the tightest cluster out of the initial pattern, one at a time.
    for rank in range(count - 1, -1, -1):
        cluster = pattern.tightest_cluster()
        pattern.switch(cluster, False)
        ranks[cluster] = rank
    # Ranks from count up: fill the largest void. Past half full Ulichney fills the tightest cluster of "off"
    # pixels instead, which is the same pixel: the "off" pixels' energy is the kernel's sum less this one.
    for rank in range(count, n):
        void = int(np.argmin(void_energy))
        void_energy += pattern.kernel_at(void).ravel()
        void_energy[void] = np.inf
        ranks[void] = rank
    return ((ranks + 0.5) / n).reshape(size, size).astype(np.float32)
