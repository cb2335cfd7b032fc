"""The physical sky's atmosphere (Hillaire 2020, "A Scalable and Production Ready Sky and Atmosphere Rendering
Technique"): Earth's air (Rayleigh, Mie, ozone) over the clouds' planet, the parameterisations of its three
lookup tables and, in float64, the integrals their texels hold. resources/shaders/atmosphere.shl computes the
tables on the GPU by the same recipes; app/reference/atmosphere.py builds them on the CPU from these functions and
checks them against converged integrals; scene.frame() takes the light on the cloud layer from them.

Units: metres; radiance per unit of the sun's illuminance at the top of the atmosphere (the shaders multiply by
SUN_ILLUMINANCE). Positions are relative to the planet's centre, y up; r is a distance from the centre, mu the
cosine of a direction's angle to the local vertical. Every function takes arrays and broadcasts."""
from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

# The sun's illuminance at the top of the atmosphere, in the renderer's radiance units: a white surface facing a
# clear noon sun reflects about this / pi. Chosen so that noon looks right under the display's clamp until the
# frame is tone mapped: the clouds as bright as the seed's (their sun light, E / (4 pi) T, near 1) and the
# zenith a clear blue (docs/clouds.md, "The sky and the atmosphere").
SUN_ILLUMINANCE = 4.0 * math.pi

TRANSMITTANCE_SIZE = (256, 64)   # (mu, r) texels
MULTISCATTER_SIZE = (32, 32)     # (mu_s, r)
SKY_VIEW_SIZE = (192, 108)       # (azimuth from the sun, view zenith)
TRANSMITTANCE_STEPS = 40         # midpoint steps along each ray of a texel
MULTISCATTER_STEPS = 20
MULTISCATTER_DIRECTIONS = 8      # 8 x 8 directions over the sphere
SKY_VIEW_STEPS = 30               # (the sky view and the aerial perspective: squared spacing)
AERIAL_STEPS = 16                # steps from the camera to a cloud, the cirrus or the ground
MIN_ALTITUDE = 1.0               # points are kept this far above the ground (a ray at the ground grazes it)


@dataclass(frozen=True)
class Atmosphere:
    """Earth's air after Hillaire 2020 (its Earth preset) between the radii `bottom` (the ground, of albedo
    `ground_albedo`) and `top` (app.model.clouds.scene.ATMOSPHERE: on the clouds' planet)."""
    bottom: float
    top: float
    ground_albedo: tuple
    rayleigh_scattering: tuple = (5.802e-6, 13.558e-6, 33.1e-6)   # per metre at the ground, red green blue
    rayleigh_height: float = 8000.0                               # exponential scale height
    mie_scattering: float = 3.996e-6
    mie_extinction: float = 4.440e-6
    mie_height: float = 1200.0
    mie_g: float = 0.8                                            # Cornette-Shanks asymmetry
    ozone_absorption: tuple = (0.650e-6, 1.881e-6, 0.085e-6)
    ozone_centre: float = 25_000.0                                # a tent: 1 at the centre, 0 at +-width
    ozone_width: float = 15_000.0
    sun_radius_deg: float = 0.2665                                # the sun's angular radius


# ---- the medium ---------------------------------------------------------------------------------------------

def coefficients(atm: Atmosphere, altitude) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(Rayleigh scattering (..., 3), Mie scattering (...), extinction (..., 3)) per metre at `altitude`."""
    h = np.maximum(np.asarray(altitude, dtype=np.float64), 0.0)
    rayleigh = np.exp(-h / atm.rayleigh_height)[..., None] * np.array(atm.rayleigh_scattering)
    mie = np.exp(-h / atm.mie_height)
    ozone = np.maximum(0.0, 1.0 - np.abs(h - atm.ozone_centre) / atm.ozone_width)
    extinction = rayleigh + (mie * atm.mie_extinction)[..., None] + ozone[..., None] * np.array(atm.ozone_absorption)
    return rayleigh, mie * atm.mie_scattering, extinction


def rayleigh_phase(nu):
    return 3.0 / (16.0 * math.pi) * (1.0 + np.asarray(nu) ** 2)


def mie_phase(atm: Atmosphere, nu):
    """Cornette-Shanks, per steradian."""
    g, nu = atm.mie_g, np.asarray(nu)
    return (3.0 / (8.0 * math.pi) * (1 - g * g) * (1 + nu * nu)
            / ((2 + g * g) * (1 + g * g - 2 * g * nu) ** 1.5))


def step_integral(extinction, dt):
    """The integral of exp(-extinction s) over 0..dt: (1 - exp(-x)) / extinction, x = extinction dt, taken as
    dt (1 - x / 2) where x is too small for float32's 1 - exp(-x) (the shaders do the same)."""
    x = extinction * dt
    small = x < 1e-4
    return np.where(small, dt * (1 - 0.5 * x), -np.expm1(-np.where(small, 1.0, x)) / np.where(small, 1.0, extinction))


