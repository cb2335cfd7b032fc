"""DICOM, NIfTI and .npz readers on the files pydicom and nibabel ship (read by the libraries themselves for the
expected values), and on small files written here for what those do not cover: series order, rescaling, mixed
series, bounds."""
from __future__ import annotations

import gzip
import shutil
import struct
import tracemalloc
from pathlib import Path

import nibabel as nib
import numpy as np
import pydicom
import pytest
from nibabel.testing import data_path
from pydicom.data import get_testdata_file

from app.io.volume_formats import (READ_ONLY, FormatError, read_dicom_files, read_volume, read_volume_file,
                                   suffix_of, write_volume)
from app.io.volume_formats.checks import rescaled
from dicom_files import ct_slice, write_series

DICOM_TESTS = Path(get_testdata_file("CT_small.dcm", download=False)).parent
NIFTI_TESTS = Path(data_path)


def dicom_file(name: str) -> Path:
    return Path(get_testdata_file(name, download=False))


def hounsfield(path: Path) -> np.ndarray:
    """What pydicom itself makes of a slice: its pixels through the modality LUT (rescale)."""
    ds = pydicom.dcmread(path)
    return pydicom.pixels.apply_rescale(ds.pixel_array, ds)


# --- DICOM: pydicom's own files ------------------------------------------------------------------------------


def test_ct_small_opens_in_hounsfield_units_with_its_pixel_spacing():
    read = read_volume_file(dicom_file("CT_small.dcm"))
    assert read.data.shape == (1, 128, 128) and read.data.dtype == np.int16  # uint16 - 1024 fits int16
    np.testing.assert_array_equal(read.data[0], hounsfield(dicom_file("CT_small.dcm")))
    assert read.spacing == (0.661468, 0.661468, 5.0)  # PixelSpacing, and SliceThickness for a single slice
    assert any("intercept -1024" in note for note in read.notes)


@pytest.mark.parametrize("name", ["MR_small.dcm", "MR_small_bigendian.dcm", "MR_small_implicit.dcm"])
def test_mr_small_reads_the_same_in_each_native_transfer_syntax(name):
    data = read_volume(dicom_file(name))
    assert data.dtype == np.int16 and data.dtype.isnative
    np.testing.assert_array_equal(data[0], pydicom.dcmread(dicom_file("MR_small.dcm")).pixel_array)


def test_a_series_folder_is_ordered_by_position_along_the_normal():
    folder = DICOM_TESTS / "dicomdirtests" / "98892001" / "CT5N"
    read = read_volume_file(folder)
    files = sorted(folder.iterdir(), key=lambda p: float(pydicom.dcmread(p).ImagePositionPatient[2]))
    assert read.data.shape == (5, 16, 16)
    for z, path in enumerate(files):
        np.testing.assert_array_equal(read.data[z], hounsfield(path))
    assert read.spacing == (0.488281, 0.488281, 2.5)


def test_the_files_of_a_series_in_any_order_make_the_same_volume():
    folder = DICOM_TESTS / "dicomdirtests" / "98892001" / "CT5N"
    files = sorted(folder.iterdir())
    forward, backward = read_dicom_files(files), read_dicom_files(files[::-1])
    np.testing.assert_array_equal(forward.data, read_volume(folder))
    np.testing.assert_array_equal(backward.data, forward.data)


def test_uneven_slice_gaps_are_said_and_the_median_taken():
    read = read_volume_file(DICOM_TESTS / "dicomdirtests" / "77654033" / "CT2")  # slices at -99.5, 103, 104.3, 105.5
    assert read.data.shape == (4, 16, 16) and read.spacing[2] == pytest.approx(1.25, abs=1e-4)
    assert any("gaps differ" in note for note in read.notes)


def test_several_series_in_a_folder_are_refused_by_name():
    with pytest.raises(FormatError, match="holds 3 DICOM series") as refused:
        read_volume(DICOM_TESTS / "dicomdirtests" / "98892003" / "MR2")
    message = str(refused.value)
    for uid in ("1196533885.18148.0.481", "1196533885.18148.0.136", "1196533885.18148.0.17"):
        assert uid in message
    assert "FAST LOCALIZER (1 file)" in message and "RF FAST PILOT (3 files)" in message


