"""The clouds on the GPU (EGL, llvmpipe): the failure cases of docs/clouds.md give finite pictures, every
optimisation saves the work it claims (texture lookups counted by the shader), and the temporal passes
neither ghost nor leave seams. Small images: the cases, not the speed, are what these test."""
from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from app.gl.clouds.renderer import uniforms
from app.gl.clouds.reprojection import NEW_SHARE, new_directions
from app.gl.core.workspace_renderer import WorkspaceRenderer
from app.model.clouds.exposure import ToneSettings
from app.model.clouds.scene import CloudRenderSettings, camera_basis
from app.model.clouds.workspace import CloudsWorkspace

SIZE = (64, 36)
# A fixed exposure: these compare pictures drawn through different histories, which an automatic one, set by each
# picture's own mean, would tell apart everywhere (tests/test_clouds_tone_map.py tests it).
PLAIN = CloudRenderSettings(steps=48, downsample=1, jitter=False, taa=False, reproject=False,
                            tone=ToneSettings(auto=False))


@pytest.fixture(scope="module")
def host(gl):
    host = WorkspaceRenderer(gl)
    yield host
    host.release()


def draw(host, state, settings=PLAIN, size=SIZE, frames=1):
    """(the picture as 0..1 floats, the float cloud buffer the composite read, the cloud renderer)."""
    ctx = host.ctx
    target = ctx.texture(size, 4)
    fbo = ctx.framebuffer([target])
    try:
        for _ in range(frames):
            host.render(fbo, state, settings)
        ctx.finish()
        rgb = np.frombuffer(fbo.read(components=3), np.uint8).reshape(size[1], size[0], 3) / 255.0
        clouds = host.renderers["clouds"].clouds
        buffer = np.frombuffer(clouds.last_clouds.read(), np.float32).reshape(*clouds.last_clouds.size[::-1], 4)
        return rgb, buffer.copy(), clouds
    finally:
        fbo.release()
        target.release()


def sky(**view) -> CloudsWorkspace:
    state = CloudsWorkspace()
    state.set_camera(**view)
    return state


CASES = {
    "below, looking up a little": dict(),
    "inside the layer": dict(altitude=3000.0),
    "above the layer": dict(altitude=12000.0, pitch=-20.0),
    "above the cirrus": dict(altitude=19000.0, pitch=-45.0),
    "at the horizon": dict(pitch=0.0),
    "straight up": dict(pitch=90.0),
    "straight down from above": dict(altitude=9000.0, pitch=-90.0),
    "sun below the horizon": dict(sun_elevation=-10.0),
}


@pytest.mark.parametrize("case", sorted(CASES))
def test_every_camera_and_sun_gives_a_finite_picture(host, case):
    rgb, buffer, _ = draw(host, sky(**CASES[case]))
    assert np.isfinite(buffer).all()
    assert (buffer[..., 3] >= 0).all() and (buffer[..., 3] <= 1 + 1e-6).all()
    assert rgb.std() > 0.002, "a flat picture: nothing drawn"


@pytest.mark.parametrize("steps", [1, 1024])
def test_one_step_and_1024_steps_are_finite(host, steps):
    _, buffer, _ = draw(host, sky(altitude=3000.0), replace(PLAIN, steps=steps), size=(16, 9))
    assert np.isfinite(buffer).all()


def test_coverage_zero_leaves_a_clear_sky_and_one_or_two_an_overcast_one(host):
    clear = sky(pitch=30.0)
    clear.params = clear.params.with_value("coverage", 0.0)
    _, buffer, _ = draw(host, clear)
    assert buffer[..., 3].max() == 0.0
    covered = []
    for coverage in (1.0, 2.0):
        overcast = sky(pitch=30.0)
        overcast.params = overcast.params.with_values({"coverage": coverage, "high_coverage": 0.0})
        _, buffer, _ = draw(host, overcast)
        assert np.isfinite(buffer).all()
        covered.append(buffer[..., 3].mean())
    assert 0.2 < covered[0] <= covered[1] and covered[1] > 0.5


def lookups(host, state, settings, frames=1, size=SIZE):
    rgb, _, clouds = draw(host, state, settings, size, frames)
    return clouds.lookups(size, state.frame(), settings)


NO_OPTIMISATION = replace(PLAIN, early_exit=False, big_steps=False, light_skip=False, detail_skip=False)


@pytest.mark.parametrize("switch", ["early_exit", "big_steps", "light_skip", "detail_skip"])
def test_each_optimisation_saves_texture_lookups(host, switch):
    state = sky(pitch=20.0)
    without = lookups(host, state, NO_OPTIMISATION)
    with_it = lookups(host, state, replace(NO_OPTIMISATION, **{switch: True}))
    assert with_it < 0.95 * without


