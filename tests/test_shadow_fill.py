"""The stencil passes' fill: ShadowVolumePass.fill (the shadows bench's fill_px) counts the fragments a volume
draw rasterises, whichever way their depth test goes, within the light's scissor rectangle; the depth bounds test
(app/gl/core/depth_bounds.py) clamps the passes to the window depths of a light's reach where GL has it (Mesa's
llvmpipe has not: there it is skipped, and the frame says so); those depths hold every pixel the light lights
(EGL, llvmpipe)."""
import numpy as np
import pytest

from app.gl.core.depth_bounds import EXTENSION, depth_bounds
from app.gl.core.headless import OffscreenTarget
from app.gl.core.shaders import ShaderLibrary
from app.gl.core.stencil import GL, clear_stencil
from app.gl.lights3d.caster_volumes import build
from app.gl.lights3d.light_reach import depth_range, reach_box, reaches, span
from app.gl.lights3d.renderer import Lights3DRenderer
from app.gl.lights3d.shadow_volume_pass import shadowed
from app.gl.lights3d.shadow_volumes import VolumeGeometry
from app.model.lights3d.scene import Light3D, Lights3DCamera, default_scene
from app.reference import lights3d as reference
from app.resources import SHADERS
from tests.gl_state import differences, snapshot
from tests.shadow_cases import stencil_host

SIZE = (64, 48)
# two triangles over the whole view at depth 0.5 (clip = world: the identity as view-projection)
SCREEN = VolumeGeometry(np.array([[-1, -1, 0, 1], [1, -1, 0, 1], [1, 1, 0, 1], [-1, -1, 0, 1], [1, 1, 0, 1],
                                  [-1, 1, 0, 1]], np.float32), 0)


@pytest.fixture(scope="module")
def host(gl):
    yield from stencil_host(gl, SIZE)


@pytest.mark.parametrize("depth", [0.0, 1.0], ids=["every depth test fails", "every one passes"])
def test_fill_counts_every_fragment_the_draw_rasterises_within_the_scissor(host, depth):
    shadow_pass, target = host
    target.fbo.scissor = None
    target.clear(depth=depth)
    before = target.read_stencil()
    for method in ("onepass", "zpass", "zfail"):
        assert shadow_pass.fill(target.fbo, method, [SCREEN], np.eye(4)) == SIZE[0] * SIZE[1]
    target.fbo.scissor = (8, 4, 16, 20)
    assert shadow_pass.fill(target.fbo, "zfail", [SCREEN], np.eye(4)) == 16 * 20
    target.fbo.scissor = None
    np.testing.assert_array_equal(target.read_stencil(), before)  # counting writes nothing
    assert GL.glGetError() == GL.GL_NO_ERROR


def test_depth_bounds_drop_fragments_over_depths_outside_them_where_gl_has_the_test(gl, host):
    """Here (llvmpipe) the test is missing: depth_bounds does nothing and says so. Where it is there, fragments
    over the cleared depth 1, outside (0, 0.5), are dropped and the state is put back."""
    shadow_pass, target = host
    target.fbo.scissor = None
    target.clear(depth=1.0)
    target.fbo.use()
    before = snapshot()
    with depth_bounds(gl, (0.0, 0.5)) as clamped:
        assert clamped == (EXTENSION in gl.extensions)
    with depth_bounds(gl, None) as clamped:
        assert not clamped
    assert differences(before, snapshot()) == {}
    fill = shadow_pass.fill(target.fbo, "zfail", [SCREEN], np.eye(4), bounds=(0.0, 0.5))
    assert fill == (0 if EXTENSION in gl.extensions else SIZE[0] * SIZE[1])
    if EXTENSION in gl.extensions:
        assert not GL.glIsEnabled(0x8890)  # GL_DEPTH_BOUNDS_TEST_EXT, off again
    assert GL.glGetError() == GL.GL_NO_ERROR


@pytest.mark.parametrize("camera", [Lights3DCamera(), Lights3DCamera(yaw=-60.0, pitch=8.0, distance=60.0)],
                         ids=["default", "low and close: reaches cut by the near plane"])
def test_a_lights_depth_range_holds_every_pixel_it_lights(camera):
    """The window depth of every surface point a light faces and reaches (the reference's) lies within the span of
    its reach's boxes' depth ranges; the background (depth 1) lies outside, so it is clamped away."""
    scene = default_scene().add_light(Light3D("point", (-60.0, 30.0, 40.0), range=45.0))
    size = (96, 72)
    ref = reference.render(scene, camera, size)
    clip_from_world = camera.clip_from_world(size)
    for i, light in enumerate(scene.lights):
        bounds = span(depth_range(clip_from_world, camera.NEAR, *reach_box(light, *o.bounds))
                      for o in scene.objects if reaches(light, o.position, o.radius))
        points = ref.position[ref.facing[i]]
        clip = np.c_[points, np.ones(len(points))] @ clip_from_world.T
        depth = (clip[:, 2] / clip[:, 3] + 1) / 2
        assert len(points) > 100
        assert bounds[0] <= depth.min() and depth.max() <= bounds[1] < 1.0
    assert depth_range(clip_from_world, camera.NEAR, (1.0, 1.0, 1.0), (0.0, 2.0, 2.0)) is None  # an empty box
    behind = camera.position() + 5 * (camera.position() - np.asarray(camera.target))
    assert depth_range(clip_from_world, camera.NEAR, behind - 1, behind + 1) is None  # wholly behind the eye


def test_a_lights_stencil_pass_draws_within_its_reach_alone(gl):
    """A small point light beside the torus: its stencil pass, scissored to its reach, rasterises part of what the
    same volumes do over the whole view, and the shadow it marks there is the same; a frame says whether its
    passes were clamped in depth too."""
    renderer, output = Lights3DRenderer(gl, ShaderLibrary(gl, [SHADERS])), None
    try:
        scene = default_scene().with_light(0, position=(90.0, 15.0, 45.0), range=45.0).remove_light(1)
        camera = Lights3DCamera(distance=250.0)
        size = (128, 96)
        mask, stats = renderer.shadow_mask(scene, camera, size, 0, "onepass")
        geometries = [build("onepass", o, scene.lights[0]) for o in scene.objects
                      if o.mesh().closed and reaches(scene.lights[0], o.position, o.radius)]
        target, view_proj = renderer.target, camera.clip_from_world(size)
        target.fbo.scissor = None
        whole = renderer.volume_pass.fill(target.fbo, "onepass", geometries, view_proj)
        print(f"\nfill within the reach {stats.fill_px}, over the whole view {whole}")
        assert 0 < stats.fill_px < 0.75 * whole  # the quads run on out of the light's reach on screen
        clear_stencil(target.fbo)
        renderer.volume_pass.mark(target.fbo, "onepass", geometries, view_proj)
        unscissored = shadowed("onepass", target.read_stencil()) & (target.read_depth() < 1)
        lit = reference.render(scene.with_light(0, shadow="onepass"), camera, size).facing[0]
        assert lit.sum() > 1000 and mask[lit].sum() > 200  # the torus's shadow on the ground
        np.testing.assert_array_equal(mask[lit], unscissored[lit])
        output = OffscreenTarget(gl, size)
        frame = renderer.render(output.fbo, scene.with_light(0, shadow="zfail"), camera, marks=False)
        assert frame.depth_bounded == (1 if EXTENSION in gl.extensions else 0)
        assert GL.glGetError() == GL.GL_NO_ERROR
    finally:
        renderer.release()
        gl.detect_framebuffer(0).use()
        if output is not None:
            output.release()
