"""Labels over a scan (app/model/volume/labels.py): painting a scalar volume paints labels, never its values;
fill, erase and undo work on them a sub-box at a time; they are allocated at the first label and count in the
memory bound; `save` writes them beside the scan as a Slicer segmentation and `load` finds them; digests of scans
with no label stay what they were."""
from __future__ import annotations

import hashlib

import nibabel as nib
import nrrd
import numpy as np
import pytest

from app.console.demo import VirtualClock
from app.editor import Editor
from app.io.atomic import name_max
from app.io.volume_labels import labels_path, read_labels, write_labels
from app.model.volume.labels import DEFAULT_COLOURS, Labels
from app.model.volume.volume import Volume
from app.model.volume.voxels import VolumeError


def scan(w=20, h=16, d=6) -> np.ndarray:
    """An int16 'CT': a block of 800 on the left half, -1000 on the right, a ramp along z."""
    values = np.full((d, h, w), -1000, np.int16)
    values[:, :, : w // 2] = 800
    values += np.arange(d, dtype=np.int16)[:, None, None]
    return values


def load(editor, tmp_path, values, name="ct.npy"):
    """Write `values` to `name` (.npy or .nrrd; another file the test has written) and load it."""
    if name.endswith(".npy"):
        np.save(tmp_path / name, values)
    elif name.endswith(".nrrd"):
        nrrd.write(str(tmp_path / name), values, index_order="C")
    assert editor.execute(f"load {tmp_path / name}"), errors(editor)
    return editor.workspaces["volume"].volume


def errors(editor) -> list[str]:
    return [line.text for line in editor.console.log if line.level == "error"]


def infos(editor) -> list[str]:
    return [line.text for line in editor.console.log if line.level != "error"]


def fingerprint(volume) -> tuple[str, str, int]:
    """The scan's values as loaded (their bytes' hash), its colours, and the values' object."""
    voxels = volume.voxels
    return (hashlib.sha256(voxels.scalars.values.tobytes()).hexdigest(),
            hashlib.sha256(voxels.data.tobytes()).hexdigest(), id(voxels.scalars.values))


def test_painting_filling_erasing_undo_and_redo_never_change_the_scan(volume_editor, tmp_path):
    vol = load(volume_editor, tmp_path, scan())
    before = fingerprint(vol)
    edits = ("label.stroke z 2 3 1 2 2 12 9", "label.stroke.preview z 3 3 2 1 1 5 5", "stroke.cancel",
             "label.fill z 2 0 0 4 0", "label.voxel 15 3 4 7", "label.stroke z 2 1 0 2 2 12 9",
             "label.fill x 5 3 3 9 255")
    for line in edits:
        assert volume_editor.execute(line), errors(volume_editor)
        assert fingerprint(vol) == before, line
    painted = vol.voxels.labels.data.copy()
    assert painted[2, 2, 2] == 0 and painted[4, 3, 15] == 7 and (painted == 4).any() and (painted == 9).any()
    steps = vol.history.undo_depth
    for _ in range(5):
        assert volume_editor.execute("undo") and fingerprint(vol) == before
    for _ in range(5):
        assert volume_editor.execute("redo") and fingerprint(vol) == before
    np.testing.assert_array_equal(vol.voxels.labels.data, painted)
    assert vol.history.undo_depth == steps
    assert vol.voxels.scalars.values.flags.writeable is False


def test_labels_are_allocated_at_the_first_label_and_released_when_it_is_undone(volume_editor, tmp_path):
    vol = load(volume_editor, tmp_path, scan())
    labels, digest, steps = vol.voxels.labels, vol.voxels.digest(), vol.history.undo_depth
    assert labels.data is None and labels.nbytes == 0  # viewed only: none held
    assert volume_editor.execute("label.stroke z 1 3 0 4 4 9 9")  # erasing nothing allocates nothing
    assert volume_editor.execute("label.stroke z 1 3 5 -50 -50 -40 -40")  # off the slice: nothing painted
    assert labels.data is None and vol.history.undo_depth == steps and vol.voxels.digest() == digest
    assert volume_editor.execute("label.stroke.preview z 1 3 5 4 4")  # a preview allocates, its end releases
    assert labels.data is not None
    assert volume_editor.execute("stroke.cancel") and labels.data is None and vol.voxels.digest() == digest
    assert volume_editor.execute("label.stroke z 1 3 5 4 4 9 9")
    assert labels.data is not None and labels.nbytes == 20 * 16 * 6 and vol.voxels.digest() != digest
    assert volume_editor.execute("undo")
    assert labels.data is None and vol.voxels.digest() == digest  # undone back: as it was, unsaved changes gone
    assert volume_editor.execute("redo") and labels.data[1, 4, 4] == 5


def test_label_steps_hold_the_changed_sub_box_as_colour_steps_do(volume_editor, tmp_path):
    vol = load(volume_editor, tmp_path, scan())
    labels = vol.voxels.labels
    assert volume_editor.execute("label.stroke z 3 1 2 4 5 9 5")
    seen = labels.version
    held = vol.history.nbytes
    assert volume_editor.execute("label.stroke z 3 3 2 2 8 6 8")
    assert vol.history.nbytes - held == 7 * 3  # the stroke's box, a byte a voxel
    box = labels.changed_since(seen)
    assert (box.x0, box.y0, box.z0, box.x1, box.y1, box.z1) == (1, 7, 3, 8, 10, 4)
    assert vol.voxels.changed_since(vol.voxels.version) is None  # the colours never changed
    assert vol.history.undo_name() == "Label Stroke"
    assert volume_editor.execute("label.fill z 3 0 0 6 255") and vol.history.undo_name() == "Label Fill"
    assert volume_editor.execute("label.voxel 0 0 0 1") and vol.history.undo_name() == "Label Voxel"


def test_fill_is_bounded_by_the_labels_and_by_the_window_colours_within_tolerance(volume_editor, tmp_path):
    vol = load(volume_editor, tmp_path, scan(w=20, h=10, d=2))
    assert volume_editor.execute("vol.window -1000 800")
    assert volume_editor.execute("label.fill z 0 2 2 1")  # tolerance 0: the left block's one colour
    filled = vol.voxels.labels.data[0] == 1
    assert filled[:, :10].all() and not filled[:, 10:].any()
    assert volume_editor.execute("label.stroke z 1 1 3 0 5 19 5")  # a line of label 3 across the slice
    assert volume_editor.execute("label.fill z 1 15 1 2 255")  # 255: the labels alone bound the flood
    top = vol.voxels.labels.data[1]
    assert (top[:5] == 2).all() and (top[5] == 3).all() and (top[6:] == 0).all()
    assert volume_editor.execute("label.fill z 1 15 1 0 255")  # label 0 erases the region
    assert (vol.voxels.labels.data[1, :5] == 0).all() and (vol.voxels.labels.data[1, 5] == 3).all()


def test_a_scan_refuses_colour_edits_and_an_rgba_volume_refuses_labels(volume_editor, tmp_path):
    vol = load(volume_editor, tmp_path, scan())
    before = (fingerprint(vol), vol.voxels.digest(), vol.history.undo_depth)
    for line in ("stroke z 1 3 255 0 0 255 2 2", "stroke.preview z 1 3 255 0 0 255 2 2", "fill z 1 0 0 1 2 3 255",
                 "voxel 1 1 1 255 0 0 255", "smooth"):
        assert not volume_editor.execute(line)
        assert "never painted" in errors(volume_editor)[-1] and "label.stroke" in errors(volume_editor)[-1]
        assert (fingerprint(vol), vol.voxels.digest(), vol.history.undo_depth) == before
    for line, needle in (("label.stroke z 1 3 256 2 2", "0..255"), ("label.color 0 1 2 3", "1..255"),
                         ("label.color 4 1 2 300", "0..255"), ("label.fill z 1 99 0 2", "outside"),
                         ("label.stroke q 1 3 2 2 2", "axis")):
        assert not volume_editor.execute(line)
        assert needle in errors(volume_editor)[-1]
        assert (fingerprint(vol), vol.voxels.digest(), vol.history.undo_depth) == before
    assert volume_editor.execute("new 8 8 8")
    rgba = vol.voxels.digest()
    for line in ("label.stroke z 1 3 2 2 2", "label.fill z 1 0 0 2", "label.voxel 1 1 1 2", "label.color 2 1 2 3",
                 "label.list"):
        assert not volume_editor.execute(line)
        assert "labels are painted over a scan" in errors(volume_editor)[-1]
    assert vol.voxels.digest() == rgba and vol.voxels.labels is None
    assert volume_editor.execute("stroke z 1 3 255 0 0 255 2 2")  # RGBA volumes paint as they did


def test_label_colours_the_eyedropper_and_the_list(volume_editor, tmp_path):
    vol = load(volume_editor, tmp_path, scan())
    labels = vol.voxels.labels
    digest = vol.voxels.digest()
    assert volume_editor.execute("label.color 2 10 20 30")
    assert tuple(labels.colours[2]) == (10, 20, 30) and vol.voxels.digest() != digest
    assert volume_editor.execute("undo") and tuple(labels.colours[2]) == tuple(DEFAULT_COLOURS[2])
    assert vol.voxels.digest() == digest
    assert volume_editor.execute("redo; label.voxel 3 4 5 2; label.voxel 3 5 5 2; pick 3 4 5")
    assert volume_editor.console.registry.cvars["brush_label"].value == 2
    assert infos(volume_editor)[-1] == "brush label 2"
    assert volume_editor.execute("label.list")
    assert infos(volume_editor)[-1] == "label 2: 2 voxels, colour 10 20 30"


def test_rotations_turn_the_labels_with_the_scan(volume_editor, tmp_path):
    values = np.arange(20 * 16 * 6, dtype=np.int32).reshape(6, 16, 20)  # each voxel its own value
    vol = load(volume_editor, tmp_path, values)
    assert volume_editor.execute("label.stroke z 2 3 2 2 2 12 9; label.voxel 15 3 4 5")
    under = {n: sorted(vol.voxels.scalars.values[vol.voxels.labels.data == n]) for n in (2, 5)}
    for axis in "xyzx":
        assert volume_editor.execute(f"rotate {axis}")
        assert vol.voxels.labels.size == vol.voxels.size
        assert {n: sorted(vol.voxels.scalars.values[vol.voxels.labels.data == n]) for n in (2, 5)} == under
    assert volume_editor.execute("undo; undo; undo; undo")
    assert vol.voxels.labels.size == (20, 16, 6) and vol.voxels.label_at(15, 3, 4) == 5


def test_save_writes_a_slicer_segmentation_beside_the_scan_and_load_reads_it(volume_editor, tmp_path):
    vol = load(volume_editor, tmp_path, scan())
    assert volume_editor.execute("label.stroke z 2 3 1 2 2 12 9; label.voxel 15 3 4 7; label.color 7 255 128 0")
    assert volume_editor.execute(f"save {tmp_path / 'out.nrrd'}")
    seg = tmp_path / "out.seg.nrrd"
    assert labels_path(tmp_path / "out.nrrd") == seg and seg.is_file()
    assert f"saved its labels beside it: {seg}, labels 1, 7" in infos(volume_editor)[-1]
    header = nrrd.read_header(str(seg))
    assert header["type"] == "uint8" and list(header["sizes"]) == [20, 16, 6]
    assert header["Segmentation_MasterRepresentation"] == "Binary labelmap"
    segments = {header[f"Segment{i}_LabelValue"]: header[f"Segment{i}_Color"] for i in range(2)}
    assert segments == {"1": "0.901961 0.0980392 0.294118", "7": "1 0.501961 0"}
    assert header["Segment1_Extent"] == "15 15 3 3 4 4"
    fresh = Editor(clock=VirtualClock())
    assert fresh.execute("workspace volume") and fresh.execute(f"load {tmp_path / 'out.nrrd'}")
    assert f"labels from {seg}: labels 1, 7" in infos(fresh)[-1]
    again = fresh.workspaces["volume"].volume.voxels
    np.testing.assert_array_equal(again.labels.data, vol.voxels.labels.data)
    assert tuple(again.labels.colours[7]) == (255, 128, 0)
    assert again.digest() == vol.voxels.digest()

    assert volume_editor.execute(f"save {tmp_path / 'copy.npy'}") and labels_path(tmp_path / "copy.npy").is_file()
    assert volume_editor.execute(f"save {tmp_path / 'colours.r3'}")
    assert "the labels are not kept" in infos(volume_editor)[-1]
    assert not (tmp_path / "colours.seg.nrrd").exists()


def test_the_labels_file_of_a_nifti_scan_or_a_dicom_folder_drops_its_whole_suffix(volume_editor, tmp_path):
    """`ct.nii.gz` -> `ct.seg.nrrd` (not `ct.nii.seg.nrrd`), a DICOM folder `series` -> `series.seg.nrrd` beside
    it; and `load` of the .nii.gz finds the labels there, with the spacing the NIfTI file gives."""
    assert labels_path(tmp_path / "ct.nii.gz") == labels_path(tmp_path / "ct.NII.GZ") == tmp_path / "ct.seg.nrrd"
    assert labels_path(tmp_path / "ct.nii") == labels_path(tmp_path / "ct.nrrd") == tmp_path / "ct.seg.nrrd"
    assert labels_path(tmp_path / "series") == tmp_path / "series.seg.nrrd"
    values = scan()
    nib.save(nib.Nifti1Image(np.ascontiguousarray(values.transpose(2, 1, 0)), np.diag([0.5, 0.5, 2.0, 1.0])),
             tmp_path / "ct.nii.gz")
    vol = load(volume_editor, tmp_path, values, "ct.nii.gz")
    assert vol.voxels.spacing == (0.5, 0.5, 2.0) and vol.voxels.labels.data is None
    labels = np.zeros(values.shape, np.uint8)
    labels[2, 3:5, 4:9] = 6
    write_labels(tmp_path / "ct.seg.nrrd", labels, DEFAULT_COLOURS)
    vol = load(volume_editor, tmp_path, values, "ct.nii.gz")
    assert f"labels from {tmp_path / 'ct.seg.nrrd'}: label 6 (10 voxels)" in infos(volume_editor)[-1]
    np.testing.assert_array_equal(vol.voxels.labels.data, labels)
    assert vol.voxels.spacing == (0.5, 0.5, 2.0)


def test_a_labels_file_left_beside_a_scan_saved_without_labels_is_cleared(volume_editor, tmp_path):
    vol = load(volume_editor, tmp_path, scan())
    assert volume_editor.execute(f"label.voxel 1 1 1 5; save {tmp_path / 'a.nrrd'}; undo")
    assert vol.voxels.labels.data is None
    assert volume_editor.execute(f"save {tmp_path / 'a.nrrd'}")
    assert "with no label" in infos(volume_editor)[-1]
    data, _colours = read_labels(tmp_path / "a.seg.nrrd", 1 << 30)
    assert not data.any()
    assert volume_editor.execute(f"load {tmp_path / 'a.nrrd'}") and vol.voxels.labels.data is None


def test_a_labels_file_that_does_not_fit_loads_the_scan_without_it(volume_editor, tmp_path):
    values = scan()
    nrrd.write(str(tmp_path / "ct.seg.nrrd"), np.ones((6, 16, 19), np.uint8), index_order="C")
    vol = load(volume_editor, tmp_path, values, "ct.nrrd")
    assert "its labels are 19 x 16 x 6 voxels, the scan 20 x 16 x 6" in errors(volume_editor)[-1]
    assert vol.voxels.labels is not None and vol.voxels.labels.data is None
    np.testing.assert_array_equal(vol.voxels.scalars.values, values)
    for data, needle in ((np.ones((6, 16, 20), np.int16), "one uint8 a voxel"),
                         (np.ones((6, 16, 20, 3), np.uint8), "one uint8 a voxel")):
        nrrd.write(str(tmp_path / "ct.seg.nrrd"), data, index_order="C")
        assert volume_editor.execute(f"load {tmp_path / 'ct.nrrd'}")
        assert needle in errors(volume_editor)[-1] and "loads without its labels" in errors(volume_editor)[-1]
    nrrd.write(str(tmp_path / "ct.seg.nrrd"), np.ones((6, 16, 20), np.uint8),
               {"Segment0_LabelValue": "1", "Segment0_Color": "2 0 0"}, index_order="C")
    assert volume_editor.execute(f"load {tmp_path / 'ct.nrrd'}")
    assert "a colour three numbers 0..1" in errors(volume_editor)[-1]
    (tmp_path / "ct.seg.nrrd").write_bytes(b"NRRD0004\ntype: uint8\n")  # truncated
    assert volume_editor.execute(f"load {tmp_path / 'ct.nrrd'}")
    assert "truncated" in errors(volume_editor)[-1]


def test_a_segmentation_written_elsewhere_gives_its_colours(tmp_path):
    """Slicer's header fields, as Slicer writes them: the colours of the labels it names come with them."""
    labels = np.zeros((4, 5, 6), np.uint8)
    labels[1, 2, 3] = 2
    header = {"space": "left-posterior-superior", "Segment0_Color": "0.5 0.25 1", "Segment0_ID": "Segment_1",
              "Segment0_LabelValue": "2", "Segment0_Layer": "0", "Segment0_Name": "tumour",
              "Segmentation_MasterRepresentation": "Binary labelmap"}
    nrrd.write(str(tmp_path / "x.seg.nrrd"), labels, header, index_order="C")
    data, colours = read_labels(tmp_path / "x.seg.nrrd", 1 << 30)
    assert colours == {2: (128, 64, 255)}
    np.testing.assert_array_equal(data, labels)


def test_labels_count_in_the_memory_bound_and_are_made_only_when_painted():
    vol = Volume.new(2, 2, 2)
    vol.replace_scalars(scan())
    assert vol.voxels.labels.nbytes == 0
    with pytest.raises(VolumeError, match="labels are 3 x 3 x 3 voxels"):
        vol.replace_scalars(scan(), labels=Labels((3, 3, 3)))
    with pytest.raises(VolumeError, match="uint8"):
        Labels.loaded(np.zeros((2, 2, 2), np.int16))
    assert Labels.loaded(np.zeros((2, 3, 4), np.uint8)).data is None  # all clear: held as none painted


def test_a_demo_replays_labels_and_a_demo_started_from_labels_snapshots_them(volume_editor, tmp_path):
    load(volume_editor, tmp_path, scan())
    assert volume_editor.execute(f"record {tmp_path / 'paint'}")
    for line in ("brush_label 3", "label.stroke z 2 3 3 2 2 12 9", "label.fill z 2 0 0 4 255", "label.color 4 1 2 3",
                 "r_labelOpacity 0.8", "label.stroke z 2 1 0 5 5"):
        assert volume_editor.execute(line)
    assert volume_editor.execute("stop")
    painted = volume_editor.digest()
    fresh = Editor(clock=VirtualClock())
    assert fresh.execute(f"timedemo {tmp_path / 'paint'}"), errors(fresh)
    assert fresh.digest() == painted
    assert (tmp_path / "paint.start.npy").is_file() and not (tmp_path / "paint.start.seg.nrrd").exists()

    assert volume_editor.execute(f"record {tmp_path / 'more'}; label.voxel 1 1 1 9; stop")  # starts with labels
    assert (tmp_path / "more.start.seg.nrrd").is_file()
    later = Editor(clock=VirtualClock())
    assert later.execute(f"timedemo {tmp_path / 'more'}"), errors(later)
    assert later.digest() == volume_editor.digest()


def test_a_record_name_with_no_room_for_the_labels_beside_its_snapshot_is_refused_at_record(volume_editor, tmp_path):
    """A scan's snapshot `<demo>.start.npy` has its labels beside it, `<demo>.start.seg.nrrd`: the longest name a
    recording writes, which `record` must leave room for (or `stop` could not write it)."""
    load(volume_editor, tmp_path, scan())
    assert volume_editor.execute("label.voxel 1 1 1 3")
    room = name_max(tmp_path) - len(".start.seg.nrrd")
    assert not volume_editor.execute(f"record {tmp_path / ('d' * (room + 1))}")  # .start.nrrd would fit
    assert (f"too long a name: with .start.seg.nrrd (a snapshot it may write beside the demo) it has "
            f"{name_max(tmp_path) + 1} bytes") in errors(volume_editor)[-1]
    assert f"give at most {room} bytes before .demo" in errors(volume_editor)[-1]
    assert volume_editor.execute(f"record {tmp_path / ('d' * room)}; stop"), errors(volume_editor)
    assert (tmp_path / f"{'d' * room}.start.seg.nrrd").is_file() and (tmp_path / f"{'d' * room}.start.npy").is_file()


def test_a_scan_with_no_label_keeps_the_digest_it_had_before_labels(volume_editor, tmp_path):
    """The digest's formula before labels (main at b806d6a): a scan never painted, or painted and undone, gives it."""
    vol = load(volume_editor, tmp_path, scan())
    voxels = vol.voxels

    def before_labels() -> str:
        h = hashlib.sha256("{}x{}x{};".format(*voxels.size).encode())
        h.update(f";{voxels.scalars.values.dtype.str};{voxels.scalars.transfer!r};".encode())
        h.update(voxels.scalars.values.data)
        return h.hexdigest()[:16]

    assert voxels.digest() == before_labels()
    assert volume_editor.execute("label.stroke z 1 2 4 3 3; r_labelOpacity 0.2; brush_label 9")
    assert voxels.digest() != before_labels()
    assert volume_editor.execute("undo") and voxels.digest() == before_labels()
