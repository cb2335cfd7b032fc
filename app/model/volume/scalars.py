"""Scalar volumes (16-bit and float CT, MRI, microscopy...): the values as loaded and the transfer function that
colours them into the RGBA volume.

The transfer function is a window (low, high) and a colour map: a value's place in the window, t = (v - low) /
(high - low) clamped to 0..1, picks the colour from the map and the alpha from t itself, so values at or below
`low` are transparent and the colours grow opaque towards `high`. t is quantised to 256 levels (the RGBA
volume's own resolution) and looked up in a 256-entry table, in slabs of CHUNK voxels, so colouring a volume
holds the RGBA volume and about 4 MiB of temporaries (5 MiB for 32-bit integers and doubles; tracemalloc's peak
while colouring 128^3 voxels). NaN values are transparent; -inf and +inf clamp.

The opacity curve (points in data units) is the translucent render mode's alone: it changes no colour, so setting
it colours nothing again.
"""
from __future__ import annotations

import math
import warnings
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

# The dtypes a scalar file may hold; uint8 grey files stay densities painted directly (app/io/volume_formats/).
SCALAR_TYPES = tuple(np.dtype(t) for t in ("int8", "uint16", "int16", "uint32", "int32", "float32", "float64"))
CHUNK = 1 << 18           # voxels coloured at once: float64 temporaries of 2 MiB
WINDOW_SAMPLE = 1 << 20   # voxels the default window's percentiles are taken from
PERCENTILES = (1.0, 99.0)

# Colour maps as control points (t, (r, g, b)), linearly interpolated: small tables instead of matplotlib.
# viridis, magma, inferno and plasma: matplotlib's at t = 0, 1/8, ..., 1 (magma, inferno and plasma as pyqtgraph
# ships them); hot and bone follow matplotlib's ramps (black, red at 3/8, yellow at 3/4, white; bone: grey with a
# blue tint). The ct_ and mr_ maps are the colours of 3D Slicer's volume-rendering presets of those names
# (app/model/volume/transfer_presets.py), spread over the window those presets set.
def _stops(*colours: tuple[int, int, int]) -> tuple[tuple[float, tuple[int, int, int]], ...]:
    """Colours evenly spaced from t = 0 to 1."""
    return tuple((i / (len(colours) - 1), c) for i, c in enumerate(colours))


COLORMAPS: dict[str, tuple[tuple[float, tuple[int, int, int]], ...]] = {
    "grey": ((0.0, (0, 0, 0)), (1.0, (255, 255, 255))),
    "hot": ((0.0, (10, 0, 0)), (0.375, (255, 0, 0)), (0.75, (255, 255, 0)), (1.0, (255, 255, 255))),
    "bone": ((0.0, (0, 0, 0)), (0.375, (81, 81, 113)), (0.75, (166, 198, 198)), (1.0, (255, 255, 255))),
    "viridis": ((0.0, (68, 1, 84)), (0.125, (72, 40, 120)), (0.25, (62, 73, 137)), (0.375, (49, 104, 142)),
                (0.5, (38, 130, 142)), (0.625, (31, 158, 137)), (0.75, (53, 183, 121)), (0.875, (110, 206, 88)),
                (1.0, (253, 231, 37))),
    "magma": _stops((0, 0, 4), (28, 16, 70), (80, 18, 123), (130, 37, 129), (182, 54, 121), (229, 80, 99),
                    (251, 135, 97), (254, 194, 135), (252, 253, 191)),
    "inferno": _stops((0, 0, 4), (32, 12, 73), (86, 15, 109), (137, 34, 106), (187, 54, 84), (227, 89, 50),
                      (249, 140, 9), (249, 201, 50), (252, 255, 164)),
    "plasma": _stops((13, 8, 135), (75, 2, 161), (125, 3, 168), (169, 34, 149), (203, 70, 120), (229, 107, 92),
                     (248, 148, 64), (253, 195, 39), (240, 249, 33)),
    # Slicer's CT-Bone: dark red where bone starts, ivory, white in the densest
    "ct_bone": ((0.0, (186, 65, 77)), (0.5, (231, 208, 141)), (1.0, (255, 255, 255))),
    # Slicer's CT-Muscle and CT-AAA: brown, flesh, pale pink
    "ct_soft_tissue": ((0.0, (140, 64, 38)), (0.5, (225, 154, 74)), (1.0, (255, 239, 243))),
    # Slicer's CT-Lung: blue, green, yellow, orange across the lungs' densities
    "ct_air": ((0.0, (77, 77, 255)), (0.35, (34, 199, 18)), (0.7, (237, 255, 28)), (1.0, (227, 65, 6))),
    # Slicer's MR-Default: black, dark red, tan, ivory, white
    "mr_default": ((0.0, (0, 0, 0)), (0.02, (43, 0, 0)), (0.04, (103, 37, 20)), (0.12, (199, 155, 97)),
                   (0.21, (216, 213, 201)), (1.0, (255, 255, 255))),
}


