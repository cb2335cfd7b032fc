"""The 3D lights renderer (EGL, llvmpipe, 128 x 96) against the CPU reference: the lit image without shadows,
each shadow method's mask per light (and z-pass failing with the eye inside a volume where z-fail does not), no
GL state left behind, work that follows what changed and what the view shows, and the shadow map's size and
PCF. The numbers measured are printed (pytest -s); docs/lights3d.md quotes the bench's."""
from dataclasses import replace

import numpy as np
import pytest

from app.gl.core.headless import OffscreenTarget
from app.gl.lights3d.light_reach import reaches
from app.gl.lights3d.renderer import Lights3DRenderer
from app.gl.lights3d.caster_volumes import build
from app.gl.lights3d.workspace import Lights3DWorkspaceRenderer
from app.gl.core.shaders import ShaderLibrary
from app.gl.core.stencil import GL
from app.gl.core.workspace_renderer import RENDERERS
from app.model.lights3d.scene import Light3D, Lights3DCamera, Object3D, Scene3D, default_scene
from app.model.lights3d.render_settings import Lights3DRenderSettings as Settings
from app.model.lights3d.workspace import Lights3DWorkspace
from app.reference import lights3d as reference
from app.resources import SHADERS
from tests.gl_state import differences, snapshot
from tests.shadow_cases import camera_at, near_a_jump

SIZE = (128, 96)
CLOSE = Lights3DCamera(distance=250.0)  # the default scene filling more of the view
STENCIL_METHODS = ("onepass", "zpass", "zfail")
SUN = Light3D("directional", (0, 120, 0), (-0.3, -1.0, 0.5), (0.35, 0.3, 0.25))
NO_BIAS = Settings(bias=0.0)  # back faces in the map: closed casters need none (see app/gl/lights3d/shadow_map.py)


def unbind_and_release(gl, target: OffscreenTarget) -> None:
    """moderngl binds the framebuffer it last used again after making another: never a deleted one."""
    gl.detect_framebuffer(0).use()
    target.release()


@pytest.fixture(scope="module")
def host(gl):
    renderer, target = Lights3DRenderer(gl, ShaderLibrary(gl, [SHADERS])), OffscreenTarget(gl, SIZE)
    yield renderer, target
    renderer.release()
    unbind_and_release(gl, target)


def shadowed_by(scene: Scene3D, method: str) -> Scene3D:
    for i in range(len(scene.lights)):
        scene = scene.with_light(i, shadow=method)
    return scene


def draw(host, scene, camera=CLOSE, settings=None, selection=None, marks=False) -> np.ndarray:
    renderer, target = host
    renderer.render(target.fbo, scene, camera, settings, selection, marks)
    return target.read()[..., :3] / 255.0


# ---- (a) the lit image -------------------------------------------------------------------------------------


@pytest.mark.parametrize("camera", [Lights3DCamera(), CLOSE], ids=["default camera", "close"])
def test_without_shadows_the_image_is_the_references(host, camera):
    """Every light kind, the formulas alone (shadow none): within 2/255 of the float64 reference everywhere but
    within a pixel of a silhouette."""
    scene = shadowed_by(default_scene().add_light(SUN), "none")
    image = draw(host, scene, camera)
    ref = reference.render(scene, camera, SIZE)
    error = np.abs(image - ref.rgb).max(axis=-1)
    edge = near_a_jump(ref, camera.position())
    print(f"\nno shadows, {camera.distance:g} away: max error {error.max() * 255:.2f}/255, off silhouettes "
          f"{error[~edge].max() * 255:.2f}/255; {edge.mean():.1%} of pixels near a silhouette, "
          f"{(error[edge] > 2 / 255).sum()} of them over 2/255")
    assert edge.mean() < 0.1
    assert error[~edge].max() <= 2 / 255
    assert (ref.object_id >= 0).mean() > 0.3  # a scene, not the background


# ---- (b) each method's shadow, per light ---------------------------------------------------------------------