@pytest.mark.parametrize("series", ["98892001/CT2N", "98892003/MR700"])
def test_slices_of_different_orientations_are_refused(series):
    with pytest.raises(FormatError, match="orientations, so they make no volume"):
        read_volume(DICOM_TESTS / "dicomdirtests" / series)


def test_a_folder_of_folders_and_a_dicomdir_are_refused_saying_what_they_hold():
    with pytest.raises(FormatError, match=r"holds no DICOM images \(only MR1/, MR2/, MR700/\)"):
        read_volume(DICOM_TESTS / "dicomdirtests" / "98892003")
    with pytest.raises(FormatError, match="DICOM file without an image"):
        read_volume(DICOM_TESTS / "dicomdirtests" / "DICOMDIR")


def test_compressed_and_unusual_pixel_data_are_refused_by_name():
    with pytest.raises(FormatError, match="transfer syntax RLE Lossless is not supported"):
        read_volume(dicom_file("MR_small_RLE.dcm"))
    with pytest.raises(FormatError, match="transfer syntax JPEG 2000"):
        read_volume(dicom_file("JPEG2000.dcm"))
    with pytest.raises(FormatError, match="1 bits"):
        read_volume(dicom_file("liver_1frame.dcm"))
    with pytest.raises(FormatError, match="less than expected"):
        read_volume(dicom_file("MR_truncated.dcm"))


def test_a_multi_frame_dose_grid_opens_its_frames_as_slices():
    path = dicom_file("rtdose.dcm")
    read = read_volume_file(path)
    ds = pydicom.dcmread(path)
    assert read.data.shape == (15, 10, 10)
    np.testing.assert_allclose(read.data, ds.pixel_array * float(ds.DoseGridScaling))  # grays
    assert read.spacing == (10.0, 10.0, 5.0)  # the frame offset grid's step


def test_an_rgb_secondary_capture_opens_as_colours():
    data = read_volume(dicom_file("SC_rgb_small_odd.dcm"))
    np.testing.assert_array_equal(data[0, ..., :3], pydicom.dcmread(dicom_file("SC_rgb_small_odd.dcm")).pixel_array)
    assert (data[..., 3] == 255).all()


def test_a_folder_passes_over_what_is_not_a_dicom_image(tmp_path):
    shutil.copytree(DICOM_TESTS / "dicomdirtests" / "98892001" / "CT5N", tmp_path / "scan")
    shutil.copy(DICOM_TESTS / "dicomdirtests" / "DICOMDIR", tmp_path / "scan")
    (tmp_path / "scan" / "README.txt").write_text("not DICOM")
    (tmp_path / "scan" / "sub").mkdir()
    read = read_volume_file(tmp_path / "scan")
    assert read.data.shape == (5, 16, 16)
    assert any("passed over" in note and "DICOMDIR" in note and "README.txt" in note and "sub/" in note
               for note in read.notes)


def test_a_dicom_file_of_no_suffix_is_known_by_its_preamble():
    path = DICOM_TESTS / "dicomdirtests" / "77654033" / "CR1" / "6154"
    assert suffix_of(path) == "" and read_volume(path).shape == (1, 16, 16)


# --- DICOM: series written here -------------------------------------------------------------------------------


def stored_ct(depth: int = 5, rows: int = 6, columns: int = 7) -> np.ndarray:
    return np.random.default_rng(depth).integers(0, 3000, (depth, rows, columns)).astype(np.uint16)


