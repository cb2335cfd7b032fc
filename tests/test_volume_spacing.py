"""Voxel spacing: read from the files that state it, `vol.spacing` to show or set it (an undo step), kept in NRRD
and in demos, and followed by the box (the ray tracer, its reference, the picker) and the painter, so a CT of
0.5 mm pixels and 2 mm slices is not squashed."""
from __future__ import annotations

import io

import nrrd
import numpy as np
import pytest
import tifffile

from app.console.demo import VirtualClock
from app.editor import Editor
from app.gl.core.headless import OffscreenTarget
from app.gl.core.shaders import ShaderLibrary
from app.gl.volume.raytracer import RayTracer, TraceSettings
from app.io.volume_formats import read_volume_file, write_volume
from app.model.camera3d import OrbitCamera
from app.model.volume.pick import first_hit
from app.model.volume.render_modes import MODES
from app.model.volume.view import VolumeView, box_extents, voxel_extent
from app.model.volume.volume import Volume
from app.model.volume.voxels import VolumeError, Voxels
from app.reference.volume import render as reference
from app.resources import SHADERS


def volume(editor):
    return editor.workspaces["volume"].volume


def errors(editor) -> list[str]:
    return [line.text for line in editor.console.log if line.level == "error"]


def said(editor) -> list[str]:
    return [line.text for line in editor.console.log]


# --- the model ----------------------------------------------------------------------------------------------------


def test_a_ct_box_takes_its_physical_shape():
    assert box_extents((512, 512, 300)) == (1.0, 1.0, 300 / 512)
    assert box_extents((512, 512, 300), (0.5, 0.5, 2.0)) == (256 / 600, 256 / 600, 1.0)
    assert voxel_extent((512, 512, 300)) == 2 / 512  # what the tracer's shadow offset used before spacing
    assert voxel_extent((512, 512, 300), (0.5, 0.5, 2.0)) == pytest.approx(2 * 0.5 / 600)


def test_spacing_is_an_undo_step_and_a_same_spacing_none():
    vol = Volume.new(4, 3, 2)
    digest = vol.voxels.digest()
    assert not vol.set_spacing((1, 1, 1)) and vol.history.undo_depth == 0
    assert vol.set_spacing((0.5, 0.5, 2)) and vol.voxels.spacing == (0.5, 0.5, 2.0)
    assert vol.voxels.digest() != digest and vol.history.undo_name() == "Set Spacing"
    version = vol.voxels.version
    vol.history.undo()
    assert vol.voxels.spacing == (1.0, 1.0, 1.0) and vol.voxels.digest() == digest
    assert vol.voxels.version == version  # no voxel changed: nothing is uploaded again
    vol.history.redo()
    assert vol.voxels.spacing == (0.5, 0.5, 2.0)


@pytest.mark.parametrize("bad", [(0, 1, 1), (1, -2, 1), (1, 1, float("nan")), (1, 1, float("inf")), (1e7, 1, 1)])
def test_a_spacing_out_of_range_is_refused_and_changes_nothing(bad):
    vol = Volume.new(2, 2, 2)
    with pytest.raises(VolumeError, match="each spacing must be within"):
        vol.set_spacing(bad)
    assert vol.voxels.spacing == (1.0, 1.0, 1.0) and vol.history.undo_depth == 0


@pytest.mark.parametrize("axis, turned", [("z", (2.0, 1.0, 3.0)), ("x", (1.0, 3.0, 2.0)), ("y", (3.0, 2.0, 1.0))])
def test_a_quarter_turn_turns_the_spacing_with_the_voxels(axis, turned):
    vol = Volume.new(5, 4, 3)
    vol.set_spacing((1, 2, 3))
    sides = [n * s for n, s in zip(vol.voxels.size, vol.voxels.spacing)]
    vol.rotate(axis)
    assert vol.voxels.spacing == turned
    assert sorted(n * s for n, s in zip(vol.voxels.size, vol.voxels.spacing)) == sorted(sides)  # the same box, turned
    vol.history.undo()
    assert vol.voxels.spacing == (1.0, 2.0, 3.0)


def test_replacing_the_volume_brings_its_spacing_and_undo_the_old_one():
    vol = Volume.new(2, 2, 2)
    vol.replace_scalars(np.zeros((3, 4, 5), np.int16), spacing=(0.7, 0.7, 2.5))
    assert vol.voxels.spacing == (0.7, 0.7, 2.5)
    vol.replace(np.zeros((2, 2, 2, 4), np.uint8))
    assert vol.voxels.spacing == (1.0, 1.0, 1.0)
    vol.history.undo()
    assert vol.voxels.spacing == (0.7, 0.7, 2.5)


# --- commands -----------------------------------------------------------------------------------------------------


