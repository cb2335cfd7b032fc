"""Fuzzing the scan readers (NIfTI, .nii.gz, .npz, DICOM files and series) as tests/test_fuzz_volume_readers.py
fuzzes the others, with its check: whatever the bytes, a read returns a valid volume within the limit or raises
FormatError, and the memory it traces stays within PEAK_LIMIT. EXAMPLES inputs a reader, half mutated from valid
small files, half built from generated headers."""
from __future__ import annotations

import gzip
import io
import zipfile

import nibabel as nib
import numpy as np
import pytest
import pydicom
from hypothesis import given
from hypothesis import strategies as st
from pydicom.dataset import FileMetaDataset
from pydicom.encaps import encapsulate
from pydicom.uid import CTImageStorage, ExplicitVRLittleEndian, ImplicitVRLittleEndian, RLELossless

from dicom_files import ct_slice
from test_fuzz_volume_readers import FUZZ, SIDES, check, mutated, npy_bytes, npy_headers, payload, rng_volume, \
    small_product


# The generated DICOM headers hold numbers pydicom warns of as it writes them ('nan' pixel spacing): they are meant.
pytestmark = pytest.mark.filterwarnings("ignore:Invalid value for VR")


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    return tmp_path_factory.mktemp("fuzz-scans")


# --- valid small files ---------------------------------------------------------------------------------------------


def nifti(values: np.ndarray, kind=nib.Nifti1Image, **fields) -> bytes:
    image = kind(values.T, np.diag([0.5, 0.75, 2.0, 1.0]))
    for key, value in fields.items():
        image.header[key] = value
    return image.to_bytes()


NII = [nifti(rng_volume((2, 3, 4), dtype="int16")), nifti(rng_volume((2, 3, 4))),
       nifti(rng_volume((2, 3, 4), dtype=">f4")), nifti(rng_volume((2, 3, 4, 2), dtype="uint16")),
       nifti(rng_volume((2, 3, 4), dtype="int16"), scl_slope=0.5, scl_inter=-3),
       nifti(rng_volume((2, 3, 4), dtype="int16"), kind=nib.Nifti2Image)]
NPZ = []
for arrays in ({"ct": rng_volume((2, 3, 4), dtype="int16")}, {"a": rng_volume((2, 3, 4)), "b": rng_volume((2, 3, 4))}):
    for save in (np.savez, np.savez_compressed):
        buffer = io.BytesIO()
        save(buffer, **arrays)
        NPZ.append(buffer.getvalue())
SLICE = rng_volume((4, 5), dtype="uint16")
DCM = [ct_slice(SLICE, 0.0, "1.2.3"), ct_slice(SLICE.astype(np.int16), 2.0, "1.2.3", big_endian=True),
       ct_slice(SLICE, 4.0, "1.2.3", slope=0.5, intercept=7)]


@pytest.mark.parametrize("name, valid", [("v.nii", NII), ("v.npz", NPZ), ("v.dcm", DCM)])
@FUZZ
@given(data=st.data())
def test_mutations(folder, name, valid, data):
    check(folder, {name: data.draw(st.sampled_from(valid).flatmap(mutated))}, name)


@FUZZ
@given(st.sampled_from(NII).flatmap(mutated).map(gzip.compress) | st.sampled_from(NII).map(gzip.compress)
       .flatmap(mutated))
def test_gzip_mutations(folder, data):
    """The NIfTI inside mutated and then compressed, or the compressed stream mutated."""
    check(folder, {"v.nii.gz": data}, "v.nii.gz")


@FUZZ
@given(st.lists(st.sampled_from(DCM).flatmap(mutated), min_size=1, max_size=3))
def test_series_mutations(folder, slices):
    check(folder, {f"s{i}": s for i, s in enumerate(slices)}, "")  # "": the folder itself, a series


# --- generated headers -------------------------------------------------------------------------------------------

# NIfTI datatype codes: the ones read, the ones refused (complex, RGB, int64...) and none at all.
NIFTI_TYPES = st.sampled_from([2, 4, 8, 16, 64, 256, 512, 768, 32, 128, 1024, 1536, 2304, 0, 7, -1])
ODD_FLOATS = st.sampled_from([0.0, 1.0, -2.5, 1e-30, 1e30, float("nan"), float("inf"), -float("inf"), 3.0])


@st.composite
def nifti_headers(draw) -> bytes:
    """A NIfTI-1 header of any sizes, type, offset, scaling and spacing, then a payload."""
    header = np.frombuffer(nib.Nifti1Header().binaryblock, nib.Nifti1Header.template_dtype).copy()
    sides = draw(st.lists(SIDES.map(lambda n: n % 32768), min_size=0, max_size=7))
    header["dim"][0] = draw(st.just(len(sides)) | st.integers(-2, 9))
    header["dim"][0, 1:1 + len(sides)] = sides
    header["datatype"] = draw(NIFTI_TYPES)
    header["bitpix"] = draw(st.sampled_from([8, 16, 32, 64, 0, 7]))
    header["vox_offset"] = draw(st.sampled_from([352.0, 348.0, 0.0, 400.0, 1e12, -4.0, float("nan")]))
    header["scl_slope"], header["scl_inter"] = draw(ODD_FLOATS), draw(ODD_FLOATS)
    header["pixdim"][0, 1:4] = [draw(ODD_FLOATS) for _ in range(3)]
    header["qform_code"], header["sform_code"] = draw(st.integers(0, 3)), draw(st.integers(-1, 3))
    header["srow_x"][0, 0] = draw(ODD_FLOATS)
    header["magic"] = draw(st.sampled_from([b"n+1", b"ni1", b"n+2", b"xyz", b""]))
    block = header.byteswap().tobytes() if draw(st.booleans()) else header.tobytes()  # either byte order's header
    gap = bytes(draw(st.sampled_from([4, 0, 52])))  # the extension flag, a short file, an extension's room
    product = small_product(sides[:3])
    return block + gap + draw(payload(product * 2 if product >= 0 else -1))


