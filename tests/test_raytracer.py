"""The ray tracer's modes on the GPU (headless) against the CPU reference, and its failure cases."""
import numpy as np
import pytest

from app.gl.core.headless import OffscreenTarget
from app.gl.volume.raytracer import RayTracer, TraceSettings
from app.gl.core.shaders import ShaderLibrary
from app.model.camera3d import OrbitCamera
from app.model.volume.render_modes import MODES
from app.model.volume.volume import Volume
from app.model.volume.voxels import Voxels
from app.model.volume.samples import coords3d, cornell_box
from app.model.volume.view import VolumeView
from app.reference.volume import Scene, render as reference
from app.resources import SHADERS

SIZE = (48, 48)


@pytest.fixture(scope="module")
def tracer(gl):
    return RayTracer(gl, ShaderLibrary(gl, [SHADERS]))


def gpu(gl, tracer, data, view, size=SIZE, **settings):
    target = OffscreenTarget(gl, size, samples=0)
    tracer.render(target.fbo, Voxels(data), view, TraceSettings(slice_planes=False, **settings))
    image = target.read()[..., :3] / 255.0
    target.release()
    return image


def cpu(data, view, mode, size=SIZE, steps=1024, **kw):
    return reference(data, view.camera, size, MODES[mode], steps=steps,
                     background=np.array(view.background) / 255.0, **kw)


VIEW = VolumeView(camera=OrbitCamera(yaw=20, pitch=15, distance=5.2))


@pytest.mark.parametrize("mode", sorted(MODES))
def test_every_mode_matches_the_reference(gl, tracer, mode):
    data = cornell_box(24)
    image = gpu(gl, tracer, data, VIEW, mode=mode, steps=128)
    err = np.abs(image - cpu(data, VIEW, mode))
    assert np.isfinite(image).all()
    assert np.sqrt((err ** 2).mean()) < 0.02  # silhouettes differ by a step; the rest agrees
    assert np.percentile(err, 95) < 0.02


def test_two_pass_and_one_pass_agree(gl, tracer):
    data = cornell_box(24)
    for two, one in ((1, 4), (2, 9), (3, 5)):
        if MODES[one].dual:
            continue
        a = gpu(gl, tracer, data, VIEW, mode=two)
        b = gpu(gl, tracer, data, VIEW, mode=one)
        assert np.abs(a - b).max() <= 2 / 255


def test_camera_inside_the_volume(gl, tracer):
    inside = VolumeView(camera=OrbitCamera(yaw=0, pitch=0, distance=0.5))
    data = cornell_box(24)
    for mode in (3, 5):  # the two-pass setup falls back to the eye as the entry
        image = gpu(gl, tracer, data, inside, mode=mode)
        err = np.abs(image - cpu(data, inside, 5))
        assert np.isfinite(image).all() and np.sqrt((err ** 2).mean()) < 0.03


def test_rays_parallel_to_box_faces(gl, tracer):
    straight = VolumeView(camera=OrbitCamera(yaw=0, pitch=0, distance=5.2))
    image = gpu(gl, tracer, coords3d(16), straight, mode=2)
    err = np.abs(image - cpu(coords3d(16), straight, 2))
    assert np.isfinite(image).all() and np.percentile(err, 95) < 0.02


@pytest.mark.parametrize("shape", [(1, 1, 1), (256, 32, 8), (8, 8, 8)])
def test_odd_shapes_empty_and_full_volumes_stay_finite(gl, tracer, shape):
    w, h, d = shape
    for data in (np.zeros((d, h, w, 4), np.uint8), np.full((d, h, w, 4), 255, np.uint8)):
        for mode in sorted(MODES):
            image = gpu(gl, tracer, data, VIEW, size=(24, 24), mode=mode)
            assert np.isfinite(image).all()
    empty = gpu(gl, tracer, np.zeros((d, h, w, 4), np.uint8), VIEW, size=(24, 24), mode=5)
    assert np.allclose(empty, np.array(VIEW.background) / 255.0, atol=1 / 255)