def test_vol_spacing_shows_sets_and_undoes(volume_editor):
    editor = volume_editor
    assert editor.execute("new 8 4 2") and editor.execute("vol.spacing")
    assert said(editor)[-1] == "spacing 1 1 1: the volume is 8 x 4 x 2"
    assert editor.execute("vol.spacing 0.5 0.5 2")
    assert volume(editor).voxels.spacing == (0.5, 0.5, 2.0)
    editor.execute("vol.spacing")
    assert said(editor)[-1] == "spacing 0.5 0.5 2: the volume is 4 x 2 x 4"
    assert editor.execute("undo") and volume(editor).voxels.spacing == (1.0, 1.0, 1.0)


@pytest.mark.parametrize("line, message", [("vol.spacing 1 2", "three sides"), ("vol.spacing 0 1 1", "within"),
                                           ("vol.spacing 1 1 x", "must be float")])
def test_vol_spacing_refuses_bad_sides_and_changes_nothing(volume_editor, line, message):
    digest = volume(volume_editor).voxels.digest()
    assert not volume_editor.execute(line)
    assert message in errors(volume_editor)[-1]
    assert volume(volume_editor).voxels.digest() == digest


def test_an_nrrd_keeps_the_spacing_and_reads_it_back(volume_editor, tmp_path):
    editor = volume_editor
    write_volume(tmp_path / "ct.nrrd", np.zeros((3, 4, 5), np.int16), spacing=(0.5, 0.25, 2.0))
    assert editor.execute(f"load {tmp_path / 'ct.nrrd'}")
    assert volume(editor).voxels.spacing == (0.5, 0.25, 2.0) and "spacing 0.5 0.25 2" in said(editor)[-2]
    assert editor.execute("vol.spacing 0.488281 0.488281 1.25") and editor.execute(f"save {tmp_path / 'out.nrrd'}")
    header = nrrd.read_header(str(tmp_path / "out.nrrd"))
    np.testing.assert_array_equal(header["spacings"], [0.488281, 0.488281, 1.25])
    assert read_volume_file(tmp_path / "out.nrrd").spacing == (0.488281, 0.488281, 1.25)
    assert editor.execute(f"save {tmp_path / 'out.r3'}")
    assert any("spacing 0.488281 0.488281 1.25 is not kept in out.r3" in line for line in said(editor)[-3:])


def test_an_rgba_nrrd_keeps_its_spacing_past_the_colour_axis(tmp_path):
    write_volume(tmp_path / "c.nrrd", np.zeros((2, 3, 4, 4), np.uint8), spacing=(1.5, 2.0, 3.0))
    assert read_volume_file(tmp_path / "c.nrrd").spacing == (1.5, 2.0, 3.0)


def test_slicers_space_directions_give_the_spacing_and_oblique_ones_say_so(tmp_path):
    directions = {"space": "left-posterior-superior", "space directions": np.diag([0.7, 0.7, 3.0])}
    nrrd.write(str(tmp_path / "slicer.nrrd"), np.zeros((5, 4, 3), np.int16), directions)  # pynrrd's order: x y z
    read = read_volume_file(tmp_path / "slicer.nrrd")
    assert read.spacing == (0.7, 0.7, 3.0) and not read.notes
    c, s = np.cos(0.3), np.sin(0.3)
    oblique = {"space": "left-posterior-superior", "space directions": np.array([[c, s, 0], [-s, c, 0], [0, 0, 2]])}
    nrrd.write(str(tmp_path / "oblique.nrrd"), np.zeros((5, 4, 3), np.int16), oblique)
    read = read_volume_file(tmp_path / "oblique.nrrd")
    assert read.spacing == pytest.approx((1.0, 1.0, 2.0)) and "oblique" in read.notes[0]


def test_an_unusable_spacing_in_a_file_opens_it_at_one_with_a_note(tmp_path):
    nrrd.write(str(tmp_path / "zero.nrrd"), np.zeros((5, 4, 3), np.int16), {"spacings": [1.0, 0.0, 1.0]})
    read = read_volume_file(tmp_path / "zero.nrrd")
    assert read.spacing is None and "is not used" in read.notes[0] and "1 1 1" in read.notes[0]


