"""10,000 hulls far outside the view add no work to a 2D frame: the renderer's index visits the same cells,
no hull geometry is built or uploaded for them, and the editor's overlay looks only at the hulls in view.
Work is counted, never timed; the frames must also be the same pixels."""
import dataclasses

import numpy as np
import pytest

from app.bench.harness import Timing
from app.bench.lighting2d import OFFVIEW_HULLS, offscreen_rows, offview_scene
from app.gl.core.headless import OffscreenTarget
from app.gl.lighting2d.renderer import Shading2D
from app.gl.lighting2d.workspace import Lighting2DWorkspaceRenderer
from app.gl.core.shaders import ShaderLibrary
from app.model.lighting2d.scene import Hull
from app.model.lighting2d.workspace import Lighting2DWorkspace
from app.resources import SHADERS

SIZE = (128, 80)


@pytest.fixture(scope="module")
def crowded():
    scene = offview_scene(OFFVIEW_HULLS)
    # far away too: an invalid hull (drawn in red when in view) and a disabled one (outlined by the wireframe)
    scene = scene.add_hull(Hull([(0, 0), (10, 10), (10, 0), (0, 10)], position=(9_000, 0)))
    scene = scene.add_hull(Hull([(0, 0), (10, 0), (0, 10)], position=(9_100, 0), enabled=False))
    assert not scene.hulls[-2].valid
    return scene


def frames(gl, scene, settings):
    """The editor's frame (lightmap, composite, overlay) twice: the work of the first (index built, geometry
    uploaded) and of the second (a steady frame), the overlay's hulls, and the second frame's pixels."""
    state = Lighting2DWorkspace(scene)
    state.selection = ("hull", 0)
    renderer = Lighting2DWorkspaceRenderer(gl, ShaderLibrary(gl, [SHADERS]))
    target = OffscreenTarget(gl, SIZE)
    try:
        work = []
        for _ in range(2):
            renderer.render(target.fbo, state, settings)
            work.append((dataclasses.replace(renderer.lighting.stats), renderer.overlay.hulls_seen))
        return work, target.read()
    finally:
        target.release()


@pytest.mark.parametrize("debug", [False, True])
def test_ten_thousand_hulls_far_away_add_no_work_to_a_frame(gl, crowded, debug):
    settings = Shading2D(debug=debug)  # the wireframe outlines every hull it is given
    (alone_first, alone_steady), alone_pixels = frames(gl, offview_scene(0), settings)
    (first, steady), pixels = frames(gl, crowded, settings)
    assert np.array_equal(pixels, alone_pixels)
    for (stats, seen), (alone, alone_seen) in ((first, alone_first), (steady, alone_steady)):
        assert seen == alone_seen == 3  # scene j's three hulls, all in view
        assert stats.hulls_considered == alone.hulls_considered > 0
        assert stats.hulls_built == alone.hulls_built
        assert stats.vertices_uploaded == alone.vertices_uploaded
    assert first[0].hulls_built > 0 and steady[0].hulls_built == steady[0].vertices_uploaded == 0
    # a steady frame asks the index one point per light; the far hulls' cells are never visited
    assert steady[0].index_cells == alone_steady[0].index_cells == 3
    assert steady[0].index_boxes <= alone_steady[0].index_boxes

def test_the_bench_compares_them_interleaved_with_the_spread_and_the_work(gl):
    lines = []
    rows = offscreen_rows(gl, (64, 40), 3, lines.append)
    assert [(r.method, r.knob) for r in rows] == [("exact", 0), ("exact+overlay", 0), ("exact", OFFVIEW_HULLS),
                                                  ("exact+overlay", OFFVIEW_HULLS)]
    spread_columns = set(Timing([0.0], [0.0]).spread())  # the spread's names; its values are times, not checked
    for r in rows:
        assert r.runs == 3 and spread_columns <= set(r.extra)
    alone, _, crowded_row, _ = rows
    assert crowded_row.rmse == alone.rmse < 2 / 255
    work = ("hulls_considered", "index_cells", "vertices_uploaded", "overlay_hulls")
    assert [rows[1].extra[k] for k in work] == [rows[3].extra[k] for k in work]
    assert len(lines) == 4