def test_the_reduced_buffer_traces_a_quarter_of_the_rays(host):
    state = sky(pitch=20.0)
    full = lookups(host, state, PLAIN)
    half = lookups(host, state, replace(PLAIN, downsample=2))
    assert 0.15 * full < half < 0.4 * full


@pytest.mark.parametrize("down", [2, 4])
def test_reprojection_traces_one_pixel_of_each_block_and_converges_to_the_full_trace(host, down):
    """Guerrilla's scheme at d = 4: one pixel of each 4x4 block a frame, as many rays as the quarter buffer,
    and after d^2 frames of a still camera every pixel is its own full-size trace."""
    state = sky(pitch=20.0)
    full = lookups(host, state, PLAIN)
    reduced = lookups(host, state, replace(PLAIN, downsample=down))
    settings = replace(PLAIN, downsample=down, reproject=True)
    reprojected = lookups(host, state, settings, frames=down * down)
    assert reprojected == pytest.approx(reduced, rel=0.25) and reprojected < 0.4 * full
    reference, _, _ = draw(host, state, PLAIN)
    shown, _, clouds = draw(host, state, settings, frames=down * down)
    assert not clouds.settling(settings)
    assert np.abs(shown - reference).max() <= 1 / 255


def seen_last_frame(state, turn: float, size=SIZE) -> np.ndarray:
    """Which output pixels (rows from the bottom) look in a direction the view `turn` degrees of yaw back saw."""
    now = camera_basis(state.view)
    f, r, u = (np.array(v) for v in camera_basis(replace(state.view, yaw=state.view.yaw - turn)))
    t = state.frame().tan_half_fov
    aspect = size[0] / size[1]
    y, x = np.mgrid[0:size[1], 0:size[0]]
    nx, ny = (x + 0.5) / size[0] * 2 - 1, (y + 0.5) / size[1] * 2 - 1
    d = np.array(now[0]) + (nx * t * aspect)[..., None] * np.array(now[1]) + (ny * t)[..., None] * np.array(now[2])
    z = d @ f
    return (np.abs(d @ r / (z * t * aspect)) < 1) & (np.abs(d @ u / (z * t)) < 1)


def test_a_fast_turn_reprojects_the_history_and_reads_nothing_outside_the_last_frame(host):
    """Eight frames turning 3 degrees each: every frame traces its blocks' next pixel only (a turn restarts the
    counts, not the order), keeps what the last frame saw (reprojected by direction: closer to the truth than
    the bilinear buffer alone) and, where the last frame saw nothing (more than the renderer traces at full size
    after a turn, NEW_SHARE of the picture), shows exactly this frame's buffer."""
    state = sky(pitch=20.0)
    settings = replace(PLAIN, downsample=2, reproject=True)
    still = lookups(host, state, settings, frames=5)
    turned = camera_basis(replace(state.view, yaw=state.view.yaw + 3.0))
    strips = new_directions(camera_basis(state.view), turned, state.frame().tan_half_fov, SIZE)
    assert sum(w * h for *_, w, h in strips) > NEW_SHARE * SIZE[0] * SIZE[1]  # too many to trace
    for _ in range(8):
        state.set_camera(yaw=state.view.yaw + 3.0)
        shown, buffer, clouds = draw(host, state, settings)
        assert np.isfinite(buffer).all()
        assert clouds.lookups(SIZE, state.frame(), settings) == pytest.approx(still, rel=0.25)
    truth, _, _ = draw(host, state, PLAIN)
    clouds._key = None  # the same view and frame again with no history: the bilinear buffer alone
    clouds.frame_index -= 2
    bilinear, _, _ = draw(host, state, settings)
    seen = seen_last_frame(state, 3.0)
    assert (~seen).sum() > 50 and (shown[~seen] == bilinear[~seen]).all()
    assert np.abs(shown - truth).mean() < np.abs(bilinear - truth).mean()


def test_four_frames_after_a_fast_turn_no_ghost_trail_is_left(host):
    """Every pixel of a 2x2 block is traced again within 4 frames: nothing of the turn's views is left."""
    state = sky(pitch=20.0)
    settings = replace(PLAIN, downsample=2, reproject=True)
    draw(host, state, settings, frames=5)
    for _ in range(4):
        state.set_camera(yaw=state.view.yaw + 6.0)
        draw(host, state, settings)
    shown, buffer, _ = draw(host, state, settings, frames=4)
    truth, _, _ = draw(host, state, PLAIN)
    ghost = np.abs(shown - truth).mean(axis=2)
    assert np.isfinite(buffer).all() and ghost.max() <= 1 / 255


