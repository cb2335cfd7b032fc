"""A scan's labels in the 3D view (headless GL): every mode, the scalar modes too, draws them as the CPU reference
does, a scan with no label draws as before, and the label texture follows the labels a sub-box at a time."""
import numpy as np
import pytest

from app.gl.core.headless import OffscreenTarget
from app.gl.core.shaders import ShaderLibrary
from app.gl.volume.raytracer import RayTracer, TraceSettings
from app.model.camera3d import OrbitCamera
from app.model.volume.render_modes import MODES
from app.model.volume.scalar_modes import SCALAR_MODES
from app.model.volume.scalars import TransferFunction
from app.model.volume.view import VolumeView
from app.model.volume.volume import Volume
from app.reference.volume import render as reference
from app.reference.volume_labels import LabelLayer
from app.reference.volume_scalar import render as scalar_reference
from app.resources import SHADERS

SIZE = (48, 48)
VIEW = VolumeView(camera=OrbitCamera(yaw=30, pitch=20, distance=4.0))


@pytest.fixture(scope="module")
def tracer(gl):
    return RayTracer(gl, ShaderLibrary(gl, [SHADERS]))


def blob_scan() -> Volume:
    """A bright ball in a 16 x 20 x 24 int16 scan, with two labels painted across it and beyond it."""
    z, y, x = np.mgrid[0:24, 0:20, 0:16]
    vol = Volume.new(2, 2, 2)
    vol.replace_scalars((1000 * np.exp(-((x - 8) ** 2 + (y - 10) ** 2 + (z - 12) ** 2) / 40.0)).astype(np.int16))
    vol.paint.stroke_label("z", 12, 5, 1, [(3, 3), (12, 15)])
    vol.paint.stroke_label("x", 8, 3, 4, [(2, 2), (18, 20)])
    return vol


def gpu(gl, tracer, vol, view=VIEW, **settings) -> np.ndarray:
    target = OffscreenTarget(gl, SIZE, samples=0)
    tracer.render(target.fbo, vol.voxels, view, TraceSettings(slice_planes=False, **settings))
    image = target.read()[..., :3] / 255.0
    target.release()
    return image


def cpu(vol, mode, opacity, view=VIEW) -> np.ndarray:
    labels = vol.voxels.labels
    layer = None if labels.data is None else LabelLayer(labels.data, labels.colours, opacity)
    return reference(vol.voxels.data, view.camera, SIZE, MODES[mode], steps=512,
                     background=np.array(view.background) / 255.0, labels=layer)


@pytest.mark.parametrize("mode", sorted(MODES))
def test_labels_over_every_mode_match_the_reference(gl, tracer, mode):
    vol = blob_scan()
    image = gpu(gl, tracer, vol, mode=mode, steps=128, label_opacity=0.7)
    expected = cpu(vol, mode, 0.7)
    unlabelled = cpu(vol, mode, 0.0)
    assert (np.abs(expected - unlabelled).max(-1) > 0.1).mean() > 0.02  # the labels show in every mode
    err = np.abs(image - expected).max(-1)
    assert np.sqrt((err ** 2).mean()) < 0.02 and np.percentile(err, 95) < 0.03


@pytest.mark.parametrize("scalar", SCALAR_MODES[1:])
def test_labels_over_every_scalar_mode_match_the_reference(gl, tracer, scalar):
    """Over the values' modes (r_scalarMode) as over the F-modes: in front of iso's surface, along the whole ray in
    the others."""
    vol = blob_scan()
    vol.set_transfer(TransferFunction(0.0, 1000.0, "bone"))
    image = gpu(gl, tracer, vol, scalar_mode=scalar, iso=400.0, steps=128, label_opacity=0.7)
    scalars, labels = vol.voxels.scalars, vol.voxels.labels

    def cpu_scalar(opacity: float) -> np.ndarray:
        return scalar_reference(scalars.values, scalars.transfer, VIEW.camera, SIZE, scalar, 128, iso=400.0,
                                background=np.array(VIEW.background) / 255.0,
                                labels=LabelLayer(labels.data, labels.colours, opacity))

    expected, unlabelled = cpu_scalar(0.7), cpu_scalar(0.0)
    assert (np.abs(expected - unlabelled).max(-1) > 0.1).mean() > 0.02  # the labels show in every mode
    err = np.abs(image - expected).max(-1)
    assert np.sqrt((err ** 2).mean()) < 0.02 and np.percentile(err, 95) < 0.03


def test_the_label_opacity_lays_them_over_in_proportion_and_0_hides_them(gl, tracer):
    vol = blob_scan()
    plain = gpu(gl, tracer, vol, mode=4, label_opacity=0.0)
    half, full = gpu(gl, tracer, vol, mode=4, label_opacity=0.5), gpu(gl, tracer, vol, mode=4, label_opacity=1.0)
    labelled = np.abs(full - plain).max(-1) > 0.1
    assert labelled.mean() > 0.02
    np.testing.assert_allclose(half[labelled], 0.5 * (plain + full)[labelled], atol=2.5 / 255)


def test_a_scan_with_no_label_draws_as_before_labels(gl, tracer):
    vol = blob_scan()
    while vol.voxels.labels.data is not None:
        vol.history.undo()
    no_labels = gpu(gl, tracer, vol, mode=5)
    before = Volume(vol.voxels.data)  # the same colours as an RGBA volume: the tracer as it was
    np.testing.assert_array_equal(no_labels, gpu(gl, tracer, before, mode=5))


def test_the_label_texture_uploads_the_changed_sub_box_and_follows_undo(gl, tracer):
    vol = blob_scan()
    gpu(gl, tracer, vol, mode=4)
    texture = tracer.labels
    read = lambda: np.frombuffer(texture.texture.read(), np.uint8).reshape(vol.voxels.labels.data.shape)  # noqa: E731
    np.testing.assert_array_equal(read(), vol.voxels.labels.data)
    texture.uploaded_voxels = 0
    box = vol.paint.stroke_label("y", 4, 1, 9, [(1, 1), (5, 1)])
    gpu(gl, tracer, vol, mode=4)
    assert texture.uploaded_voxels == box.shape[0] * box.shape[1] * box.shape[2] == 5
    np.testing.assert_array_equal(read(), vol.voxels.labels.data)
    vol.set_label_colour(9, (1, 2, 3))
    gpu(gl, tracer, vol, mode=4)
    assert texture.uploaded_voxels == 5  # a colour is the table's alone
    assert tuple(np.frombuffer(texture.colours.read(), np.uint8).reshape(256, 4)[9, :3]) == (1, 2, 3)
    while vol.voxels.labels.data is not None:
        vol.history.undo()
    gpu(gl, tracer, vol, mode=4)
    assert texture.texture is None  # none painted: none held on the GPU either