def test_imagej_and_tiff_resolutions_give_the_spacing(tmp_path):
    buffer = io.BytesIO()
    tifffile.imwrite(buffer, np.zeros((3, 4, 5), np.uint16), imagej=True, resolution=(1 / 0.5, 1 / 0.25),
                     metadata={"spacing": 2.0, "unit": "um", "axes": "ZYX"})
    (tmp_path / "ij.tif").write_bytes(buffer.getvalue())
    read = read_volume_file(tmp_path / "ij.tif")
    assert read.spacing == (0.5, 0.25, 2.0) and "um" in read.notes[-1]
    tifffile.imwrite(tmp_path / "plain.tif", np.zeros((3, 4, 5), np.uint16), resolution=(4, 2),
                     resolutionunit="CENTIMETER", photometric="minisblack")
    read = read_volume_file(tmp_path / "plain.tif")
    assert read.spacing == (0.25, 0.5, 0.25) and any("not in the file" in n for n in read.notes)
    tifffile.imwrite(tmp_path / "none.tif", np.zeros((3, 4, 5), np.uint16), photometric="minisblack")  # resolution 1
    assert read_volume_file(tmp_path / "none.tif").spacing is None


def test_a_demo_keeps_the_spacing_set_before_and_while_it_records(volume_editor, tmp_path):
    editor = volume_editor
    assert editor.execute("new 6 5 4") and editor.execute("vol.spacing 0.5 0.5 2")
    editor.execute("record spaced")
    editor.demos.clock.advance(0.5)
    editor.execute("vol.spacing 0.5 0.5 3")
    editor.execute("stop")
    assert "vol.spacing 0.5 0.5 2.0" in (tmp_path / "spaced.demo").read_text()  # the opening state
    fresh = Editor(clock=VirtualClock())
    assert fresh.execute(f"timedemo {tmp_path / 'spaced'}")
    assert volume(fresh).voxels.spacing == (0.5, 0.5, 3.0)
    assert fresh.digest() == editor.digest()


# --- the box on the GPU, in the reference and under the picker ----------------------------------------------------


@pytest.fixture(scope="module")
def tracer(gl):
    return RayTracer(gl, ShaderLibrary(gl, [SHADERS]))


FRONT = VolumeView(camera=OrbitCamera(yaw=0, pitch=0, distance=5.2), background=(0, 0, 0))


def gpu(gl, tracer, voxels, view, size=(64, 64), **settings):
    target = OffscreenTarget(gl, size, samples=0)
    tracer.render(target.fbo, voxels, view, TraceSettings(slice_planes=False, **settings))
    image = target.read()[..., :3] / 255.0
    target.release()
    return image


def silhouette(image) -> tuple[int, int]:
    """Columns and rows the volume covers."""
    covered = image.sum(-1) > 0.05
    return int(covered.any(0).sum()), int(covered.any(1).sum())


def test_a_volume_of_flat_voxels_is_a_cube_when_its_spacing_says_so(gl, tracer):
    """16 x 8 x 8 voxels of 1 x 2 x 2 mm: a 16 mm cube, seen square from the front; at spacing 1, twice as wide."""
    data = np.full((8, 8, 16, 4), 200, np.uint8)
    flat, spaced = Voxels(data), Voxels(data)
    spaced.spacing = (1.0, 2.0, 2.0)
    width, height = silhouette(gpu(gl, tracer, flat, FRONT, mode=2))
    assert width == pytest.approx(2 * height, abs=2)
    width, height = silhouette(gpu(gl, tracer, spaced, FRONT, mode=2))
    assert width == pytest.approx(height, abs=1)


@pytest.mark.parametrize("mode", [2, 5])
def test_the_gpu_and_the_reference_agree_on_a_spaced_volume(gl, tracer, mode):
    from app.model.volume.samples import cornell_box

    view = VolumeView(camera=OrbitCamera(yaw=25, pitch=20, distance=5.2))
    data = cornell_box(24)[::2]  # 12 slices of 24 x 24, each twice as thick
    voxels = Voxels(data)
    voxels.spacing = (1.0, 1.0, 2.0)
    image = gpu(gl, tracer, voxels, view, size=(48, 48), mode=mode, steps=128)
    truth = reference(data, view.camera, (48, 48), MODES[mode], steps=1024,
                      background=np.array(view.background) / 255.0, spacing=(1.0, 1.0, 2.0))
    err = np.abs(image - truth)
    assert np.sqrt((err ** 2).mean()) < 0.02 and np.percentile(err, 95) < 0.02


def test_the_picker_finds_voxels_in_the_spaced_box():
    data = np.zeros((4, 8, 8, 4), np.uint8)
    data[3, 4, 4, 3] = 255  # the voxel furthest from a viewer in front
    voxels = Voxels(data)
    voxels.spacing = (1.0, 1.0, 2.0)  # the box is 8 x 8 x 8 mm: its back face at world z = -1
    extent = box_extents(voxels.size, voxels.spacing)
    assert extent == (1.0, 1.0, 1.0)
    x = (4.5 / 8) * 2 - 1
    y = -((4.5 / 8) * 2 - 1)
    assert first_hit(voxels, np.array([x, y, 5.0]), np.array([0.0, 0.0, -1.0])) == (4, 4, 3)