# ---- rays from a point at radius r, direction mu -------------------------------------------------------------

def hits_ground(atm: Atmosphere, r, mu):
    r, mu = np.asarray(r, dtype=np.float64), np.asarray(mu, dtype=np.float64)
    return (mu < 0) & (r * r * (mu * mu - 1) + atm.bottom ** 2 >= 0)


def distance_to_top(atm: Atmosphere, r, mu):
    r, mu = np.asarray(r, dtype=np.float64), np.asarray(mu, dtype=np.float64)
    return np.maximum(-r * mu + np.sqrt(np.maximum(r * r * (mu * mu - 1) + atm.top ** 2, 0.0)), 0.0)


def distance_to_ground(atm: Atmosphere, r, mu):
    r, mu = np.asarray(r, dtype=np.float64), np.asarray(mu, dtype=np.float64)
    return np.maximum(-r * mu - np.sqrt(np.maximum(r * r * (mu * mu - 1) + atm.bottom ** 2, 0.0)), 0.0)


def ray_end(atm: Atmosphere, r, mu):
    """(distance to where the ray leaves the atmosphere or meets the ground, whether it meets the ground)."""
    ground = hits_ground(atm, r, mu)
    return np.where(ground, distance_to_ground(atm, r, mu), distance_to_top(atm, r, mu)), ground


def along(r, mu, t):
    """The radius at distance t along the ray."""
    return np.sqrt(np.maximum(r * r + t * t + 2 * r * mu * t, 0.0))


# ---- the lookup tables' parameterisations (Bruneton 2017, Hillaire 2020) --------------------------------------

def unit_to_texel(x, n: int):
    """0..1 onto the texel centres of n texels, so a table's ends are read exactly."""
    return 0.5 / n + np.asarray(x) * (1 - 1 / n)


def texel_to_unit(u, n: int):
    return (np.asarray(u) - 0.5 / n) / (1 - 1 / n)


def _horizon_length(atm: Atmosphere) -> float:
    return math.sqrt(atm.top ** 2 - atm.bottom ** 2)


def transmittance_uv(atm: Atmosphere, r, mu):
    """(u, v) of the transmittance table at (r, mu): u the distance to the top between its least and most at r,
    v the distance to the horizon; rays that meet the ground are not in it."""
    r, mu = np.asarray(r, dtype=np.float64), np.asarray(mu, dtype=np.float64)
    H = _horizon_length(atm)
    rho = np.sqrt(np.maximum((r - atm.bottom) * (r + atm.bottom), 0.0))
    d = distance_to_top(atm, r, mu)
    d_min, d_max = atm.top - r, rho + H
    return (unit_to_texel((d - d_min) / (d_max - d_min), TRANSMITTANCE_SIZE[0]),
            unit_to_texel(rho / H, TRANSMITTANCE_SIZE[1]))


def transmittance_params(atm: Atmosphere, u, v):
    """(r, mu) of the transmittance table at (u, v), its inverse."""
    H = _horizon_length(atm)
    rho = H * texel_to_unit(v, TRANSMITTANCE_SIZE[1])
    r = np.sqrt(rho * rho + atm.bottom ** 2)
    d_min, d_max = atm.top - r, rho + H
    d = d_min + texel_to_unit(u, TRANSMITTANCE_SIZE[0]) * (d_max - d_min)
    mu = np.where(d == 0, 1.0, (H * H - rho * rho - d * d) / (2 * r * np.where(d == 0, 1.0, d)))
    return r, np.clip(mu, -1.0, 1.0)


def multiscatter_uv(atm: Atmosphere, r, mu_s):
    return (unit_to_texel(np.asarray(mu_s) * 0.5 + 0.5, MULTISCATTER_SIZE[0]),
            unit_to_texel((np.asarray(r) - atm.bottom) / (atm.top - atm.bottom), MULTISCATTER_SIZE[1]))


def multiscatter_params(atm: Atmosphere, u, v):
    mu_s = 2 * texel_to_unit(u, MULTISCATTER_SIZE[0]) - 1
    r = atm.bottom + texel_to_unit(v, MULTISCATTER_SIZE[1]) * (atm.top - atm.bottom)
    return np.maximum(r, atm.bottom + MIN_ALTITUDE), mu_s


