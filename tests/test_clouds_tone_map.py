"""The clouds' HDR frame to the picture (docs/clouds.md, "Exposure and tone mapping"): the shader's tone map is
the CPU reference's (app/reference/tone_map.py) on a ramp of HDR values, automatic exposure reads the frame's
log-average luminance and adapts to it over frames, and at the default view almost no pixel clips."""
from __future__ import annotations

import subprocess
import sys

from dataclasses import replace

import numpy as np
import pytest

from app.gl.clouds.tone_map import ToneMap
from app.gl.core.shaders import ShaderLibrary
from app.gl.core.workspace_renderer import WorkspaceRenderer
from app.io.png import read_png
from app.model.clouds.exposure import ADAPT, AUTO_RANGE, SETTLED_EV, TONE_MAPS, ToneSettings
from app.model.clouds.scene import CloudRenderSettings
from app.model.clouds.workspace import CloudsWorkspace
from app.reference import tone_map as rt
from app.resources import SHADERS


@pytest.fixture(scope="module")
def tone(gl):
    return ToneMap(gl, ShaderLibrary(gl, [SHADERS]))


def ramp() -> np.ndarray:
    """(2, 241, 3) radiance: a grey and a coloured ramp, 2^-12 .. 2^8 in steps of 1/12 EV."""
    v = 2.0 ** np.linspace(-12, 8, 241)
    return np.stack([np.stack([v, v, v], -1), np.stack([v, 0.5 * v, 0.1 * v], -1)]).astype(np.float32)


def mapped(gl, tone: ToneMap, hdr: np.ndarray, settings: ToneSettings, restart: bool = True) -> np.ndarray:
    """The tone map of `hdr` (rows from the bottom) drawn on the GPU into a float target."""
    h, w, _ = hdr.shape
    texture = gl.texture((w, h), 4, np.concatenate([hdr, np.ones((h, w, 1), np.float32)], -1).tobytes(), dtype="f4")
    out = gl.texture((w, h), 4, dtype="f4")
    previous, fbo = gl.fbo, gl.framebuffer([out])
    try:
        tone.apply(texture, fbo, settings, restart)
        return np.frombuffer(out.read(), np.float32).reshape(h, w, 4)[..., :3].astype(np.float64)
    finally:
        previous.use()  # not the one released: moderngl binds it again when it makes the next framebuffer
        for thing in (fbo, out, texture):
            thing.release()


@pytest.mark.parametrize("curve", TONE_MAPS)
@pytest.mark.parametrize("ev", [-3.0, 0.0, 1.5])
def test_the_shader_tone_map_is_the_references_on_a_ramp_of_hdr_values(gl, tone, curve, ev):
    hdr = ramp()
    shown = mapped(gl, tone, hdr, ToneSettings(ev=ev, auto=False, curve=curve))
    expected = rt.tone_map(hdr, ev, curve)
    np.testing.assert_allclose(shown, expected, atol=2e-5)
    assert 0 <= expected.min() and expected.max() <= 1
    grey = expected[0, :, 1]
    assert np.all(np.diff(grey) >= 0) and grey[-1] - grey[0] > 0.9  # rising, from black to (nearly) white
    if curve != "clamp":  # the filmic curves roll off: 1 EV over the linear clip still shows detail
        over = np.flatnonzero(hdr[0, :, 0] * 2.0 ** ev >= 2.0)[0]
        assert grey[over] < 254.5 / 255


def test_the_seeds_look_is_the_radiance_clamped_and_the_curves_encode_srgb():
    x = np.array([[0.0, 0.5, 1.0, 3.0]]).T * np.ones(3)
    np.testing.assert_array_equal(rt.tone_map(x, 0.0, "clamp")[:, 0], [0.0, 0.5, 1.0, 1.0])
    np.testing.assert_allclose(rt.srgb_encode(np.array([0.0, 0.0031308, 0.18, 1.0])),
                               [0.0, 0.04045, 0.46135612950044164, 1.0], atol=1e-5)
    with pytest.raises(ValueError, match="no tone curve 'filmic'"):
        rt.tone_map(x, 0.0, "filmic")


def test_automatic_exposure_shows_the_frames_log_average_at_middle_grey(gl, tone):
    rng = np.random.default_rng(3)
    hdr = (2.0 ** rng.normal(1.0, 2.0, (61, 97, 3))).astype(np.float32)  # not a power of 2 either way
    settings = ToneSettings(ev=0.5, auto=True, curve="aces")
    shown = mapped(gl, tone, hdr, settings)
    adapted, frame = tone.averages()
    assert frame == pytest.approx(rt.log2_average(hdr), abs=1e-4) and adapted == frame
    np.testing.assert_allclose(shown, rt.tone_map(hdr, rt.exposure_ev(0.5, True, hdr), "aces"), atol=1e-4)
    black = mapped(gl, tone, np.zeros((9, 16, 3), np.float32), settings)
    assert black.max() == 0 and not tone.settling()  # lifted by AUTO_RANGE at most: black stays black
    dim = np.full((9, 16, 3), 2.0 ** -20, np.float32)
    np.testing.assert_allclose(mapped(gl, tone, dim, settings), rt.tone_map(dim, 0.5 + AUTO_RANGE, "aces"), atol=1e-6)


