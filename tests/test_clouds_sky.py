"""The clouds under the physical sky, on the real render path (small float pictures): twilight darkens smoothly
and keeps its colour, the cirrus are brighter than the sky at noon and tinted at sunset, the GPU draws what the
CPU reference draws, looking around remakes no table, and the seed's colours stay an option."""
from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from app.gl.core.workspace_renderer import WorkspaceRenderer
from app.io.clouds.textures import noise_textures
from app.model.clouds.exposure import ToneSettings
from app.model.clouds.scene import CloudParams, CloudRenderSettings, CloudTextures, CloudView, frame
from app.model.clouds.workspace import CloudsWorkspace
from app.reference import clouds as rc
from app.reference import clouds_sky

SIZE = (64, 36)
# linear radiance clamped to 0..1 ("clamp": no exposure, no curve, no sRGB), so twilight is measured as light,
# not as automatic exposure shows it
PLAIN = CloudRenderSettings(steps=32, downsample=1, jitter=False, taa=False, reproject=False,
                            tone=ToneSettings(0.0, False, "clamp"))
LUMINANCE = np.array([0.2126, 0.7152, 0.0722])
CLEAR = {"coverage": 0.0, "high_coverage": 0.0}
TWILIGHT_STEP = 1.25   # the sky's mean luminance changes by less than this factor per degree of the sun


@pytest.fixture(scope="module")
def host(gl):
    host = WorkspaceRenderer(gl)
    yield host
    host.release()


def state_of(params: dict | None = None, **view) -> CloudsWorkspace:
    state = CloudsWorkspace()
    state.set_camera(**view)
    state.params = state.params.with_values(params or {})
    return state


def draw(host, state, size=SIZE, settings=PLAIN) -> np.ndarray:
    """The picture in linear float (the composite's clamp to 0..1, no 8-bit rounding), row 0 at the top."""
    target = host.ctx.texture(size, 4, dtype="f4")
    fbo = host.ctx.framebuffer([target])
    try:
        host.render(fbo, state, settings)
        return np.frombuffer(fbo.read(components=3, dtype="f4"), np.float32).reshape(size[1], size[0], 3)[::-1] \
            .astype(np.float64)
    finally:
        fbo.release()
        target.release()


def directions(state, size=SIZE) -> np.ndarray:
    return rc.ray_directions(state.frame(), *size)


def tables_made(host) -> dict:
    return dict(host.renderers["clouds"].clouds.atmosphere.computed)


# --- twilight ------------------------------------------------------------------------------------------------

def test_twilight_darkens_smoothly_and_keeps_its_colour(host):
    """Looking towards the sun, 15 degrees up, a clear sky as the sun goes from 10 degrees up to 6 down."""
    means, horizon = [], {}
    for elevation in range(10, -7, -1):
        state = state_of(CLEAR, pitch=15.0, sun_azimuth=0.0, sun_elevation=float(elevation))
        picture, d = draw(host, state), directions(state)
        means.append((picture @ LUMINANCE)[d[..., 1] > 0].mean())
        horizon[elevation] = picture[(d[..., 1] > 0) & (d[..., 1] < 0.06) & (np.abs(d[..., 0]) < 0.3)].mean(0)
    means = np.array(means)
    assert np.all(np.diff(means) < 0), means                              # darker at every degree
    assert np.all(means[:-1] / means[1:] < TWILIGHT_STEP), means[:-1] / means[1:]
    assert means[-1] > 20 / 255                                           # at -6 degrees: no black frame
    red, green, blue = horizon[-3]
    assert red > green > blue and (red - blue) / red > 0.3, horizon[-3]   # a golden glow, not grey


# --- cirrus --------------------------------------------------------------------------------------------------

def cirrus_and_sky(host, **view):
    """(the picture with the cirrus, without them, where they are) of a sky with no low clouds."""
    with_cirrus = draw(host, state_of({"coverage": 0.0}, **view))
    without = draw(host, state_of(CLEAR, **view))
    where = np.abs(with_cirrus - without).max(-1) > 0.03
    assert where.mean() > 0.05, "no cirrus in view"
    return with_cirrus[where], without[where]


def test_cirrus_are_brighter_than_the_sky_at_noon(host):
    cirrus, sky = cirrus_and_sky(host, pitch=30.0, sun_elevation=65.0, sun_azimuth=180.0)
    brighter = cirrus @ LUMINANCE > sky @ LUMINANCE
    assert brighter.mean() > 0.95 and (cirrus @ LUMINANCE).mean() > 1.2 * (sky @ LUMINANCE).mean()
    assert (cirrus[:, 2] - cirrus[:, 0]).mean() < (sky[:, 2] - sky[:, 0]).mean()   # whiter than the blue behind