class ScalarError(ValueError):
    """A window, colour map or scalar array the volume refuses; the message is meant for the user."""


# An opacity curve's points: (value in data units, opacity 0..1 per voxel of ray), values increasing.
OpacityPoints = tuple[tuple[float, float], ...]
MAX_OPACITY_POINTS = 64


@dataclass(frozen=True, repr=False)
class TransferFunction:
    """The window and colour map colour the values; the opacity curve (`points`, None: the ramp over the window)
    makes them translucent in the translucent render mode."""

    low: float
    high: float
    colormap: str = "grey"
    points: OpacityPoints | None = None

    def __post_init__(self) -> None:
        low, high = check_window(self.low, self.high)  # floats, so a window of whole numbers has one form (digests)
        object.__setattr__(self, "low", low)
        object.__setattr__(self, "high", high)
        check_colormap(self.colormap)
        if self.points is not None:
            object.__setattr__(self, "points", check_opacity_points(self.points))

    def __repr__(self) -> str:
        """What the volume's digest hashes: without a curve of its own, the text it had before curves existed, so
        old demos keep their digests."""
        text = f"TransferFunction(low={self.low!r}, high={self.high!r}, colormap={self.colormap!r}"
        return text + (")" if self.points is None else f", points={self.points!r})")

    def table(self) -> np.ndarray:
        """(256, 4) uint8: entry i is the colour and alpha of t = i / 255."""
        return _table(self.colormap)

    def opacity(self) -> OpacityPoints:
        """The opacity curve the translucent mode composites with (app/model/volume/scalar_modes.py): (value in
        data units, opacity per voxel of ray) points, linear between them, constant beyond the ends. Without points
        of its own (`vol.opacity`, a preset), a ramp over the window, 0 at low to 1 at high."""
        return self.points if self.points is not None else ((self.low, 0.0), (self.high, 1.0))

    def same_colours(self, other: TransferFunction) -> bool:
        """Whether the two colour every value alike (they may differ in their opacity curves)."""
        return (self.low, self.high, self.colormap) == (other.low, other.high, other.colormap)


def check_opacity_points(points) -> OpacityPoints:
    """The points as (float, float) pairs, if they make an opacity curve: 1 to MAX_OPACITY_POINTS of them, finite
    values increasing, opacities within 0..1; else ScalarError, the first fault named."""
    pairs = tuple((float(v), float(a)) for v, a in points)
    if not 1 <= len(pairs) <= MAX_OPACITY_POINTS:
        raise ScalarError(f"an opacity curve has 1 to {MAX_OPACITY_POINTS} points, got {len(pairs)}")
    for i, (value, alpha) in enumerate(pairs):
        if not math.isfinite(value):
            raise ScalarError(f"opacity point {i + 1}'s value must be finite, got {value:g}")
        if not 0.0 <= alpha <= 1.0:  # NaN fails too
            raise ScalarError(f"opacity point {i + 1}'s opacity must be within 0..1, got {alpha:g}")
        if i and value <= pairs[i - 1][0]:
            raise ScalarError(f"the opacity points' values must increase: point {i + 1}'s {value:g} comes after "
                              f"{pairs[i - 1][0]:g}")
    return pairs


def check_window(low: float, high: float) -> tuple[float, float]:
    """(low, high) as floats, if they make a window; else ScalarError."""
    low, high = float(low), float(high)
    if not (math.isfinite(low) and math.isfinite(high)):
        raise ScalarError(f"the window's low and high must be finite, got {low:g} {high:g}")
    if low >= high:
        raise ScalarError(f"the window's low must be below its high, got {low:g} {high:g}")
    return low, high


def check_colormap(name: str) -> str:
    """`name`, if it is a colour map's; else ScalarError."""
    if name not in COLORMAPS:
        raise ScalarError(f"no colour map {name!r}; choose one of {', '.join(COLORMAPS)}")
    return name


@dataclass(frozen=True)
class Scalars:
    """The loaded values, (depth, height, width) in native byte order, read-only; and how they are coloured."""

    values: np.ndarray
    transfer: TransferFunction

    @property
    def nbytes(self) -> int:
        return self.values.nbytes


@lru_cache(maxsize=None)
def _table(name: str) -> np.ndarray:
    points = COLORMAPS[name]
    t = np.linspace(0.0, 1.0, 256)
    stops = [p for p, _ in points]
    table = np.empty((256, 4), np.uint8)
    for c in range(3):
        table[:, c] = np.interp(t, stops, [rgb[c] for _, rgb in points]).round()
    table[:, 3] = np.arange(256)  # alpha from the value
    table.flags.writeable = False
    return table


