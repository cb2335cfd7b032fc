"""Float64 CPU reference of the physical sky (Hillaire 2020), numpy only: its three lookup tables built by the
shaders' recipes (resources/shaders/atmosphere*.glsl) from app.model.clouds.atmosphere's integrals and read as GL
reads them, the light scattered along a ray from them, and the converged integrals the tables approximate (the
transmittance and the single scattering, with no table and many steps) that check them."""
from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from app.model.clouds import atmosphere as am
from app.model.clouds.atmosphere import Atmosphere


def sample_clamped(table: np.ndarray, u, v) -> np.ndarray:
    """table[j, i, channel] at (u, v), i along u: GL's bilinear filtering with clamp to edge."""
    def axis(x, n):
        c = np.clip(np.asarray(x, dtype=np.float64) * n - 0.5, 0.0, n - 1.0)
        i0 = np.minimum(np.floor(c), max(n - 2, 0)).astype(np.int64)
        return i0, np.minimum(i0 + 1, n - 1), (c - i0)[..., None]

    i0, i1, fu = axis(u, table.shape[1])
    j0, j1, fv = axis(v, table.shape[0])
    return ((table[j0, i0] * (1 - fu) + table[j0, i1] * fu) * (1 - fv)
            + (table[j1, i0] * (1 - fu) + table[j1, i1] * fu) * fv)


def texel_centres(size: tuple[int, int]) -> tuple[np.ndarray, np.ndarray]:
    """(u, v) of every texel's centre, (height, width) arrays: row j is v = (j + 0.5) / height, as GL stores it."""
    return np.meshgrid((np.arange(size[0]) + 0.5) / size[0], (np.arange(size[1]) + 0.5) / size[1], indexing="xy")


@dataclass(frozen=True, eq=False)
class Tables:
    """The three tables, (height, width, 3) float64 each, per unit sun illuminance."""
    atm: Atmosphere
    transmittance: np.ndarray
    multiscatter: np.ndarray
    sky_view: np.ndarray
    camera_radius: float
    sun_y: float

    def sun_transmittance(self, r, mu_s) -> np.ndarray:
        """The sun's transmittance from radius r, from its table (am.sun_transmittance)."""
        t = sample_clamped(self.transmittance, *am.transmittance_uv(self.atm, r, mu_s))
        return t * am.sun_visible(self.atm, r, mu_s)[..., None]

    def multiple(self, r, mu_s) -> np.ndarray:
        return sample_clamped(self.multiscatter, *am.multiscatter_uv(self.atm, r, mu_s))

    def sky(self, mu, cos_azimuth) -> np.ndarray:
        """The sky from the camera (per unit sun illuminance) in the direction (mu, cos azimuth from the sun)."""
        return sample_clamped(self.sky_view, *am.sky_view_uv(self.atm, self.camera_radius, mu, cos_azimuth))


def transmittance_table(atm: Atmosphere) -> np.ndarray:
    return am.transmittance(atm, *am.transmittance_params(atm, *texel_centres(am.TRANSMITTANCE_SIZE)))


def multiscatter_table(atm: Atmosphere, transmittance: np.ndarray) -> np.ndarray:
    partial = Tables(atm, transmittance, np.zeros((1, 1, 3)), np.zeros((1, 1, 3)), atm.bottom, 0.0)
    r, mu_s = am.multiscatter_params(atm, *texel_centres(am.MULTISCATTER_SIZE))
    return am.multiple_scattering(atm, r, mu_s, sun=partial.sun_transmittance)


