"""The geometry shader's outline, captured with transform feedback, against the CPU polyline."""
import numpy as np
import pytest

from app.gl.core.headless import OffscreenTarget
from app.gl.core.shaders import ShaderLibrary
from app.gl.snowflake.renderer import CHUNK_DEPTH, SnowflakeRenderer, chunk_layout
from app.model.camera2d import Camera2D
from app.model.snowflake import Flake, SnowflakeScene
from app.reference.snowflake import segments
from app.resources import SHADERS

PORTABLE_GS_VERTICES = 256  # GL's minimum for GL_MAX_GEOMETRY_OUTPUT_VERTICES


@pytest.fixture(scope="module")
def renderer(gl):
    return SnowflakeRenderer(gl, ShaderLibrary(gl, [SHADERS]))


def two_flakes(level):
    return SnowflakeScene((Flake(0.0, 0.0, 0.6), Flake(-1.1, 0.7, 0.25)), level)


@pytest.mark.parametrize("level", [0, 0.5, 1, 2, 2.25, 3, 4, 5.5, 6, 7])
def test_shader_outline_matches_cpu_polyline(renderer, level):
    scene = two_flakes(level)
    gpu = renderer.capture(scene, Camera2D())
    cpu = segments(scene.flakes, level)
    assert gpu.shape == cpu.shape
    assert np.abs(gpu - cpu).max() < 2e-6  # float32 arithmetic against float64, on a unit-sized flake


def test_level_six_and_beyond_within_portable_emission_limit(renderer):
    program = renderer.shaders.program("snowflake")
    assert program.geometry_vertices == 4 ** CHUNK_DEPTH + 1 <= PORTABLE_GS_VERTICES
    for level in (6, 7, 8):
        m, _t, depth, chunks = chunk_layout(level)
        assert chunks * 4 ** depth == 3 * 4 ** m  # the chunks tile every segment of the outline


def test_render_draws_the_outline_and_nothing_else(gl, renderer):
    target = OffscreenTarget(gl, (128, 128))
    scene = SnowflakeScene((Flake(0.0, 0.0, 1.0),), 3)
    renderer.render(target.fbo, scene, Camera2D(height=2.4))
    image = target.read()
    lit = image[..., 1] > 60
    ys, xs = np.nonzero(lit)
    assert 300 < lit.sum() < 3000  # an outline, not a fill and not nothing
    assert image[64, 64, 1] < 60 and image[2, 2, 1] < 60  # inside and far outside are background
    # the outline spans the flake: tip at the top (y = +1 world -> row ~11), symmetric about x
    assert abs(ys.min() - 64 * (1 - 1 / 1.2)) <= 2
    assert abs((xs.min() + xs.max()) / 2 - 63.5) <= 1.5
    target.release()


def test_empty_scene_draws_background_only(gl, renderer):
    target = OffscreenTarget(gl, (32, 32))
    renderer.render(target.fbo, SnowflakeScene(), Camera2D())
    image = target.read()
    assert (image == image[0, 0]).all()
    assert renderer.capture(SnowflakeScene(), Camera2D()).shape == (0, 2, 2)
    target.release()


def test_flake_buffer_reuploaded_only_on_change(gl, renderer):
    target = OffscreenTarget(gl, (32, 32))
    scene = two_flakes(2)
    renderer.render(target.fbo, scene, Camera2D())
    uploaded = renderer._uploaded
    renderer.render(target.fbo, scene, Camera2D())
    renderer.render(target.fbo, scene.with_level(3), Camera2D())  # a level change shares the flakes
    assert renderer._uploaded is uploaded is scene.flakes
    moved = scene.moved(1, 0.5, 0.5)
    renderer.render(target.fbo, moved, Camera2D())
    assert renderer._uploaded is moved.flakes is not uploaded
    target.release()
