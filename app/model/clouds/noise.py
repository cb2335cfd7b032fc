"""Tileable noise textures for volumetric clouds (after Guerrilla's Nubis, as the seed jaagupku/volumetric-clouds
uses them): a 3D shape texture, a 3D detail texture, a 2D curl field and a 2D cirrus texture, made once and cached
(app.io.clouds.noise_cache); and the tileable Perlin, Worley and simplex noise they and the weather maps are made of.

Every texture wraps: its lattices (Perlin gradients, Worley feature points) are periodic with a whole number of
cells per tile, so texel 0 follows texel size-1 as smoothly as any two interior neighbours. All frequencies are
powers of two in cells per tile, so `size` must be a power of two; a frequency above `size` is clamped to it (one
cell per texel), which only happens at the small sizes tests use. Simplex noise, sampled point by point rather
than by blocks, takes any size and any whole frequency.

How it stays fast in numpy: the texture is viewed as (n, b, n, b, n, b), n cells of b texels per axis. Inside
a cell the texel's offset along one axis depends on that axis alone, and the lattice data (a gradient, a feature
point) on the cell alone, so each per-axis term is a small (n, 1, n, 1, n, b)-like array and only their sum is
full size. A Worley pass is 27 neighbour offsets x (two full-size adds and one minimum); a Perlin pass 8 corners x
about four full-size operations. Temporaries stay at two or three full-size float32 arrays (8 MiB each at 128^3).

Randomness comes from numpy's Generator (default_rng(seed)), drawn in a fixed order: one seed, one texture.
"""
from __future__ import annotations

import itertools
from collections.abc import Sequence
from typing import Callable

import numpy as np
from scipy import ndimage

Progress = Callable[[float], None]
Frequency = int | Sequence[int]  # cells per tile: one for every axis, or one per axis

# Worley fBm: octaves at f, 2f, 4f with these weights (Schneider's Nubis fBm weights, sum 1).
WORLEY_FBM_WEIGHTS = (0.625, 0.25, 0.125)
# The shape texture's four channels, summed with halving weights normalised to 1 (8, 4, 2, 1) / 15.
SHAPE_WEIGHTS = (8 / 15, 4 / 15, 2 / 15, 1 / 15)
# The detail texture's three channels, halving weights (4, 2, 1) / 7.
DETAIL_WEIGHTS = (4 / 7, 2 / 7, 1 / 7)
SHAPE_PERLIN_FREQUENCY = 4  # the Perlin fBm's lowest octave, cells per tile; octaves double up to half the size
SHAPE_WORLEY_FREQUENCIES = (4, 4, 8, 16)  # base frequency of the Worley fBm in R (with Perlin), G, B, A
DETAIL_WORLEY_FREQUENCIES = (2, 4, 8)  # base frequency of the Worley fBm in R, G, B
CURL_FREQUENCY = 4  # the curl potential's lowest octave
CURL_OCTAVES = 3
# Cirrus: streak lattice periods per axis [y, x] (strands 8 times longer than wide, along x), its octaves and the
# power that thins its ridges; the bend's frequency, octaves and reach (a share of the tile); the patch mask's
# frequency, octaves and the fBm values over which it rises from clear to full.
CIRRUS_STREAK_FREQUENCY = (16, 2)
CIRRUS_OCTAVES = 3
CIRRUS_SHARPNESS = 6
CIRRUS_WARP_FREQUENCY = 2
CIRRUS_WARP_OCTAVES = 2
CIRRUS_WARP = 0.1
CIRRUS_MASK_FREQUENCY = 2
CIRRUS_MASK_OCTAVES = 2
CIRRUS_MASK_EDGES = (-0.2, 0.4)


class _Steps:
    """Calls progress(done / total) after each of `total` steps; the last call is exactly 1.0."""

    def __init__(self, progress: Progress | None, total: int) -> None:
        self._progress = progress
        self._total = total
        self._done = 0

    def step(self) -> None:
        self._done = min(self._done + 1, self._total)
        if self._progress is not None:
            self._progress(1.0 if self._done == self._total else self._done / self._total)


def _check_size(size: int) -> None:
    if size < 2 or size & (size - 1):
        raise ValueError(f"noise size must be a power of two of at least 2, not {size}")


def _cells(size: int, frequency: int) -> tuple[int, int]:
    """(n cells per axis, b texels per cell) for a frequency, clamped to one cell per texel."""
    n = max(1, min(int(frequency), size))
    return n, size // n