def test_an_8_bit_series_opens_as_a_scan(tmp_path):
    """8-bit grey slices (ultrasound, secondary captures) are a scan too: widened to uint16, the values kept."""
    folder = tmp_path / "us"
    folder.mkdir()
    stored = np.random.default_rng(3).integers(0, 256, (3, 4, 5)).astype(np.uint8)
    for z, pixels in enumerate(stored):
        ds = pydicom.dcmread(pydicom.filebase.DicomBytesIO(ct_slice(pixels.astype(np.uint16), z * 2.0, "1.2.3",
                                                                       intercept=0.0)))
        ds.BitsAllocated, ds.BitsStored, ds.HighBit, ds.PixelData = 8, 8, 7, pixels.tobytes()
        ds.save_as(folder / f"IM{z}", enforce_file_format=True)
    read = read_volume_file(folder)
    assert read.data.dtype == np.uint16
    np.testing.assert_array_equal(read.data, stored)
    assert "8-bit values: opened as a scan (uint16), windowed" in read.notes


def test_a_uint16_ct_with_intercept_becomes_int16_in_place(tmp_path):
    stored = stored_ct()
    write_series(tmp_path / "ct", stored, gap=2.5)
    read = read_volume_file(tmp_path / "ct")
    assert read.data.dtype == np.int16 and read.spacing == (0.6, 0.7, 2.5)  # x: between columns, y: between rows
    np.testing.assert_array_equal(read.data, stored.astype(np.int32) - 1024)


def test_a_ct_whose_values_do_not_fit_int16_widens(tmp_path):
    stored = stored_ct()
    stored[0, 0, 0] = 60000
    write_series(tmp_path / "ct", stored)
    data = read_volume(tmp_path / "ct")
    assert data.dtype == np.int32 and data[0, 0, 0] == 60000 - 1024


def test_slices_rescaled_each_their_own_way_become_floats(tmp_path):
    folder = tmp_path / "pet"
    folder.mkdir()
    stored = stored_ct(depth=3)
    for z in range(3):
        (folder / f"s{z}").write_bytes(ct_slice(stored[z], z * 3.0, "1.2.3", slope=0.5 * (z + 1), intercept=z))
    data = read_volume(folder)
    assert data.dtype == np.float32
    for z in range(3):
        np.testing.assert_allclose(data[z], stored[z] * 0.5 * (z + 1) + z)


def test_a_series_of_two_sizes_is_refused_listing_them(tmp_path):
    folder = tmp_path / "mixed"
    folder.mkdir()
    (folder / "a").write_bytes(ct_slice(stored_ct(1, 6, 7)[0], 0.0, "1.2.3"))
    (folder / "b").write_bytes(ct_slice(stored_ct(1, 8, 7)[0], 2.0, "1.2.3"))
    with pytest.raises(FormatError, match=r"differ in size or voxel type.*7x6 u2 \(1 file\); 7x8 u2 \(1 file\)"):
        read_volume(folder)


def test_two_slices_at_one_position_are_refused_as_several_volumes(tmp_path):
    folder = tmp_path / "echoes"
    folder.mkdir()
    for name in "ab":
        (folder / name).write_bytes(ct_slice(stored_ct(1)[0], 4.0, "1.2.3"))
    with pytest.raises(FormatError, match="same position"):
        read_volume(folder)


def test_an_oblique_series_is_ordered_along_its_own_normal(tmp_path):
    oblique = (0.8, 0.6, 0.0, 0.0, 0.0, -1.0)  # a sagittal-ish plane
    stored = stored_ct(depth=4)
    write_series(tmp_path / "oblique", stored, gap=1.5, orientation=oblique)
    read = read_volume_file(tmp_path / "oblique")
    np.testing.assert_array_equal(read.data, stored.astype(np.int32) - 1024)
    assert read.spacing[2] == pytest.approx(1.5)


def test_a_series_over_the_limit_is_refused_before_its_pixels_are_read(tmp_path):
    write_series(tmp_path / "ct", stored_ct(depth=4, rows=32, columns=32))
    tracemalloc.start()
    try:
        with pytest.raises(FormatError, match="over the size limit"):
            read_volume(tmp_path / "ct", max_bytes=4 * 32 * 32 * 3 - 1)  # int16 values and a label byte a voxel
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 1 << 20


# --- NIfTI: nibabel's own files --------------------------------------------------------------------------------


