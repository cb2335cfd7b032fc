"""The volume's 3D view headless: sub-box uploads keep the texture exact, and the picture is right."""
import numpy as np
import pytest

from app.bench import harness, paint
from app.gl.core.headless import OffscreenTarget
from app.gl.core.shaders import ShaderLibrary
from app.gl.volume.raytracer import RayTracer, TraceSettings
from app.gl.volume.texture import VolumeTexture
from app.model.camera3d import OrbitCamera
from app.model.volume.volume import Volume
from app.model.volume.voxels import Voxels
from app.model.volume.pick import first_hit
from app.model.volume.samples import coords3d, cornell_box
from app.model.volume.view import VolumeView
from app.resources import SHADERS


def test_sub_box_uploads_keep_the_texture_equal_to_the_model(gl):
    vol = Volume(cornell_box(32))
    texture = VolumeTexture(gl)
    texture.sync(vol.voxels)
    full = texture.uploaded_voxels
    vol.paint.stroke("z", 5, 3, (255, 0, 0, 255), [(2, 2), (20, 9)])
    texture.sync(vol.voxels)
    assert texture.uploaded_voxels - full == 21 * 10 * 1  # just the stroke's box
    vol.paint.fill("y", 16, 10, 10, (0, 0, 255, 128))
    vol.history.undo()
    texture.sync(vol.voxels)
    np.testing.assert_array_equal(texture.read(), vol.voxels.data)
    vol.rotate("y")
    texture.sync(vol.voxels)
    np.testing.assert_array_equal(texture.read(), vol.voxels.data)


@pytest.fixture(scope="module")
def renderer(gl):
    return RayTracer(gl, ShaderLibrary(gl, [SHADERS]))


def render(gl, renderer, voxels, view, size=(96, 96), mode=2):
    target = OffscreenTarget(gl, size, samples=0)
    renderer.render(target.fbo, voxels, view, TraceSettings(mode=mode, steps=128))
    image = target.read()
    target.release()
    return image


def test_front_view_of_coords3d_shows_its_front_face(gl, renderer):
    view = VolumeView(camera=OrbitCamera(yaw=0, pitch=0, distance=5.2))
    image = render(gl, renderer, Voxels(coords3d(16)), view)
    # The front face is index z = 0 (blue = 0): x grows to the right (red), y downwards (green).
    centre = image[48, 48, :3].astype(int)
    assert centre[2] < 40
    left, right = image[48, 34, 0], image[48, 62, 0]
    top, bottom = image[34, 48, 1], image[62, 48, 1]
    assert right > left + 60 and bottom > top + 60
    corner = image[2, 2, :3]
    assert tuple(corner) == view.background  # outside the box: the background colour


def test_empty_volume_shows_only_the_background(gl, renderer):
    view = VolumeView(background=(10, 20, 30), camera=OrbitCamera(yaw=0, pitch=0), axis="x", index=0)
    image = render(gl, renderer, Volume.new(8, 8, 8).voxels, view)
    background = np.all(image[..., :3] == (10, 20, 30), axis=2)
    assert background[:, 48:].all()  # the right half has no voxel and no plane
    assert background.mean() > 0.9  # the left: only the edited slice's faint plane, seen nearly edge-on


def test_picker_highlight_tints_the_slice(gl, renderer):
    vol = Volume.new(16, 16, 16).voxels
    plain = render(gl, renderer, vol, VolumeView(camera=OrbitCamera(yaw=30, pitch=20)))
    lit = render(gl, renderer, vol, VolumeView(camera=OrbitCamera(yaw=30, pitch=20), highlight=("x", 8)))
    changed = np.any(plain != lit, axis=2)
    assert 200 < changed.sum() < 96 * 96 // 2


def test_first_hit_finds_the_first_opaque_voxel():
    vol = Volume.new(8, 8, 8)
    vol.paint.set_voxel(3, 4, 5, (255, 255, 255, 255))
    cam = OrbitCamera(yaw=0, pitch=0, distance=5.2)
    origin = cam.position()
    target = np.array([(3.5 / 8) * 2 - 1, -((4.5 / 8) * 2 - 1), -((5.5 / 8) * 2 - 1)])  # voxel centre, world
    direction = (target - origin) / np.linalg.norm(target - origin)
    assert first_hit(vol.voxels, origin, direction) == (3, 4, 5)
    assert first_hit(vol.voxels, origin, np.array([0.0, 1.0, 0.0])) is None  # straight up misses the box
    assert first_hit(Volume.new(8, 8, 8).voxels, origin, -origin / 5.2)[2] == 0  # empty: where the ray enters


def test_paint_bench_sub_box_uploads_a_fraction_of_the_full_volume(gl):
    tech = paint.technique()
    tech.scenes = {"32^3": 32}
    for m in tech.methods:
        m.values = (1,)
    rows = harness.run(gl, tech, runs=3)
    assert all(r.max_abs_error == 0 for r in rows)  # the GPU holds exactly the model's voxels
    uploaded = {}
    for method in tech.methods:  # the work each method does for one stroke, counted, not timed
        state = method.setup(gl)
        state.prepare(32)
        before = state.texture.uploaded_voxels
        state.stroke(1)
        uploaded[method.name] = state.texture.uploaded_voxels - before
    assert uploaded["full"] == 32 ** 3
    assert 0 < uploaded["subbox"] <= 6 * 4  # the stroke's box: 6 x 4 voxels of one slice
