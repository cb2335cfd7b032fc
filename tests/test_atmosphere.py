"""The physical sky's tables (Hillaire 2020): the GPU's are the CPU's recipes (app/reference/atmosphere.py) to
float32's precision, and the recipes approximate the converged integrals within the stated tolerances: the
transmittance table within 0.5 %, the sky-view table of single scattering within 1.5 % (1 % farther than 20
degrees from the sun). The tables are remade only when what they depend on changes."""
from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from app.gl.clouds.atmosphere import AtmosphereTables
from app.gl.core.shaders import ShaderLibrary
from app.model.clouds import atmosphere as am
from app.model.clouds.scene import ATMOSPHERE
from app.reference import atmosphere as ra
from app.resources import SHADERS

ATM = ATMOSPHERE


@pytest.fixture(scope="module")
def tables(gl):
    return AtmosphereTables(gl, ShaderLibrary(gl, [SHADERS]))


def read(texture) -> np.ndarray:
    return np.frombuffer(texture.read(), np.float32).reshape(texture.size[1], texture.size[0], 4)[..., :3] \
        .astype(np.float64)


def relative(a, b, floor):
    return np.abs(a - b) / np.maximum(np.abs(b), floor)


# --- the model's parameterisations ---------------------------------------------------------------------------

def test_each_table_parameterisation_inverts_its_mapping():
    rng = np.random.default_rng(0)
    u, v = rng.uniform(0.03, 0.99, (2, 200))   # above the multiscattering table's lowest metre (kept off the ground)
    r, mu = am.transmittance_params(ATM, u, v)
    np.testing.assert_allclose(am.transmittance_uv(ATM, r, mu), (u, v), atol=1e-9)
    assert not am.hits_ground(ATM, r, mu).any()                          # the table holds no ray into the ground
    r, mu_s = am.multiscatter_params(ATM, u, v)
    np.testing.assert_allclose(am.multiscatter_uv(ATM, r, mu_s), (u, v), atol=1e-9)
    radius = ATM.bottom + 3000.0
    mu, cos_az = am.sky_view_params(ATM, radius, u, v)
    np.testing.assert_allclose(am.sky_view_uv(ATM, radius, mu, cos_az), (u, v), atol=1e-9)
    above = am.texel_to_unit(v, am.SKY_VIEW_SIZE[1]) < 0.5               # the upper half: the sky
    assert np.array_equal(~am.hits_ground(ATM, radius, mu), above)


def test_the_light_at_the_layer_reddens_and_fades_as_the_sun_sets():
    noon, low, below = (am.layer_light(ATM, math.sin(math.radians(e)), (1500.0, 5500.0)) for e in (65, 3, -3))
    assert np.all(noon.sun > 0.7) and np.all(noon.sun[1] > noon.sun[0])  # whiter and brighter at the top
    assert low.sun[0, 0] > 2 * low.sun[0, 2]                             # red at sun 3 degrees
    assert np.all(below.sun[1] > 0.05) and np.all(below.sun[0] < below.sun[1])  # the top still sees it at -3
    assert np.all(noon.ambient > low.ambient) and np.all(low.ambient > below.ambient) and np.all(below.ambient > 0)
    assert noon.ambient[0, 2] > noon.ambient[0, 0]                       # the sky's light is blue


# --- the GPU's tables are the CPU's recipes ------------------------------------------------------------------

@pytest.mark.parametrize("altitude, elevation", [(200.0, 25.0), (3000.0, -3.0)])
def test_the_gpu_tables_are_the_cpu_recipes(tables, altitude, elevation):
    sun_y = math.sin(math.radians(elevation))
    tables.update(ATM, altitude, sun_y)
    cpu = ra.tables(ATM, altitude, sun_y)
    t, m, s = (read(tables.tables[n]) for n in ("transmittance", "multiscatter", "sky_view"))
    assert relative(t, cpu.transmittance, 1e-3).max() < 1e-4
    assert relative(m, cpu.multiscatter, 1e-3 * cpu.multiscatter.max()).max() < 1e-3
    sky = relative(s, cpu.sky_view, 1e-3 * cpu.sky_view.max())
    horizon = am.SKY_VIEW_SIZE[1] // 2
    sky[horizon - 1:horizon + 1] = 0   # the rays that graze the ground: float32 cannot place them
    # float32's acos puts a texel's direction some 1e-5 off, which moves samples in the planet's penumbra a little
    assert sky.max() < (2e-3 if elevation > 0 else 2e-2)
    assert np.median(sky) < 1e-4


