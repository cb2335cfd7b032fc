"""Float64 CPU reference of the volumetric clouds (docs/clouds.md, "The model"), numpy only.

The same model as the GPU shader (resources/shaders/clouds.shl), from the same per-frame constants
(app.model.clouds.scene.frame), written out literally: rays, the segment marched, the density and light
(app/reference/clouds_medium.py), the integration, the cirrus, the ground and the sky. All the rays of an
image march in lockstep over the step index k, a block of steps at a time, with masks for the rays whose
segment has ended (or that have no clouds); the light march runs only at the samples with rho > 0.
Meant for small images (<= 96 x 54) at any number of steps.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import numpy as np

from app.model.clouds import scene as cm
from app.model.clouds.scene import CloudParams, CloudTextures, CloudView, Frame
from app.reference import clouds_sky
from app.reference.clouds_medium import (CENTRE, R0, R1, density, f64, height, hg, light, light_lookups, phase,
                                         powder, sample2d, sample3d, sun_energy, weather)

__all__ = ["Image", "render", "sample2d", "sample3d", "ray_directions", "segment", "density", "light", "hg",
           "phase", "sun_energy", "powder", "march", "cirrus", "background", "steps_for", "height"]

R = cm.PLANET_RADIUS
RC = cm.PLANET_RADIUS + cm.CIRRUS_ALTITUDE
# The spec's literals that app.model.clouds.scene does not name.
EARLY_EXIT = 0.99                       # r_cloudEarlyExit: stop once 1 - T > 0.99
CIRRUS_GAIN, CIRRUS_AMBIENT, CIRRUS_SUN, CIRRUS_MAX = 2.0, 1.5, 0.2, 0.7
HAZE = 30_000.0                         # the ground's haze distance, metres
SUN_GAIN, SUN_POWER = 4.0, 1000.0       # the sun's disc in the sky: 4 sun_light max(cos, 0)^1000
BLOCK = 1 << 16                         # (ray, step) samples evaluated at once


@dataclass
class Image:
    rgb: np.ndarray         # (H, W, 3) linear radiance, unclamped, row 0 at the top
    clouds: np.ndarray      # (H, W, 4) premultiplied clouds (layer and cirrus) before the background
    samples: np.ndarray     # (H, W) texture lookups per pixel


def ray_directions(frame: Frame, width: int, height: int) -> np.ndarray:
    """(H, W, 3) unit directions through the pixel centres, row 0 at the top."""
    x = (2 * (np.arange(width) + 0.5) / width - 1) * frame.tan_half_fov * width / height
    y = (1 - 2 * (np.arange(height) + 0.5) / height) * frame.tan_half_fov
    d = (np.array(frame.forward) + x[None, :, None] * np.array(frame.right)
         + y[:, None, None] * np.array(frame.up))
    return d / np.linalg.norm(d, axis=-1, keepdims=True)


def sphere(o, d, r: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(hit, near, far) of t^2 + 2 b t + c = 0, b = d . (o - C), c = (|o - C| - r)(|o - C| + r): the roots
    q = -(b + sign(b) sqrt(b^2 - c)) and c / q, with sign(0) = 1 (GLSL's is 0) and c / q = 0 where q = 0."""
    oc = np.asarray(o, dtype=np.float64) - CENTRE
    length = np.linalg.norm(oc, axis=-1)
    b = (np.asarray(d) * oc).sum(-1)
    c = (length - r) * (length + r)
    disc = b * b - c
    q = -(b + np.where(b >= 0, 1.0, -1.0) * np.sqrt(np.maximum(disc, 0.0)))
    other = c / np.where(q == 0, 1.0, q) * (q != 0)
    return disc >= 0, np.minimum(q, other), np.maximum(q, other)


