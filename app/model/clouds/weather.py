"""Weather maps for the clouds and the blend from one to the next.

A weather map is (n, n, 3) float32 in 0..1, sampled with GL_REPEAT: R coverage, G cloud type (0 stratus, 0.5
stratocumulus, 1 cumulus), B precipitation. weather_map() follows the seed's (jaagupku/volumetric-clouds)
WeatherSystem shader, made tileable: every noise is periodic with a whole number of cells per tile (the seed's
map is a window onto endless noise, shown with mirrored wrapping).
"""
from __future__ import annotations

import itertools

import numpy as np

from app.model.clouds.noise import Progress, _check_size, _Steps, simplex, smoothstep, worley

# (cells per tile, weight): the seed's simplex fBm, its frequencies whole numbers already (a simplex tile may hold
# any whole number of cells).
SIMPLEX_OCTAVES = ((2, 1.0), (9, 0.2), (18, 0.09), (24, 0.05))
SIMPLEX_SUM = 1.34  # the weights' sum: the seed divides by it
# The seed's Worley fBm at 4, 9 and 19 cells, rounded to 4, 8 and 16: Worley's blocked lattice needs a frequency
# that divides the (power of two) size.
CELL_OCTAVES = ((4, 1.0), (8, 0.4), (16, 0.1))
PRECIPITATION_FREQUENCY = 1  # the seed's, one rain cell per tile
TYPE_HIGH_FREQUENCIES = (2, 1)  # the seed's
TYPE_MEDIUM_FREQUENCY = 1  # the seed's 0.3: under one cell per tile cannot repeat, so one
# The seed draws its Worley amplitude offset z (_Randomness.z) from this range for every new map: cells scaled by
# z + 1 for coverage, z + 3 for rain, z + 2.5 for the high type and z for the medium type.
AMPLITUDE_RANGE = (-0.2, 1.3)


def _inverted_worley(size: int, frequency: int, rng: np.random.Generator, amplitude: float) -> np.ndarray:
    """The seed's invertedWorley: 1 - amplitude d, d the distance to the nearest feature point in cells (clipped
    to 1 here, and not in the seed; a texel that far from every point is rare, and amplitudes of 1 or more make it
    0 or less either way)."""
    w = worley(size, frequency, rng, dim=2)
    return 1 - np.float32(amplitude) * w


def _remap_to_one(x: np.ndarray, low: np.ndarray) -> np.ndarray:
    """The seed's remap(x, low, 1, 0, 1). Where low is 1 the shader divides by zero and its saturate turns the
    result to 0; a tiny divisor gives the same after the clamps that follow."""
    return (x - low) / np.maximum(1 - low, np.float32(1e-6))


def weather_map(seed: int, size: int = 256, progress: Progress | None = None) -> np.ndarray:
    """A tileable weather map, (size, size, 3) float32 in 0..1 ([y, x], channels coverage, type, precipitation),
    the same for the same seed; size a power of two."""
    _check_size(size)
    rng = np.random.default_rng(seed)
    z = float(rng.uniform(*AMPLITUDE_RANGE))
    steps = _Steps(progress, len(SIMPLEX_OCTAVES) + len(CELL_OCTAVES) + 1 + len(TYPE_HIGH_FREQUENCIES) + 2)

    noise = np.zeros((size, size), np.float32)
    for frequency, weight in SIMPLEX_OCTAVES:
        noise += np.float32(weight) * simplex(size, frequency, rng)
        steps.step()
    base = np.clip((noise * 0.5 + 0.5) / SIMPLEX_SUM, 0, 1)  # the seed's saturate(simplexNoise / 1.34)

    cell = np.zeros((size, size), np.float32)
    for frequency, weight in CELL_OCTAVES:
        cell += np.float32(weight) * _inverted_worley(size, frequency, rng, z + 1)
        steps.step()
    coverage = _remap_to_one(base, np.clip(1 - cell / 1.5, 0, 1))
    coverage = np.clip(coverage * 0.55 + 0.65, 0, 1)

    # The seed's render target is 8-bit, which clamps its (unclamped) rain to 0..1.
    rain = np.clip(_inverted_worley(size, PRECIPITATION_FREQUENCY, rng, z + 3), 0, 1) * coverage
    steps.step()

    high = np.zeros((size, size), np.float32)
    for frequency in TYPE_HIGH_FREQUENCIES:
        high += _inverted_worley(size, frequency, rng, z + 2.5)
        steps.step()
    kind = smoothstep(0.1, 0.6, _remap_to_one(base, np.clip(1 - np.minimum(high, 1), 0, 1))) * 0.5
    # Two medium fields averaged. The seed's second remaps the first's result where it means its own Worley noise
    # (typeMed for typeMed2, a slip); each is its own here.
    for _ in range(2):
        medium = _inverted_worley(size, TYPE_MEDIUM_FREQUENCY, rng, z)
        kind += 0.5 * smoothstep(0.1, 0.6, _remap_to_one(base, np.clip(1 - medium, 0, 1)))
        steps.step()
    kind = np.clip(kind, 0, 1)

    return np.stack([coverage, kind, rain], axis=-1).astype(np.float32)