def _horizon_angles(atm: Atmosphere, r):
    """(beta, the horizon's depression below the horizontal; the horizon's zenith angle, pi - beta)."""
    beta = np.arccos(np.clip(np.sqrt(np.maximum((r - atm.bottom) * (r + atm.bottom), 0.0)) / r, -1.0, 1.0))
    return beta, math.pi - beta


def sky_view_uv(atm: Atmosphere, r, mu, cos_azimuth):
    """(u, v) of the sky-view table seen from radius r: u = sqrt((1 - cos azimuth) / 2) (finer towards the sun),
    v from the zenith (0) to the horizon (0.5, squared: finer at the horizon) to the nadir (1)."""
    beta, horizon = _horizon_angles(atm, r)
    zenith = np.arccos(np.clip(mu, -1.0, 1.0))
    above = zenith <= horizon
    up = 0.5 * (1 - np.sqrt(np.maximum(1 - zenith / horizon, 0.0)))
    down = 0.5 + 0.5 * np.sqrt(np.clip((zenith - horizon) / np.maximum(beta, 1e-12), 0.0, 1.0))
    return (unit_to_texel(np.sqrt(np.clip(0.5 - 0.5 * np.asarray(cos_azimuth), 0.0, 1.0)), SKY_VIEW_SIZE[0]),
            unit_to_texel(np.where(above, up, down), SKY_VIEW_SIZE[1]))


def sky_view_params(atm: Atmosphere, r, u, v):
    """(mu, cos azimuth) of the sky-view table seen from radius r at (u, v), its inverse."""
    beta, horizon = _horizon_angles(atm, r)
    y = texel_to_unit(v, SKY_VIEW_SIZE[1])
    x = texel_to_unit(u, SKY_VIEW_SIZE[0])
    up = 1 - (1 - 2 * y) ** 2
    down = (2 * y - 1) ** 2
    zenith = np.where(y < 0.5, horizon * up, horizon + beta * down)
    return np.cos(zenith), 1 - 2 * x * x


# ---- the tables' integrals ----------------------------------------------------------------------------------

def transmittance(atm: Atmosphere, r, mu, steps: int = TRANSMITTANCE_STEPS):
    """T (..., 3) from radius r along mu to the top of the atmosphere (through the ground if the ray meets it):
    exp(-sum extinction dt) at `steps` midpoints."""
    r, mu = np.broadcast_arrays(np.asarray(r, dtype=np.float64), np.asarray(mu, dtype=np.float64))
    dt = distance_to_top(atm, r, mu) / steps
    tau = np.zeros(r.shape + (3,))
    for i in range(steps):
        t = (i + 0.5) * dt
        tau += coefficients(atm, along(r, mu, t) - atm.bottom)[2] * dt[..., None]
    return np.exp(-tau)


def sun_visible(atm: Atmosphere, r, mu_s):
    """The share of the sun's disc above the horizon at radius r (Bruneton 2017's smoothstep over the disc): the
    planet's shadow has the penumbra the sun's size gives it, so a ray's samples do not flip in and out of it."""
    r = np.asarray(r, dtype=np.float64)
    sin_h = atm.bottom / r
    cos_h = -np.sqrt(np.maximum((r - atm.bottom) * (r + atm.bottom), 0.0)) / r
    edge = sin_h * math.radians(atm.sun_radius_deg)
    x = np.clip((np.asarray(mu_s) - cos_h + edge) / (2 * edge), 0.0, 1.0)
    return x * x * (3 - 2 * x)


def sun_transmittance(atm: Atmosphere, r, mu_s, steps: int = TRANSMITTANCE_STEPS):
    """The sun's transmittance from radius r, times the share of its disc above the horizon (the transmittance
    at the horizon while it sets)."""
    r, mu_s = np.asarray(r, dtype=np.float64), np.asarray(mu_s, dtype=np.float64)
    horizon = -np.sqrt(np.maximum((r - atm.bottom) * (r + atm.bottom), 0.0)) / r
    return transmittance(atm, r, np.maximum(mu_s, horizon), steps) * sun_visible(atm, r, mu_s)[..., None]


def sphere_directions(n: int = MULTISCATTER_DIRECTIONS) -> np.ndarray:
    """n x n directions (n^2, 3) spread evenly over the sphere (equal areas), y up."""
    i, j = np.meshgrid(np.arange(n), np.arange(n), indexing="xy")
    theta = 2 * math.pi * (i.reshape(-1) + 0.5) / n
    cos_phi = 1 - 2 * (j.reshape(-1) + 0.5) / n
    sin_phi = np.sqrt(1 - cos_phi ** 2)
    return np.stack([np.cos(theta) * sin_phi, cos_phi, np.sin(theta) * sin_phi], -1)