def mismatches(host, scene, camera, method, settings=None) -> list[float]:
    """Per light, the share of the pixels it faces and reaches whose shadow differs from the reference's."""
    ref = reference.render(scene, camera, SIZE)
    out = []
    for i in range(len(scene.lights)):
        mask, _ = host[0].shadow_mask(scene, camera, SIZE, i, method, settings)
        truth = ref.facing[i] & ~ref.visible[i]
        out.append(float(((mask != truth) & ref.facing[i]).sum() / ref.facing[i].sum()))
    return out


@pytest.mark.parametrize("method, settings, bound", [
    ("onepass", None, 0.002), ("zpass", None, 0.002), ("zfail", None, 0.002),
    ("map", Settings(), 0.005), ("map", NO_BIAS, 0.005),
    ("map", Settings(bias=0.005), 0.03)],  # 0.5 units at the point light's range: peter-panning at feet and rims
    ids=["onepass", "zpass", "zfail", "map", "map without bias", "map with a big bias"])
def test_each_method_matches_the_references_shadow(host, method, settings, bound):
    errors = mismatches(host, default_scene().add_light(SUN), CLOSE, method, settings)
    print(f"\n{method} {settings or ''}: mismatch point {errors[0]:.3%}, spot {errors[1]:.3%}, "
          f"directional {errors[2]:.3%}")
    assert max(errors) <= bound


def test_the_eye_inside_a_shadow_volume_breaks_zpass_not_zfail(host):
    scene = Scene3D(objects=(Object3D("plane", (400.0,), (0, 0, 0)), Object3D("box", (60, 60, 60), (0, 70, 0))),
                    lights=(Light3D("point", (10, 250, 5), range=1000.0),))
    camera = camera_at((0, 15, 0), (-150, 0, -80))  # under the box, looking across its shadow
    ref = reference.render(scene, camera, SIZE)
    assert (ref.facing[0] & ~ref.visible[0]).mean() > 0.1 and (ref.facing[0] & ref.visible[0]).mean() > 0.1
    errors = {m: mismatches(host, scene, camera, m)[0] for m in STENCIL_METHODS}
    print(f"\neye inside a volume: mismatch {', '.join(f'{m} {e:.2%}' for m, e in errors.items())}")
    assert errors["zfail"] <= 0.002
    assert errors["zpass"] > 0.3  # the count starts one short: lit and shadowed swap


# ---- (c) state -------------------------------------------------------------------------------------------


@pytest.mark.parametrize("method", [*STENCIL_METHODS, "map", "none"])
def test_a_frame_leaves_no_gl_state_behind(host, method):
    renderer, target = host
    scene = shadowed_by(default_scene(), method)
    draw(host, scene, selection=("object", 2), marks=True)  # first: what it makes (moderngl binds new objects)
    target.fbo.use()
    before = snapshot()
    draw(host, scene, selection=("object", 2), marks=True)
    after = snapshot()
    assert differences(before, after) == {}
    assert not after["GL_STENCIL_TEST"] and not after["GL_DEPTH_CLAMP"] and not after["GL_BLEND"]
    assert GL.glGetError() == GL.GL_NO_ERROR
    renderer.shadow_mask(default_scene(), CLOSE, SIZE, 0, "map" if method == "none" else method)
    assert differences(before, snapshot()).keys() <= {"GL_DRAW_FRAMEBUFFER_BINDING", "GL_READ_FRAMEBUFFER_BINDING",
                                                       "GL_PACK_ALIGNMENT"}  # its target bound, read from
    assert GL.glGetError() == GL.GL_NO_ERROR


def test_a_framebuffer_deleted_while_bound_elsewhere_does_not_break_a_frame(gl, host):
    """moderngl leaves GL_INVALID_OPERATION queued when it binds a deleted framebuffer again: the frame binds
    the host's first, so making its target queues none, and it takes what was queued before it."""
    other = OffscreenTarget(gl, (16, 16))
    other.fbo.use()
    other.release()
    fresh = OffscreenTarget(gl, (72, 48))  # made while the deleted one is moderngl's current: the error queues
    host[0].render(fresh.fbo, default_scene(), CLOSE)  # a new size: the frame makes its target too
    assert GL.glGetError() == GL.GL_NO_ERROR
    unbind_and_release(gl, fresh)