def _resample_axis(a: np.ndarray, size: int, axis: int) -> np.ndarray:
    n = a.shape[axis]
    k = max(1, round(n / size))  # the box filter's width, old texels: one new texel's footprint when shrinking
    # Each new texel centre in old texels (GL's texel coordinate); a box of even width is centred half a texel
    # before the index it is stored at.
    c = (np.arange(size) + 0.5) * n / size - 0.5 + 0.5 * (1 - k % 2)
    i0 = np.floor(c).astype(np.int64)
    shape = [1] * a.ndim
    shape[axis] = size
    w = (c - i0).astype(np.float32).reshape(shape)

    def box(i: np.ndarray) -> np.ndarray:  # the mean of k texels, wrapping, at the indices i only
        return sum(np.take(a, (i - k // 2 + m) % n, axis=axis) for m in range(k)) / np.float32(k)

    return box(i0) * (1 - w) + box(i0 + 1) * w


def resample(weather: np.ndarray, size: int) -> np.ndarray:
    """A weather map (n, n, 3) at (size, size, 3) float32, as GL_REPEAT would show it: read linearly between texel
    centres with wrapping, after a box filter over one new texel's footprint when it shrinks (so a 2048 map made
    256 is the mean of each 8 x 8 block). A tileable map stays tileable; the values stay within the old ones'."""
    a = np.asarray(weather, dtype=np.float32)
    if a.ndim != 3 or a.shape[0] != a.shape[1] or a.shape[2] != 3 or size < 1:
        raise ValueError(f"a weather map is (n, n, 3) and a size at least 1, not {a.shape} and {size}")
    if a.shape[0] == size:
        return a.copy()
    return _resample_axis(_resample_axis(a, size, 0), size, 1).astype(np.float32)


# Versions are drawn from one counter, so a renderer shown another workspace state's blend never takes its
# maps for the ones it holds.
_VERSIONS = itertools.count(1)


class WeatherBlend:
    """The old and the new weather map and the new one's weight in time, rising linearly from 0 to 1 over the
    blend; the renderer draws mix(old, new, weight(clock)). Maps are read-only float32 copies of one shape."""

    def __init__(self, initial: np.ndarray) -> None:
        self._new = self._checked(initial, None)
        self._old = self._new
        self._start = 0.0
        self._duration = 0.0
        self._version = next(_VERSIONS)

    @staticmethod
    def _checked(weather: np.ndarray, shape: tuple[int, ...] | None) -> np.ndarray:
        a = np.array(weather, dtype=np.float32)  # a copy: a caller's later edits must not reach the maps
        if a.ndim != 3 or a.shape[0] != a.shape[1] or a.shape[2] != 3:
            raise ValueError(f"a weather map is (n, n, 3), not {a.shape}")
        if shape is not None and a.shape != shape:
            raise ValueError(f"a new weather map must be {shape} like the old, not {a.shape}")
        a.setflags(write=False)
        return a

    @property
    def maps(self) -> tuple[np.ndarray, np.ndarray]:
        """(old, new)."""
        return self._old, self._new

    @property
    def version(self) -> int:
        """Changes whenever the maps do, and no two blends share one: a renderer uploads the maps again when
        it differs from the one it has (whichever blend that came from)."""
        return self._version

    def weight(self, clock: float) -> float:
        """The new map's weight at time clock, in 0..1: 0 until the blend starts, 1 once it is over."""
        if self._duration <= 0:
            return 1.0
        return min(max((clock - self._start) / self._duration, 0.0), 1.0)

    def done(self, clock: float) -> bool:
        return self.weight(clock) >= 1.0

    def current(self, clock: float) -> np.ndarray:
        """What is on screen at clock: mix(old, new, weight), as the shader's mix computes it."""
        w = self.weight(clock)
        if w >= 1.0:
            return self._new
        if w <= 0.0:
            return self._old
        return self._old * np.float32(1 - w) + self._new * np.float32(w)

    def snapshot(self) -> tuple:
        """The maps and the blend's timing, for undo (the maps are read-only: no copies)."""
        return self._old, self._new, self._start, self._duration

    def restore(self, state: tuple) -> None:
        """Put back what snapshot() gave, under a new version: a renderer holding any earlier version uploads."""
        self._old, self._new, self._start, self._duration = state
        self._version = next(_VERSIONS)

    def begin(self, new_map: np.ndarray, clock: float, duration: float) -> None:
        """Blend to new_map from time clock over duration seconds (0: at once). During a blend the old map
        becomes what is on screen now, so the weather never jumps."""
        if not (np.isfinite(clock) and np.isfinite(duration)) or duration < 0:
            raise ValueError(f"a blend needs a finite clock and a duration >= 0, not {clock}, {duration}")
        new = self._checked(new_map, self._new.shape)
        self._old = self.current(clock)
        self._old.setflags(write=False)
        self._new = new
        self._start = float(clock)
        self._duration = float(duration)
        self._version = next(_VERSIONS)
