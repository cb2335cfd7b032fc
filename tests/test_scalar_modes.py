"""A scalar volume's render modes (r_scalarMode) on the GPU, headless, against the CPU reference; the values on the
GPU in data units for every scalar type; what is uploaded; and the failure cases (NaN, infinities, odd shapes, the
camera inside)."""
import numpy as np
import pytest

from app.gl.core.headless import OffscreenTarget
from app.gl.core.shaders import ShaderLibrary
from app.gl.volume.raytracer import RayTracer
from app.model.camera3d import OrbitCamera
from app.model.volume.phantom import ct_phantom
from app.model.volume.render_modes import TraceSettings
from app.model.volume.scalar_modes import SCALAR_MODES, brick_maxima, clear_below, opacity_table
from app.model.volume.scalars import TransferFunction
from app.model.volume.view import VolumeView
from app.model.volume.volume import Volume
from app.reference.volume_scalar import render as reference
from app.resources import SHADERS

SIZE = (48, 48)
VIEW = VolumeView(camera=OrbitCamera(yaw=20, pitch=15, distance=4.6))
WINDOW = TransferFunction(-200.0, 1200.0, "bone")
WINDOWS = {"minip": TransferFunction(-3100.0, -900.0), "average": TransferFunction(-1100.0, 100.0)}  # air, tissue
ISO = 300.0
MODES = SCALAR_MODES[1:]


@pytest.fixture(scope="module")
def tracer(gl):
    return RayTracer(gl, ShaderLibrary(gl, [SHADERS]))


@pytest.fixture(scope="module")
def phantom():
    return ct_phantom(24)


def scalar_volume(values, transfer=WINDOW, spacing=(1.0, 1.0, 1.0)) -> Volume:
    volume = Volume.new(1, 1, 1)
    volume.replace_scalars(values, transfer, spacing=spacing)
    return volume


def gpu(gl, tracer, volume, scalar, view=VIEW, size=SIZE, steps=128, **settings):
    """The picture in scalar mode `scalar`; `settings` more of TraceSettings (the F-mode, shadows, lights...)."""
    target = OffscreenTarget(gl, size, samples=0)
    settings = {"iso": ISO, "slice_planes": False, **settings}
    tracer.render(target.fbo, volume.voxels, view, TraceSettings(scalar_mode=scalar, steps=steps, **settings))
    image = target.read()[..., :3] / 255.0
    target.release()
    return image


def cpu(values, scalar, view=VIEW, size=SIZE, steps=128, transfer=WINDOW, **kw):
    return reference(values, transfer, view.camera, size, scalar, steps, **{"iso": ISO, **kw},
                     background=np.array(view.background) / 255.0)


def rmse(a, b) -> float:
    return float(np.sqrt(((a - b) ** 2).mean()))


@pytest.mark.parametrize("mode", MODES)
def test_every_scalar_mode_matches_its_reference(gl, tracer, phantom, mode):
    window = WINDOWS.get(mode, WINDOW)
    image = gpu(gl, tracer, scalar_volume(phantom, window), mode)
    truth = cpu(phantom, mode, transfer=window)
    assert rmse(image, truth) < 0.006
    assert np.percentile(np.abs(image - truth), 99) < 0.02  # the same samples: only rounding differs
    assert np.abs(image - np.array(VIEW.background) / 255.0).max() > 0.2  # and it drew something


def test_the_reference_converges_where_the_gpu_takes_fewer_steps(gl, tracer, phantom):
    fine = cpu(phantom, "mip", steps=1024)
    coarse, finer = (rmse(gpu(gl, tracer, scalar_volume(phantom), "mip", steps=s), fine) for s in (16, 128))
    assert finer < coarse and finer < 0.02


@pytest.mark.parametrize("dtype", ["int16", "uint16", "int8", "float32", "float64", "int32", "uint32"])
def test_every_scalar_type_is_read_in_data_units(gl, tracer, dtype):
    values = np.linspace(0, 100, 8 * 8 * 8).reshape(8, 8, 8).round()
    values = values - 50 if np.dtype(dtype).kind in "if" else values  # signed types hold negative values
    volume = scalar_volume(values.astype(dtype), TransferFunction(float(values.min()), float(values.max())))
    image = gpu(gl, tracer, volume, "mip", size=(24, 24))
    truth = cpu(values.astype(dtype), "mip", size=(24, 24), transfer=volume.voxels.scalars.transfer)
    assert rmse(image, truth) < 0.006


