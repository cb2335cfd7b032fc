"""The clouds' light conserves energy (docs/clouds.md, "Energy"): the phase the shader computes integrates to 1
over the sphere at every setting of the panel, the multiple-scattering octaves and powder never give a sample
more than the sun it receives, and a white furnace shows it on the GPU (EGL) and in the CPU reference: with the
sun off the clouds vanish, with it on no cloud pixel returns more than the sun and the sky give it."""
from __future__ import annotations

import itertools
import math
from dataclasses import replace

import numpy as np
import pytest
from scipy.integrate import quad

from app.bench import clouds_energy
from app.commands.clouds import render_settings
from app.editor import Editor
from app.gl.clouds.renderer import uniforms
from app.gl.core.shader_source import load_stage
from app.gl.core.shaders import query_gs_limits
from app.gl.core.uniforms import set_uniforms
from app.gl.core.workspace_renderer import WorkspaceRenderer
from app.model.clouds import scene as cm
from app.model.clouds.exposure import ToneSettings
from app.model.clouds.scene import PARAM, CloudParams, CloudRenderSettings, CloudView, ParamError
from app.model.clouds.workspace import CloudsWorkspace
from app.reference import clouds as rc
from app.resources import SHADERS
from tests.test_clouds_reference import textures

SIZE = (48, 27)
# The picture as its linear radiance, clamped to 0..1 (0 EV, no automatic exposure, the clamp curve), so the
# furnace's 1 shows as 1.
LINEAR = ToneSettings(0.0, False, "clamp")
PLAIN = CloudRenderSettings(steps=48, downsample=1, jitter=False, taa=False, reproject=False, furnace=True,
                            tone=LINEAR)
TOLERANCE = 2 / 255


def panel_frames():
    """Frames over the panel's ranges of every parameter the phase and the octaves read, at four suns (the sun's
    height weakens the back lobe): each range's ends and a middle value."""
    ends = {name: (PARAM[name].lo, PARAM[name].default, PARAM[name].hi)
            for name in ("hg_forward", "hg_back", "hg_back_weight", "octave_eccentricity")}
    for values in itertools.product(*ends.values(), (-5.0, 5.0, 25.0, 45.0)):
        params = CloudParams(**dict(zip(ends, values[:-1])))
        yield cm.frame(params, CloudView(sun_elevation=values[-1]))


# --- the phase -----------------------------------------------------------------------------------------------

def test_the_sphere_quadrature_integrates_peaked_lobes_as_scipy_does():
    for g in (0.0, 0.54, -0.5, 0.99, -0.99):
        expected, _ = quad(lambda c: rc.hg(c, g), -1.0, 1.0, points=[1 - 1e-4, -1 + 1e-4], limit=400, epsabs=1e-13)
        assert 4 * math.pi * clouds_energy.mean_over_directions(lambda c: rc.hg(c, g)) == pytest.approx(
            2 * math.pi * expected, abs=1e-9)
    assert clouds_energy.sphere_nodes()[1].sum() == pytest.approx(2.0, abs=1e-13)


def test_the_phase_integrates_to_one_for_every_setting_of_the_panel():
    """Every octave's lobe (g scaled by c^k) at every corner and middle of the panel's ranges."""
    worst = 0.0
    for fr in panel_frames():
        for k in range(cm.OCTAVES):
            worst = max(worst, abs(clouds_energy.phase_integral(fr, fr.octave_eccentricity ** k) - 1))
    assert worst < 1e-3
    assert worst < 1e-9  # the mix of two normalised lobes: the quadrature's own error only


def test_the_seeds_max_of_the_lobes_is_kept_for_comparison_and_makes_light():
    for elevation, expected in ((25.0, 1.576), (45.0, 1.679)):
        fr = cm.frame(CloudParams(phase_max=1), CloudView(sun_elevation=elevation))
        assert clouds_energy.phase_integral(fr) == pytest.approx(expected, abs=1e-3)


PROBE_FS = """#version 330 core
//#INCLUDE {shl}
//#INSERT clouds
uniform sampler2D u_inputs;  // per texel: cos, tau, rho, the phase's scale
out vec4 out_value;

void main() {{
    vec4 x = texelFetch(u_inputs, ivec2(gl_FragCoord.xy), 0);
    out_value = vec4(phase(x.r, x.a), sun_energy(x.g, x.b, x.r), 0.0, 1.0);
}}
"""


