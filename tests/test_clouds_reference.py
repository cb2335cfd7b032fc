"""The clouds' float64 CPU reference (app/reference/clouds.py): its building blocks against docs/clouds.md's
formulas, Beer's law through a constant slab, convergence of the energy integration, and finite images in
the hard cases. Its images are linear radiance, as the GPU's HDR frame before the tone map: the bench compares
the two linear against linear (tests/test_clouds_bench.py). Tiny images and tiny textures throughout."""
from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.ndimage import map_coordinates

from app.model.clouds import noise as cn
from app.model.clouds import scene as cm
from app.model.clouds.scene import CloudParams, CloudTextures, CloudView
from app.reference import clouds as rc
from app.reference import clouds_medium


def textures(seed: int = 0, weather=None) -> CloudTextures:
    rng = np.random.default_rng(seed)
    w = rng.random((8, 8, 3), dtype=np.float32) if weather is None else weather
    return CloudTextures(shape=cn.shape_noise(8, seed), detail=cn.detail_noise(4, seed), curl=cn.curl_noise(8, seed),
                         cirrus=rng.random((8, 8), dtype=np.float32), weather_old=w[::-1].copy(), weather_new=w)


@pytest.fixture(scope="module")
def tex():
    return textures()


def flat_weather(coverage: float = 1.0, kind: float = 1.0, rain: float = 0.0) -> np.ndarray:
    return np.broadcast_to(np.array([coverage, kind, rain], dtype=np.float32), (4, 4, 3)).copy()


# --- phase ---------------------------------------------------------------------------------------------------

@pytest.mark.parametrize("g", [0.0, 0.2, cm.PARAM["hg_forward"].default, -cm.PARAM["hg_back"].default, 0.8, -0.9])
def test_each_hg_lobe_integrates_to_one_over_the_sphere(g):
    total, _ = quad(lambda c: rc.hg(c, g), -1.0, 1.0, points=[1.0, -1.0], limit=200, epsabs=1e-12)
    assert 2 * math.pi * total == pytest.approx(1.0, abs=1e-8)


def test_the_default_frames_lobes_integrate_to_one():
    fr = cm.frame(CloudParams(), CloudView())
    assert fr.g_back < 0 < fr.g_forward
    for scale in (1.0, 0.5, 0.25):
        for g in (fr.g_forward * scale, fr.g_back * scale):
            total, _ = quad(lambda c: rc.hg(c, g), -1.0, 1.0, limit=200, epsabs=1e-12)
            assert 2 * math.pi * total == pytest.approx(1.0, abs=1e-8)
    cos = np.linspace(-1, 1, 11)
    w = fr.back_weight
    np.testing.assert_allclose(rc.phase(fr, cos, 1.0), (1 - w) * rc.hg(cos, fr.g_forward) + w * rc.hg(cos, fr.g_back),
                               rtol=1e-14)
    seed = cm.frame(CloudParams(phase_max=1), CloudView())
    np.testing.assert_array_equal(rc.phase(seed, cos, 1.0), np.maximum(rc.hg(cos, fr.g_forward),
                                                                       rc.hg(cos, fr.g_back)))


# --- sampling ------------------------------------------------------------------------------------------------

def test_sample2d_texel_centres_halfway_and_wrap():
    tex = np.random.default_rng(1).random((4, 8)).astype(np.float32)  # 4 rows along v, 8 columns along u
    j, i = np.meshgrid(np.arange(4), np.arange(8), indexing="ij")
    u, v = (i + 0.5) / 8, (j + 0.5) / 4
    np.testing.assert_allclose(rc.sample2d(tex, u, v), tex, rtol=0, atol=1e-12)
    np.testing.assert_allclose(rc.sample2d(tex, u + 0.5 / 8, v), (tex + np.roll(tex, -1, 1)) / 2, atol=1e-12)
    np.testing.assert_allclose(rc.sample2d(tex, u, v + 0.5 / 4), (tex + np.roll(tex, -1, 0)) / 2, atol=1e-12)
    edge = (float(tex[0, 0]) + float(tex[0, 7])) / 2                    # u = 0: halfway to the last texel (repeat)
    assert rc.sample2d(tex, 0.0, 0.5 / 4) == pytest.approx(edge, abs=1e-12)
    pts = np.random.default_rng(2).uniform(-3, 3, (2, 50))
    a = rc.sample2d(tex, *pts)
    np.testing.assert_allclose(rc.sample2d(tex, pts[0] + 1, pts[1] - 2), a, atol=1e-12)
    expected = map_coordinates(tex.astype(np.float64), [pts[1] * 4 - 0.5, pts[0] * 8 - 0.5], order=1,
                               mode="grid-wrap")
    np.testing.assert_allclose(a, expected, atol=1e-12)
    rgb = np.random.default_rng(3).random((4, 4, 3))
    np.testing.assert_allclose(rc.sample2d(rgb, 1.5 / 4, 2.5 / 4), rgb[2, 1], atol=1e-12)  # T[j, i], i along u