def test_a_window_change_uploads_the_colours_alone_and_the_rgba_texture_waits(gl, tracer, phantom):
    volume = scalar_volume(phantom)
    tracer.scalars.uploaded_voxels = tracer.volume.uploaded_voxels = 0
    before = gpu(gl, tracer, volume, "mip")
    assert tracer.scalars.uploaded_voxels == phantom.size
    volume.set_transfer(TransferFunction(-1000.0, 400.0, "hot"))
    after = gpu(gl, tracer, volume, "mip")
    assert tracer.scalars.uploaded_voxels == phantom.size  # the values stay on the GPU
    assert tracer.volume.uploaded_voxels == 0  # the colours go up only when the F-modes draw them
    assert rmse(after, cpu(phantom, "mip", transfer=volume.voxels.scalars.transfer)) < 0.006
    assert rmse(before, after) > 0.05


def test_colour_mode_and_a_volume_without_scalars_draw_the_f_modes(gl, tracer, phantom):
    volume = scalar_volume(phantom)
    f5 = gpu(gl, tracer, volume, "colour", mode=5)
    assert rmse(f5, gpu(gl, tracer, volume, "mip", mode=5)) > 0.02
    rgba = Volume(volume.voxels.data.copy())  # the same colours, no scalars
    for scalar in MODES:
        assert np.array_equal(gpu(gl, tracer, rgba, scalar, mode=5), f5)


def test_iso_is_lit_as_f5_its_shadow_and_light_follow_the_settings(gl, tracer, phantom):
    volume = scalar_volume(phantom)
    lit = gpu(gl, tracer, volume, "iso")
    unshadowed = gpu(gl, tracer, volume, "iso", shadows=False)
    assert rmse(unshadowed, cpu(phantom, "iso", shadows=False)) < 0.006
    assert rmse(lit, unshadowed) > 0.001  # the ribs shadow the spine
    moved = gpu(gl, tracer, volume, "iso", lights=((-2.5, 1.5, 1.5),))
    assert rmse(moved, cpu(phantom, "iso", lights=((-2.5, 1.5, 1.5),))) < 0.006


def test_iso_below_every_value_draws_the_box_and_above_them_nothing(gl, tracer, phantom):
    volume = scalar_volume(phantom)
    background = np.array(VIEW.background) / 255.0
    above = gpu(gl, tracer, volume, "iso", iso=5000.0)
    assert np.abs(above - background).max() < 1 / 255
    below = gpu(gl, tracer, volume, "iso", iso=-5000.0)
    assert rmse(below, cpu(phantom, "iso", iso=-5000.0)) < 0.01


@pytest.mark.parametrize("mode", MODES)
def test_nan_and_infinities_draw_finite_pictures_as_the_reference(gl, tracer, phantom, mode):
    values = phantom.astype(np.float32)
    values[10:14, 8:16, 8:16] = np.nan
    values[3, 3, 3], values[20, 20, 20], values[12, 12, 4] = np.inf, -np.inf, np.inf
    image = gpu(gl, tracer, scalar_volume(values), mode)
    assert np.isfinite(image).all()
    assert rmse(image, cpu(values, mode)) < 0.01


@pytest.mark.parametrize("shape", [(1, 1, 1), (8, 32, 256), (2, 9, 5)])
def test_odd_shapes_stay_finite_and_match(gl, tracer, shape):
    rng = np.random.default_rng(3)
    values = rng.integers(-1000, 1500, shape).astype(np.int16)
    volume = scalar_volume(values)
    for mode in MODES:
        image = gpu(gl, tracer, volume, mode, size=(24, 24))
        assert np.isfinite(image).all()
        assert rmse(image, cpu(values, mode, size=(24, 24))) < 0.02, mode


def test_the_camera_inside_the_volume(gl, tracer, phantom):
    inside = VolumeView(camera=OrbitCamera(yaw=10, pitch=5, distance=0.5))
    volume = scalar_volume(phantom)
    for mode in ("mip", "translucent", "iso"):
        image = gpu(gl, tracer, volume, mode, view=inside)
        assert rmse(image, cpu(phantom, mode, view=inside)) < 0.01, mode