def _cell_shape(a: np.ndarray, dim: int) -> np.ndarray:
    """A per-cell array (n,)*dim seen as (n, 1, n, 1, ...) to broadcast over the blocked texture."""
    shape: list[int] = []
    for n in a.shape[:dim]:
        shape += [n, 1]
    return a.reshape(shape)


def _axis_shape(v: np.ndarray, axis: int, dim: int) -> np.ndarray:
    """A per-texel-in-cell 1D array along `axis` seen as (1, 1, ..., b, ...) in the blocked texture."""
    shape = [1] * (2 * dim)
    shape[2 * axis + 1] = v.shape[0]
    return v.reshape(shape)


def _per_axis(frequency: Frequency, dim: int) -> tuple[int, ...]:
    """A frequency for every axis: one number for all, or one per axis in array-axis order ([y, x] in 2D)."""
    frequencies = (int(frequency),) * dim if isinstance(frequency, (int, np.integer)) else tuple(map(int, frequency))
    if len(frequencies) != dim:
        raise ValueError(f"{dim} frequencies needed, not {frequency}")
    return frequencies


def _random_gradients(rng: np.random.Generator, cells: tuple[int, ...]) -> np.ndarray:
    dim = len(cells)
    g = rng.standard_normal(cells + (dim,), dtype=np.float32)
    g /= np.maximum(np.sqrt((g * g).sum(axis=-1, keepdims=True)), np.float32(1e-12))
    return g


def perlin(size: int, frequency: Frequency, rng: np.random.Generator, dim: int = 3) -> np.ndarray:
    """Tileable gradient noise, (size,)*dim float32, roughly -1..1 (about +-0.87 at most for unit gradients).

    `frequency` lattice cells per tile (or one per axis: periods are per axis, so the lattice may be stretched), a
    random unit gradient at each lattice point (periodic), quintic fade, sampled at texel centres.
    """
    _check_size(size)
    cells = [_cells(size, f) for f in _per_axis(frequency, dim)]
    grads = _random_gradients(rng, tuple(n for n, _ in cells))
    fs = [((np.arange(b, dtype=np.float32) + 0.5) / b).astype(np.float32) for _, b in cells]
    fades = [f * f * f * (f * (f * 6 - 15) + 10) for f in fs]
    out = np.zeros(tuple(x for cell in cells for x in cell), dtype=np.float32)
    term = np.empty_like(out)
    for corner in itertools.product((0, 1), repeat=dim):
        g = np.roll(grads, shift=[-c for c in corner], axis=tuple(range(dim)))  # the gradient at cell + corner
        term.fill(0)
        weight: np.ndarray | float = 1.0
        for k in range(dim):
            term += _cell_shape(g[..., k], dim) * _axis_shape(fs[k] - corner[k], k, dim)  # the dot product, axis k
            weight = weight * _axis_shape(fades[k] if corner[k] else 1 - fades[k], k, dim)
        term *= weight
        out += term
    return out.reshape((size,) * dim)


def perlin_fbm(size: int, frequency: Frequency, rng: np.random.Generator, octaves: int | None = None, dim: int = 3,
               steps: _Steps | None = None) -> np.ndarray:
    """Octaves of Perlin noise at frequency, 2x, 4x ... (up to half the size on the finest axis, at least one, or
    `octaves` of them), amplitude halving, scaled back to about -1..1."""
    out = np.zeros((size,) * dim, dtype=np.float32)
    total = 0.0
    amplitude = 1.0
    f = np.array(_per_axis(frequency, dim))
    for _ in range(min(octaves or 32, _perlin_octaves(size, int(f.max())))):
        octave = perlin(size, tuple(f), rng, dim)
        octave *= np.float32(amplitude)
        out += octave
        del octave
        total += amplitude
        amplitude *= 0.5
        f *= 2
        if steps is not None:
            steps.step()
    out /= np.float32(total)
    return out