def test_too_few_steps_is_measurably_worse(gl, tracer):
    """The seed's defect: too few ray steps miss thin walls; the error falls as cl_steps grows."""
    data = cornell_box(32)
    truth = cpu(data, VIEW, 2)
    errors = [np.sqrt(((gpu(gl, tracer, data, VIEW, mode=2, steps=s) - truth) ** 2).mean()) for s in (4, 16, 128)]
    assert errors[0] > errors[1] > errors[2]
    assert errors[0] > 0.05 and errors[2] < 0.02


def test_constant_shadow_steps_err_where_correct_ones_do_not(gl, tracer):
    """The seed's constant 20 (or 50) shadow steps skip thin occluders on long shadow rays."""
    data = cornell_box(32)
    truth = cpu(data, VIEW, 8, steps=1024)
    few = np.sqrt(((gpu(gl, tracer, data, VIEW, mode=5, shadow_steps=3) - truth) ** 2).mean())
    correct = np.sqrt(((gpu(gl, tracer, data, VIEW, mode=8, steps=256) - truth) ** 2).mean())
    assert correct < few


def test_distance_skipping_takes_fewer_samples(gl, tracer):
    data = cornell_box(64)
    into = VolumeView(camera=OrbitCamera(yaw=0, pitch=0, distance=3.2))  # through the open front
    target = OffscreenTarget(gl, SIZE, samples=0)
    fbo = gl.framebuffer([gl.renderbuffer(SIZE, 4, dtype="f4")])
    counts = {}
    for mode in (5, 7):
        tracer.render(fbo, Voxels(data), into, TraceSettings(mode=mode, debug_samples=True, slice_planes=False))
        counts[mode] = np.frombuffer(fbo.read(components=4, dtype="f4"), "f4")[0::4].mean()
    target.release()
    assert counts[7] < 0.8 * counts[5]
    plain = gpu(gl, tracer, data, into, mode=5)
    skipped = gpu(gl, tracer, data, into, mode=7)
    assert np.abs(plain - skipped).max() <= 1 / 255 + 1e-9


def test_distance_texture_clamps_after_an_edit_and_refines_when_idle(gl, tracer):
    from app.gl.volume.raytracer import DistanceTexture, distance_field

    volume = Volume(cornell_box(32))
    texture = DistanceTexture(gl)
    texture.sync(volume.voxels)
    volume.paint.stroke("z", 16, 3, (255, 0, 0, 255), [(10, 10), (20, 12)])
    texture.sync(volume.voxels)
    exact = distance_field(volume.voxels.data)
    gpu_field = np.frombuffer(texture.texture.read(), "f4").reshape(exact.shape)
    assert texture.stale and (gpu_field <= exact + 1e-4).all()  # never more than the truth: skipping stays safe
    assert (gpu_field[16, 11, 10:20] == 0).all()
    volume.history.undo()  # erasing: the clamped field stays small, which is slower but still safe
    texture.sync(volume.voxels)
    assert texture.refine() and not texture.stale
    np.testing.assert_allclose(np.frombuffer(texture.texture.read(), "f4").reshape(exact.shape),
                               distance_field(volume.voxels.data))


def rmse(a, b):
    return float(np.sqrt(((a - b) ** 2).mean()))


def test_shadow_offset_near_the_surface(gl, tracer):
    """The seed's defect: starting shadow rays on the surface shadows the surface itself (acne)."""
    data = cornell_box(32)
    truth = cpu(data, VIEW, 5)
    on_surface = rmse(gpu(gl, tracer, data, VIEW, mode=5, shadow_offset=0.0), truth)
    offset = rmse(gpu(gl, tracer, data, VIEW, mode=5), truth)
    assert on_surface > 2 * offset


def test_too_large_distance_multiplier_skips_surfaces(gl, tracer):
    """The seed's defect: a distance multiplier over 1 steps past thin walls the distance texture allowed for."""
    data = cornell_box(48)
    into = VolumeView(camera=OrbitCamera(yaw=15, pitch=10, distance=3.2))
    truth = cpu(data, into, 7)
    safe = rmse(gpu(gl, tracer, data, into, mode=7, distance_scale=1.0), truth)
    reckless = rmse(gpu(gl, tracer, data, into, mode=7, distance_scale=6.0), truth)
    assert reckless > safe + 0.01