def nibabel_first_volume(name: str) -> np.ndarray:
    """nibabel's (i, j, k) voxels, scaled, of the first volume, as (k, j, i)."""
    image = nib.load(NIFTI_TESTS / name)
    data = np.asanyarray(image.dataobj)
    return (data[..., 0] if data.ndim == 4 else data).T


@pytest.mark.parametrize("name, spacing", [
    ("anatomical.nii", (2.0, 2.0, 2.0)),            # big-endian int16
    ("example4d.nii.gz", (2.0, 2.0, 2.199999)),     # 4D, gzip, an oblique affine
    ("example_nifti2.nii.gz", (2.0, 2.0, 2.199999)),  # NIfTI-2
    ("functional.nii", (4.0, 4.0, 8.0)),            # 4D, scl_slope and scl_inter
    ("reoriented_anat_moved.nii", (4.0, 4.0, 4.0)),  # big-endian float32
])
def test_nibabels_files_read_as_nibabel_reads_them(name, spacing):
    read = read_volume_file(NIFTI_TESTS / name)
    expected = nibabel_first_volume(name)
    assert read.data.shape == expected.shape and read.data.dtype.isnative and read.data.flags.c_contiguous
    np.testing.assert_allclose(read.data, expected, rtol=1e-6)
    assert read.spacing == pytest.approx(spacing, rel=1e-6)
    assert any("orientation" in note for note in read.notes)


def test_a_4d_file_says_it_opens_its_first_volume():
    assert "a 4D file of 20 volumes: the first opens" in read_volume_file(NIFTI_TESTS / "functional.nii").notes


def test_a_uint8_nifti_is_a_scan_with_its_voxel_sizes():
    """What neuroimaging tools write in 8 bits (an MRI template) opens as a scan, windowed, not as grey colours."""
    read = read_volume_file(NIFTI_TESTS / "standard.nii.gz")
    expected = nibabel_first_volume("standard.nii.gz")
    assert read.data.dtype == np.uint16 and read.data.shape == expected.shape and read.spacing == (1.0, 3.0, 2.0)
    np.testing.assert_array_equal(read.data, expected)
    assert "8-bit values: opened as a scan (uint16), windowed" in read.notes


def nifti_bytes(values: np.ndarray, compressed: bool = False, **header) -> bytes:
    image = nib.Nifti1Image(values.T, np.diag([0.5, 0.5, 2.0, 1.0]))
    for key, value in header.items():
        image.header[key] = value
    data = image.to_bytes()
    return gzip.compress(data) if compressed else data


def test_nifti_sizes_are_checked_before_any_voxel_is_read(tmp_path):
    data = bytearray(nifti_bytes(np.zeros((2, 3, 4), np.int16)))
    data[42:48] = struct.pack("<hhh", 4096, 4096, 4096)  # dim[1..3]: 128 GiB of voxels in a tiny file
    (tmp_path / "big.nii").write_bytes(data)
    tracemalloc.start()
    try:
        with pytest.raises(FormatError, match="over the size limit"):
            read_volume(tmp_path / "big.nii")
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 1 << 20


def test_a_truncated_nifti_and_a_header_without_voxels_are_refused(tmp_path):
    (tmp_path / "short.nii.gz").write_bytes(nifti_bytes(np.ones((3, 4, 5), np.float32), compressed=True)[:-20])
    with pytest.raises(FormatError):
        read_volume(tmp_path / "short.nii.gz")
    pair = bytearray(nifti_bytes(np.ones((2, 2, 2), np.int16)))
    pair[344:348] = b"ni1\x00"
    (tmp_path / "pair.nii").write_bytes(pair)
    with pytest.raises(FormatError, match="separate .img file"):
        read_volume(tmp_path / "pair.nii")


# --- .npz --------------------------------------------------------------------------------------------------------


def npz(path: Path, **arrays) -> Path:
    np.savez_compressed(path, **arrays)
    return path


def test_an_npz_of_one_array_opens_it(tmp_path):
    ct = np.arange(24, dtype=np.int16).reshape(2, 3, 4)
    np.testing.assert_array_equal(read_volume(npz(tmp_path / "one.npz", ct=ct)), ct)


