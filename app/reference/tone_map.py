"""The tone map on the CPU, float64: what resources/shaders/tone_map.shl and the clouds' tone-map passes compute
(docs/clouds.md, "Exposure and tone mapping"), for the tests to hold the shader to. Images are (..., 3) linear
radiance; out come display values in 0..1 (sRGB-encoded but for `clamp`, the seed's look)."""
from __future__ import annotations

import numpy as np

from app.model.clouds.exposure import LUMINANCE, MIN_LUMINANCE, TONE_MAPS, auto_ev

# AgX (Sobotka), as Wrensch's minimal fit writes it: the inset matrix, a log2 window, the contrast polynomial,
# the outset matrix; rows act on (r, g, b) column vectors.
AGX_INSET = np.array([[0.842479062253094, 0.0784335999999992, 0.0792237451477643],
                      [0.0423282422610123, 0.878468636469772, 0.0791661274605434],
                      [0.0423756549057051, 0.0784336, 0.879142973793104]])
AGX_OUTSET = np.array([[1.19687900512017, -0.0980208811401368, -0.0990297440797205],
                       [-0.0528968517574562, 1.15190312990417, -0.0989611768448433],
                       [-0.0529716355144438, -0.0980434501171241, 1.15107367264116]])
AGX_MIN_EV, AGX_MAX_EV = -12.47393, 4.026069
AGX_POLY = (15.5, -40.14, 31.96, -6.868, 0.4298, 0.1191, -0.00232)  # x^6 .. x^0
# ACES fitted (Hill, BakingLab): sRGB -> AP1 with the RRT's saturation, the RRT + ODT fit, back to sRGB.
ACES_IN = np.array([[0.59719, 0.35458, 0.04823], [0.07600, 0.90834, 0.01566], [0.02840, 0.13383, 0.83777]])
ACES_OUT = np.array([[1.60475, -0.53108, -0.07367], [-0.10208, 1.10813, -0.00605], [-0.00327, -0.07276, 1.07602]])


def luminance(rgb: np.ndarray) -> np.ndarray:
    return np.asarray(rgb, np.float64) @ np.array(LUMINANCE)


def log2_average(rgb: np.ndarray) -> float:
    """The mean over the pixels of log2 luminance (at least MIN_LUMINANCE): what automatic exposure reads."""
    return float(np.log2(np.maximum(luminance(rgb), MIN_LUMINANCE)).mean())


def exposure_ev(ev: float, auto: bool, rgb: np.ndarray | None = None) -> float:
    """The exposure applied: `ev` alone, or with `auto` the frame's automatic exposure plus `ev`."""
    return ev + (auto_ev(log2_average(rgb)) if auto else 0.0)


def agx(x: np.ndarray) -> np.ndarray:
    v = x @ AGX_INSET.T
    v = (np.clip(np.log2(np.maximum(v, 2.0 ** AGX_MIN_EV)), AGX_MIN_EV, AGX_MAX_EV) - AGX_MIN_EV) / (
        AGX_MAX_EV - AGX_MIN_EV)
    v = np.polyval(AGX_POLY, v) @ AGX_OUTSET.T
    return np.maximum(v, 0.0) ** 2.2  # the fit's display encoding (gamma 2.2) undone: linear display light


def aces(x: np.ndarray) -> np.ndarray:
    v = x @ ACES_IN.T
    v = (v * (v + 0.0245786) - 0.000090537) / (v * (0.983729 * v + 0.4329510) + 0.238081)
    return v @ ACES_OUT.T


def srgb_encode(x: np.ndarray) -> np.ndarray:
    x = np.clip(x, 0.0, 1.0)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * x ** (1 / 2.4) - 0.055)


def tone_map(rgb: np.ndarray, ev: float, curve: str) -> np.ndarray:
    """Display values of linear `rgb` at exposure `ev` through `curve` (one of TONE_MAPS)."""
    if curve not in TONE_MAPS:
        raise ValueError(f"no tone curve {curve!r} ({', '.join(TONE_MAPS)})")
    x = np.maximum(np.asarray(rgb, np.float64), 0.0) * 2.0 ** ev
    if curve == "clamp":
        return np.clip(x, 0.0, 1.0)
    return srgb_encode(agx(x) if curve == "agx" else aces(x))