def worley(size: int, frequency: int, rng: np.random.Generator, dim: int = 3) -> np.ndarray:
    """Tileable Worley (cellular) noise, (size,)*dim float32 in 0..1: the distance from each texel centre to the
    nearest feature point, in cell widths, clipped to 1. One random point per cell of a periodic grid of
    `frequency`^dim cells; the nearest lies in one of the 3^dim cells around the texel's own."""
    _check_size(size)
    n, b = _cells(size, frequency)
    points = rng.random((n,) * dim + (dim,), dtype=np.float32)
    u = (np.arange(b, dtype=np.float32) + 0.5) / b
    best = np.full((n, b) * dim, np.inf, dtype=np.float32)
    d2 = np.empty_like(best)
    for offset in itertools.product((-1, 0, 1), repeat=dim):
        p = np.roll(points, shift=[-o for o in offset], axis=tuple(range(dim)))  # the point of cell + offset
        parts = [(_axis_shape(u, k, dim) - _cell_shape(p[..., k] + np.float32(offset[k]), dim)) ** 2
                 for k in range(dim)]
        np.add(sum(parts[1:-1], parts[0]), parts[-1], out=d2)  # only the last sum is full size
        np.minimum(best, d2, out=best)
    np.sqrt(best, out=best)
    np.minimum(best, 1.0, out=best)
    return best.reshape((size,) * dim)


def worley_fbm(size: int, frequency: int, rng: np.random.Generator, steps: _Steps | None = None) -> np.ndarray:
    """Inverted Worley (1 - w) at frequency, 2x and 4x, weighted by WORLEY_FBM_WEIGHTS: 0..1, 1 at the points."""
    out = np.zeros((size,) * 3, dtype=np.float32)
    for octave, weight in enumerate(WORLEY_FBM_WEIGHTS):
        w = worley(size, frequency << octave, rng)
        np.subtract(1, w, out=w)
        w *= np.float32(weight)
        out += w
        del w
        if steps is not None:
            steps.step()
    return out


# Simplex noise on a periodic plane. 3D simplex noise works on the lattice Z^3 unskewed by M = I - J / 6 (J all
# ones), where |M n|^2 = n.n - (n.(1, 1, 1))^2 / 4. In skewed coordinates e1 = (1, 0, 1) and e2 = (0, -1, -1) are
# orthogonal and of unit length under M, so the plane they span holds a square lattice of simplex lattice points
# (no plane of the 2D simplex lattice does: its lattice is triangular). With (e1, e2, (1, 0, 0)) a basis of Z^3,
# a lattice point n is n = a e1 + b e2 + c (1, 0, 0) with a = n.z - n.y, b = -n.y, c = n.x + n.y - n.z; drawing its
# gradient from a table indexed (a mod fx, b mod fy, c mod 8) makes the noise repeat every fx e1 and fy e2.
_G3 = 1 / 6  # the 3D simplex unskew factor (the samples are placed in skewed coordinates directly)
_PLANE_E1, _PLANE_E2 = np.array([1.0, 0.0, 1.0]), np.array([0.0, -1.0, -1.0])
# Halfway between two layers of lattice points (c = 0 and 1): simplex noise is 0 at every lattice point, and a plane
# through them would show their grid as a grid of zeros.
_PLANE_ORIGIN = np.array([0.5, 0.0, 0.0])
_SIMPLEX_LAYERS = 8  # gradient tables along c; one simplex spans at most three consecutive layers
_SIMPLEX_R2 = 0.5  # the kernel's squared radius: 0.5 keeps the noise continuous (0.6 leaves small steps)
# One kernel's peak, (0.5 - r^2)^4 r at r^2 = 1/18, scaled to 1; the sums of four rarely pass it (the largest |noise|
# over 40 seeds at 256^2 is 0.99).
_SIMPLEX_SCALE = 1 / ((4 / 9) ** 4 * (1 / 18) ** 0.5)


def simplex(size: int, frequency: Frequency, rng: np.random.Generator) -> np.ndarray:
    """Tileable 2D simplex noise, (size, size) float32 indexed [y, x], about -1..1 (any size).

    3D simplex noise (Perlin 2001, in Gustavson's formulation) sampled at texel centres on a plane through its
    lattice that repeats every `frequency` lattice units (one per axis possible, [y, x]): exact simplex noise, with
    neither the stretch of a rhombic tile nor the curvature of a torus in 4D. Random unit gradients from rng.
    """
    fy, fx = _per_axis(frequency, 2)
    grads = rng.standard_normal((fx, fy, _SIMPLEX_LAYERS, 3))
    grads /= np.maximum(np.sqrt((grads * grads).sum(axis=-1, keepdims=True)), 1e-12)
    u = (np.arange(size) + 0.5) / size
    s = (_PLANE_ORIGIN + (u * fx)[None, :, None] * _PLANE_E1 + (u * fy)[:, None, None] * _PLANE_E2).reshape(-1, 3)
    base = np.floor(s)
    x0 = s - base
    x0 -= x0.sum(axis=1, keepdims=True) * _G3  # the offset from the simplex's first corner, unskewed
    # The simplex holding x0: from corner 0, a unit step along x0's largest component, then along all but its least.
    step1 = np.eye(3)[np.argmax(x0, axis=1)]
    step2 = 1 - np.eye(3)[np.argmin(x0, axis=1)]
    out = np.zeros(len(s))
    for k, step in enumerate((0.0, step1, step2, 1.0)):
        n = (base + step).astype(np.int64)
        d = x0 - step + k * _G3
        t = np.maximum(_SIMPLEX_R2 - (d * d).sum(axis=1), 0)
        g = grads[(n[:, 2] - n[:, 1]) % fx, -n[:, 1] % fy, (n[:, 0] + n[:, 1] - n[:, 2]) % _SIMPLEX_LAYERS]
        t *= t
        out += t * t * (g * d).sum(axis=1)
    return (out * _SIMPLEX_SCALE).reshape(size, size).astype(np.float32)


