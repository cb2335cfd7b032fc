"""The 2D editor's overlay builds and uploads its lines only when the scene, the view or the selection changed,
and draws the icons of the lights in view only. Work is counted (layers built, segments uploaded, icons),
never timed; the frames are compared as pixels."""
from dataclasses import replace

import numpy as np
import pytest

from app.gl.core.headless import OffscreenTarget
from app.gl.lighting2d.renderer import Shading2D
from app.gl.lighting2d.overlay import ICON_LINES, ICON_PX, ICON_RIM, icons_in
from app.gl.lighting2d.workspace import Lighting2DWorkspaceRenderer
from app.gl.core.shaders import ShaderLibrary
from app.model.lighting2d.scene import Hull, Light, Scene2D
from app.model.lighting2d.workspace import Lighting2DWorkspace
from app.resources import SHADERS

SIZE = (128, 96)
PER_ICON = len(ICON_LINES) + len(ICON_RIM)  # segments: the sun's lines and their dark rim


def scene(far_lights: int) -> Scene2D:
    """Two lights and a hull in a 400-unit high view about (0, 0), and `far_lights` lights 10,000 units away."""
    near = [Light(position=(-60.0, 30.0), radius=8.0), Light(position=(70.0, -40.0), radius=8.0)]
    far = [Light(position=(10_000.0 + 50 * k, 0.0), radius=8.0) for k in range(far_lights)]
    return Scene2D(view=(0.0, 0.0, 400.0), lights=near + far, hulls=[Hull([(0, 0), (30, 0), (30, 30), (0, 30)])])


@pytest.fixture
def editor_frame(gl):
    """draw(state, settings) -> (the overlay's stats, the frame's pixels), with one renderer and target."""
    renderer = Lighting2DWorkspaceRenderer(gl, ShaderLibrary(gl, [SHADERS]))
    target = OffscreenTarget(gl, SIZE)

    def draw(state, settings=Shading2D()):
        renderer.render(target.fbo, state, settings)
        return renderer.overlay.stats, target.read()

    yield draw
    target.release()


@pytest.mark.parametrize("settings", [Shading2D(), Shading2D(debug=True, flip_y=True)])
def test_a_still_frame_builds_and_uploads_no_overlay_lines(editor_frame, settings):
    state = Lighting2DWorkspace(scene(0))
    state.selection = ("hull", 0)
    first, first_pixels = editor_frame(state, settings)
    assert first.layers_built == 2 and first.segments_uploaded > 2 * PER_ICON and first.icons == 2
    still, still_pixels = editor_frame(state, settings)
    assert (still.layers_built, still.segments_uploaded, still.icons) == (0, 0, 2)
    assert np.array_equal(still_pixels, first_pixels)  # drawn all the same

    state.selection = ("light", 1)  # only the selection's lines change
    selected, _ = editor_frame(state, settings)
    assert selected.layers_built == 1 and 0 < selected.segments_uploaded < first.segments_uploaded
    state.selection = ("hull", 0)
    back, back_pixels = editor_frame(state, settings)
    assert back.layers_built == 1 and np.array_equal(back_pixels, first_pixels)

    state.camera.cx += 10.0  # the view moved: the lines are built again where it shows them
    panned, _ = editor_frame(state, settings)
    assert panned.layers_built == 2 and panned.segments_uploaded == first.segments_uploaded
    state.scene = state.scene.with_light(0, replace(state.scene.lights[0], position=(-50.0, 30.0)))  # an edit
    edited, _ = editor_frame(state, settings)
    assert edited.layers_built == 2


def test_the_icons_of_lights_outside_the_view_are_not_drawn(editor_frame):
    near, near_pixels = editor_frame(Lighting2DWorkspace(scene(0)))
    crowded, crowded_pixels = editor_frame(Lighting2DWorkspace(scene(200)))
    assert near.icons == crowded.icons == 2
    assert crowded.segments_uploaded == near.segments_uploaded == 2 * PER_ICON + 4  # and the hull's outline
    assert np.array_equal(crowded_pixels, near_pixels)


def test_an_icon_whose_centre_is_just_outside_the_view_still_shows(editor_frame):
    unit = 400.0 / SIZE[1]  # world units a pixel, in a 400-unit high view
    edge = 200.0 * SIZE[0] / SIZE[1]  # the view's right edge
    lights = [Light(position=(edge + 0.5 * ICON_PX * unit, 0.0)), Light(position=(edge + 2 * ICON_PX * unit, 0.0))]
    s = Scene2D(view=(0.0, 0.0, 400.0), lights=lights)
    assert len(icons_in(s, unit, -edge, -200.0, edge, 200.0)) == 1  # half of the first one's rays show
    stats, pixels = editor_frame(Lighting2DWorkspace(s))
    assert stats.icons == 1
    edge_pixels = pixels[SIZE[1] // 2 - 2:SIZE[1] // 2 + 3, -3:].astype(int)  # about its left ray
    assert (edge_pixels[..., 0] - edge_pixels[..., 2] > 100).any()  # the icon's orange, not the light's white