def test_reprojection_while_the_wind_blows_keeps_to_what_is_traced_around(host):
    """With the clock running (5 frames a second), a kept pixel is at most 3 frames old and clamped to the
    traced pixels around it: the picture stays closer to a full trace than the bilinear buffer alone."""
    state = sky(pitch=20.0)
    settings = replace(PLAIN, downsample=2, reproject=True)
    draw(host, state, settings, frames=5)
    for _ in range(8):
        state.advance(0.2)
        shown, buffer, _ = draw(host, state, settings)
    truth, _, _ = draw(host, state, PLAIN)
    host.renderers["clouds"].clouds._key = None
    bilinear, _, _ = draw(host, state, settings)
    assert np.isfinite(buffer).all()
    assert np.abs(shown - truth).mean() <= np.abs(bilinear - truth).mean()


def test_taa_restarts_on_a_turn_and_leaves_no_ghost_trail(host):
    state = sky(pitch=20.0)
    settings = replace(PLAIN, taa=True)
    draw(host, state, settings, frames=16)
    for _ in range(4):
        state.set_camera(yaw=state.view.yaw + 6.0)
        shown, buffer, _ = draw(host, state, settings)
    truth, _, _ = draw(host, state, PLAIN)
    ghost = np.abs(shown - truth).mean(axis=2)
    assert np.isfinite(buffer).all() and ghost.max() <= 1 / 255


def test_no_seam_where_the_reduced_buffer_meets_the_full_size_picture(host):
    """At the horizon the half-size cloud buffer meets the full-size ground: every ground row, the one
    against the sky included, is the same as in the full-size picture (no band of cloud bleeds onto it)."""
    state = sky(pitch=2.0)
    full, buffer, _ = draw(host, state, PLAIN, size=(96, 54))
    half, _, _ = draw(host, state, replace(PLAIN, downsample=2), size=(96, 54))
    ground = np.flatnonzero(buffer[..., 3].max(axis=1) == 0)  # rows (from the bottom) with no cloud at all
    assert len(ground) > 10 and (ground == np.arange(len(ground))).all()
    assert np.abs(full[ground] - half[ground]).max() <= 1 / 255


def test_a_weather_interrupted_mid_blend_does_not_jump(host):
    state = sky(pitch=25.0)
    state.params = state.params.with_value("weather_blend", 20.0)
    from app.model.clouds.weather import weather_map
    state.new_weather(weather_map(3, 256), "new 3")
    state.advance(8.0)
    before, _, _ = draw(host, state)
    state.new_weather(weather_map(4, 256), "new 4")
    after, _, _ = draw(host, state)
    assert np.abs(after - before).max() <= 1.5 / 255


def test_the_sample_count_view_is_grey_by_lookups(host):
    state = sky(pitch=20.0)
    rgb, _, _ = draw(host, state, replace(PLAIN, debug_samples=True))
    assert np.allclose(rgb[..., 0], rgb[..., 1]) and np.allclose(rgb[..., 1], rgb[..., 2])
    assert rgb.max() > 0.02


def test_weather_maps_are_uploaded_only_when_they_change(host):
    state = sky(pitch=20.0)
    draw(host, state)
    textures = host.renderers["clouds"].clouds.textures
    assert textures.sync_weather(state.weather) == 0  # the frame drawn has them
    state.advance(1.0)
    draw(host, state)
    assert textures.sync_weather(state.weather) == 0  # the clock moved, the maps did not
    from app.model.clouds.weather import weather_map
    state.new_weather(weather_map(7, 256), "new 7")
    assert textures.sync_weather(state.weather) == 2


def test_a_renderer_shown_another_state_uploads_its_weather(host):
    """Two states whose blends went through as many changes: the second's maps are not taken for the first's."""
    from app.model.clouds.weather import weather_map
    first, second = sky(pitch=20.0), sky(pitch=20.0)
    first.new_weather(weather_map(3, 256), "new 3")
    second.new_weather(weather_map(4, 256), "new 4")
    draw(host, first)
    assert host.renderers["clouds"].clouds.textures.sync_weather(second.weather) == 2


def test_every_uniform_the_passes_share_is_read_by_one_of_them(host):
    """The passes share the frame's uniforms, each reading those it needs (CloudRenderer._draw lets a pass lack
    any of them), so a shared name that no pass reads is one a shader renamed: this says so."""
    state = sky()
    draw(host, state, replace(PLAIN, downsample=2, reproject=True))  # trace, resolve, composite
    _, _, clouds = draw(host, state, replace(PLAIN, taa=True))  # and taa
    read = set().union(*(set(clouds.shaders.program(p))
                         for p in ("clouds_trace", "clouds_resolve", "clouds_taa", "clouds_composite")))
    shared = {*uniforms(state.frame(), PLAIN, 1.0, 0), *clouds.textures.use(clouds.units), "u_buffer"}
    assert shared <= read, f"no pass reads {sorted(shared - read)}"