def test_sample3d_texel_centres_halfway_and_wrap():
    tex = np.random.default_rng(4).random((2, 3, 4)).astype(np.float32)  # T[k, j, i]: w, v, u
    k, j, i = np.meshgrid(np.arange(2), np.arange(3), np.arange(4), indexing="ij")
    u, v, w = (i + 0.5) / 4, (j + 0.5) / 3, (k + 0.5) / 2
    np.testing.assert_allclose(rc.sample3d(tex, u, v, w), tex, atol=1e-12)
    for axis, (du, dv, dw) in ((2, (0.5 / 4, 0, 0)), (1, (0, 0.5 / 3, 0)), (0, (0, 0, 0.5 / 2))):
        np.testing.assert_allclose(rc.sample3d(tex, u + du, v + dv, w + dw), (tex + np.roll(tex, -1, axis)) / 2,
                                   atol=1e-12)
    pts = np.random.default_rng(5).uniform(-2, 2, (3, 60))
    a = rc.sample3d(tex, *pts)
    np.testing.assert_allclose(rc.sample3d(tex, pts[0] - 1, pts[1] + 1, pts[2] + 3), a, atol=1e-12)
    expected = map_coordinates(tex.astype(np.float64), [pts[2] * 2 - 0.5, pts[1] * 3 - 0.5, pts[0] * 4 - 0.5],
                               order=1, mode="grid-wrap")
    np.testing.assert_allclose(a, expected, atol=1e-12)


# --- rays and segments ---------------------------------------------------------------------------------------

def test_ray_directions_row_zero_at_the_top_and_the_centre_on_forward():
    fr = cm.frame(CloudParams(), CloudView(pitch=0.0, yaw=30.0))
    d = rc.ray_directions(fr, 5, 3)
    np.testing.assert_allclose(np.linalg.norm(d, axis=-1), 1.0, atol=1e-14)
    np.testing.assert_allclose(d[1, 2], fr.forward, atol=1e-14)
    assert d[0, 2, 1] > 0 > d[2, 2, 1]                                       # row 0 looks up
    assert np.dot(d[1, 4], fr.right) > 0 > np.dot(d[1, 0], fr.right)         # the last column to the right
    assert d[0, 2, 1] == pytest.approx(math.sin(math.atan(fr.tan_half_fov * 2 / 3)), abs=1e-14)


def test_segments_below_inside_and_above_the_layer():
    up, down = np.array([[0.0, 1.0, 0.0]]), np.array([[0.0, -1.0, 0.0]])
    for altitude, d, expected in ((200.0, up, (1300.0, 5300.0)), (3000.0, up, (0.0, 2500.0)),
                                  (3000.0, down, (0.0, 1500.0)), (12000.0, down, (6500.0, 10500.0))):
        fr = cm.frame(CloudParams(), CloudView(altitude=altitude))
        t0, t1, has, ground = rc.segment(fr, d)
        assert has[0] and (t0[0], t1[0]) == pytest.approx(expected, abs=1e-6)
    fr = cm.frame(CloudParams(), CloudView(altitude=200.0))
    t0, t1, has, ground = rc.segment(fr, down)
    assert not has[0] and ground[0] == pytest.approx(200.0, abs=1e-6) and t0[0] == t1[0] == 0
    fr = cm.frame(CloudParams(), CloudView(altitude=12000.0))
    assert not rc.segment(fr, up)[2][0]                                      # above, looking away
    # a grazing ray from above that just misses the base sphere: through the whole shell, capped at MAX_MARCH
    o = cm.PLANET_RADIUS + 12000.0
    sin = (cm.PLANET_RADIUS + cm.LAYER_BOTTOM + 10.0) / o
    d = np.array([[sin, -math.sqrt(1 - sin * sin), 0.0]])
    t0, t1, has, ground = rc.segment(fr, d)
    assert has[0] and t1[0] - t0[0] == pytest.approx(cm.MAX_MARCH) and not np.isfinite(ground[0])


