"""The early exit (r_cloudEarlyExit) stops a ray once its clouds are 99 % opaque. The 1 % left showed whatever lay
behind: in front of the sun's disc (some 10^4 times the sky's radiance) that was a hundred times the cloud's own
light. An exited ray is opaque now, its remaining light taken as the mean so far, and rays towards the sun's disc
march on (docs/clouds.md, "Optimisations"). The GPU and the CPU reference agree on both."""
from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from app.bench.clouds_frames import NONE, CloudScene, CloudState, Shared
from app.gl.core.headless import create_context, release_context
from app.model.clouds import scene as cm
from app.model.clouds.scene import CloudParams, CloudView
from app.reference import clouds as rc
from tests.test_clouds_reference import textures

SIZE = (49, 27)  # odd: the middle pixel's ray is the view's axis, straight at the sun
SUN = CloudView(yaw=30.0, pitch=25.0, sun_azimuth=30.0, sun_elevation=25.0)


@pytest.fixture(scope="module")
def frames():
    """Linear radiance looking at the sun through an overcast sky and through a clear one, with and without the
    early exit."""
    ctx = create_context()
    try:
        shared, out = Shared(), {}
        for sky, coverage in (("overcast", 1.0), ("clear", 0.0)):
            scene = CloudScene(sky, params=CloudParams(coverage=coverage), view=SUN)
            for name, exits in (("none", False), ("exit", True)):
                state = CloudState(ctx, shared)
                state.steady(scene, replace(NONE, steps=64, early_exit=exits), SIZE)
                out[sky, name] = state.image(SIZE).copy()
        yield out
    finally:
        release_context(ctx)


def test_an_early_exit_lets_no_sunlight_through_the_clouds(frames):
    disc = frames["clear", "none"][13, 24].max()
    behind = frames["overcast", "none"][13, 24]
    assert behind.max() < disc / 1000  # a cloud hides the sun's disc here: 1 % of it would be ten times brighter
    assert np.allclose(frames["overcast", "exit"][13, 24], behind, rtol=1e-4)
    difference = np.abs(frames["overcast", "exit"] - frames["overcast", "none"])
    assert difference.max() < 0.1 and difference.mean() < 0.5 / 255


def test_the_reference_exits_as_the_shader_does():
    """An exited ray is opaque and its light near what the whole march gathers; a ray at the sun's disc never
    exits, even through an opaque cloud."""
    grid = [(a, e) for a in np.arange(0.0, 90.0, 7.5) for e in (5.0, 10.0, 15.0, 20.0)]
    d = np.array([cm.direction(a, e) for a, e in grid])
    n = np.full(len(d), 96)

    def marches(view: CloudView, **kw):
        frame = cm.frame(CloudParams(coverage=1.0), view, 0.0, 1.0)
        t0, t1, _has, _ground = rc.segment(frame, d)
        return rc.march(frame, textures(), d, t0, t1, n, **kw)

    opaque = np.flatnonzero(marches(SUN)[1] > 0.995)
    assert len(opaque) >= 3, "the overcast sky has opaque rays to exit"
    a, e = grid[opaque[0]]
    view = replace(SUN, sun_azimuth=a, sun_elevation=e)  # the sun behind the first opaque ray
    full, exited = marches(view), marches(view, early_exit=True)
    out = exited[1] == 1.0
    assert not out[opaque[0]] and np.allclose(exited[0][opaque[0]], full[0][opaque[0]])  # the sun's ray marched on
    assert set(opaque[1:]) <= set(np.flatnonzero(out))
    assert np.all(full[1][out] > rc.EARLY_EXIT) and np.all(exited[2][out] < full[2][out])  # fewer lookups
    assert np.allclose(exited[0][out], full[0][out], rtol=0.02)