def check_values(values: np.ndarray) -> tuple[int, int, int]:
    """The (depth, height, width) of an array of a SCALAR_TYPES dtype (either byte order), else ScalarError."""
    if not isinstance(values, np.ndarray) or values.ndim != 3 or values.dtype.newbyteorder("=") not in SCALAR_TYPES:
        raise ScalarError(f"scalars must be a (depth, height, width) array of {', '.join(map(str, SCALAR_TYPES))}, "
                          f"got {getattr(values, 'dtype', type(values).__name__)} of shape "
                          f"{getattr(values, 'shape', None)}")
    return values.shape


def own_values(values: np.ndarray, copy: bool = True) -> np.ndarray:
    """The model's own values, read-only, C-ordered and native-endian, which nobody writes to: a copy, or with
    copy=False `values` itself made read-only where it already is so laid out (a reader's fresh array)."""
    kept = not copy and values.dtype.isnative and values.flags.c_contiguous
    own = values if kept else np.array(values, dtype=values.dtype.newbyteorder("="), order="C")
    own.flags.writeable = False
    return own


def value_range(values: np.ndarray) -> tuple[float, float]:
    """The least and greatest value, NaN left out (NaN, NaN if that is all there is)."""
    with np.errstate(invalid="ignore"), warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # an all-NaN array
        return float(np.nanmin(values)), float(np.nanmax(values))


def default_window(values: np.ndarray) -> tuple[float, float]:
    """The 1st and 99th percentiles of the finite values above the volume's minimum.

    The minimum is left out because scanners fill the background or the outside of their field of view with
    one value (0 in MRI and microscopy, -1024 or -3024 in CT): counted, it drags the low end down so that air
    comes out as fog. Taken from at most WINDOW_SAMPLE evenly strided voxels. A window the percentiles
    collapse (a mask of two values) widens to min..max; a constant volume gets min..min + 1.
    """
    flat = values.reshape(-1)
    sample = flat[:: max(1, flat.size // WINDOW_SAMPLE)]
    if sample.dtype.kind == "f":
        sample = sample[np.isfinite(sample)]
    if not sample.size:
        return 0.0, 1.0
    least, most = sample.min(), sample.max()
    above = sample[sample > least]
    low, high = (float(p) for p in np.percentile(above, PERCENTILES)) if above.size else (least, least)
    if low >= high:
        low, high = float(least), float(most)
    if sample.dtype.kind in "iu":  # whole numbers for whole-number data
        low, high = math.floor(low), math.ceil(high)
    else:
        low, high = float(f"{low:.6g}"), float(f"{high:.6g}")
    return (low, high) if low < high else (low, low + 1.0)


def value_histogram(values: np.ndarray, bins: int) -> tuple[np.ndarray, np.ndarray]:
    """(bins + 1 edges, bins counts) of the finite values from min to max, counted in at most WINDOW_SAMPLE evenly
    strided voxels (the transfer-function editor draws it). A constant volume gets one unit around its value; one
    without finite values, 0..1 and no counts."""
    flat = values.reshape(-1)
    sample = flat[:: max(1, flat.size // WINDOW_SAMPLE)]
    if sample.dtype.kind == "f":
        sample = sample[np.isfinite(sample)]
    if not sample.size:
        return np.linspace(0.0, 1.0, bins + 1), np.zeros(bins, np.int64)
    least, most = float(sample.min()), float(sample.max())
    if least == most:
        least, most = least - 0.5, most + 0.5
    counts, edges = np.histogram(sample, bins, (least, most))
    return edges, counts


def colour(values: np.ndarray, transfer: TransferFunction, out: np.ndarray) -> None:
    """Write the colours of `values` (d, h, w) into `out` (d, h, w, 4) uint8, C-contiguous, in place."""
    if out.shape != values.shape + (4,) or out.dtype != np.uint8 or not out.flags.c_contiguous:
        raise ScalarError(f"cannot colour {values.shape} scalars into a {out.dtype} array of shape {out.shape}")
    table = transfer.table()
    work = np.result_type(values.dtype, np.float32)  # float64 for 32-bit integers and doubles
    scale = 255.0 / (transfer.high - transfer.low)
    flat_in, flat_out = values.reshape(-1), out.reshape(-1, 4)
    t = np.empty(min(CHUNK, flat_in.size), work)
    index = np.empty(t.size, np.uint8)
    for start in range(0, flat_in.size, CHUNK):
        block = flat_in[start:start + CHUNK]
        n = block.size
        np.subtract(block, transfer.low, out=t[:n], dtype=work)
        t[:n] *= scale
        t[:n] += 0.5  # round to the nearest level
        np.clip(t[:n], 0.0, 255.0, out=t[:n])
        if values.dtype.kind == "f":
            t[:n][np.isnan(t[:n])] = 0.0  # NaN: transparent
        index[:n] = t[:n]  # truncates: floor of t + 0.5
        np.take(table, index[:n], axis=0, out=flat_out[start:start + n])
