"""A still view of the clouds draws until TAA has converged (docs/clouds.md, "Upsampling and reprojection"): the
renderer settles once a frame changes its clouds by less than 0.1/255, and `shadelab render` draws exactly that
many frames. Each test makes its own headless context (`render` makes and releases one of its own)."""
from __future__ import annotations

import re

import numpy as np
import pytest

from app.bench.clouds_frames import CloudScene, CloudState, Shared
from app.gl.clouds.renderer import CONVERGED, MAX_SETTLING, STOP_FRAMES, TAA_FRAMES
from app.gl.core.headless import create_context, release_context
from app.model.clouds.scene import CloudRenderSettings

SIZE = (48, 27)


def converging(settings: CloudRenderSettings) -> tuple[int, list[float | None]]:
    """Frames of the default still view until the renderer stops settling, and each frame's change of the cloud
    buffer as measured here from the buffers read back (None while there is no last frame)."""
    ctx = create_context()
    try:
        state = CloudState(ctx, Shared())
        scene = CloudScene("test")
        changes, before = [], None
        for frame in range(1, MAX_SETTLING + 2):
            state.draw(scene, settings, SIZE)
            clouds = state.renderer.last_clouds
            buffer = np.frombuffer(clouds.read(), np.float32).reshape(-1, 4)[:, :3].copy()
            changes.append(None if before is None or before.shape != buffer.shape else
                           float(np.abs(buffer - before).mean()))
            before = buffer
            if not state.renderer.settling(settings):
                return frame, changes
        raise AssertionError("never settled")
    finally:
        release_context(ctx)


@pytest.mark.parametrize("settings", [CloudRenderSettings(), CloudRenderSettings(reproject=False)],
                         ids=["reprojection", "taa"])
def test_a_still_view_settles_once_a_frame_changes_the_clouds_by_less_than_a_tenth_of_a_level(settings):
    """Not after one cycle of reprojection (4 frames at d = 2) or 16 frames of TAA, as before: every frame after
    the first cycle changed the cloud buffer by 0.1/255 or more on average, the last by less."""
    frames, changes = converging(settings)
    cycle = settings.downsample ** 2 if settings.reproject else 1
    assert frames > max(cycle, 16)
    assert changes[-1] < CONVERGED
    assert all(c >= CONVERGED for c in changes[cycle:-1] if c is not None)


def test_a_running_clock_settles_once_the_fading_average_is_full():
    """The winds blowing, nothing converges (the animation draws on anyway): the view counts as settled, for the
    editor's screenshot, once TAA's fading average holds its 16 frames."""
    ctx = create_context()
    try:
        state, scene, settings = CloudState(ctx, Shared()), CloudScene("test"), CloudRenderSettings()
        for frame in range(1, MAX_SETTLING):
            scene.wind_time += 0.2
            state.draw(scene, settings, SIZE)
            if not state.renderer.settling(settings):
                break
        assert frame == TAA_FRAMES
    finally:
        release_context(ctx)


def test_render_draws_as_many_frames_as_the_convergence_rule_asks(tmp_path, capsys):
    """`shadelab render clouds` stops where the renderer's rule says: its frame count is the one found here again
    from the buffers read back, beyond the first cycle."""
    from app import cli

    settings = CloudRenderSettings()  # the cvars' defaults
    out = tmp_path / "sky.png"
    assert cli.main(["render", "clouds", "--size", f"{SIZE[0]}x{SIZE[1]}", "--out", str(out)]) == 0
    said = re.search(rf"wrote .* \({SIZE[0]}x{SIZE[1]}, (\d+) frames,", capsys.readouterr().out)
    assert said and out.is_file()
    expected, _ = converging(settings)
    assert int(said.group(1)) == expected > settings.downsample ** 2


def test_a_clock_that_ticks_every_other_frame_settles_and_a_stopped_one_converges():
    """The editor draws frames between its animation's ticks: the clock moves on every other frame. Each still frame
    counted as a stop restarted reprojection's count, and the view never settled (the editor's `--screenshot` of the
    clouds waited its 5 minutes). A clock still for STOP_FRAMES frames has stopped; the view converges after."""
    ctx = create_context()
    try:
        state, scene, settings = CloudState(ctx, Shared()), CloudScene("test"), CloudRenderSettings()
        settled = None
        for frame in range(1, 4 * TAA_FRAMES):
            scene.wind_time += 0.2 * (frame % 2)
            state.draw(scene, settings, SIZE)
            if not state.renderer.settling(settings):
                settled = frame
                break
        assert settled is not None and settled <= 2 * TAA_FRAMES
        assert state.renderer.clock_running
        stops = []
        for frame in range(STOP_FRAMES + 2):  # the clock stands still from here
            state.draw(scene, settings, SIZE)
            stops.append(state.renderer.reprojected_frames)
        assert not state.renderer.clock_running
        assert stops[STOP_FRAMES - 1] == 1  # the stop seen: the count restarts, the kept values as prior samples
        assert state.renderer.settling(settings)  # ... and the still view converges from there
    finally:
        release_context(ctx)