def test_each_brick_holds_the_greatest_value_a_sample_in_it_reads():
    rng = np.random.default_rng(5)
    for values in (rng.integers(-1000, 1000, (19, 13, 21)).astype(np.int16), rng.normal(size=(9, 17, 4))):
        values[0, 0, 0] = np.nan if values.dtype.kind == "f" else values[0, 0, 0]
        maxima = brick_maxima(values, 4)
        drawn = np.nan_to_num(values, nan=np.nanmin(values))
        d, h, w = values.shape
        for z, y, x in np.ndindex(*maxima.shape):
            rim = drawn[max(0, 4 * z - 1):4 * z + 5, max(0, 4 * y - 1):4 * y + 5, max(0, 4 * x - 1):4 * x + 5]
            assert maxima[z, y, x] == np.float32(rim.max())


def test_iso_skips_bricks_yet_finds_a_lone_voxel(gl, tracer):
    values = np.full((40, 40, 40), -1000, np.int16)
    values[21, 17, 22] = 2000  # one voxel: every brick but its own and its rim's skipped
    near, white = VolumeView(camera=OrbitCamera(0, 0, 1.5)), TransferFunction(-1000.0, 0.0)  # the iso value white
    image = gpu(gl, tracer, scalar_volume(values, white), "iso", iso=0.0, view=near)
    assert rmse(image, cpu(values, "iso", iso=0.0, view=near, transfer=white)) < 0.006
    assert (np.abs(image - np.array(VIEW.background) / 255.0).max(-1) > 0.2).sum() >= 2  # a third of a voxel across


def test_translucent_skips_only_what_the_opacity_table_reads_as_clear():
    first, last, table = opacity_table(WINDOW.opacity())
    assert clear_below(first, last, table) == WINDOW.low  # the ramp: clear up to the window's low
    curve = ((0.0, 0.0), (10.0, 0.0), (10.01, 0.5), (20.0, 1.0))  # clear, then a step between two table entries
    first, last, table = opacity_table(curve)
    clear = clear_below(first, last, table)
    at = lambda v: np.interp((v - first) / (last - first) * (len(table) - 1), np.arange(len(table)), table)  # noqa
    assert at(clear) == 0.0 and at(clear + (last - first) / len(table)) > 0.0 and clear <= 10.0
    assert clear_below(*opacity_table(((0.0, 0.1), (1.0, 1.0)))) < -1e38  # opaque from the start: nothing skipped
    assert clear_below(*opacity_table(((0.0, 0.0), (1.0, 0.0)))) > 1e38   # clear throughout


def test_translucent_draws_what_lies_past_a_clear_stretch(gl, tracer):
    values = np.full((48, 24, 24), -1000, np.int16)  # air, clear through the window, around one bright slab
    values[30:34] = 1000
    side = VolumeView(camera=OrbitCamera(yaw=0, pitch=0, distance=3.0))
    image = gpu(gl, tracer, scalar_volume(values), "translucent", view=side)
    assert rmse(image, cpu(values, "translucent", view=side)) < 0.006
    assert image.max() > 0.3


def test_the_painters_slice_shows_in_every_mode_where_nothing_hides_it(gl, tracer, phantom):
    volume = scalar_volume(phantom)
    view = VolumeView(camera=VIEW.camera, axis="x", index=12, highlight=("y", 12))
    for mode in MODES:
        plain = gpu(gl, tracer, volume, mode, view=view, iso=5000.0)  # iso: a surface nowhere, every ray through
        planes = gpu(gl, tracer, volume, mode, view=view, iso=5000.0, slice_planes=True)
        assert (np.abs(planes - plain).max(-1) > 0.02).sum() > 100, mode


@pytest.mark.parametrize("mode", MODES)
def test_spaced_voxels_take_the_box_and_steps_of_their_physical_size(gl, tracer, phantom, mode):
    spacing = (0.8, 0.8, 2.5)  # a CT's thick slices: the box deeper than wide
    window = WINDOWS.get(mode, WINDOW)
    image = gpu(gl, tracer, scalar_volume(phantom, window, spacing), mode)
    truth = cpu(phantom, mode, transfer=window, spacing=spacing)
    assert rmse(image, truth) < 0.006
    assert rmse(image, cpu(phantom, mode, transfer=window)) > 0.01  # not the cube it would be at 1 1 1
