"""The clouds reference's medium: GL texture sampling, the density rho(p) and the light S at a sample, float64.

docs/clouds.md, "The model": "Textures and sampling", "Density" and "Light", written out literally; every
per-frame number comes from an app.model.clouds.scene.Frame. app/reference/clouds.py marches rays through it and
re-exports these functions. Points are (..., 3) arrays; every function works on any number of them at once.
"""
from __future__ import annotations

import math

import numpy as np

from app.model.clouds import scene as cm
from app.model.clouds.scene import CloudTextures, Frame

CENTRE = np.array([0.0, -cm.PLANET_RADIUS, 0.0])
R0 = cm.PLANET_RADIUS + cm.LAYER_BOTTOM
R1 = cm.PLANET_RADIUS + cm.LAYER_TOP
# The spec's literals that app.model.clouds.scene does not name.
FADE_TOP, FADE_POWER = 1.2, 0.1       # the shape's height fade (1.2 - h)^0.1
FLAT_SHAPE = 0.7                      # the shape sample with shape_noise 0
DETAIL_RAMP = 10.0                    # m = mix(1 - e, e, clamp(10 h, 0, 1))
POWDER = 2.0                          # powder = mix(1, 1 - exp(-2 rho), 0.5 - 0.5 cos)
BEER_FLOOR, BEER_SOFT = 0.7, 0.5      # multiscatter 0: max(exp(-tau), 0.7 exp(-tau / 2))
GRADIENTS = np.array(cm.GRADIENTS)    # stratus, stratocumulus, cumulus
CONE = np.array(cm.CONE_VECTORS)


def f64(textures: CloudTextures) -> CloudTextures:
    """The same textures as float64 arrays (no copy where they already are): convert once per render."""
    return CloudTextures(*(np.asarray(getattr(textures, k), dtype=np.float64) for k in
                           ("shape", "detail", "curl", "cirrus", "weather_old", "weather_new")))


