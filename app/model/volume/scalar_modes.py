"""How a scalar volume's values are drawn (cvar r_scalarMode), as data the GPU shader
(resources/shaders/scalar_modes.shl) and the CPU reference (app/reference/volume_scalar.py) both obey.

Every mode marches the samples the F-modes march (app/model/volume/render_modes.py: S = cl_steps * |AB| midpoints,
trilinear), of the values in data units, clamped at the box's faces (a scan's outside is its edge, not 0):
- colour: the F-modes draw the coloured volume (the scalars through the window), as for an RGBA volume;
- mip, minip, average: the greatest, least or mean value along the ray (mip and minip search around their best
  sample, up to two steps either side, for the extreme between the samples: the reference's, at fine steps);
- attenuated_mip: vispy's attenuated MIP, in the window's units t = (v - low) / (high - low): each sample's t is
  scaled by exp(-r_mipAttenuation * (A - 1)), A the clamped t accumulated along the ray so far per voxel of ray (vispy
  divides that sum by its step size where the integral multiplies; the two agree at one voxel a step), and the
  greatest scaled t is shown;
- iso: the first crossing of the iso value (`vol.iso`, data units), bisected as the F-modes' hits are, lit as F5
  (Phong, the first light, its shadow if shadows are on), its normal from the values' gradient and its colour the
  colour map's at the iso value;
- translucent: front-to-back compositing of the colour map's colours with the opacity curve's alpha
  (TransferFunction.opacity, per voxel of ray; corrected for the step: 1 - (1 - a)^(voxels a step)), stopped
  once OPAQUE.
The projections (mip, minip, attenuated_mip, average) show the colour map's colour of their value over the
background with its alpha, as the window defines them (values at low and below transparent). NaN counts as the
least finite value (never a maximum, a surface or opaque), -inf and +inf as the least and greatest.
"""
from __future__ import annotations

import numpy as np

# r_scalarMode's values; the shader's SCALAR_MODE is the index (0: colour, the F-modes).
SCALAR_MODES = ("colour", "mip", "minip", "attenuated_mip", "iso", "average", "translucent")
SCALAR_DEFAULT = "mip"       # what a scalar volume opens in; an RGBA volume opens in colour
ISO_MODE = "iso"
MIP_ATTENUATION = 0.05       # r_mipAttenuation's default: napari's (vispy's own default, 1, hides all but the front)
OPAQUE = 0.995               # a translucent ray stops here: what lies behind adds at most 0.5 %
OPACITY_TABLE = 1024         # entries of the GPU's opacity curve, from its first point's value to its last's
COLOUR_LEVELS = 256          # the colour map's table (TransferFunction.table)
BRICK = 8                    # voxels a side of the bricks whose greatest values let iso and translucent skip samples


def mode_number(name: str) -> int:
    return SCALAR_MODES.index(name)


def opacity_table(points: tuple[tuple[float, float], ...]) -> tuple[float, float, np.ndarray]:
    """The opacity curve (value, opacity) points sampled at OPACITY_TABLE values evenly from the first point's value
    to the last's: (first, last, float32 table). Beyond its ends the curve keeps its end opacities."""
    values = np.array([p[0] for p in points], float)
    first, last = float(values[0]), float(values[-1])
    if last <= first:
        last = first + 1.0  # one point: a constant curve
    at = np.linspace(first, last, OPACITY_TABLE)
    return first, last, np.interp(at, values, [p[1] for p in points]).astype(np.float32)


def clear_below(first: float, last: float, table: np.ndarray) -> float:
    """The greatest value up to which the opacity table (opacity_table's) reads 0, linear filtering included: its
    entries are 0 from the first to this one's. Translucent skips the bricks whose greatest value is no more (air
    below the window): they add nothing. The least float32 where the curve starts above 0."""
    if table[0] > 0:
        return float(np.finfo(np.float32).min)
    zero_run = len(table) if not table.any() else int(np.argmax(table > 0))
    return float(np.finfo(np.float32).max) if zero_run == len(table) else first + (last - first) * (
        (zero_run - 1) / (len(table) - 1))


def finite_span(values: np.ndarray) -> tuple[float, float]:
    """The least and greatest finite value (0, 0 if there is none), a slab of 1M values at a time."""
    if values.dtype.kind != "f":
        return (float(values.min()), float(values.max())) if values.size else (0.0, 0.0)
    lo, hi = np.inf, -np.inf
    flat = values.reshape(-1)
    for start in range(0, flat.size, 1 << 20):
        part = flat[start:start + (1 << 20)]
        part = part[np.isfinite(part)]
        if part.size:
            lo, hi = min(lo, part.min()), max(hi, part.max())
    return (float(lo), float(hi)) if lo <= hi else (0.0, 0.0)


def drawable(values: np.ndarray, span: tuple[float, float]) -> np.ndarray:
    """`values` as the modes draw them: float32, NaN and -inf as span's least, +inf as its greatest."""
    lo, hi = span
    return np.nan_to_num(values.astype(np.float32), nan=lo, neginf=lo, posinf=hi)


def brick_maxima(values: np.ndarray, brick: int = BRICK) -> np.ndarray:
    """(bricks down z, y, x) float32: the greatest value (as drawn) each brick of `brick`^3 voxels and the 1-voxel rim
    around it hold, which is every voxel a trilinear sample within the brick reads. No sample in a brick whose
    greatest value is at most the iso value passes it, nor is one at most clear_below's opaque at all: iso and
    translucent skip the brick, and draw exactly what they draw without skipping. A z slab at a time."""
    d, h, w = values.shape
    cz, cy, cx = (-(-n // brick) for n in (d, h, w))
    span = finite_span(values) if values.dtype.kind == "f" else None
    out = np.empty((cz, cy, cx), np.float32)
    for z in range(cz):
        slab = values[max(0, z * brick - 1):min(d, (z + 1) * brick + 1)]
        out[z] = _bricks((drawable(slab, span) if span is not None else slab).max(0), brick)
    return out


def _bricks(plane: np.ndarray, brick: int) -> np.ndarray:
    """A (h, w) plane's greatest value over each brick and its rim: (bricks down y, x)."""
    for axis in (0, 1):
        first, last = np.take(plane, [0], axis), np.take(plane, [-1], axis)
        ahead = np.concatenate([np.delete(plane, 0, axis), last], axis)
        behind = np.concatenate([first, np.delete(plane, -1, axis)], axis)
        plane = np.maximum(np.maximum(plane, ahead), behind)
    h, w = plane.shape
    cy, cx = -(-h // brick), -(-w // brick)
    plane = np.pad(plane, ((0, cy * brick - h), (0, cx * brick - w)), mode="edge")
    return plane.reshape(cy, brick, cx, brick).max(axis=(1, 3))


def colour_of(table: np.ndarray, t: np.ndarray) -> np.ndarray:
    """The colour map's RGBA (0..1) at window units t (clamped to 0..1), interpolated between its table's
    COLOUR_LEVELS entries (as the GPU's linear filter does)."""
    x = np.clip(np.nan_to_num(t, nan=0.0), 0.0, 1.0) * (COLOUR_LEVELS - 1)
    levels = np.arange(COLOUR_LEVELS)
    return np.stack([np.interp(x, levels, table[:, c] / 255.0) for c in range(4)], -1)