def test_stereo_magnify_and_wireframe(gl, tracer):
    data = coords3d(16)
    plain = gpu(gl, tracer, data, VIEW, mode=2)
    left_right = gpu(gl, tracer, data, VolumeView(camera=VIEW.camera, stereo=True), mode=2)
    assert np.isfinite(left_right).all() and not np.array_equal(plain, left_right)
    near = gpu(gl, tracer, data, VolumeView(camera=VIEW.camera, magnify=True), mode=2)
    bg = np.array(VIEW.background) / 255
    covered = lambda img: (np.abs(img - bg).sum(-1) > 0.02).mean()  # noqa: E731
    assert covered(near) > 2 * covered(plain)
    edges = gpu(gl, tracer, data, VolumeView(camera=VIEW.camera, wireframe=True), mode=2)
    assert (np.abs(edges - plain).sum(-1) > 0.1).sum() > 50


def test_non_cube_two_pass_matches_one_pass(gl, tracer):
    data = np.ascontiguousarray(coords3d(16)[:8])  # 16 x 16 x 8: the box is not a cube
    data[..., 3] = 90  # translucent, so every ray's whole length counts
    two = gpu(gl, tracer, data, VIEW, mode=1)
    one = gpu(gl, tracer, data, VIEW, mode=4)
    assert np.abs(two - one).max() <= 2 / 255
    assert rmse(one, cpu(data, VIEW, 4)) < 0.01


ORANGE = (255, 140, 40, 255)
LIT = [m for m in sorted(MODES) if MODES[m].kind == "phong"]  # F3, F5-F8, F10, F11


def thin(kind: str, z: int) -> np.ndarray:
    """One orange voxel, or a 1-voxel line across x, on slice z of an empty 8^3 volume."""
    data = np.zeros((8, 8, 8, 4), np.uint8)
    data[z, 4, 4 if kind == "voxel" else slice(1, 7)] = ORANGE
    return data


@pytest.mark.parametrize("z", [4, 0], ids=["inside", "on the box's face"])
@pytest.mark.parametrize("kind", ["voxel", "line"])
def test_a_lone_voxel_and_a_thin_line_are_lit_in_every_lit_mode(gl, tracer, kind, z):
    """Issue 25: a 1-voxel orange stroke came out near-black in the Phong modes. The filtered sample at the surface
    mixes in the empty neighbours' transparent black (42 % of the colour, 42 % opaque), and on the box's face the
    gradient, clamped to the edge, pointed into the volume: N.L < 0 and the voxel shadowed itself."""
    data = thin(kind, z)
    view = VolumeView(camera=OrbitCamera(yaw=25, pitch=18, distance=3.0))
    covered = np.abs(cpu(data, view, 2) - np.array(view.background) / 255).sum(-1) > 0.02
    assert covered.sum() >= (20 if kind == "voxel" else 80)
    colour = np.array(ORANGE[:3]) / 255
    for mode in LIT:
        image, truth = gpu(gl, tracer, data, view, mode=mode), cpu(data, view, mode)
        lit = image[covered].mean(0)
        assert lit.sum() > 0.45 * colour.sum(), (mode, lit)  # F11 mixes in a quarter of the background
        assert lit[0] > lit[1] > lit[2], (mode, lit)  # still orange
        err = np.abs(image - truth)
        assert rmse(image, truth) < 0.02 and np.percentile(err, 95) < 0.02, mode
        assert np.abs(image[covered] - truth[covered]).mean() < 0.03, mode


def test_the_reference_surface_takes_the_colour_of_its_voxels_not_their_empty_neighbours():
    scene = Scene(thin("voxel", 0))
    centre = (np.array([4, 4, 0]) + 0.5) / 8  # texture space (x, y, z)
    near = centre + np.array([[0.0, 0.0, 0.0], [0.07, 0.0, 0.0], [0.0, -0.07, 0.07], [0.0, 0.0, -0.0625]])
    assert np.allclose(scene.material(near), np.array(ORANGE) / 255)  # the last point lies on the box's face
    assert scene.sample(near)[1, 3] < 0.5  # the filtered sample there is half transparent black
    assert np.allclose(scene.material(np.array([[0.9, 0.9, 0.9]])), 0.0)  # nothing near: nothing