def multiple_scattering(atm: Atmosphere, r, mu_s, sun=None, steps: int = MULTISCATTER_STEPS,
                        directions: int = MULTISCATTER_DIRECTIONS):
    """Psi_ms (..., 3) at radius r with the sun at mu_s (Hillaire's eq. 5-10): the light of the second order
    arriving from every direction (single scattering with an isotropic phase, and the lit ground) averaged over
    the sphere, L2, times 1 / (1 - f_ms), the sum of the higher orders (f_ms: the share of light an isotropic
    scatterer there gets back after one more scattering). Scattering coefficients times Psi_ms is the light the
    orders above the first scatter per metre; Psi_ms itself is the mean radiance of the sky around the point.
    `sun(r, mu_s)`: the sun's transmittance (default the integral; the tables' builder reads its table)."""
    sun_t = sun or (lambda rr, mm: sun_transmittance(atm, rr, mm))
    r, mu_s = np.broadcast_arrays(np.asarray(r, dtype=np.float64), np.asarray(mu_s, dtype=np.float64))
    shape = r.shape
    r, mu_s = r.reshape(-1, 1), mu_s.reshape(-1, 1)
    dirs = sphere_directions(directions)
    mu, sx = dirs[None, :, 1], np.sqrt(np.maximum(1 - mu_s ** 2, 0.0))   # the sun at (sx, mu_s, 0)
    dot_sun = dirs[None, :, 0] * sx + mu * mu_s
    end, ground = ray_end(atm, r, mu)
    dt = end / steps
    lum, f, throughput = np.zeros((len(r), len(dirs), 3)), np.zeros((len(r), len(dirs), 3)), 1.0
    for i in range(steps):
        t = (i + 0.5) * dt
        rp = along(r, mu, t)
        mu_sp = (r * mu_s + t * dot_sun) / rp
        rayleigh, mie, ext = coefficients(atm, rp - atm.bottom)
        scattering = rayleigh + mie[..., None]
        integral = step_integral(ext, dt[..., None])
        lum += throughput * scattering * sun_t(rp, mu_sp) / (4 * math.pi) * integral
        f += throughput * scattering * integral
        throughput = throughput * np.exp(-ext * dt[..., None])
    rg = along(r, mu, end)
    mu_g = (r * mu_s + end * dot_sun) / rg
    lit = np.where(ground, np.maximum(mu_g, 0.0), 0.0)[..., None]
    lum += throughput * sun_t(np.full_like(rg, atm.bottom), mu_g) * lit * np.array(atm.ground_albedo) / math.pi
    l2, fms = lum.mean(1), f.mean(1)
    return (l2 / (1 - fms)).reshape(shape + (3,))


@dataclass(frozen=True)
class LayerLight:
    """The light at a few altitudes with the sun at one elevation, per unit sun illuminance, (n, 3) each: the
    sun's transmittance and Psi_ms (the sky's mean radiance there)."""
    sun: np.ndarray
    ambient: np.ndarray


@lru_cache(maxsize=64)
def layer_light(atm: Atmosphere, sun_y: float, altitudes: tuple[float, ...]) -> LayerLight:
    """The sun's transmittance and the sky's light at `altitudes` above the ground with the sun's direction at
    height sun_y (its elevation's sine), seen where the camera stands (the sky overhead there)."""
    r = atm.bottom + np.maximum(np.array(altitudes, dtype=np.float64), MIN_ALTITUDE)
    mu_s = np.full(len(r), float(sun_y))
    return LayerLight(sun_transmittance(atm, r, mu_s), multiple_scattering(atm, r, mu_s))


def physical_light(atm: Atmosphere, sun_y: float, direct: float, ambient_gain: float,
                   altitudes: tuple[float, float, float]) -> dict:
    """The frame's light on the clouds under the physical sky (app.model.clouds.scene.Frame's fields) at the
    layer's base and top and at the cirrus (`altitudes`): the sun's transmitted light in the shader's units (the
    light march multiplies it by 4 pi times the phase, so it is the illuminance over 4 pi), times `direct`; and
    the sky's mean radiance there (Psi_ms) as their ambient light, times `ambient_gain`."""
    light = layer_light(atm, float(sun_y), tuple(altitudes))
    sun = light.sun * SUN_ILLUMINANCE / (4 * math.pi) * direct
    ambient = light.ambient * SUN_ILLUMINANCE * ambient_gain
    rgb = [tuple(float(c) for c in row) for row in (*sun, *ambient)]
    return dict(sun_light=rgb[0], sun_light_top=rgb[1], cirrus_light=rgb[2], ambient_base=rgb[3],
                ambient_top=rgb[4], cirrus_ambient=rgb[5], sun_illuminance=SUN_ILLUMINANCE)