# ---- (d) work ----------------------------------------------------------------------------------------------


def test_meshes_volumes_and_maps_are_made_again_only_when_they_change(host):
    renderer, target = host
    scene = default_scene().with_light(0, shadow="zfail").with_light(1, shadow="map")
    renderer.render(target.fbo, scene.with_object(0, colour=(0.5, 0.5, 0.5)), CLOSE)  # every object new
    first = renderer.render(target.fbo, scene, CLOSE)
    assert first.uploads == 1 and first.lights_drawn == 2  # only the recoloured ground changed
    still = renderer.render(target.fbo, scene, CLOSE)
    assert (still.uploads, still.volumes_built, still.volume_bytes, still.maps_rendered) == (0, 0, 0, 0)
    assert still.volumes_drawn == 4 and still.volume_triangles > 0  # every caster within the point light's range
    turned = renderer.render(target.fbo, scene, replace(CLOSE, yaw=80.0))
    assert (turned.uploads, turned.volumes_built, turned.volume_bytes) == (0, 0, 0)
    assert turned.maps_rendered == 1  # the map fits what the view sees: another view, another map...
    assert renderer.render(target.fbo, scene, replace(CLOSE, yaw=80.0)).maps_rendered == 0  # ...kept while it stays
    scene = scene.with_object_moved(2, (10.0, 20.0, 5.0))
    moved = renderer.render(target.fbo, scene, CLOSE)
    assert (moved.uploads, moved.volumes_built, moved.maps_rendered) == (1, 1, 1)
    relit = renderer.render(target.fbo, scene.with_light(0, colour=(1.0, 0.5, 0.5)), CLOSE)
    assert (relit.uploads, relit.volumes_built) == (0, 0)  # a colour is no volume's business
    recoloured = renderer.render(target.fbo, scene.with_object(2, colour=(0.1, 0.9, 0.1)), CLOSE)
    assert (recoloured.uploads, recoloured.volumes_built, recoloured.volume_bytes) == (1, 0, 0)
    renderer.forget_shadows()
    again = renderer.render(target.fbo, scene, CLOSE)
    assert (again.volumes_built, again.maps_rendered) == (4, 1)


@pytest.mark.parametrize("method", STENCIL_METHODS)
def test_a_moved_light_builds_and_uploads_its_own_volumes_alone(host, method):
    renderer, target = host
    scene = shadowed_by(default_scene(), method)
    renderer.render(target.fbo, scene, CLOSE)
    assert renderer.render(target.fbo, scene, CLOSE).volume_bytes == 0
    moved = scene.with_light(1, position=(190.0, 160.0, 10.0))
    spot = moved.lights[1]
    casters = [o for o in moved.objects if o.mesh().closed and reaches(spot, o.position, o.radius)]
    stats = renderer.render(target.fbo, moved, CLOSE)
    assert 0 < stats.volumes_built == len(casters) < stats.volumes_drawn  # the point light's kept
    assert stats.volume_bytes == sum(build(method, o, spot).vertices.nbytes for o in casters)
    assert renderer.render(target.fbo, moved, CLOSE).volume_bytes == 0


def test_a_light_out_of_view_is_skipped_and_only_casters_in_reach_cast(host):
    renderer, target = host
    behind = np.asarray(CLOSE.position()) + 150 * (np.asarray(CLOSE.position()) - CLOSE.target) / CLOSE.distance
    scene = shadowed_by(default_scene().add_object(Object3D("box", (20, 20, 20), tuple(behind - (0, 40, 0))))
                        .add_light(Light3D("point", tuple(behind), range=80.0)), "zfail")
    out_of_view = renderer.render(target.fbo, scene, CLOSE)
    assert (out_of_view.lights_drawn, out_of_view.lights_skipped) == (2, 1)
    assert out_of_view.objects_drawn == 5  # the box behind the eye is not drawn either
    # the point light's 4 casters and the spot's 4 (the torus's bounding sphere touches the cone); none for the box
    # behind the eye, which only the skipped light reaches
    assert out_of_view.volumes_drawn == 4 + 4
    torus_only = default_scene().with_light(0, position=(60.0, 25.0, 45.0), range=30.0, shadow="zfail")
    small = renderer.render(target.fbo, torus_only.remove_light(1), CLOSE)
    assert small.volumes_drawn == 1  # the torus, the one caster within 30 of the light
    assert small.scissor_pixels < 0.25 * SIZE[0] * SIZE[1]  # its passes scissored to the range around it


