"""Writing small DICOM CT slices as a scanner does (pydicom): what the reader tests, the fuzz and
scripts/measure_load_memory.py read back."""
from __future__ import annotations

import io
from pathlib import Path

import numpy as np
import pydicom
from pydicom.dataset import FileMetaDataset
from pydicom.uid import CTImageStorage, ExplicitVRBigEndian, ExplicitVRLittleEndian, generate_uid


def ct_slice(pixels: np.ndarray, position: float, series: str, *, spacing=(0.7, 0.6), orientation=(1, 0, 0, 0, 1, 0),
             slope: float = 1.0, intercept: float = -1024.0, instance: int = 1, big_endian: bool = False) -> bytes:
    """One CT slice file: `pixels` (rows, columns) uint16 or int16 at `position` mm along the slice normal."""
    meta = FileMetaDataset()
    meta.MediaStorageSOPClassUID, meta.MediaStorageSOPInstanceUID = CTImageStorage, generate_uid()
    meta.TransferSyntaxUID = ExplicitVRBigEndian if big_endian else ExplicitVRLittleEndian
    ds = pydicom.Dataset()
    ds.file_meta = meta
    ds.SOPClassUID, ds.SOPInstanceUID = CTImageStorage, meta.MediaStorageSOPInstanceUID
    ds.Modality, ds.SeriesInstanceUID, ds.SeriesDescription = "CT", series, "test series"
    ds.Rows, ds.Columns = pixels.shape
    ds.SamplesPerPixel, ds.PhotometricInterpretation = 1, "MONOCHROME2"
    ds.BitsAllocated, ds.BitsStored, ds.HighBit = 16, 16, 15
    ds.PixelRepresentation = int(pixels.dtype.kind == "i")
    row, column = np.array(orientation[:3], float), np.array(orientation[3:], float)
    ds.ImageOrientationPatient = list(orientation)
    ds.ImagePositionPatient = [float(v) for v in np.cross(row, column) * position]
    ds.PixelSpacing = list(spacing)
    ds.RescaleSlope, ds.RescaleIntercept, ds.InstanceNumber = slope, intercept, instance
    ds.PixelData = pixels.astype(pixels.dtype.newbyteorder(">" if big_endian else "<")).tobytes()
    buffer = io.BytesIO()
    ds.save_as(buffer, enforce_file_format=True)
    return buffer.getvalue()


def write_series(folder: Path, stored: np.ndarray, gap: float = 2.0, **options) -> list[Path]:
    """`stored` (depth, rows, columns) as one series of slice files `gap` mm apart, named out of slice order (as
    scanners' numbering often is); slice z lies at z * gap along the normal."""
    folder.mkdir(parents=True, exist_ok=True)
    series = generate_uid()
    names = np.random.default_rng(len(stored)).permutation(len(stored))
    paths = []
    for z, pixels in enumerate(stored):
        path = folder / f"IM{names[z]:05d}"
        path.write_bytes(ct_slice(pixels, z * gap, series, instance=len(stored) - z, **options))
        paths.append(path)
    return paths