@FUZZ
@given(nifti_headers(), st.booleans())
def test_nifti_headers(folder, data, compressed):
    name = "v.nii.gz" if compressed else "v.nii"
    check(folder, {name: gzip.compress(data) if compressed else data}, name)


@st.composite
def npz_files(draw) -> bytes:
    """A zip of one to three members: generated .npy headers or valid arrays, under .npy names or others."""
    buffer = io.BytesIO()
    method = draw(st.sampled_from([zipfile.ZIP_STORED, zipfile.ZIP_DEFLATED]))
    with zipfile.ZipFile(buffer, "w", method) as zf:
        for i in range(draw(st.integers(1, 3))):
            member = draw(npy_headers() | st.just(npy_bytes(rng_volume((2, 3, 4), dtype="int16"))))
            zf.writestr(draw(st.sampled_from([f"a{i}.npy", f"a{i}", f"d/a{i}.npy"])), member)
    return buffer.getvalue()


@FUZZ
@given(npz_files())
def test_npz_headers(folder, data):
    check(folder, {"v.npz": data}, "v.npz")


US = st.sampled_from([0, 1, 2, 3, 4, 5, 4096, 4097, 65535]) | st.integers(0, 40)
# What pydicom writes (it refuses text that is no number at all: the mutations above make that).
NUMBER_TEXT = st.sampled_from(["1", "0", "-1", "0.5", "1e9", "nan", "inf", "", "1e300", "2.5"])


@st.composite
def dicom_slice(draw, series: str) -> bytes:
    """A CT-like slice of any sizes, pixel layout, geometry and rescale (values as text, as DICOM keeps them)."""
    meta = FileMetaDataset()
    meta.MediaStorageSOPClassUID = CTImageStorage
    meta.MediaStorageSOPInstanceUID = "1.2.3.4"
    meta.TransferSyntaxUID = draw(st.sampled_from([ExplicitVRLittleEndian, ImplicitVRLittleEndian, RLELossless]))
    ds = pydicom.Dataset()
    ds.file_meta = meta
    ds.SOPClassUID, ds.SOPInstanceUID, ds.SeriesInstanceUID, ds.Modality = CTImageStorage, "1.2.3.4", series, "CT"
    ds.Rows, ds.Columns = draw(US), draw(US)
    if draw(st.integers(0, 3)) == 0:
        ds.NumberOfFrames = draw(st.sampled_from(["2", "0", "-1", "4096", "1"]))
    ds.BitsAllocated = draw(st.sampled_from([16, 8, 32, 1, 12, 0]))
    ds.BitsStored, ds.HighBit = ds.BitsAllocated, max(ds.BitsAllocated - 1, 0)
    ds.PixelRepresentation = draw(st.sampled_from([0, 1, 2]))
    ds.SamplesPerPixel = draw(st.sampled_from([1, 3, 0, 4]))
    ds.PhotometricInterpretation = draw(st.sampled_from(["MONOCHROME2", "MONOCHROME1", "RGB", "PALETTE COLOR"]))
    ds.ImageOrientationPatient = draw(st.sampled_from([[1, 0, 0, 0, 1, 0], [0, 1, 0, 0, 0, -1], [1, 0, 0], []]))
    ds.ImagePositionPatient = [0, 0, draw(st.sampled_from([0.0, 1.5, 3.0, 1e300]))]
    ds.PixelSpacing = draw(st.sampled_from([["0.5", "0.5"], ["0", "1"], ["nan", "1"], ["1"], ["1e300", "1"]]))
    ds.RescaleSlope, ds.RescaleIntercept = draw(NUMBER_TEXT), draw(NUMBER_TEXT)
    ds.SliceThickness = draw(NUMBER_TEXT)
    product = small_product([ds.Rows, ds.Columns])
    pixels = draw(payload(product * 2 if product >= 0 else -1))
    ds.PixelData = encapsulate([pixels + b"\0\0"]) if meta.TransferSyntaxUID == RLELossless else pixels
    buffer = io.BytesIO()
    ds.save_as(buffer, enforce_file_format=True)
    return buffer.getvalue()


@FUZZ
@given(st.lists(st.sampled_from(["1.2.3", "1.2.4"]).flatmap(dicom_slice), min_size=1, max_size=3))
def test_dicom_headers(folder, slices):
    check(folder, {f"s{i}.dcm": s for i, s in enumerate(slices)}, "" if len(slices) > 1 else "s0.dcm")