def _normalise(a: np.ndarray) -> np.ndarray:
    """a stretched in place to exactly 0..1 (a constant array becomes 0)."""
    a -= a.min()
    top = a.max()
    if top > 0:
        a /= top
    return a


def smoothstep(edge0: float, edge1: float, x: np.ndarray) -> np.ndarray:
    """GLSL's smoothstep."""
    t = np.clip((x - edge0) / (edge1 - edge0), 0, 1)
    return t * t * (3 - 2 * t)


def _perlin_octaves(size: int, frequency: int) -> int:
    """Octaves up to two texels a cell (finer ones alias), at least one."""
    return max(1, sum(1 for o in range(32) if frequency << o <= size // 2))


def shape_noise(size: int = 128, seed: int = 0, progress: Progress | None = None) -> np.ndarray:
    """The low-frequency cloud shape, (size,)^3 float32 in 0..1, packed to one channel.

    The seed's texture is RGBA: R = Perlin-Worley, G, B, A = Worley fBm of rising frequency (bases 4, 8, 16
    cells per tile), and the seed packs the four channels into one beforehand by summing them with decreasing
    weights; we do the same, with halving weights (8, 4, 2, 1) / 15 (SHAPE_WEIGHTS; the seed does not publish
    its weights, halving is the usual fBm gain). The alternative, Nubis's remap of R by the GBA fBm,
    R' = remap(R, GBA - 1, 1, 0, 1), needs the channels apart in the shader; the single channel keeps the
    texture at 8 MiB and one fetch.

    Perlin-Worley (Schneider, Nubis 2015): a billowy Perlin fBm P (|noise|, inverted, octaves 4, 8, ... up to half the
    size) remapped by a Worley fBm W: remap(P, 0, 1, W, 1) = W + P (1 - W), so the Perlin fills the gaps of the
    cells. The sum is finally stretched to exactly 0..1.
    """
    _check_size(size)
    rng = np.random.default_rng(seed)
    steps = _Steps(progress, _perlin_octaves(size, SHAPE_PERLIN_FREQUENCY) + 3 * len(SHAPE_WORLEY_FREQUENCIES) + 1)
    p = perlin_fbm(size, SHAPE_PERLIN_FREQUENCY, rng, steps=steps)
    np.abs(p, out=p)
    np.minimum(p, 1.0, out=p)
    np.subtract(1, p, out=p)  # billowy: 1 on the zero set of the noise, falling towards its extremes
    w = worley_fbm(size, SHAPE_WORLEY_FREQUENCIES[0], rng, steps)
    out = np.subtract(1, w)  # remap(P, 0, 1, W, 1) = W + P (1 - W), then weighted
    out *= p
    out += w
    out *= np.float32(SHAPE_WEIGHTS[0])
    del p, w
    for frequency, weight in zip(SHAPE_WORLEY_FREQUENCIES[1:], SHAPE_WEIGHTS[1:]):
        channel = worley_fbm(size, frequency, rng, steps)
        channel *= np.float32(weight)
        out += channel
        del channel
    out = _normalise(out)
    steps.step()
    return out


def detail_noise(size: int = 32, seed: int = 0, progress: Progress | None = None) -> np.ndarray:
    """The high-frequency detail that erodes the shape's edges, (size,)^3 float32 in 0..1, packed to one channel.

    The seed's texture is RGB Worley of rising frequency, packed beforehand with decreasing weights; here each
    channel is a Worley fBm (inverted, octaves f, 2f, 4f) at bases 2, 4, 8 cells per tile, summed with halving
    weights (4, 2, 1) / 7 (DETAIL_WEIGHTS) and stretched to exactly 0..1.
    """
    _check_size(size)
    rng = np.random.default_rng(seed)
    steps = _Steps(progress, 3 * len(DETAIL_WORLEY_FREQUENCIES) + 1)
    out = np.zeros((size,) * 3, dtype=np.float32)
    for frequency, weight in zip(DETAIL_WORLEY_FREQUENCIES, DETAIL_WEIGHTS):
        channel = worley_fbm(size, frequency, rng, steps)
        channel *= np.float32(weight)
        out += channel
    out = _normalise(out)
    steps.step()
    return out


def curl_noise(size: int = 128, seed: int = 0, progress: Progress | None = None) -> np.ndarray:
    """A tileable 2D divergence-free field, (size, size, 2) float32 indexed [y, x], components (u, v) in -1..1.

    The potential P is a periodic 2D Perlin fBm (CURL_OCTAVES octaves from CURL_FREQUENCY); the field is its curl
    (dP/dy, -dP/dx), taken with periodic central differences, so the same central-difference divergence is zero
    to rounding. Scaled so that the largest |component| is 1.
    """
    _check_size(size)
    rng = np.random.default_rng(seed)
    steps = _Steps(progress, min(CURL_OCTAVES, _perlin_octaves(size, CURL_FREQUENCY)) + 1)
    potential = perlin_fbm(size, CURL_FREQUENCY, rng, octaves=CURL_OCTAVES, dim=2, steps=steps).astype(np.float64)
    d_dy = (np.roll(potential, -1, axis=0) - np.roll(potential, 1, axis=0)) / 2
    d_dx = (np.roll(potential, -1, axis=1) - np.roll(potential, 1, axis=1)) / 2
    field = np.stack([d_dy, -d_dx], axis=-1)
    scale = float(np.abs(field).max())
    if scale > 0:
        field /= scale
    steps.step()
    return field.astype(np.float32)


def cirrus_noise(size: int = 256, seed: int = 0, progress: Progress | None = None) -> np.ndarray:
    """Wispy high-altitude streaks, (size, size) float32 indexed [y, x], in 0..1 (stretched to exactly that).

    Ridges (1 - min(2 |n|, 1))^CIRRUS_SHARPNESS of a Perlin fBm n whose lattice is 8 times finer across y than
    along x make long thin strands along x; a low-frequency Perlin displacement bends them, and a patchy Perlin
    mask thins them out in places. Every part has whole lattice periods and the bend samples with wrapping, so the
    texture tiles.
    """
    _check_size(size)
    rng = np.random.default_rng(seed)
    octaves = [min(n, _perlin_octaves(size, max(_per_axis(f, 2)))) for n, f in (
        (CIRRUS_OCTAVES, CIRRUS_STREAK_FREQUENCY), (CIRRUS_WARP_OCTAVES, CIRRUS_WARP_FREQUENCY),
        (CIRRUS_MASK_OCTAVES, CIRRUS_MASK_FREQUENCY))]
    steps = _Steps(progress, octaves[0] + 2 * octaves[1] + octaves[2] + 1)
    streaks = perlin_fbm(size, CIRRUS_STREAK_FREQUENCY, rng, octaves=CIRRUS_OCTAVES, dim=2, steps=steps)
    ridges = (1 - np.minimum(np.abs(streaks) * 2, 1)) ** CIRRUS_SHARPNESS
    # Bend: sample the ridges at (y + dy, x + dx), texels, from a periodic displacement, linear and wrapping.
    dy, dx = (perlin_fbm(size, CIRRUS_WARP_FREQUENCY, rng, octaves=CIRRUS_WARP_OCTAVES, dim=2, steps=steps)
              * np.float32(CIRRUS_WARP * size) for _ in range(2))
    yx = np.indices((size, size), dtype=np.float32)
    bent = ndimage.map_coordinates(ridges, [yx[0] + dy, yx[1] + dx], order=1, mode="grid-wrap")
    mask = perlin_fbm(size, CIRRUS_MASK_FREQUENCY, rng, octaves=CIRRUS_MASK_OCTAVES, dim=2, steps=steps)
    mask = smoothstep(*CIRRUS_MASK_EDGES, mask)  # patches: clear sky where the mask's fBm is low
    out = _normalise(bent * mask)
    steps.step()
    return out