@pytest.fixture(scope="module")
def probe(gl, tmp_path_factory):
    """A program of clouds.shl's phase() and sun_energy(): (frame, inputs (n, 4)) -> (n, 2) as the GPU computes
    them, in float32."""
    path = tmp_path_factory.mktemp("probe") / "clouds_probe_FS.glsl"
    path.write_text(PROBE_FS.format(shl=(SHADERS / "clouds.shl").as_posix()))
    limits = query_gs_limits(gl)
    program = gl.program(vertex_shader=load_stage(SHADERS / "fullscreen_VS.glsl", limits).text,
                         fragment_shader=load_stage(path, limits).text)
    vao = gl.vertex_array(program, [])

    def run(fr, inputs: np.ndarray) -> np.ndarray:
        width = 256
        rows = -(-len(inputs) // width)
        data = np.zeros((rows * width, 4), np.float32)
        data[:len(inputs)] = inputs
        source = gl.texture((width, rows), 4, data.tobytes(), dtype="f4")
        out = gl.texture((width, rows), 4, dtype="f4")
        previous = gl.fbo
        fbo = gl.framebuffer([out])
        try:
            values = uniforms(fr, CloudRenderSettings(), 1.0, 0)
            set_uniforms(program, values, optional=values.keys())
            source.use(0)
            program["u_inputs"] = 0
            fbo.use()
            vao.render(vertices=3)
            result = np.frombuffer(out.read(), np.float32).reshape(-1, 4)
        finally:
            previous.use()  # moderngl must not keep the released one bound
            fbo.release()
            out.release()
            source.release()
        return result[:len(inputs), :2].astype(np.float64)

    yield run
    vao.release()
    program.release()


def test_the_gpu_computes_the_references_phase_and_sun_energy(probe):
    """On the quadrature's directions (float32) at the panel's corners: the same numbers to float32's precision,
    so the shader's phase integrates to 1 as the reference's does."""
    cos = clouds_energy.sphere_nodes()[0].astype(np.float32).astype(np.float64)
    rng = np.random.default_rng(3)
    frames = list(panel_frames())
    for fr in [frames[i] for i in rng.choice(len(frames), 12, replace=False)] + [cm.frame(CloudParams(), CloudView())]:
        for multiscatter, phase_max in ((1, 0), (0, 0), (1, 1)):
            f = replace(fr, multiscatter=multiscatter, phase_max=phase_max)
            scale = f.octave_eccentricity
            tau = rng.uniform(0, 4, len(cos)).astype(np.float32).astype(np.float64)
            rho = rng.uniform(0, 1, len(cos)).astype(np.float32).astype(np.float64)
            gpu = probe(f, np.stack([cos, tau, rho, np.full_like(cos, scale)], 1))
            cpu_phase = rc.phase(f, cos, np.float32(scale))
            np.testing.assert_allclose(gpu[:, 0], cpu_phase, rtol=2e-5, atol=1e-7)
            # powder's 1 - exp(-2 rho) loses float32 digits at tiny rho (3e-4 relative at rho 1e-4)
            np.testing.assert_allclose(gpu[:, 1], rc.sun_energy(f, tau, rho, cos), rtol=1e-3, atol=1e-6)
            if not phase_max:
                weights = clouds_energy.sphere_nodes()[1]
                assert 2 * math.pi * (gpu[:, 0] * weights).sum() == pytest.approx(1.0, abs=1e-4)


# --- octaves and powder --------------------------------------------------------------------------------------

def test_wrenninges_condition_a_at_most_b_is_refused_with_a_reason_and_changes_nothing():
    params = CloudParams()
    with pytest.raises(ParamError, match="octave_scattering must not exceed octave_extinction"):
        params.with_value("octave_scattering", 0.6)
    with pytest.raises(ParamError, match="Wrenninge"):
        params.with_value("octave_extinction", 0.4)
    assert params.with_values({"octave_scattering": 0.9, "octave_extinction": 1.0}).octave_scattering == 0.9
    editor = Editor()
    assert editor.execute("workspace clouds")
    before = editor.digest()
    assert not editor.execute("clouds.set octave_scattering 0.8")
    assert editor.digest() == before


def test_no_octave_sum_exceeds_albedo_one_and_powder_only_darkens():
    """At optical depth 0 the octaves' weights sum to 1 (albedo 1 shared between the lobes); deeper, every
    octave loses light; powder is a factor in [0, 1]. So the sun a sample scatters in all (its directional mean)
    never exceeds the sun it would receive unshaded, at any a <= b, c, depth and density."""
    cos = np.linspace(-1, 1, 201)
    for rho in (0.0, 0.05, 0.5, 1.0):
        p = rc.powder(np.full_like(cos, rho), cos)
        assert p.min() >= 0 and p.max() <= 1
    for a, b, c in itertools.product((0.0, 0.25, 0.5, 1.0), (0.0, 0.5, 1.0), (0.0, 0.5, 1.0)):
        if a > b:
            continue
        params = CloudParams(octave_scattering=a, octave_extinction=b, octave_eccentricity=c)
        for multiscatter in (1, 0):
            fr = cm.frame(replace(params, multiscatter=multiscatter), CloudView(sun_elevation=45.0))
            without_powder = clouds_energy.mean_over_directions(
                lambda x: rc.sun_energy(fr, 0.0, 0.0, x) / rc.powder(0.0, x))
            assert without_powder == pytest.approx(1.0, abs=1e-9)
            means = [clouds_energy.sun_energy_mean(fr, tau, rho) for tau in (0.0, 0.1, 1.0, 10.0)
                     for rho in (0.05, 1.0)]
            assert max(means) <= 1 + 1e-9
            assert clouds_energy.sun_energy_mean(fr, 10.0, 1.0) < clouds_energy.sun_energy_mean(fr, 0.1, 1.0)


# --- the furnace ---------------------------------------------------------------------------------------------

VIEWS = {"below, looking up": dict(pitch=30.0), "at the sun": dict(yaw=30.0, pitch=25.0),
         "inside the layer": dict(altitude=3000.0, pitch=5.0),
         "above, looking down": dict(altitude=9000.0, pitch=-40.0, yaw=200.0)}
# Plenty of cloud, no cirrus (its light is the sky's part of issue 28, not this test's).
CLOUDY = dict(coverage=1.6, high_coverage=0.0)


@pytest.fixture(scope="module")
def host(gl):
    host = WorkspaceRenderer(gl)
    yield host
    host.release()


def render(host, params: CloudParams, view: dict, settings=PLAIN, frames: int = 1):
    """(the picture as float32 RGB, the premultiplied cloud buffer, its rays' cos to the sun), rows from the top."""
    state = CloudsWorkspace()
    state.params = params
    state.set_camera(**view)
    ctx = host.ctx
    target = ctx.texture(SIZE, 4, dtype="f4")
    fbo = ctx.framebuffer([target])
    try:
        for _ in range(frames):
            host.render(fbo, state, settings)
        picture = np.frombuffer(fbo.read(components=3, dtype="f4"), np.float32).reshape(SIZE[1], SIZE[0], 3)[::-1]
        buffer = host.renderers["clouds"].clouds.last_clouds
        clouds = np.frombuffer(buffer.read(), np.float32).reshape(*buffer.size[::-1], 4)[::-1]
    finally:
        fbo.release()
        target.release()
    fr = state.frame()
    cos = rc.ray_directions(fr, *buffer.size) @ np.array(fr.sun_dir)
    return picture.astype(np.float64), clouds.astype(np.float64), cos


@pytest.mark.parametrize("view", sorted(VIEWS))
def test_a_white_furnace_hides_the_clouds_on_the_gpu(host, view):
    """Albedo 1, the sun off, radiance 1 from every direction: the clouds scatter back exactly what they take out
    of each ray, L = 1 - T, so the picture is 1 everywhere and the same as without clouds, within 2/255."""
    params = CloudParams(direct=0.0, **CLOUDY)
    picture, clouds, _ = render(host, params, VIEWS[view])
    assert clouds[..., 3].max() > 0.5, "no clouds in view: the test would show nothing"
    shown = clouds[..., :3] + (1 - clouds[..., 3:])  # before the composite's clamp to 0..1
    assert np.abs(shown - 1).max() <= TOLERANCE
    clear, _, _ = render(host, replace(params, coverage=0.0), VIEWS[view])
    assert np.abs(picture - clear).max() <= TOLERANCE and np.abs(clear - 1).max() <= TOLERANCE


def test_a_white_furnace_hides_the_clouds_with_every_optimisation(host):
    params = CloudParams(direct=0.0, **CLOUDY)
    # reduced buffer, reprojection, jitter, TAA, skips
    settings = CloudRenderSettings(steps=48, furnace=True, tone=LINEAR)
    picture, clouds, _ = render(host, params, VIEWS["below, looking up"], settings, frames=6)
    assert clouds[..., 3].max() > 0.5
    shown = clouds[..., :3] + (1 - clouds[..., 3:])
    assert np.abs(picture - 1).max() <= TOLERANCE and np.abs(shown - 1).max() <= TOLERANCE


def the_most_the_sun_and_sky_give(fr, alpha: np.ndarray, cos: np.ndarray) -> np.ndarray:
    """(..., 3): alpha (1 + sun_light 4 pi max_k P(cos, c^k)) -- what a non-absorbing layer of opacity alpha
    returns at most towards the eye if every sample in it sees the whole sun unshaded and the whole unit sky:
    it scatters the sky's 1 and the sun by the phase (the largest of the octaves' lobes), never more than it
    takes out of the ray. sun_light: the brighter of the layer's base and top (the physical sky's differ)."""
    lobes = np.max([rc.phase(fr, cos, fr.octave_eccentricity ** k) for k in range(cm.OCTAVES)], axis=0)
    sun = np.maximum(fr.sun_light, fr.sun_light_top)
    return alpha[..., None] * (1 + sun * 4 * math.pi * lobes[..., None])


@pytest.mark.parametrize("view", sorted(VIEWS))
def test_with_the_sun_on_no_cloud_pixel_returns_more_than_the_sun_and_sky_give_it(host, view):
    """The furnace's sky (radiance 1 everywhere, ambient 1) and the sun at its brightest (`direct` 1.5): each
    pixel's cloud light L (premultiplied, before the composite) is at most alpha (1 + sun_light 4 pi
    max_k P(cos, c^k)) in every channel, alpha = 1 - T its opacity and cos its ray's angle to the sun."""
    params = CloudParams(direct=PARAM["direct"].hi, **CLOUDY)
    _, clouds, cos = render(host, params, VIEWS[view])
    fr = cm.furnace(cm.frame(params, CloudView(**VIEWS[view])))
    bound = the_most_the_sun_and_sky_give(fr, clouds[..., 3], cos)
    assert clouds[..., 3].max() > 0.5
    assert np.all(clouds[..., :3] <= bound * (1 + 1e-4) + 1e-5)
    assert (clouds[..., :3] > clouds[..., 3:]).any(), "the sun adds light somewhere"


def test_the_references_furnace_hides_its_clouds_and_bounds_them_with_the_sun():
    tex = textures(weather=np.broadcast_to(np.array([0.8, 1.0, 0.0], np.float32), (4, 4, 3)).copy())
    view = CloudView(pitch=30.0)
    off = rc.render(CloudParams(direct=0.0, **CLOUDY), view, tex, size=(16, 9), steps=64, furnace=True)
    assert off.clouds[..., 3].max() > 0.5
    assert np.abs(off.rgb - 1).max() <= 1e-12 and np.abs(off.clouds[..., :3] - off.clouds[..., 3:]).max() <= 1e-12
    params = CloudParams(direct=PARAM["direct"].hi, **CLOUDY)
    on = rc.render(params, view, tex, size=(16, 9), steps=64, furnace=True)
    fr = cm.furnace(cm.frame(params, view))
    cos = rc.ray_directions(fr, 16, 9) @ np.array(fr.sun_dir)
    assert np.all(on.clouds[..., :3] <= the_most_the_sun_and_sky_give(fr, on.clouds[..., 3], cos) + 1e-12)


def test_r_cloud_furnace_is_a_cvar_that_reaches_the_renderers_settings():
    editor = Editor()
    assert editor.execute("workspace clouds")
    state = editor.workspaces["clouds"]
    assert not render_settings(editor.console, state).furnace
    assert editor.execute("r_cloudFurnace 1")
    assert render_settings(editor.console, state).furnace
    values = uniforms(state.frame(), render_settings(editor.console, state), 1.0, 0)
    assert values["u_furnace"] == 1 and values["u_sky_zenith"] == values["u_ambient_base"] == (1.0, 1.0, 1.0)