def scatter(tables: Tables, r, mu, mu_s, nu, t_end, steps: int, multiple: bool = True
            ) -> tuple[np.ndarray, np.ndarray]:
    """(light scattered towards r along (r, mu) over 0..t_end (..., 3), the ray's transmittance over it): the
    shaders' scatter(): step i over t_end (i/n)^2 .. t_end ((i+1)/n)^2, integrated exactly for the medium at its
    middle; the sun at mu_s, nu = view . sun."""
    atm = tables.atm
    r, mu, mu_s, nu, t_end = np.broadcast_arrays(*(np.asarray(x, dtype=np.float64) for x in (r, mu, mu_s, nu, t_end)))
    phase_r, phase_m = am.rayleigh_phase(nu)[..., None], am.mie_phase(atm, nu)[..., None]
    lum, throughput = np.zeros(r.shape + (3,)), np.ones(r.shape + (3,))
    for i in range(steps):
        a, b = i / steps, (i + 1) / steps
        t, dt = t_end * 0.5 * (a * a + b * b), (t_end * (b * b - a * a))[..., None]
        rp = am.along(r, mu, t)
        mu_sp = (r * mu_s + t * nu) / rp
        rayleigh, mie, extinction = am.coefficients(atm, rp - atm.bottom)
        source = tables.sun_transmittance(rp, mu_sp) * (rayleigh * phase_r + mie[..., None] * phase_m)
        if multiple:
            source = source + (rayleigh + mie[..., None]) * tables.multiple(rp, mu_sp)
        lum += throughput * source * am.step_integral(extinction, dt)
        throughput = throughput * np.exp(-extinction * dt)
    return lum, throughput


def sky_view_table(tables: Tables, multiple: bool = True) -> np.ndarray:
    atm, r, sun_y = tables.atm, tables.camera_radius, tables.sun_y
    u, v = texel_centres(am.SKY_VIEW_SIZE)
    mu, cos_az = am.sky_view_params(atm, r, u, v)
    nu = np.sqrt(np.maximum(1 - mu * mu, 0.0)) * cos_az * math.sqrt(max(1 - sun_y * sun_y, 0.0)) + mu * sun_y
    ground = am.texel_to_unit(v, am.SKY_VIEW_SIZE[1]) >= 0.5    # the table's lower half (as the shader decides)
    end = np.where(ground, am.distance_to_ground(atm, r, mu), am.distance_to_top(atm, r, mu))
    return scatter(tables, r, mu, sun_y, nu, end, am.SKY_VIEW_STEPS, multiple)[0]


@lru_cache(maxsize=8)
def tables(atm: Atmosphere, altitude: float, sun_y: float, multiple: bool = True) -> Tables:
    """The tables the GPU makes for a camera at `altitude` with the sun's direction at height sun_y."""
    transmittance = transmittance_table(atm)
    partial = Tables(atm, transmittance, multiscatter_table(atm, transmittance), np.zeros((1, 1, 3)),
                     atm.bottom + max(altitude, am.MIN_ALTITUDE), sun_y)
    return Tables(atm, partial.transmittance, partial.multiscatter, sky_view_table(partial, multiple),
                  partial.camera_radius, sun_y)


# ---- the converged integrals --------------------------------------------------------------------------------

def single_scattering(atm: Atmosphere, r, mu, mu_s, nu, steps: int = 2000, sun_steps: int = 200) -> np.ndarray:
    """The light scattered once towards r along (r, mu) to the top of the atmosphere or the ground, per unit
    sun illuminance (..., 3): integral of T(0, t) (sigma_R P_R + sigma_M P_M) T_sun(t) dt by `steps` midpoints,
    the view's transmittance and the sun's (sun_steps each, no table) integrated along."""
    r, mu, mu_s, nu = np.broadcast_arrays(*(np.asarray(x, dtype=np.float64) for x in (r, mu, mu_s, nu)))
    dt = am.ray_end(atm, r, mu)[0] / steps
    phase_r, phase_m = am.rayleigh_phase(nu)[..., None], am.mie_phase(atm, nu)[..., None]
    lum, depth = np.zeros(r.shape + (3,)), np.zeros(r.shape + (3,))
    for i in range(steps):
        t = (i + 0.5) * dt
        rp = am.along(r, mu, t)
        rayleigh, mie, extinction = am.coefficients(atm, rp - atm.bottom)
        seen = np.exp(-(depth + extinction * dt[..., None] / 2))         # the view's transmittance to t
        sun = am.sun_transmittance(atm, rp, (r * mu_s + t * nu) / rp, sun_steps)
        lum += seen * sun * (rayleigh * phase_r + mie[..., None] * phase_m) * dt[..., None]
        depth += extinction * dt[..., None]
    return lum