def test_step_counts():
    d = np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, -1.0, 0.0], [0.6, 0.8, 0.0]])
    assert rc.steps_for(d, 64).tolist() == [64, 32, 32, 38]
    assert rc.steps_for(d, 1).tolist() == [1, 1, 1, 1]


# --- density -------------------------------------------------------------------------------------------------

def smooth(e0, e1, x):
    t = min(max((x - e0) / (e1 - e0), 0.0), 1.0)
    return t * t * (3 - 2 * t)


def tap(tex, coords):
    """GL linear + repeat, one point, summing the 2^dims corners (scalar, independent of the module's)."""
    axes = []
    for c, n in zip(coords, tex.shape):
        x = c * n - 0.5
        i0 = math.floor(x)
        axes.append(((i0 % n, 1 - (x - i0)), ((i0 + 1) % n, x - i0)))
    total = 0.0
    for corner in np.ndindex(*(2,) * len(coords)):
        w, idx = 1.0, []
        for axis, bit in zip(axes, corner):
            idx.append(axis[bit][0])
            w *= axis[bit][1]
        total = total + w * tex[tuple(idx)].astype(np.float64)
    return total


def scalar_density(fr, t: CloudTextures, p, full):
    """docs/clouds.md's "Density", steps 1 to 7, one point at a time."""
    h = min(max((math.dist(p, clouds_medium.CENTRE) - clouds_medium.R0) / (clouds_medium.R1 - clouds_medium.R0),
                0.0), 1.0)
    uv = ((p[2] + fr.weather_offset[1]) * fr.weather_freq, (p[0] + fr.weather_offset[0]) * fr.weather_freq)
    w = tap(t.weather_old, uv) * (1 - fr.blend) + tap(t.weather_new, uv) * fr.blend
    c = min(max(w[0] - fr.coverage_shift, 0.0), 1.0)
    if c == 0:
        return 0.0, w[2], 1
    q = np.array(p) + np.array(fr.wind_offset) + h * cm.SHEAR * np.array(fr.wind_dir)
    s = tap(t.shape, q[::-1] * fr.shape_freq) * (1.2 - h) ** 0.1 if fr.shape_noise else 0.7
    s = (s - fr.shape_min) / (fr.shape_max - fr.shape_min)
    a, b = min(max(2 * w[1], 0.0), 1.0), min(max(2 * w[1] - 1, 0.0), 1.0)
    g = [(x * (1 - a) + y * a) * (1 - b) + z * b for x, y, z in zip(*cm.GRADIENTS)]
    s *= smooth(g[0], g[1], h) - smooth(g[2], g[3], h)
    lo = h / c
    s = min(max((s - lo) / (1 - lo), 0.0), 1.0) if lo < 1 else 0.0
    s *= c
    count = 1 + fr.shape_noise
    if s > 0 and full and fr.detail_noise:
        count += 1 + fr.curl_noise
        if fr.curl_noise:
            k = tap(t.curl, (p[2] * fr.curl_freq, p[0] * fr.curl_freq))
            q = q + np.array([k[0], 0.0, k[1]]) * h * fr.curl_amount
        e = tap(t.detail, q[::-1] * fr.detail_freq)
        m = (1 - e) * (1 - min(10 * h, 1.0)) + e * min(10 * h, 1.0)
        lo = m * fr.detail_modifier
        s = (s - lo) / (1 - lo) if lo < 1 else 0.0
    return min(max(s, 0.0), 1.0), w[2], count


