"""The translucent mode follows the opacity curve (`vol.opacity`, a preset) on the GPU as in the CPU reference: a value
range the curve hides leaves no trace, a curve change uploads the curve alone, and each preset draws as its
reference does."""
import numpy as np
import pytest

from app.model.volume.phantom import ct_phantom
from app.model.volume.scalars import TransferFunction
from app.model.volume.transfer_presets import PRESETS
from tests.test_scalar_modes import VIEW, cpu, gpu, rmse, scalar_volume, tracer  # noqa: F401 (a fixture)

# clear over 400..600: soft tissue at 500 hides; a faint haze below 300 and the bone above 700 show
HIDING = ((300.0, 0.05), (400.0, 0.0), (600.0, 0.0), (700.0, 0.6), (1200.0, 0.9))
TISSUE, BONE, AROUND = 500, 1000, 450  # the hidden cube, the shown one, what surrounds both (hidden too)


def cubes(with_tissue: bool) -> np.ndarray:
    values = np.full((24, 24, 24), AROUND, np.int16)
    values[4:12, 6:18, 4:12] = BONE
    if with_tissue:
        values[10:20, 8:20, 14:22] = TISSUE  # two voxels from the bone: samples at its edges read 450..500, hidden
    return values


def test_a_value_range_the_curve_hides_leaves_no_trace(gl, tracer):  # noqa: F811
    transfer = TransferFunction(0.0, 1200.0, "bone", HIDING)
    shown, hidden = cubes(with_tissue=True), cubes(with_tissue=False)
    image = gpu(gl, tracer, scalar_volume(shown, transfer), "translucent")
    assert np.array_equal(image, gpu(gl, tracer, scalar_volume(hidden, transfer), "translucent"))
    truth = cpu(shown, "translucent", transfer=transfer)
    assert rmse(image, truth) < 0.006
    assert np.array_equal(truth, cpu(hidden, "translucent", transfer=transfer))  # no trace in the reference either
    assert np.abs(image - np.array(VIEW.background) / 255.0).max() > 0.2  # the bone shows
    # a curve clear only where the surroundings are shows the tissue
    showing = TransferFunction(0.0, 1200.0, "bone", ((470.0, 0.0), (500.0, 0.5), (700.0, 0.6), (1200.0, 0.9)))
    assert rmse(gpu(gl, tracer, scalar_volume(shown, showing), "translucent"),
                gpu(gl, tracer, scalar_volume(hidden, showing), "translucent")) > 0.01


def test_a_curve_change_uploads_the_curve_alone_and_colours_nothing(gl, tracer):  # noqa: F811
    values = ct_phantom(24)
    volume = scalar_volume(values, TransferFunction(-200.0, 1200.0, "bone"))
    before = gpu(gl, tracer, volume, "translucent")
    tracer.scalars.uploaded_voxels = tracer.volume.uploaded_voxels = 0
    version, colours = volume.voxels.version, volume.voxels.data.copy()
    assert volume.set_transfer(TransferFunction(-200.0, 1200.0, "bone", ((150.0, 0.0), (700.0, 0.3))), "Set Opacity")
    after = gpu(gl, tracer, volume, "translucent")
    assert volume.voxels.version == version and np.array_equal(volume.voxels.data, colours)
    assert tracer.scalars.uploaded_voxels == 0 and tracer.volume.uploaded_voxels == 0
    assert rmse(after, cpu(values, "translucent", transfer=volume.voxels.scalars.transfer)) < 0.006
    assert rmse(before, after) > 0.02


@pytest.mark.parametrize("name", PRESETS)
def test_each_preset_draws_as_its_reference(gl, tracer, name):  # noqa: F811
    values = ct_phantom(24)
    if PRESETS[name].relative:  # an MRI: no air below 0, a head of a few hundred units
        values = np.clip(values + 1000, 0, None).astype(np.int16)
    transfer = PRESETS[name].transfer(values)
    image = gpu(gl, tracer, scalar_volume(values, transfer), "translucent")
    assert rmse(image, cpu(values, "translucent", transfer=transfer)) < 0.006
    assert np.abs(image - np.array(VIEW.background) / 255.0).max() > 0.1  # it shows something of the phantom


@pytest.mark.parametrize("mode", ["mip", "minip", "average", "iso"])
def test_the_projections_and_iso_take_a_presets_colour_map(gl, tracer, mode):  # noqa: F811
    values = ct_phantom(24)
    low, high = (-3100.0, -900.0) if mode == "minip" else (-1100.0, 1200.0)  # minip: the air's range
    transfer = TransferFunction(low, high, "ct_bone", PRESETS["ct_bone"].points)
    image = gpu(gl, tracer, scalar_volume(values, transfer), mode)
    assert rmse(image, cpu(values, mode, transfer=transfer)) < 0.006
    grey = gpu(gl, tracer, scalar_volume(values, TransferFunction(low, high, "grey")), mode)
    assert rmse(image, grey) > 0.01  # the colours are the map's