def _axis(u: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """GL linear filtering with repeat along one axis: c = u n - 0.5, i0 = floor(c), weight c - i0, mod n."""
    c = np.asarray(u, dtype=np.float64) * n - 0.5
    i0 = np.floor(c)
    f = c - i0
    i0 = i0.astype(np.int64) % n
    return i0, (i0 + 1) % n, f


def _lerp(a, b, t):
    """GLSL mix(a, b, t) = a (1 - t) + b t."""
    return a * (1.0 - t) + b * t


def sample2d(tex: np.ndarray, u, v) -> np.ndarray:
    """T[j, i] (or T[j, i, channel]) at (u, v), i along u: bilinear between texel centres, repeat."""
    tex = np.asarray(tex, dtype=np.float64)
    i0, i1, fu = _axis(u, tex.shape[1])
    j0, j1, fv = _axis(v, tex.shape[0])
    if tex.ndim == 3:
        fu, fv = fu[..., None], fv[..., None]
    return _lerp(_lerp(tex[j0, i0], tex[j0, i1], fu), _lerp(tex[j1, i0], tex[j1, i1], fu), fv)


def sample3d(tex: np.ndarray, u, v, w) -> np.ndarray:
    """T[k, j, i] at (u, v, w), i along u, j along v, k along w: trilinear between texel centres, repeat."""
    tex = np.asarray(tex, dtype=np.float64)
    nk, nj, ni = tex.shape
    i0, i1, fu = _axis(u, ni)
    j0, j1, fv = _axis(v, nj)
    k0, k1, fw = _axis(w, nk)
    flat = tex.reshape(-1)
    rows = [(k * nj + j) * ni for k in (k0, k1) for j in (j0, j1)]  # (k0 j0), (k0 j1), (k1 j0), (k1 j1)
    x = [_lerp(flat[r + i0], flat[r + i1], fu) for r in rows]
    return _lerp(_lerp(x[0], x[1], fv), _lerp(x[2], x[3], fv), fw)


def height(p: np.ndarray) -> np.ndarray:
    """h = clamp((|p - C| - r0) / (r1 - r0), 0, 1), the height fraction in the layer."""
    r = np.linalg.norm(np.asarray(p, dtype=np.float64) - CENTRE, axis=-1)
    return np.clip((r - R0) / (R1 - R0), 0.0, 1.0)


def weather(frame: Frame, textures: CloudTextures, x, z, freq: float, offset: tuple) -> np.ndarray:
    """mix(W0, W1, blend) at ((x, z) + offset) freq, (..., 3): one lookup whether one map or two blended."""
    u, v = (x + offset[0]) * freq, (z + offset[1]) * freq
    if frame.blend == 1.0:  # mix(a, b, 1) = b exactly: the old map is not read
        return sample2d(textures.weather_new, u, v)
    if frame.blend == 0.0:
        return sample2d(textures.weather_old, u, v)
    return _lerp(sample2d(textures.weather_old, u, v), sample2d(textures.weather_new, u, v), frame.blend)


def smoothstep(e0, e1, x):
    t = np.clip((x - e0) / (e1 - e0), 0.0, 1.0)
    return t * t * (3.0 - 2.0 * t)


def density(frame: Frame, textures: CloudTextures, p, full: bool) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(rho in 0..1, precipitation B, texture lookups) at points p (..., 3); `full`: with the detail."""
    p = np.asarray(p, dtype=np.float64)
    shape = p.shape[:-1]
    p = p.reshape(-1, 3)
    rho = np.zeros(len(p))
    lookups = np.ones(len(p), dtype=np.int64)                     # 1. the weather
    h = height(p)
    w = weather(frame, textures, p[:, 0], p[:, 2], frame.weather_freq, frame.weather_offset)
    precip = w[:, 2].copy()
    c = np.clip(w[:, 0] - frame.coverage_shift, 0.0, 1.0)
    on = np.flatnonzero(c > 0)                                     # c = 0: rho = 0
    p, h, c, kind = p[on], h[on], c[on], w[on, 1]
    q = p + np.array(frame.wind_offset) + (h * cm.SHEAR)[:, None] * np.array(frame.wind_dir)  # 2.
    if frame.shape_noise:                                          # 3.
        s = sample3d(textures.shape, *(q * frame.shape_freq).T) * (FADE_TOP - h) ** FADE_POWER
        lookups[on] += 1
    else:
        s = np.full(len(p), FLAT_SHAPE)
    s = (s - frame.shape_min) / (frame.shape_max - frame.shape_min)
    g = _lerp(_lerp(GRADIENTS[0], GRADIENTS[1], np.clip(2 * kind, 0, 1)[:, None]), GRADIENTS[2],
              np.clip(2 * kind - 1, 0, 1)[:, None])                # 4.
    s = s * (smoothstep(g[:, 0], g[:, 1], h) - smoothstep(g[:, 2], g[:, 3], h))
    lo = h / c                                                     # 5.
    below = lo < 1
    s = np.where(below, np.clip((s - lo) / np.where(below, 1 - lo, 1.0), 0.0, 1.0), 0.0) * c
    if full and frame.detail_noise:                                # 6.
        sub = np.flatnonzero(s > 0)
        qd, hd = q[sub], h[sub]
        if frame.curl_noise:
            k = sample2d(textures.curl, p[sub, 0] * frame.curl_freq, p[sub, 2] * frame.curl_freq)
            qd = qd + np.stack([k[:, 0], np.zeros(len(sub)), k[:, 1]], -1) * (hd * frame.curl_amount)[:, None]
            lookups[on[sub]] += 1
        e = sample3d(textures.detail, *(qd * frame.detail_freq).T)
        lookups[on[sub]] += 1
        lo = _lerp(1 - e, e, np.clip(DETAIL_RAMP * hd, 0.0, 1.0)) * frame.detail_modifier
        below = lo < 1
        s[sub] = np.where(below, (s[sub] - lo) / np.where(below, 1 - lo, 1.0), 0.0)
    rho[on] = np.clip(s, 0.0, 1.0)                                 # 7.
    return rho.reshape(shape), precip.reshape(shape), lookups.reshape(shape)


def hg(cos, g):
    """Henyey-Greenstein: (1 - g^2) / (4 pi (1 + g^2 - 2 g cos)^1.5), per steradian, as the shader writes it:
    1 + g^2 - 2 g cos = (1 - |g|)^2 + 2 |g| (1 - sign(g) cos), two terms >= 0."""
    cos, a = np.asarray(cos, dtype=np.float64), np.abs(g)
    q = (1 - a) ** 2 + 2 * a * np.where(np.asarray(g) >= 0, 1 - cos, 1 + cos)
    return (1 - a) * (1 + a) / (4 * math.pi * q * np.sqrt(q))


def phase(frame: Frame, cos, scale: float):
    """P(cos, g') = (1 - w) HG(cos, g_forward g') + w HG(cos, g_back g'), w = back_weight: the two lobes' mix,
    integrating to 1 over the sphere; with phase_max the seed's max(HG(cos, g_forward g'), HG(cos, g_back g'))."""
    forward, back = hg(cos, frame.g_forward * scale), hg(cos, frame.g_back * scale)
    if frame.phase_max:
        return np.maximum(forward, back)
    return _lerp(forward, back, frame.back_weight)


def sun_energy(frame: Frame, tau, rho, cos):
    """The sun's part of S per unit sun_light at a sample of density rho with optical depth tau towards the sun,
    cos = d . sun: E powder. With multiscatter, Wrenninge's octaves: E = sum_k w_k 4 pi P(cos, c^k) exp(-b^k tau),
    w_k = a^k / sum_j a^j (the weights share albedo 1); else the seed's double Beer. Powder, in [0, 1], only
    darkens. Over the sphere of directions its mean is at most 1 (with the mixed phase)."""
    tau, rho, cos = (np.asarray(x, dtype=np.float64) for x in (tau, rho, cos))
    if frame.multiscatter:
        energy, weights, a, b, c = 0.0, 0.0, 1.0, 1.0, 1.0
        for _ in range(cm.OCTAVES):
            energy = energy + a * 4 * math.pi * phase(frame, cos, c) * np.exp(-b * tau)
            weights += a
            a, b, c = a * frame.octave_scattering, b * frame.octave_extinction, c * frame.octave_eccentricity
        energy = energy / weights
    else:
        energy = 4 * math.pi * phase(frame, cos, 1.0) * np.maximum(np.exp(-tau), BEER_FLOOR * np.exp(-tau * BEER_SOFT))
    return energy * powder(rho, cos)


def powder(rho, cos):
    """mix(1, 1 - exp(-2 rho), (1 - cos) / 2): in [1 - exp(-2 rho), 1], a factor that only darkens (the seed's)."""
    return _lerp(1.0, 1 - np.exp(-POWDER * np.asarray(rho, dtype=np.float64)), 0.5 - 0.5 * np.asarray(cos))


def light_lookups(frame: Frame, textures: CloudTextures, p, rho, cos) -> tuple[np.ndarray, np.ndarray]:
    """(S (..., 3), texture lookups) at samples p with density rho > 0, cos = d . sun."""
    p = np.asarray(p, dtype=np.float64)
    shape = p.shape[:-1]
    p = p.reshape(-1, 3)
    rho = np.asarray(rho, dtype=np.float64).reshape(-1)
    cos = np.broadcast_to(np.asarray(cos, dtype=np.float64), shape).reshape(-1)
    sun, step = np.array(frame.sun_dir), frame.light_step
    pos, cone = p, []
    for i in range(len(CONE)):                                     # the cone: 5 samples with detail
        pos = pos + sun * step
        cone.append(pos + CONE[i] * (step * frame.cone_radius * (i + 1)))
    r, b, count = density(frame, textures, np.stack(cone, 1), True)
    total = (r * (1 + b)).sum(1)
    lookups = count.sum(1)
    if frame.light_samples == cm.LONG_LIGHT_SAMPLES:               # 25 samples 4 light steps apart
        j = np.arange(1, cm.LONG_LIGHT_SAMPLES - len(CONE) + 1)
        weight, far = cm.LONG_SPACING, pos[:, None, :] + (cm.LONG_SPACING * j * step)[None, :, None] * sun
    else:                                                          # one far sample 32 light steps on
        weight, far = cm.FAR_WEIGHT, (pos + cm.FAR_LIGHT_STEPS * step * sun)[:, None, :]
    r, b, count = density(frame, textures, far, False)
    total = total + weight * (r * (1 + b)).sum(1)
    lookups = lookups + count.sum(1)
    tau = frame.extinction * step * total
    h = height(p)[:, None]
    sun = _lerp(np.array(frame.sun_light), np.array(frame.sun_light_top), h)
    ambient = _lerp(np.array(frame.ambient_base), np.array(frame.ambient_top), h)
    s = sun * sun_energy(frame, tau, rho, cos)[:, None] + ambient
    return s.reshape(shape + (3,)), lookups.reshape(shape)


def light(frame: Frame, textures: CloudTextures, p, rho, cos) -> np.ndarray:
    """S (..., 3), the light scattered towards the camera at samples p with density rho > 0."""
    return light_lookups(frame, textures, p, rho, cos)[0]