# ---- (e) the shadow map ------------------------------------------------------------------------------------


def test_a_bigger_map_misses_less_and_a_wider_kernel_softens_more(host):
    scene = default_scene()
    ref = reference.render(scene, CLOSE, SIZE)
    missed, soft = {}, {}
    for size, pcf in ((256, 1), (2048, 1), (256, 3), (256, 5)):
        missed[size, pcf] = soft[size, pcf] = 0
        for i in range(len(scene.lights)):
            mask, stats = host[0].shadow_mask(scene, CLOSE, SIZE, i, "map", Settings(size, pcf, 0.0))
            region = ref.facing[i]
            missed[size, pcf] += int(((mask != (region & ~ref.visible[i])) & region).sum())
            visibility = stats.visibility[region]
            soft[size, pcf] += int(((visibility > 0.01) & (visibility < 0.99)).sum())
    print(f"\nmap, mismatched pixels by (size, pcf): {missed}; partly lit pixels: {soft}")
    assert missed[256, 1] > 4 * max(missed[2048, 1], 1)
    assert soft[256, 1] < soft[256, 3] < soft[256, 5]
    assert soft[2048, 1] < soft[256, 1]  # finer texels: a narrower penumbra of the filtered taps


# ---- the workspace -----------------------------------------------------------------------------------------


def test_the_workspace_renderer_draws_the_state_with_its_marks(gl):
    assert RENDERERS["lights3d"] is Lights3DWorkspaceRenderer
    workspace = Lights3DWorkspaceRenderer(gl, ShaderLibrary(gl, [SHADERS]))
    target = OffscreenTarget(gl, SIZE)
    state = Lights3DWorkspace()
    state.camera = replace(CLOSE)
    assert workspace.render(target.fbo, state, Settings(map_size=256)) is False
    plain = target.read()[..., :3].astype(int)
    state.selection = ("object", 2)
    workspace.render(target.fbo, state, Settings(map_size=256))
    marked = target.read()[..., :3].astype(int)
    changed = np.abs(marked - plain).max(axis=-1) > 0
    assert 0.002 < changed.mean() < 0.1  # the gizmo and the box around the sphere, nothing else
    red = (marked[..., 0] > 200) & (marked[..., 1] < 100) & (marked[..., 2] < 100)
    assert red.any()  # the x handle
    assert workspace.release() > 0
    unbind_and_release(gl, target)


# ---- debug views (r_shadowDebug) ---------------------------------------------------------------------------


def test_the_mask_view_is_white_where_the_first_light_lights(host):
    scene = default_scene().with_light(0, shadow="zfail")
    image = draw(host, scene, settings=Settings(debug="mask"))
    ref = reference.render(scene, CLOSE, SIZE)
    white, lit = image.min(axis=-1) > 0.5, ref.facing[0] & ref.visible[0]
    assert (image[~white] == 0).all()  # black elsewhere, background included
    assert lit.mean() > 0.1 and (white != lit).mean() < 0.002


def test_the_stencil_view_shows_the_first_stencil_lights_values_as_grey(host):
    scene = default_scene().with_light(0, shadow="map").with_light(1, shadow="onepass")
    grey = np.round(draw(host, scene, settings=Settings(debug="stencil")) * 255).astype(int)
    assert (grey == grey[..., :1]).all()
    values = set(np.unique(grey))
    assert values <= {0, 1, 0xFC, 0xFD} and 0xFC in values  # onepass: one pass, one fail, both: the shadow
    shadow, _ = host[0].shadow_mask(scene, CLOSE, SIZE, 1, "onepass")
    assert (shadow[grey[..., 0] == 0xFC]).all()