def segment(frame: Frame, d: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(t0, t1, has_clouds, t_ground) per ray d (..., 3); t0 = t1 = 0 without clouds, t_ground = inf on a miss."""
    o = np.array(frame.camera)
    radius = float(np.linalg.norm(o - CENTRE))
    g_hit, g_near, _ = sphere(o, d, R)
    ground = g_hit & (g_near > 0)
    hit0, near0, far0 = sphere(o, d, R0)
    hit1, near1, far1 = sphere(o, d, R1)
    enters0, enters1 = hit0 & (near0 > 0), hit1 & (near1 > 0)
    if radius < R0:                     # below the layer
        has, t0, t1 = ~ground, far0, far1
    elif radius <= R1:                  # inside it
        has, t0, t1 = np.ones(ground.shape, bool), np.zeros(ground.shape), np.minimum(far1, np.where(enters0,
                                                                                                     near0, np.inf))
    else:                               # above it
        has, t0, t1 = enters1, near1, np.where(enters0, near0, far1)
    t1 = np.minimum(t1, t0 + cm.MAX_MARCH)
    has = has & (t1 > t0)
    return np.where(has, t0, 0.0), np.where(has, t1, 0.0), has, np.where(ground, g_near, np.inf)


def steps_for(d: np.ndarray, steps: int) -> np.ndarray:
    """n = max(1, round(N (1 - |d.y| / 2))), rounding halves up (floor(x + 0.5))."""
    return np.maximum(1, np.floor(steps * (1 - np.abs(d[..., 1]) / 2) + 0.5)).astype(np.int64)


def march(frame: Frame, textures: CloudTextures, d: np.ndarray, t0: np.ndarray, t1: np.ndarray, n: np.ndarray,
          jitter: np.ndarray | None = None, integration: str = "energy", early_exit: bool = False,
          density_fn: Callable | None = None, light_fn: Callable | None = None, depth: bool = False
          ) -> tuple[np.ndarray, ...]:
    """(L (N, 3), alpha (N,), lookups (N,)): the clouds along N rays d from the camera, n[i] samples at
    t0 + (k + 0.5 + j) dt, dt = (t1 - t0) / n (n = 0: no samples). density_fn(p, full) -> (rho, B, lookups)
    and light_fn(p, rho, cos) -> (S, lookups) replace the model's (tests march constant media). `depth`: and
    the samples' mean distance weighted by what each adds, T a (t1 where none adds), the aerial perspective's."""
    if integration not in ("energy", "seed"):
        raise ValueError(f"integration must be 'energy' or 'seed', not {integration!r}")
    if density_fn is None or light_fn is None:
        tex = f64(textures)
        density_fn = density_fn or (lambda p, full: density(frame, tex, p, full))
        light_fn = light_fn or (lambda p, rho, cos: light_lookups(frame, tex, p, rho, cos))
    d = np.asarray(d, dtype=np.float64).reshape(-1, 3)
    t0, t1 = np.asarray(t0, dtype=np.float64).reshape(-1), np.asarray(t1, dtype=np.float64).reshape(-1)
    n = np.asarray(n, dtype=np.int64).reshape(-1)
    j = np.zeros(len(d)) if jitter is None else np.asarray(jitter, dtype=np.float64).reshape(-1)
    dt = (t1 - t0) / np.maximum(n, 1)
    cos = d @ np.array(frame.sun_dir)
    o = np.array(frame.camera)
    radiance, transmittance = np.zeros((len(d), 3)), np.ones(len(d))
    lookups = np.zeros(len(d), dtype=np.int64)
    distance, weight = np.zeros(len(d)), np.zeros(len(d))
    alive = n > 0
    # as the shader: no early exit before the sun's disc, where every bit of transmittance shows
    exits = early_exit & ~(bool(frame.physical_sky) & (cos > clouds_sky.SUN_COS_RADIUS))
    k0 = 0
    while True:
        rays = np.flatnonzero(alive & (n > k0))
        if len(rays) == 0:
            break
        ks = k0 + np.arange(max(1, min(int(n[rays].max()) - k0, BLOCK // len(rays))))
        k0 += len(ks)
        valid = ks[None, :] < n[rays, None]                                      # (A, B)
        t = t0[rays, None] + (ks[None, :] + 0.5 + j[rays, None]) * dt[rays, None]
        p = o + t[..., None] * d[rays, None, :]
        rho = np.zeros(valid.shape)
        count = np.zeros(valid.shape, dtype=np.int64)
        rho[valid], _, count[valid] = density_fn(p[valid], True)
        a = 1 - np.exp(-frame.extinction * rho * dt[rays, None]) if integration == "energy" else rho.copy()
        a[~valid] = 0.0
        keep = np.cumprod(1 - a, axis=1)
        before = transmittance[rays, None] * np.concatenate([np.ones((len(rays), 1)), keep[:, :-1]], axis=1)
        taken = valid & ((1 - before <= EARLY_EXIT) | ~exits[rays, None])
        lit = taken & (rho > 0)
        s = np.zeros(valid.shape + (3,))
        extra = np.zeros(valid.shape, dtype=np.int64)
        if lit.any():
            s[lit], extra[lit] = light_fn(p[lit], rho[lit], np.broadcast_to(cos[rays, None], valid.shape)[lit])
        radiance[rays] += (before[..., None] * s * a[..., None] * taken[..., None]).sum(1)
        adds = np.where(taken, before * a, 0.0)
        distance[rays] += (adds * t).sum(1)
        weight[rays] += adds.sum(1)
        transmittance[rays] *= np.where(taken, 1 - a, 1.0).prod(1)
        lookups[rays] += np.where(taken, count + extra, 0).sum(1)
        alive[rays] &= (1 - transmittance[rays] <= EARLY_EXIT) | ~exits[rays]
    if early_exit:  # as the shader: an exited ray's clouds hide what lies behind, their light the mean so far
        out = exits & (1 - transmittance > EARLY_EXIT)
        radiance[out] /= (1 - transmittance[out])[:, None]
        transmittance[out] = 0.0
    if depth:
        return radiance, 1 - transmittance, lookups, np.where(weight > 0, distance / np.where(weight > 0, weight, 1),
                                                                 t1)
    return radiance, 1 - transmittance, lookups


def cirrus(frame: Frame, textures: CloudTextures, d: np.ndarray, t_ground: np.ndarray
           ) -> tuple[np.ndarray, np.ndarray]:
    """(premultiplied rgba (N, 4), lookups (N,)) of the high clouds on the shell of radius R + CIRRUS_ALTITUDE."""
    o = np.array(frame.camera)
    hit, near, far = sphere(o, d, RC)
    if np.linalg.norm(o - CENTRE) <= RC:   # where the ray leaves it from below, unless it hits the ground
        there, t = ~np.isfinite(t_ground), far
    else:                                  # where it enters it from above
        there, t = hit & (near > 0), near
    x = o + np.where(there, t, 0.0)[..., None] * d
    u, v = x[..., 0] + frame.high_offset[0], x[..., 2] + frame.high_offset[1]
    e = CIRRUS_GAIN * sample2d(textures.cirrus, u * frame.high_freq, v * frame.high_freq)
    w = weather(frame, textures, x[..., 0], x[..., 2], frame.high_coverage_freq, frame.high_offset)
    c = np.clip(w[..., 0] - frame.high_coverage_shift, 0.0, 1.0)
    alpha = np.where(there & (c > 0), np.clip(e - 1 + c, 0.0, 1.0), 0.0)
    cos = d @ np.array(frame.sun_dir)
    if frame.physical_sky:
        seen = np.concatenate([clouds_sky.cirrus_light(frame, cos) * alpha[..., None], alpha[..., None]], -1)
        return (clouds_sky.aerial_perspective(frame, clouds_sky.tables(frame), seen, d, np.where(there, t, 0.0)),
                np.where(there, 2, 0))
    colour = np.minimum(CIRRUS_AMBIENT * np.array(frame.ambient_top)
                        + CIRRUS_SUN * np.array(frame.sun_light) * (4 * math.pi * phase(frame, cos, 1.0))[..., None],
                        CIRRUS_MAX)
    return np.concatenate([colour * alpha[..., None], alpha[..., None]], -1), np.where(there, 2, 0)


def background(frame: Frame, textures: CloudTextures, d: np.ndarray, t_ground: np.ndarray
               ) -> tuple[np.ndarray, np.ndarray]:
    """(rgb (N, 3), lookups (N,)): the hazed ground where the ray hits it, else the sky with the sun; in the
    white furnace 1 everywhere."""
    if frame.furnace:
        return np.ones((len(d), 3)), np.zeros(len(d), dtype=np.int64)
    sun = np.array(frame.sun_dir)
    cos = d @ sun
    zenith, horizon, sun_light = np.array(frame.sky_zenith), np.array(frame.sky_horizon), np.array(frame.sun_light)
    if frame.physical_sky:
        air = clouds_sky.tables(frame)
        sky = clouds_sky.physical_sky(frame, air, d, cos)
    else:
        up = np.sqrt(np.maximum(d[..., 1], 0.0))[..., None]
        sky = horizon * (1 - up) + zenith * up
        sky = sky + SUN_GAIN * sun_light * (np.maximum(cos, 0) ** SUN_POWER)[..., None]
    lookups = np.zeros(len(d), dtype=np.int64)
    ground = np.flatnonzero(np.isfinite(t_ground))
    if len(ground) == 0:
        return sky, lookups
    tg = t_ground[ground]
    x = np.array(frame.camera) + tg[:, None] * d[ground]
    normal = (x - CENTRE) / np.linalg.norm(x - CENTRE, axis=-1, keepdims=True)
    shadow = np.ones(len(ground))
    if frame.ground_shadows:           # 8 midpoint samples without detail along the sun's ray through the layer
        rays = np.broadcast_to(sun, x.shape)
        _, _, ta = sphere(x, rays, R0)
        _, _, tb = sphere(x, rays, R1)
        step = (tb - ta) / cm.GROUND_SHADOW_SAMPLES
        i = np.arange(cm.GROUND_SHADOW_SAMPLES) + 0.5
        p = x[:, None, :] + (ta[:, None] + i[None, :] * step[:, None])[..., None] * sun
        rho, _, count = density(frame, f64(textures), p, False)
        shadow = np.exp(-frame.extinction * (rho * step[:, None]).sum(1))
        lookups[ground] = count.sum(1)
    if frame.physical_sky:
        seen = np.concatenate([clouds_sky.physical_ground(frame, air, normal, shadow), np.ones((len(ground), 1))], -1)
        sky[ground] = clouds_sky.aerial_perspective(frame, air, seen, d[ground], tg)[:, :3]
        return sky, lookups
    lit = sun_light * (np.maximum(normal @ sun, 0) * shadow)[:, None] + (horizon + zenith) / 2
    colour = np.array(cm.GROUND_ALBEDO) * lit
    haze = (1 - np.exp(-tg / HAZE))[:, None]
    sky[ground] = colour * (1 - haze) + horizon * haze
    return sky, lookups


def render(params: CloudParams, view: CloudView, textures: CloudTextures, size: tuple[int, int] = (96, 54),
           steps: int = 256, integration: str = "energy", wind_time: float = 0.0, blend: float = 1.0,
           early_exit: bool = False, jitter: np.ndarray | None = None, furnace: bool = False) -> Image:
    """The reference image: clouds (layer and cirrus) over the ground or sky, as linear radiance (the GPU's HDR
    frame before its tone map); `furnace`: in the white furnace's unit environment
    (app.model.clouds.scene.furnace)."""
    width, height_ = size
    fr = cm.frame(params, view, wind_time, blend)
    if furnace:
        fr = cm.furnace(fr)
    tex = f64(textures)
    d = ray_directions(fr, width, height_).reshape(-1, 3)
    t0, t1, has, t_ground = segment(fr, d)
    n = np.where(has, steps_for(d, steps), 0)
    j = None if jitter is None else np.asarray(jitter, dtype=np.float64).reshape(-1)
    layer_rgb, layer_a, samples, depth = march(fr, tex, d, t0, t1, n, j, integration, early_exit, depth=True)
    layer = np.concatenate([layer_rgb, layer_a[:, None]], -1)
    if fr.physical_sky:
        layer = clouds_sky.aerial_perspective(fr, clouds_sky.tables(fr), layer, d, depth)
    high, high_count = cirrus(fr, tex, d, t_ground)
    if fr.camera[1] > cm.CIRRUS_ALTITUDE:       # the cirrus in front of the layer
        clouds = high + (1 - high[:, 3:]) * layer
    else:
        clouds = layer + (1 - layer[:, 3:]) * high
    bg, bg_count = background(fr, tex, d, t_ground)
    rgb = clouds[:, :3] + (1 - clouds[:, 3:]) * bg
    samples = samples + high_count + bg_count
    return Image(rgb.reshape(height_, width, 3), clouds.reshape(height_, width, 4),
                 samples.reshape(height_, width))