@pytest.mark.parametrize("full", [True, False])
@pytest.mark.parametrize("curl", [1, 0])
@pytest.mark.parametrize("blend", [1.0, 0.3])
def test_density_matches_the_spec_point_by_point(tex, full, curl, blend):
    params = CloudParams(coverage=1.6, curl_noise=curl)
    fr = cm.frame(params, CloudView(), wind_time=37.0, blend=blend)
    rng = np.random.default_rng(6)
    p = np.stack([rng.uniform(-20000, 20000, 300), rng.uniform(1000, 3500, 300), rng.uniform(-20000, 20000, 300)], 1)
    p[:20, 1] = rng.uniform(5000, 7000, 20)                             # some above the layer
    rho, rain, lookups = rc.density(fr, tex, p, full)
    expected = np.array([scalar_density(fr, tex, x, full) for x in p])
    np.testing.assert_allclose(rho, expected[:, 0], atol=1e-12)
    np.testing.assert_allclose(rain, expected[:, 1], atol=1e-12)
    np.testing.assert_array_equal(lookups, expected[:, 2])
    assert 0.1 < (rho > 0).mean() < 0.9 and rho.max() <= 1
    if full:
        assert lookups.max() == 3 + curl                                # weather, shape, (curl), detail


@pytest.mark.parametrize("multiscatter", [1, 0])
def test_light_without_extinction_is_phase_powder_and_ambient(tex, multiscatter):
    fr = cm.frame(CloudParams(density=0.0, multiscatter=multiscatter), CloudView())
    p = np.array([[0.0, 1500.0 + 0.25 * 4000, 0.0], [0.0, 1500.0 + 0.75 * 4000, 0.0]])  # h 0.25, 0.75
    rho, cos = np.array([0.3, 1.0]), np.array([0.9, -0.4])
    s = rc.light(fr, tex, p, rho, cos)
    if multiscatter:                                                    # tau = 0: every exp is 1
        weights = [fr.octave_scattering ** k for k in range(cm.OCTAVES)]
        energy = sum(w * 4 * math.pi * rc.phase(fr, cos, fr.octave_eccentricity ** k)
                     for k, w in enumerate(weights)) / sum(weights)
    else:
        energy = 4 * math.pi * rc.phase(fr, cos, 1.0)
    powder = 1 + (1 - np.exp(-2 * rho) - 1) * (0.5 - 0.5 * cos)
    h = np.array([0.25, 0.75])[:, None]
    ambient = np.array(fr.ambient_base) * (1 - h) + np.array(fr.ambient_top) * h
    sun = np.array(fr.sun_light) * (1 - h) + np.array(fr.sun_light_top) * h   # the layer's base .. top
    np.testing.assert_allclose(s, sun * (energy * powder)[:, None] + ambient, rtol=1e-12)
    short = clouds_medium.light_lookups(fr, tex, p, rho, cos)[1]
    long = clouds_medium.light_lookups(cm.frame(CloudParams(light_samples=30), CloudView()), tex, p, rho, cos)[1]
    assert np.all(short >= 6) and np.all(long - short >= 24)           # 5 cone + 1 far, or + 25 long


def slab_setup(coverage: float = 0.6, density: float = 0.05):
    """Constant weather (coverage 1, cumulus), the flat 0.7 shape remapped to 2 and no detail: rho = c exactly
    at heights 0.0676 .. c (the cumulus profile is 1 there and step 5's remap clamps to 1)."""
    params = CloudParams(coverage=coverage, density=density, shape_noise=0, detail_noise=0, shape_min=0.0,
                         shape_max=0.35, high_coverage=0.0)
    return params, textures(weather=flat_weather())


def test_transmittance_through_a_constant_slab_is_beer():
    params, tex = slab_setup()
    fr = cm.frame(params, CloudView(altitude=200.0))
    bottom, top = 1500 + 0.1 * 4000, 1500 + 0.5 * 4000
    heights = np.linspace(bottom, top, 50)
    rho, _, _ = rc.density(fr, tex, np.stack([np.zeros(50), heights, np.zeros(50)], 1), True)
    np.testing.assert_allclose(rho, 0.6, atol=1e-12)
    for n in (1, 7, 64):
        radiance, alpha, lookups = rc.march(fr, tex, np.array([[0.0, 1.0, 0.0]]), [bottom - 200], [top - 200], [n])
        expected = math.exp(-fr.extinction * 0.6 * (top - bottom))
        assert 1 - alpha[0] == pytest.approx(expected, rel=1e-2)
        assert 1 - alpha[0] == pytest.approx(expected, rel=1e-12)                  # exact per step
        assert lookups[0] > n and np.all(radiance > 0)
        seed = rc.march(fr, tex, np.array([[0.0, 1.0, 0.0]]), [bottom - 200], [top - 200], [n], integration="seed")
        assert seed[1][0] == pytest.approx(1 - 0.4 ** n, abs=1e-12)                # a = rho per sample