def test_the_transmittance_table_is_the_integral(tables):
    tables.update(ATM, 200.0, 0.5)
    table = read(tables.tables["transmittance"])
    rng = np.random.default_rng(1)
    r = ATM.bottom + rng.uniform(0.0, 90_000.0, 300)
    mu = rng.uniform(-0.3, 1.0, 300)
    keep = ~am.hits_ground(ATM, r, mu)
    exact = am.transmittance(ATM, r[keep], mu[keep], steps=2000)
    assert np.abs(exact - am.transmittance(ATM, r[keep], mu[keep], steps=1000)).max() < 1e-5   # converged
    looked_up = ra.sample_clamped(table, *am.transmittance_uv(ATM, r[keep], mu[keep]))
    assert relative(looked_up, exact, 1e-3).max() < 5e-3


@pytest.mark.parametrize("altitude, elevation", [(200.0, 65.0), (200.0, 5.0), (3000.0, -3.0)])
def test_the_sky_view_table_of_single_scattering_is_the_integral(tables, altitude, elevation):
    sun_y = math.sin(math.radians(elevation))
    tables.update(ATM, altitude, sun_y, multiple=False)
    table = read(tables.tables["sky_view"])
    rng = np.random.default_rng(2)
    el, az = np.radians(rng.uniform(2.0, 89.0, 12)), np.radians(rng.uniform(0.0, 180.0, 12))
    el[0], az[0] = math.radians(max(elevation, 0.0) + 6.0), 0.0      # near the sun, in its Mie halo
    mu, cos_az = np.sin(el), np.cos(az)
    nu = np.cos(el) * cos_az * math.sqrt(1 - sun_y * sun_y) + mu * sun_y
    radius = ATM.bottom + altitude
    exact = ra.single_scattering(ATM, radius, mu, sun_y, nu, steps=600, sun_steps=60)
    coarse = ra.single_scattering(ATM, radius, mu, sun_y, nu, steps=300, sun_steps=30)
    assert relative(coarse, exact, 1e-6).max() < 2e-3                    # the integral has converged
    error = relative(ra.sample_clamped(table, *am.sky_view_uv(ATM, radius, mu, cos_az)), exact, 1e-6).max(-1)
    far = np.degrees(np.arccos(nu)) > 20
    assert error.max() < 0.015 and error[far].max() < 0.01


# --- made only when needed -----------------------------------------------------------------------------------

def test_a_table_is_remade_only_when_what_it_depends_on_changes(gl):
    fresh = AtmosphereTables(gl, ShaderLibrary(gl, [SHADERS]))
    fresh.update(ATM, 200.0, 0.4)
    assert fresh.computed == {"transmittance": 1, "multiscatter": 1, "sky_view": 1}
    fresh.update(ATM, 200.0, 0.4)
    assert fresh.computed == {"transmittance": 1, "multiscatter": 1, "sky_view": 1}
    fresh.update(ATM, 200.0, 0.1)                                        # the sun sinks
    fresh.update(ATM, 3000.0, 0.1)                                       # the camera climbs
    assert fresh.computed == {"transmittance": 1, "multiscatter": 1, "sky_view": 3}
    fresh.update(replace(ATM, mie_scattering=8e-6, mie_extinction=8.9e-6), 3000.0, 0.1)   # hazier air
    assert fresh.computed == {"transmittance": 2, "multiscatter": 2, "sky_view": 4}