def test_the_exposure_adapts_over_frames_and_takes_a_restart_at_once(gl, tone):
    settings = ToneSettings(auto=True)
    dark, bright = np.full((8, 8, 3), 0.05, np.float32), np.full((8, 8, 3), 0.8, np.float32)
    mapped(gl, tone, dark, settings)
    start, goal = rt.log2_average(dark), rt.log2_average(bright)
    adapted = [tone.averages()[0]]
    while tone.settling() or len(adapted) == 1:
        mapped(gl, tone, bright, settings, restart=False)
        adapted.append(tone.averages()[0])
        assert len(adapted) < 20
    expected = goal + (start - goal) * (1 - ADAPT) ** np.arange(len(adapted))
    np.testing.assert_allclose(adapted, expected, atol=1e-4)
    assert abs(adapted[-1] - goal) <= SETTLED_EV < abs(adapted[-2] - goal)
    mapped(gl, tone, dark, settings, restart=True)
    assert tone.averages()[0] == pytest.approx(start, abs=1e-5) and not tone.settling()
    mapped(gl, tone, bright, ToneSettings(auto=False), restart=False)
    assert not tone.settling()  # a fixed exposure has nothing to adapt
    mapped(gl, tone, bright, settings, restart=False)  # and automatic again starts from this frame
    assert tone.averages()[0] == pytest.approx(goal, abs=1e-5)


def render(tmp_path, name: str, *commands: str) -> np.ndarray:
    out = tmp_path / f"{name}.png"
    cmd = [a for c in commands for a in ("--cmd", c)]
    run = subprocess.run([sys.executable, "-m", "app", "render", "clouds", "--size", "320x180", *cmd, "--out",
                          str(out)], capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stderr
    return read_png(out)[..., :3]


def test_at_the_default_view_at_most_one_percent_of_pixels_clip(tmp_path):
    """`shadelab render clouds --size 320x180`, the editor's default scene; the seed's look (clamped radiance)
    clipped 30 % of them."""
    shown = render(tmp_path, "default")
    assert (shown == 255).any(-1).mean() <= 0.01
    seed = render(tmp_path, "seed", "r_cloudToneMap clamp", "r_cloudAutoExposure 0")
    assert (seed == 255).any(-1).mean() > 0.2 and (seed == 255).all(-1).mean() > 0.1
    assert shown.std() > 20  # a picture, not a grey field


def test_a_change_of_exposure_or_curve_keeps_the_clouds_histories(gl):
    """Exposure and the curve act after the clouds: TAA goes on averaging through a change of either."""
    host = WorkspaceRenderer(gl)
    state = CloudsWorkspace()
    settings = CloudRenderSettings(steps=8, reproject=False, tone=ToneSettings(auto=False))
    out = gl.texture((32, 18), 4)
    fbo = gl.framebuffer([out])
    try:
        for _ in range(3):
            host.render(fbo, state, settings)
        clouds = host.renderers["clouds"].clouds
        assert clouds.taa_frames == 3
        host.render(fbo, state, replace(settings, tone=ToneSettings(ev=1.0, auto=True, curve="agx")))
        assert clouds.taa_frames == 4
        host.render(fbo, state, replace(settings, steps=9))
        assert clouds.taa_frames == 1
    finally:
        fbo.release()
        out.release()
        host.release()



def test_the_panel_sends_exposure_automatic_and_curve_as_commands(qtbot):
    from app.editor import Editor
    from app.views.clouds_panel import CloudsPanel

    editor = Editor(configs=False)
    assert editor.execute("workspace clouds")
    sent = []
    panel = CloudsPanel(editor, editor.current, lambda line: sent.append(line) or editor.execute(line))
    qtbot.addWidget(panel)
    assert (panel.exposure.spin.value(), panel.checks["r_cloudAutoExposure"].isChecked(),
            panel.tone_map.currentText()) == (0.0, True, "aces")
    panel.exposure.spin.setValue(1.25)
    panel.checks["r_cloudAutoExposure"].setChecked(False)
    panel.tone_map.setCurrentText("agx")
    assert sent == ["r_cloudExposure 1.25", "r_cloudAutoExposure 0", "r_cloudToneMap agx"]
    assert editor.render_settings().tone == ToneSettings(ev=1.25, auto=False, curve="agx")
    assert editor.execute("r_cloudExposure -2") and editor.execute("r_cloudToneMap clamp")
    panel.sync()  # typed in the console: the panel shows it without sending it back
    assert (panel.exposure.spin.value(), panel.tone_map.currentText(), len(sent)) == (-2.0, "clamp", 3)