def test_an_npz_of_several_arrays_is_refused_by_their_names_unless_one_is_chosen(tmp_path):
    ct, mask = np.ones((2, 3, 4), np.float32), np.zeros((2, 3, 4), np.uint8)
    path = npz(tmp_path / "two.npz", ct=ct, mask=mask)
    with pytest.raises(FormatError, match=r"holds 2 arrays: ct, mask; choose one by its name"):
        read_volume(path)
    np.testing.assert_array_equal(read_volume_file(path, array="ct").data, ct)
    assert read_volume_file(path, array="mask").data.shape == (2, 3, 4, 4)
    with pytest.raises(FormatError, match="no array 'dose'; it holds ct, mask"):
        read_volume_file(path, array="dose")
    with pytest.raises(FormatError, match="only an .npz file holds arrays"):
        read_volume_file(tmp_path / "x.nrrd", array="ct")


def test_an_npz_never_unpickles(tmp_path):
    path = tmp_path / "objects.npz"
    np.savez(path, ct=np.array([[[object()]]], dtype=object), allow_pickle=True)
    with pytest.raises(FormatError, match="voxels are object"):
        read_volume(path)


def test_an_npz_array_over_the_limit_is_refused_before_it_is_inflated(tmp_path):
    path = npz(tmp_path / "zeros.npz", ct=np.zeros((64, 64, 64), np.int16))  # 512 KiB, a few KiB compressed
    tracemalloc.start()
    try:
        with pytest.raises(FormatError, match="over the size limit"):
            read_volume(path, max_bytes=64 * 64 * 64 * 3 - 1)  # int16 values and a label byte a voxel
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 256 << 10


# --- what all of them share -----------------------------------------------------------------------------------


@pytest.mark.parametrize("name", ["v.nii", "v.nii.gz", "v.npz", "v.dcm"])
def test_read_only_formats_are_refused_for_writing_saying_what_to_use(tmp_path, name):
    assert suffix_of(name) in READ_ONLY
    with pytest.raises(FormatError, match="reads .* files but does not write them; save as"):
        write_volume(tmp_path / name, np.zeros((2, 2, 2), np.int16))


def test_rescaling_keeps_whole_numbers_in_place_and_widens_only_when_it_must():
    values = np.array([[[0, 4000]]], np.uint16)
    kept = rescaled("x", values, 1.0, -1024.0, notes := [], 1 << 20)
    assert kept.dtype == np.int16 and np.shares_memory(kept, values) and kept.tolist() == [[[-1024, 2976]]]
    assert "into int16" in notes[0]
    wide = rescaled("x", np.array([[[0, 65535]]], np.uint16), 2.0, 0.0, [], 1 << 20)
    assert wide.dtype.itemsize == 4 and wide.dtype.kind in "iu" and wide.tolist() == [[[0, 131070]]]
    fraction = rescaled("x", np.array([[[1, 3]]], np.int16), 0.5, 0.25, [], 1 << 20)
    assert fraction.dtype == np.float32 and fraction.tolist() == [[[0.75, 1.75]]]
    same = np.array([[[1, 2]]], np.int16)
    assert rescaled("x", same, None, None, [], 1 << 20) is same and rescaled("x", same, 0.0, 0.0, [], 1) is same


def test_the_stream_reader_is_no_bigger_than_the_volume(tmp_path):
    """A .nii.gz inflates into the voxel buffer: the read peaks at the volume, not twice it."""
    values = np.random.default_rng(0).integers(-1000, 1000, (64, 128, 128)).astype(np.int16)  # 2 MiB
    (tmp_path / "ct.nii.gz").write_bytes(nifti_bytes(values, compressed=True))
    tracemalloc.start()
    try:
        data = read_volume(tmp_path / "ct.nii.gz")
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    np.testing.assert_array_equal(data, values)
    assert peak < values.nbytes + (640 << 10)  # the voxels, a 256 KiB piece, gzip's window and buffers



# --- the commands ----------------------------------------------------------------------------------------------