def test_cirrus_are_tinted_by_the_low_sun(host):
    cirrus, sky = cirrus_and_sky(host, pitch=20.0, sun_elevation=3.0, sun_azimuth=40.0)
    added = (cirrus - sky).mean(0)                                        # the light the ice adds over the sky
    assert added[0] > 1.5 * added[2] and added[0] > 0.02, added


# --- the GPU against the CPU reference -----------------------------------------------------------------------

@pytest.mark.parametrize("params, view", [
    ({}, {}),
    ({}, dict(sun_elevation=3.0, sun_azimuth=0.0)),
    ({}, dict(sun_elevation=-3.0, sun_azimuth=0.0, altitude=3000.0)),
    ({}, dict(altitude=12000.0, pitch=-20.0)),
    ({"physical_sky": 0}, dict(sun_elevation=3.0, sun_azimuth=0.0)),
])
def test_the_gpu_draws_what_the_cpu_reference_draws(host, params, view):
    size = (32, 18)
    settings = replace(PLAIN, steps=24, early_exit=False, big_steps=False)
    state = state_of(params, **view)
    gpu = draw(host, state, size, settings)
    noise, weather = noise_textures(), state.weather
    textures = CloudTextures(noise.shape, noise.detail, noise.curl, noise.cirrus, *weather.maps)
    cpu = rc.render(state.params, state.view, textures, size, 24, blend=state.blend())
    error = np.abs(gpu - np.clip(cpu.rgb, 0.0, 1.0)) * 255   # the reference's linear radiance, as "clamp" shows it
    assert error.mean() < 0.1 and error.max() < 1.0, (error.mean(), error.max())
    assert cpu.clouds[..., 3].max() > 0.5                                 # clouds in view


def test_aerial_perspective_fades_what_is_far_into_the_air():
    """A black opaque thing along a ray low over the ground: the farther, the more of the air's light, never more
    than the sky itself gives."""
    fr = frame(CloudParams(), CloudView(sun_elevation=20.0))
    d = np.array([[0.0, 0.05, 1.0]]) / np.linalg.norm([0.0, 0.05, 1.0])
    air = clouds_sky.tables(fr)
    black = np.array([[0.0, 0.0, 0.0, 1.0]])
    seen = np.concatenate([clouds_sky.aerial_perspective(fr, air, black, d, np.array([t]))
                           for t in (0.0, 1e3, 1e4, 5e4, 2e5)])
    assert np.all(seen[0, :3] == 0) and np.all(np.diff(seen[:, :3], axis=0) > 0)
    sky = clouds_sky.physical_sky(fr, air, d, d @ np.array(fr.sun_dir))
    assert np.all(seen[-1, :3] <= sky[0] * 1.01) and seen[-1, 2] > 0.5 * sky[0, 2]
    assert seen[1, 2] > seen[1, 0]                                        # the near air is blue


# --- tables and options --------------------------------------------------------------------------------------

def test_looking_around_remakes_no_table(host):
    state = state_of(CLEAR, sun_elevation=12.0)
    draw(host, state)
    made = tables_made(host)
    for yaw, pitch in ((40.0, 5.0), (-120.0, 60.0), (0.0, -30.0)):
        state.set_camera(yaw=yaw, pitch=pitch)
        draw(host, state)
    state.set_sun(150.0, 12.0)                                            # the sun's azimuth: the same sky turned
    draw(host, state)
    assert tables_made(host) == made
    state.set_sun(150.0, 11.0)
    draw(host, state)
    assert tables_made(host) == {**made, "sky_view": made["sky_view"] + 1}


def test_the_seed_sky_stays_an_option():
    seed = frame(CloudParams(physical_sky=0), CloudView(sun_elevation=1.0))
    physical = frame(CloudParams(), CloudView(sun_elevation=1.0))
    assert seed.sun_light_top == seed.sun_light and seed.sun_light[2] < 0.01        # the seed's red, faded sun
    assert physical.sun_light_top[2] > physical.sun_light[2] > 0.05                # the air's: bluer higher up
    assert "physical_sky" not in repr(CloudParams())                                 # old demos keep their digests
    assert "physical_sky=0" in repr(CloudParams(physical_sky=0))