def test_march_on_a_constant_medium_and_its_radiance():
    fr = cm.frame(CloudParams(), CloudView())
    d = np.array([[0.0, 0.6, 0.8], [0.0, 1.0, 0.0]])

    def medium(p, full):
        return np.full(len(p), 0.25), np.zeros(len(p)), np.full(len(p), 3)

    def lit(p, rho, cos):
        return np.full((len(p), 3), 2.0), np.full(len(p), 5)

    radiance, alpha, lookups = rc.march(fr, None, d, [100.0, 0.0], [900.0, 400.0], [16, 3],
                                        density_fn=medium, light_fn=lit)
    transmittance = np.exp(-fr.extinction * 0.25 * np.array([800.0, 400.0]))
    np.testing.assert_allclose(1 - alpha, transmittance, rtol=1e-12)
    np.testing.assert_allclose(radiance, 2 * alpha[:, None] * np.ones(3), rtol=1e-12)   # L = S (1 - T)
    assert lookups.tolist() == [16 * 8, 3 * 8]


def test_the_render_of_a_vertical_ray_follows_beer_through_the_layer():
    params, tex = slab_setup(density=0.05)
    view = CloudView(altitude=200.0, pitch=90.0)
    image = rc.render(params, view, tex, size=(3, 3), steps=512)
    fr = cm.frame(params, view)
    t = np.linspace(1300.0, 5300.0, 40001)                              # the layer along the centre ray
    rho = rc.density(fr, tex, np.array(fr.camera) + t[:, None] * np.array(fr.forward), True)[0]
    optical = fr.extinction * np.trapezoid(rho, t)
    assert optical > 0.5
    assert 1 - image.clouds[1, 1, 3] == pytest.approx(math.exp(-optical), rel=1e-2)


# --- the image -----------------------------------------------------------------------------------------------

def test_energy_converges_with_steps_and_seed_does_not(tex):
    images = {(m, n): rc.render(CloudParams(), CloudView(), tex, size=(24, 14), steps=n, integration=m)
              for m in ("energy", "seed") for n in (64, 128, 256)}

    def change(m, a, b, channels=slice(0, 3)):
        key = "rgb" if channels == slice(0, 3) else "clouds"
        return float(np.abs(getattr(images[m, a], key)[..., channels] - getattr(images[m, b], key)[..., channels])
                     .mean())

    assert change("energy", 128, 256) < 0.6 * change("energy", 64, 128)
    assert change("seed", 128, 256) > 3 * change("energy", 128, 256)
    assert change("seed", 64, 128) > 1.5 * change("energy", 64, 128)
    alpha = 3                                                           # the clouds' opacity alone
    assert change("energy", 128, 256, alpha) < 0.6 * change("energy", 64, 128, alpha)
    assert change("seed", 64, 128, alpha) > 5 * change("energy", 64, 128, alpha)
    assert change("seed", 128, 256, alpha) > 5 * change("energy", 128, 256, alpha)
    assert change("seed", 128, 256, alpha) > 0.5 * change("seed", 64, 128, alpha)   # the seed's does not settle


def test_block_size_does_not_change_the_march(tex, monkeypatch):
    jitter = np.random.default_rng(7).uniform(-0.5, 0.5, (7, 12))
    kwargs = dict(size=(12, 7), steps=40, jitter=jitter, early_exit=True)
    a = rc.render(CloudParams(coverage=1.6), CloudView(altitude=3000.0), tex, **kwargs)
    monkeypatch.setattr(rc, "BLOCK", 1)                                 # one step at a time: the plain loop
    b = rc.render(CloudParams(coverage=1.6), CloudView(altitude=3000.0), tex, **kwargs)
    np.testing.assert_allclose(a.rgb, b.rgb, atol=1e-12)
    np.testing.assert_allclose(a.clouds, b.clouds, atol=1e-12)
    np.testing.assert_array_equal(a.samples, b.samples)