def logged(editor, level: str | None = None) -> list[str]:
    return [line.text for line in editor.console.log if level is None or line.level == level]


def test_open_finds_the_volume_workspace_by_a_double_suffix_and_says_what_the_reader_chose(volume_editor):
    editor = volume_editor
    assert editor.execute("workspace lighting2d")
    assert editor.execute(f"open {NIFTI_TESTS / 'example4d.nii.gz'}")
    assert editor.workspaces.name == "volume"
    voxels = editor.workspaces["volume"].volume.voxels
    assert voxels.size == (128, 96, 24) and voxels.spacing == (2.0, 2.0, 2.199999)
    text = "\n".join(logged(editor))
    assert "spacing 2 2 2.2" in text and "a 4D file of 2 volumes: the first opens" in text
    assert editor.documents.save_path(editor.current) is None  # NIfTI is read, never written: Save asks where


def test_load_takes_an_npz_array_by_name(volume_editor, tmp_path):
    path = npz(tmp_path / "scan.npz", ct=np.ones((2, 3, 4), np.int16), mask=np.zeros((2, 3, 4), np.uint8))
    assert not volume_editor.execute(f"load {path}")
    assert f"choose one by its name (load {path} ct)" in logged(volume_editor, "error")[-1]
    assert volume_editor.execute(f"load {path} ct")
    assert volume_editor.workspaces["volume"].volume.voxels.scalars.values.dtype == np.int16
    assert not volume_editor.execute(f"load {path} ct mask")
    assert "chosen by one name" in logged(volume_editor, "error")[-1]


def test_load_takes_the_files_of_one_series_and_undo_brings_back_the_volume_before(volume_editor):
    editor = volume_editor
    before = editor.workspaces["volume"].volume.voxels.digest()
    files = sorted((DICOM_TESTS / "dicomdirtests" / "98892001" / "CT5N").iterdir())
    assert editor.execute("load " + " ".join(map(str, files)))
    voxels = editor.workspaces["volume"].volume.voxels
    assert voxels.size == (16, 16, 5) and voxels.spacing == (0.488281, 0.488281, 2.5)
    assert "and 4 more: 16x16x5, spacing 0.488281 0.488281 2.5" in "\n".join(logged(editor))
    assert editor.execute("undo") and voxels.digest() == before and voxels.spacing == (1.0, 1.0, 1.0)


def test_a_mixed_series_changes_nothing(volume_editor):
    volume = volume_editor.workspaces["volume"].volume
    before = (volume.voxels.digest(), volume.history.undo_depth)
    assert not volume_editor.execute(f"load {DICOM_TESTS / 'dicomdirtests' / '98892003' / 'MR2'}")
    assert "holds 3 DICOM series" in logged(volume_editor, "error")[-1]
    assert (volume.voxels.digest(), volume.history.undo_depth) == before


def test_a_script_reads_no_series_in_a_folder_beside_it_but_the_user_may(volume_editor, tmp_path):
    """Scripts read beside the file that runs, not below it: a series folder's files are below."""
    shutil.copytree(DICOM_TESTS / "dicomdirtests" / "98892001" / "CT5N", tmp_path / "scripts" / "ct")
    (tmp_path / "scripts" / "s.cfg").write_text(f"load {tmp_path / 'scripts' / 'ct'}\n")  # the folder is beside it
    assert not volume_editor.execute(f"exec {tmp_path / 'scripts' / 's.cfg'}")
    assert any(f"may not read {tmp_path / 'scripts' / 'ct' / '*'}" in line for line in logged(volume_editor, "error"))
    assert volume_editor.execute(f"load {tmp_path / 'scripts' / 'ct'}")


def test_an_orientation_a_mutated_affine_leaves_undefined_is_a_note_not_a_crash():
    """Found by the fuzz: an affine of NaN made nibabel's SVD fail, an all-zero one gave None axis codes."""
    from app.io.volume_formats.nifti import orientation
    assert orientation(np.full((4, 4), np.nan)) == "unknown"
    assert orientation(np.zeros((4, 4))) == "???"
    assert orientation(np.eye(4)) == "RAS"