def test_early_exit_stops_at_opacity(tex):
    view, params = CloudView(altitude=3000.0), CloudParams(coverage=2.0, density=2.0)
    full = rc.render(params, view, tex, size=(12, 7), steps=64)
    early = rc.render(params, view, tex, size=(12, 7), steps=64, early_exit=True)
    assert early.samples.sum() < full.samples.sum()
    assert np.abs(early.clouds[..., 3] - full.clouds[..., 3]).max() <= 0.01 + 1e-12
    # linear radiance against linear: what is left out is the light behind the exit, seen through T < 0.01
    np.testing.assert_allclose(early.rgb, full.rgb, rtol=0.02)


def test_no_clouds_at_coverage_zero_and_the_lookups_counted(tex):
    params = CloudParams(coverage=0.0, high_coverage=0.0, ground_shadows=0)
    view = CloudView(pitch=20.0)
    image = rc.render(params, view, tex, size=(16, 9), steps=32)
    assert np.all(image.clouds == 0)
    fr = cm.frame(params, view)
    d = rc.ray_directions(fr, 16, 9)
    _, _, has, ground = rc.segment(fr, d)
    expected = np.where(has, rc.steps_for(d, 32), 0) + np.where(np.isfinite(ground), 0, 2)  # weather; cirrus
    np.testing.assert_array_equal(image.samples, expected)
    assert has.any() and (~has).any()


CASES = {
    "inside the layer": (dict(), dict(altitude=3000.0)),
    "above the layer": (dict(), dict(altitude=12000.0, pitch=-20.0)),
    "at the horizon": (dict(), dict(pitch=0.0)),
    "straight up": (dict(), dict(pitch=90.0)),
    "straight down from above": (dict(), dict(altitude=12000.0, pitch=-90.0)),
    "above the cirrus": (dict(light_samples=30, multiscatter=0), dict(altitude=20000.0, pitch=-30.0)),
    "sun below the horizon": (dict(), dict(sun_elevation=-10.0)),
    "coverage 2": (dict(coverage=2.0), dict(altitude=3000.0)),
    "detail modifier 1": (dict(detail_modifier=1.0), dict()),
    "shape range narrow": (dict(shape_min=0.6, shape_max=0.6001), dict()),
}


@pytest.mark.parametrize("case", CASES)
@pytest.mark.parametrize("steps", [1, 16])
def test_hard_cases_give_finite_images(tex, case, steps):
    params, view = CASES[case]
    image = rc.render(CloudParams(**params), CloudView(**view), tex, size=(16, 9), steps=steps, blend=0.5,
                      wind_time=100.0)
    for a in (image.rgb, image.clouds):
        assert np.all(np.isfinite(a))
    assert image.rgb.shape == (9, 16, 3) and image.clouds.shape == (9, 16, 4) and image.samples.shape == (9, 16)
    assert image.rgb.min() >= 0  # linear radiance: unclamped (the tone map is app/reference/tone_map.py's)
    assert image.clouds[..., 3].min() >= 0 and image.clouds[..., 3].max() <= 1 + 1e-12
    assert image.samples.min() >= 0


def test_many_steps_on_a_tiny_image(tex):
    image = rc.render(CloudParams(), CloudView(pitch=5.0), tex, size=(6, 4), steps=1024)
    assert np.all(np.isfinite(image.rgb)) and image.clouds[..., 3].max() > 0.1
    assert image.samples.max() > 1024


def test_coverage_zero_leaves_the_background():
    tex = textures()
    clear = CloudParams(coverage=0.0, high_coverage=0.0)
    for view in (CloudView(), CloudView(altitude=3000.0), CloudView(altitude=12000.0, pitch=-45.0)):
        image = rc.render(clear, view, tex, size=(8, 5), steps=8)
        assert np.all(image.clouds[..., 3] == 0) and np.all(np.isfinite(image.rgb))
