"""Volume readers/writers: round trips, variants, malformed files, atomic saves and an R3 fuzz."""
from __future__ import annotations

import bz2
import gzip
import io
import math
import os
import struct
import threading
import tracemalloc
from collections.abc import Callable
from pathlib import Path

import nrrd
import numpy as np
import pytest
import tifffile
from hypothesis import given, settings
from hypothesis import strategies as st
from PIL import Image

from app.io import atomic
from app.io.volume_formats import SUPPORTED, FormatError, read_volume, read_volume_file, write_volume
from app.model.volume.scalars import TransferFunction

SHAPE = (3, 7, 5)  # depth, height, width: no two sides alike, so a transposed read cannot pass


def random_volume(seed: int = 0, shape: tuple[int, int, int] = SHAPE) -> np.ndarray:
    return np.random.default_rng(seed).integers(0, 256, shape + (4,), dtype=np.uint8)


def assert_volume(result: np.ndarray, shape: tuple[int, int, int] = SHAPE) -> None:
    assert result.dtype == np.uint8 and result.shape == shape + (4,) and result.flags.c_contiguous


def r3_bytes(volume: np.ndarray) -> bytes:
    d, h, w, _ = volume.shape
    return b"R3" + struct.pack("<HHH", w, h, d) + volume.tobytes()


# --- round trips -----------------------------------------------------------------------------------------------


@pytest.mark.parametrize("name", ["v.r3", "v.raw", "v.npy", "v.tif", "v.tiff", "v.nrrd",
                                  "s_%i.png", "s_%d.tga", "s_%03i.PNG"])
def test_lossless_round_trip(tmp_path, name):
    volume = random_volume()
    write_volume(tmp_path / name, volume)
    result = read_volume(tmp_path / name)
    assert_volume(result)
    np.testing.assert_array_equal(result, volume)


def test_r3_layout_is_header_then_rgba_voxels_in_z_y_x_order(tmp_path):
    volume = random_volume()
    write_volume(tmp_path / "v.r3", volume)
    data = (tmp_path / "v.r3").read_bytes()
    assert data[:8] == b"R3" + struct.pack("<HHH", 5, 7, 3)
    assert data[8:12] == volume[0, 0, 0].tobytes() and data[12:16] == volume[0, 0, 1].tobytes()
    assert len(data) == 8 + 3 * 7 * 5 * 4


def test_bmp_keeps_rgb_and_reads_alpha_as_opaque(tmp_path):
    volume = random_volume()
    write_volume(tmp_path / "s_%i.bmp", volume)
    result = read_volume(tmp_path / "s_%i.bmp")
    assert_volume(result)
    np.testing.assert_array_equal(result[..., :3], volume[..., :3])
    assert (result[..., 3] == 255).all()


def test_jpeg_is_close_and_opaque(tmp_path):
    z, y, x = np.mgrid[0:3, 0:7, 0:5]
    volume = np.stack([x * 50, y * 30, z * 80, np.full_like(x, 7)], axis=-1).astype(np.uint8)  # smooth, as JPEG likes
    write_volume(tmp_path / "s_%i.jpg", volume)
    result = read_volume(tmp_path / "s_%i.jpg")
    assert_volume(result)
    assert np.abs(result[..., :3].astype(int) - volume[..., :3]).max() <= 12
    assert (result[..., 3] == 255).all()


def test_gif_with_few_colours_and_on_off_alpha_round_trips(tmp_path):
    rng = np.random.default_rng(1)
    palette = np.array([[0, 0, 0, 0], [255, 0, 0, 255], [10, 200, 30, 255], [40, 50, 250, 255]], np.uint8)
    volume = palette[rng.integers(0, 4, SHAPE)]
    write_volume(tmp_path / "s_%i.gif", volume)
    np.testing.assert_array_equal(read_volume(tmp_path / "s_%i.gif"), volume)


def test_nrrd_is_readable_by_pynrrd_in_c_order(tmp_path):
    volume = random_volume()
    write_volume(tmp_path / "v.nrrd", volume)
    data, header = nrrd.read(str(tmp_path / "v.nrrd"), index_order="C")
    assert list(header["sizes"]) == [4, 5, 7, 3]
    np.testing.assert_array_equal(data, volume)


def test_single_voxel_volume(tmp_path):
    volume = random_volume(shape=(1, 1, 1))
    for name in ["v.r3", "v.npy", "v.tif", "v.nrrd", "s_%i.png"]:
        write_volume(tmp_path / name, volume)
        np.testing.assert_array_equal(read_volume(tmp_path / name), volume)


def test_series_writer_removes_slices_of_a_deeper_volume(tmp_path):
    write_volume(tmp_path / "s_%i.png", random_volume(shape=(5, 7, 5)))
    volume = random_volume(1)
    write_volume(tmp_path / "s_%i.png", volume)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s_%i.png.series.json", "s_0.png", "s_1.png", "s_2.png"]
    np.testing.assert_array_equal(read_volume(tmp_path / "s_%i.png"), volume)


# --- greyscale and RGB variants --------------------------------------------------------------------------------

GREY = np.random.default_rng(2).integers(0, 256, SHAPE, dtype=np.uint8)
GREY[0, 0, :3] = 0  # some empty voxels, which must come out transparent
RGB = np.random.default_rng(3).integers(0, 256, SHAPE + (3,), dtype=np.uint8)


def expected_grey() -> np.ndarray:
    alpha = np.where(GREY > 0, 255, 0).astype(np.uint8)
    return np.stack([GREY, GREY, GREY, alpha], axis=-1)


def expected_rgb() -> np.ndarray:
    return np.concatenate([RGB, np.full(SHAPE + (1,), 255, np.uint8)], axis=-1)


def save_npy(path: Path, array: np.ndarray) -> None:
    np.save(path, array)


def save_tiff(path: Path, array: np.ndarray) -> None:
    tifffile.imwrite(path, array, photometric="rgb" if array.ndim == 4 else "minisblack")


def save_nrrd(path: Path, array: np.ndarray, encoding: str = "gzip") -> None:
    nrrd.write(str(path), array, {"encoding": encoding}, index_order="C")


@pytest.mark.parametrize("ext, save", [(".npy", save_npy), (".tif", save_tiff), (".nrrd", save_nrrd)])
@pytest.mark.parametrize("array, expected", [(GREY, expected_grey), (RGB, expected_rgb)], ids=["grey", "rgb"])
def test_array_formats_read_grey_and_rgb(tmp_path, ext, save, array, expected):
    save(tmp_path / f"v{ext}", array)
    result = read_volume(tmp_path / f"v{ext}")
    assert_volume(result)
    np.testing.assert_array_equal(result, expected())


@pytest.mark.parametrize("encoding", ["raw", "gzip", "bzip2"])
def test_nrrd_encodings(tmp_path, encoding):
    volume = random_volume()
    nrrd.write(str(tmp_path / "v.nrrd"), volume, {"encoding": encoding}, index_order="C")
    np.testing.assert_array_equal(read_volume(tmp_path / "v.nrrd"), volume)


def test_fortran_ordered_npy(tmp_path):
    volume = random_volume()
    np.save(tmp_path / "v.npy", np.asfortranarray(volume))
    result = read_volume(tmp_path / "v.npy")
    assert result.flags.c_contiguous
    np.testing.assert_array_equal(result, volume)


def test_tiff_single_page_and_planar_rgba(tmp_path):
    tifffile.imwrite(tmp_path / "page.tif", GREY[1])
    np.testing.assert_array_equal(read_volume(tmp_path / "page.tif"), expected_grey()[1:2])
    volume = random_volume()
    planar = np.moveaxis(volume, -1, 1).copy()  # (d, 4, h, w), stored one colour plane after another
    tifffile.imwrite(tmp_path / "planar.tif", planar, photometric="rgb", planarconfig="separate",
                     extrasamples=["unassalpha"])
    np.testing.assert_array_equal(read_volume(tmp_path / "planar.tif"), volume)


def test_image_series_of_grey_rgb_and_palette_pngs(tmp_path):
    for z in range(3):
        Image.fromarray(GREY[z]).save(tmp_path / f"l_{z}.png")
        Image.fromarray(RGB[z]).save(tmp_path / f"rgb_{z}.png")
    grey = read_volume(tmp_path / "l_%i.png")
    np.testing.assert_array_equal(grey[..., :3], np.stack([GREY] * 3, axis=-1))
    assert (grey[..., 3] == 255).all()  # a picture's black is opaque, unlike a density volume's zero
    np.testing.assert_array_equal(read_volume(tmp_path / "rgb_%i.png"), expected_rgb())

    palette = Image.new("P", (5, 7))
    palette.putpalette([0, 0, 0, 255, 0, 0])
    palette.putpixel((1, 2), 1)
    palette.save(tmp_path / "p_0.png", transparency=0)
    result = read_volume(tmp_path / "p_%i.png")
    assert tuple(result[0, 2, 1]) == (255, 0, 0, 255) and result[0, 0, 0, 3] == 0


# --- scalar volumes: 16-bit and float greyscale ----------------------------------------------------------------

SCALAR_DTYPES = ["int8", "uint16", "int16", "uint32", "int32", "float32", "float64"]


def scalar_array(dtype: str, order: str = "=") -> np.ndarray:
    """Values spread over much of the type's range, negative ones where it has them, NaN and infinities in floats."""
    info = np.iinfo(dtype) if np.dtype(dtype).kind in "iu" else np.finfo(dtype)
    values = np.random.default_rng(7).uniform(max(info.min, -1e6), min(info.max, 1e6), SHAPE).astype(dtype)
    if values.dtype.kind == "f":
        values[0, 0, :3] = (np.nan, np.inf, -np.inf)
    return values.astype(values.dtype.newbyteorder(order))


def save_nrrd_scalars(encoding: str) -> Callable[[Path, np.ndarray], None]:
    return lambda path, array: save_nrrd(path, array, encoding)


@pytest.mark.parametrize("dtype", SCALAR_DTYPES)
@pytest.mark.parametrize("order", ["<", ">"])
@pytest.mark.parametrize("name, save", [
    ("v.npy", save_npy), ("raw.nrrd", save_nrrd_scalars("raw")), ("gzip.nrrd", save_nrrd_scalars("gzip")),
    ("bzip2.nrrd", save_nrrd_scalars("bzip2")),
    ("v.tif", lambda path, array: tifffile.imwrite(path, array, photometric="minisblack",
                                                   byteorder=array.dtype.byteorder.replace("|", "<"))),
    ("zlib.tif", lambda path, array: tifffile.imwrite(path, array, photometric="minisblack", compression="zlib")),
])
def test_scalar_files_read_as_their_values_in_native_byte_order(tmp_path, dtype, order, name, save):
    values = scalar_array(dtype, order)
    save(tmp_path / name, values)
    result = read_volume(tmp_path / name)
    assert result.dtype == np.dtype(dtype) and result.dtype.isnative and result.flags.c_contiguous
    np.testing.assert_array_equal(result, values)


@pytest.mark.parametrize("dtype", SCALAR_DTYPES)
@pytest.mark.parametrize("name", ["v.npy", "v.nrrd", "v.tif", "v.tiff"])
def test_scalars_round_trip(tmp_path, dtype, name):
    values = scalar_array(dtype)
    write_volume(tmp_path / name, values)
    np.testing.assert_array_equal(read_volume(tmp_path / name), values)
    if name.endswith(".nrrd"):  # readable by others, in the same order as colour volumes
        data, header = nrrd.read(str(tmp_path / name), index_order="C")
        assert list(header["sizes"]) == [5, 7, 3] and data.dtype == values.dtype


def test_nrrd_keeps_the_scalars_window_and_colour_map_and_the_other_formats_do_not(tmp_path):
    values, transfer = scalar_array("float32"), TransferFunction(-0.1, 1 / 3, "bone")  # 1/3: a repr to keep exact
    for name in ("v.nrrd", "v.npy", "v.tif"):
        write_volume(tmp_path / name, values, transfer)
        read = read_volume_file(tmp_path / name)
        np.testing.assert_array_equal(read.data, values)
        assert read.transfer == (transfer if name == "v.nrrd" else None)
    _data, header = nrrd.read(str(tmp_path / "v.nrrd"), index_order="C")  # a key/value field others pass over
    assert header["shadelab_window"] == "-0.1 0.3333333333333333 bone"
    assert read_volume_file(tmp_path / "v.nrrd").transfer.high == 1 / 3
    write_volume(tmp_path / "plain.nrrd", values)
    assert read_volume_file(tmp_path / "plain.nrrd").transfer is None
    with pytest.raises(FormatError, match="a window goes with scalars"):
        write_volume(tmp_path / "rgba.nrrd", random_volume(), transfer)
    assert not (tmp_path / "rgba.nrrd").exists()


@pytest.mark.parametrize("field, dtype, needle", [
    ("1 2", "int16", "must be 'low high colour-map'"),
    ("1 2 grey x", "int16", "must be 'low high colour-map'"),
    ("1 2 grey", "uint8", "with uint8 voxels"),
    ("one 2 grey", "int16", "could not convert string to float"),
    ("5 1 grey", "int16", "low must be below its high, got 5 1"),
    ("nan 1 grey", "int16", "must be finite"),
    ("1 2 jet", "int16", "no colour map 'jet'; choose one of grey"),
])
def test_a_malformed_nrrd_window_is_refused(tmp_path, field, dtype, needle):
    path = tmp_path / "v.nrrd"
    nrrd.write(str(path), np.zeros((2, 3, 4), dtype), {"encoding": "raw", "shadelab_window": field},
               index_order="C")
    refused(path, "shadelab_window", needle)


@pytest.mark.parametrize("name", ["v.r3", "s_%i.png"])
def test_scalars_are_not_written_to_colour_formats(tmp_path, name):
    with pytest.raises(FormatError, match=r"int16 scalars go into \.npy, \.nrrd, \.tif, \.tiff files"):
        write_volume(tmp_path / name, scalar_array("int16"))
    assert not list(tmp_path.iterdir())


def test_the_size_limit_counts_the_values_and_a_label_byte(tmp_path):
    save_nrrd(tmp_path / "v.nrrd", scalar_array("float64"))
    voxels = math.prod(SHAPE)
    refused(tmp_path / "v.nrrd", "its values and a label byte a voxel", str(voxels * 9), max_bytes=voxels * 9 - 1)
    assert read_volume(tmp_path / "v.nrrd", max_bytes=voxels * 9).shape == SHAPE


# --- malformed files -------------------------------------------------------------------------------------------


def write_file(path: Path, data: bytes) -> Path:
    path.write_bytes(data)
    return path


def refused(path: Path, *fragments: str, max_bytes: int = 2 * 2**30, culprit: str = "") -> str:
    """Reading path raises FormatError naming the file (or the culprit slice) and containing every fragment."""
    with pytest.raises(FormatError) as info:
        read_volume(path, max_bytes=max_bytes)
    message = str(info.value)
    assert (culprit or path.name) in message
    for fragment in fragments:
        assert fragment in message
    return message


def test_r3_refusals(tmp_path):
    good = r3_bytes(random_volume())
    refused(write_file(tmp_path / "magic.r3", b"R4" + good[2:]), "'R3'")
    refused(write_file(tmp_path / "empty.r3", b""), "'R3'")
    refused(write_file(tmp_path / "header.r3", good[:5]), "header is truncated")
    refused(write_file(tmp_path / "zero.r3", b"R3" + struct.pack("<HHH", 5, 0, 3)), "5x0x3", "empty side")
    refused(write_file(tmp_path / "wide.r3", b"R3" + struct.pack("<HHH", 5000, 1, 1)), "4096")
    refused(write_file(tmp_path / "short.raw", good[:-3]), "truncated", "expected 420", "found 417")
    refused(write_file(tmp_path / "long.r3", good + b"xyz"), "trailing", "expected 420", "found 423")


def test_r3_header_over_the_size_limit_is_refused_before_reading(tmp_path):
    # 20 bytes claiming 256 GiB: the limit is reported, not the (also true) truncation, so nothing was read or
    # allocated.
    path = write_file(tmp_path / "huge.r3", b"R3" + struct.pack("<HHH", 4096, 4096, 4096) + bytes(12))
    message = refused(path, "4096x4096x4096", "size limit", str(4096**3 * 4))
    assert "truncated" not in message
    refused(write_file(tmp_path / "small.r3", r3_bytes(random_volume())), "size limit", max_bytes=419)
    assert read_volume(tmp_path / "small.r3", max_bytes=420).shape == SHAPE + (4,)


def test_npy_refusals(tmp_path):
    refused(write_file(tmp_path / "junk.npy", b"not numpy at all"), "not a valid .npy")
    np.save(tmp_path / "i64.npy", GREY.astype(np.int64))
    refused(tmp_path / "i64.npy", "int64", "8-bit", "float32")
    np.save(tmp_path / "u16rgb.npy", RGB.astype(np.uint16))
    refused(tmp_path / "u16rgb.npy", "not a scalar volume", "(3, 7, 5, 3)")
    np.save(tmp_path / "flat.npy", GREY[0])
    refused(tmp_path / "flat.npy", "(7, 5)", "not a volume")
    np.save(tmp_path / "two.npy", np.zeros(SHAPE + (2,), np.uint8))
    refused(tmp_path / "two.npy", "not a volume")
    np.save(tmp_path / "objects.npy", np.array([None, 1], dtype=object), allow_pickle=True)
    refused(tmp_path / "objects.npy", "object")
    np.save(tmp_path / "cut.npy", random_volume())
    write_file(tmp_path / "cut.npy", (tmp_path / "cut.npy").read_bytes()[:-10])
    refused(tmp_path / "cut.npy", "not a valid .npy")

    header = io.BytesIO()
    np.lib.format.write_array_header_1_0(header, {"descr": "|u1", "fortran_order": False,
                                                  "shape": (4096, 4096, 4096, 4)})
    refused(write_file(tmp_path / "huge.npy", header.getvalue()), "size limit")


def test_tiff_refusals(tmp_path):
    refused(write_file(tmp_path / "junk.tif", b"II*\x00garbage"), "not a valid TIFF")
    tifffile.imwrite(tmp_path / "u16rgb.tif", RGB.astype(np.uint16), photometric="rgb")
    refused(tmp_path / "u16rgb.tif", "uint16", "not a scalar volume")
    tifffile.imwrite(tmp_path / "c64.tif", GREY.astype(np.complex64), photometric="minisblack")
    refused(tmp_path / "c64.tif", "complex64", "8-bit")
    tifffile.imwrite(tmp_path / "hyper.tif", np.zeros((2, 3, 7, 5), np.uint8), photometric="minisblack")
    refused(tmp_path / "hyper.tif", "not a single stack")
    tifffile.imwrite(tmp_path / "big.tif", random_volume(), photometric="rgb")
    refused(tmp_path / "big.tif", "size limit", max_bytes=100)
    tifffile.imwrite(tmp_path / "inverted.tif", GREY, photometric="miniswhite")
    refused(tmp_path / "inverted.tif", "MINISWHITE")


def test_a_tiff_page_chain_that_loops_back_is_refused_not_followed_for_ever():
    # Found by test_fuzz_volume_readers: a mutated 2-page file whose second IFD, inside the first one's entries,
    # names itself as the next page; tifffile's `series` followed it for ever.
    with pytest.raises(FormatError, match="not a valid TIFF file"):
        read_volume(Path(__file__).parent / "fixtures" / "tiff_ifd_loop.tif")


def test_nrrd_refusals(tmp_path):
    refused(write_file(tmp_path / "junk.nrrd", b"\x00" * 100), "not a NRRD file")
    refused(write_file(tmp_path / "noend.nrrd", b"NRRD0004\ntype: uchar"), "header is truncated")
    refused(write_file(tmp_path / "bad.nrrd", b"NRRD0004\ndimension: three\n\n"), "not a valid NRRD header")
    header = "NRRD0004\ntype: {type}\ndimension: 3\nsizes: 5 7 3\nencoding: raw\n{extra}\n"
    raw = header.format(type="uchar", extra="").encode()
    refused(write_file(tmp_path / "short.nrrd", raw + bytes(104)), "truncated", "expected 105", "found 104")
    refused(write_file(tmp_path / "long.nrrd", raw + bytes(106)), "trailing", "found 106")
    long64 = header.format(type="int64", extra="endian: little\n").encode() + bytes(840)
    refused(write_file(tmp_path / "long64.nrrd", long64), "int64", "8-bit", "float64")
    short16 = header.format(type="short", extra="").encode() + bytes(210)
    refused(write_file(tmp_path / "short16.nrrd", short16), "short", "endian: little", "None")
    refused(write_file(tmp_path / "middle.nrrd", header.format(type="short", extra="endian: middle\n").encode()
                       + bytes(210)), "'middle'")
    short_cut = header.format(type="short", extra="endian: little\n").encode()
    refused(write_file(tmp_path / "shortcut.nrrd", short_cut + bytes(209)), "truncated", "expected 210", "found 209")
    refused(write_file(tmp_path / "colour16.nrrd", b"NRRD0004\ntype: short\nendian: big\ndimension: 4\n"
                       b"sizes: 4 5 7 3\nencoding: raw\n\n" + bytes(840)), "not a scalar volume")
    detached = header.format(type="uchar", extra="data file: /etc/passwd\n").encode()
    refused(write_file(tmp_path / "detached.nrrd", detached), "detached")
    huge = b"NRRD0004\ntype: uchar\ndimension: 3\nsizes: 4096 4096 4096\nencoding: raw\n\n"
    refused(write_file(tmp_path / "huge.nrrd", huge), "size limit")
    write_volume(tmp_path / "cut.nrrd", random_volume())
    refused(write_file(tmp_path / "cut.nrrd", (tmp_path / "cut.nrrd").read_bytes()[:-20]), "truncated")


def test_nrrd_gzip_bomb_is_refused_without_inflating_it(tmp_path):
    header = b"NRRD0004\ntype: uchar\ndimension: 3\nsizes: 5 7 3\nencoding: gzip\n\n"
    bomb = gzip.compress(bytes(50 * 2**20))  # 50 MiB of zeros in ~50 KiB
    refused(write_file(tmp_path / "bomb.nrrd", header + bomb), "more than the 105 bytes")
    bz_header = header.replace(b"gzip", b"bzip2")
    refused(write_file(tmp_path / "tail.nrrd", bz_header + bz2.compress(bytes(105)) + b"junk"), "trailing")


@pytest.mark.parametrize("name", ["v.r3", "v.npy", "v.tif", "v.nrrd", "s_%i.png", "s_%i.tga", "s_%i.gif"])
def test_every_truncation_is_refused_or_complete(tmp_path, name):
    """Cut a valid file at every length: the reader either refuses it or (cut after the pixels) returns all of it."""
    volume = random_volume()
    write_volume(tmp_path / name, volume)
    target = tmp_path / name.replace("%i", "1")  # for series, damage the middle slice
    data = target.read_bytes()
    expected = read_volume(tmp_path / name)
    for n in range(len(data)):
        target.write_bytes(data[:n])
        try:
            result = read_volume(tmp_path / name)
        except FormatError as exc:
            assert target.name in str(exc)
        else:
            np.testing.assert_array_equal(result, expected)


def test_missing_files_and_unknown_types(tmp_path):
    for name in ["none.r3", "none.raw", "none.npy", "none.tif", "none.nrrd"]:
        assert str(tmp_path / name) in refused(tmp_path / name, "cannot read", "No such file or directory")
    refused(tmp_path / "none_%i.png", "slice 0", "none_0.png", "No such file or directory")
    message = refused(write_file(tmp_path / "v.xyz", b"R3"), "unsupported file type .xyz")
    assert all(ext in message for ext in SUPPORTED)
    refused(tmp_path / "plain.png", "%i")
    with pytest.raises(FormatError, match="unsupported"):
        write_volume(tmp_path / "v.xyz", random_volume())


def test_series_refusals_and_numbering(tmp_path):
    for z in (1, 2):
        Image.fromarray(RGB[z]).save(tmp_path / f"nozero_{z}.png")
    refused(tmp_path / "nozero_%i.png", "slice 0")

    for z, size in enumerate([(5, 7), (5, 7), (6, 7), (5, 8)]):
        Image.new("RGB", size).save(tmp_path / f"odd_{z}.png")
    refused(tmp_path / "odd_%i.png", "6x7", "but slice 0", "odd_0.png", "5x7", culprit="odd_2.png")

    for z in (0, 1, 3):  # slice 2 is missing: the volume ends at 1
        Image.fromarray(RGB[z % 3]).save(tmp_path / f"gap_{z:03d}.png")
    result = read_volume(tmp_path / "gap_%03i.png")
    np.testing.assert_array_equal(result[..., :3], RGB[:2])
    refused(tmp_path / "gap_%i.png", "slice 0")  # unpadded names do not match gap_000.png

    write_file(tmp_path / "junk_0.png", b"\x89PNG not really")
    refused(tmp_path / "junk_%i.png", "is not a BMP, PNG, JPEG, GIF or TGA image", culprit="junk_0.png")
    Image.fromarray(GREY[0].astype(np.uint16) * 200).save(tmp_path / "deep_0.png")
    refused(tmp_path / "deep_%i.png", "8-bit", culprit="deep_0.png")
    Image.fromarray(RGB[0]).save(tmp_path / "big_0.png")
    refused(tmp_path / "big_%i.png", "size limit", max_bytes=100)


# --- only regular files, read within bounds ---------------------------------------------------------------------


def read_without_hanging(path: Path, seconds: float = 30.0) -> str:
    """read_volume(path)'s FormatError message; a read that blocks fails the test instead of hanging the run."""
    outcome: dict[str, str] = {}

    def read() -> None:
        try:
            read_volume(path)
        except FormatError as exc:
            outcome["message"] = str(exc)

    thread = threading.Thread(target=read, daemon=True)
    thread.start()
    thread.join(seconds)
    if thread.is_alive():
        with open(path, "wb"):  # the writer a FIFO's reader waits for: the blocked open returns
            pass
        thread.join()
        pytest.fail(f"reading {path.name} blocked")
    assert "message" in outcome, f"{path.name} was read as a volume"
    return outcome["message"]


def test_a_fifo_is_refused_without_waiting_for_a_writer(tmp_path):
    os.mkfifo(tmp_path / "pipe.r3")
    message = read_without_hanging(tmp_path / "pipe.r3")
    assert "pipe.r3" in message and "FIFO" in message and "not a regular file" in message


@pytest.mark.parametrize("name", ["zero.r3", "zero.npy", "zero.tif", "zero.nrrd"])
def test_devices_and_folders_are_refused(tmp_path, name):
    (tmp_path / name).symlink_to("/dev/zero")
    assert "is a device, not a regular file" in read_without_hanging(tmp_path / name)
    (tmp_path / f"folder{Path(name).suffix}").mkdir()
    assert "is a folder, not a regular file" in read_without_hanging(tmp_path / f"folder{Path(name).suffix}")


def test_a_file_far_bigger_than_any_volume_within_the_limit_is_refused_unread(tmp_path):
    save_tiff(tmp_path / "padded.tif", GREY)
    with open(tmp_path / "padded.tif", "ab") as f:  # tifffile would read past data nobody points to
        f.write(bytes(2 << 20))
    refused(tmp_path / "padded.tif", "over the size limit of 1050576 bytes", max_bytes=1000)
    assert read_volume(tmp_path / "padded.tif").shape == SHAPE + (4,)


# --- memory -----------------------------------------------------------------------------------------------------

PEAK_SHAPE = (64, 64, 64)
PEAK_SLACK = 64 << 10  # bytes: decoders' own buffers and Python objects


def traced_peak(read: Callable[[], np.ndarray]) -> tuple[np.ndarray, int]:
    """read()'s result and the most memory traced while it ran: numpy reports its arrays to tracemalloc."""
    tracemalloc.start()
    try:
        result = read()
        return result, tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()


@pytest.mark.parametrize("name, channels, dtype, save", [
    ("gzip.nrrd", (), "uint8", lambda path, array: save_nrrd(path, array)),
    ("raw.nrrd", (), "uint8", lambda path, array: save_nrrd(path, array, "raw")),
    ("bzip2.nrrd", (3,), "uint8", lambda path, array: save_nrrd(path, array, "bzip2")),
    ("grey.npy", (), "uint8", save_npy),
    ("rgb.npy", (3,), "uint8", save_npy),
    ("grey.tif", (), "uint8", save_tiff),
    ("rgb.tif", (3,), "uint8", save_tiff),
    ("v.r3", (4,), "uint8", write_volume),
    ("s_%i.png", (4,), "uint8", write_volume),
    # scalars come back as they are: the volume returned is the scalars
    ("int16.nrrd", (), ">i2", lambda path, array: save_nrrd(path, array)),
    ("uint16.nrrd", (), "<u2", lambda path, array: save_nrrd(path, array, "bzip2")),
    ("float32.nrrd", (), ">f4", lambda path, array: save_nrrd(path, array, "raw")),
    ("float64.npy", (), ">f8", save_npy),
    ("int16.tif", (), "<i2", save_tiff),
])
def test_a_read_peaks_within_twice_the_volume(tmp_path, name, channels, dtype, save):
    # 8x4096x4096 grey gzip NRRD peaked at 3.5 times its 512 MiB volume: an int64 np.where made the alpha.
    array = np.random.default_rng(5).integers(0, 3, PEAK_SHAPE + channels).astype(dtype)
    save(tmp_path / name, array)
    result, peak = traced_peak(lambda: read_volume(tmp_path / name))
    assert result.shape == (PEAK_SHAPE + (4,) if dtype == "uint8" else PEAK_SHAPE)
    assert peak <= 2 * result.nbytes + PEAK_SLACK, f"peak {peak} for a {result.nbytes}-byte volume"


# --- numbered series: pattern and manifest --------------------------------------------------------------------


@pytest.mark.parametrize("pattern", ["s_%010i.png", "s_%0500000000i.png", "s_%0" + "9" * 5000 + "i.png"])
def test_series_number_width_is_capped_before_a_name_is_made(tmp_path, pattern):
    for action in (lambda: read_volume(tmp_path / pattern), lambda: write_volume(tmp_path / pattern, random_volume())):
        with pytest.raises(FormatError, match="padded to 9 digits at most") as info:
            traced_peak(action)
        assert pattern[:6] in str(info.value)
    _, peak = traced_peak(lambda: refused(tmp_path / pattern, "%09i"))
    assert peak < 1 << 20  # %0500000000i used to build 500-million-character names
    write_volume(tmp_path / "s_%09i.png", random_volume())
    assert (tmp_path / "s_000000002.png").is_file()
    np.testing.assert_array_equal(read_volume(tmp_path / "s_%09i.png"), random_volume())


class FailAfter:
    """Stands in for an os function: the first `calls` calls go through, then every call fails as a full disk."""

    def __init__(self, real: Callable, calls: int) -> None:
        self.real, self.calls = real, calls

    def __call__(self, *args):
        self.calls -= 1
        if self.calls < 0:
            raise OSError(28, "No space left on device")
        return self.real(*args)


@pytest.mark.parametrize("written", [0, 1, 3])
def test_a_series_save_that_fails_writing_leaves_the_old_series(tmp_path, monkeypatch, written):
    old = random_volume(shape=(5, 7, 5))
    write_volume(tmp_path / "s_%i.png", old)
    monkeypatch.setattr(atomic.os, "fsync", FailAfter(os.fsync, written))  # the disk fills after `written` slices
    with pytest.raises(FormatError, match="No space left on device"):
        write_volume(tmp_path / "s_%i.png", random_volume(1))
    monkeypatch.undo()
    np.testing.assert_array_equal(read_volume(tmp_path / "s_%i.png"), old)
    assert not [p for p in tmp_path.iterdir() if p.name.endswith(".tmp")]


@pytest.mark.parametrize("renamed", [1, 2, 3])  # the manifest, then slices 0 and 1
def test_a_series_save_cut_short_while_renaming_is_refused_not_mixed(tmp_path, monkeypatch, renamed):
    write_volume(tmp_path / "s_%i.png", random_volume(shape=(5, 7, 5)))
    monkeypatch.setattr(atomic.os, "replace", FailAfter(os.replace, renamed))  # as if the power went
    with pytest.raises(FormatError):
        write_volume(tmp_path / "s_%i.png", random_volume(1))
    monkeypatch.undo()
    message = refused(tmp_path / "s_%i.png", "not the ones saved together", culprit=f"s_{renamed - 1}.png")
    assert "s_%i.png.series.json" in message


def test_a_series_changed_by_another_program_is_refused_until_its_manifest_goes(tmp_path):
    volume = random_volume()
    write_volume(tmp_path / "s_%i.png", volume)
    Image.fromarray(volume[1, ..., ::-1].copy()).save(tmp_path / "s_1.png")
    refused(tmp_path / "s_%i.png", "is not the slice s_%i.png.series.json lists", "delete s_%i.png.series.json",
            culprit="s_1.png")
    write_volume(tmp_path / "s_%d.png", volume)  # the same files by another spelling: the same manifest
    Image.fromarray(volume[0]).save(tmp_path / "s_3.png")
    refused(tmp_path / "s_%i.png", "4 slices found, s_%i.png.series.json lists 3")
    (tmp_path / "s_%i.png.series.json").unlink()
    assert read_volume(tmp_path / "s_%i.png").shape == (4, 7, 5, 4)
    write_file(tmp_path / "s_%i.png.series.json", b'{"format": "shadelab-image-series", "version": 1, "sha256": 3}')
    refused(tmp_path / "s_%i.png", "sha256: expected a list, got a number", culprit="s_%i.png.series.json")


# --- atomic writes ---------------------------------------------------------------------------------------------


@pytest.mark.parametrize("name", ["v.r3", "v.npy", "v.tif", "v.nrrd", "s_%i.png"])
def test_failed_write_leaves_the_good_file_untouched(tmp_path, monkeypatch, name):
    write_volume(tmp_path / name, random_volume())
    target = tmp_path / name.replace("%i", "0")
    good = target.read_bytes()

    with pytest.raises(FormatError, match="uint8"):
        write_volume(tmp_path / name, random_volume().astype(np.float32))
    with pytest.raises(FormatError, match=r"\(depth, height, width, 4\)"):
        write_volume(tmp_path / name, random_volume()[..., :3])
    with pytest.raises(FormatError, match="empty side"):
        write_volume(tmp_path / name, np.zeros((0, 2, 2, 4), np.uint8))

    def disk_full(fd: int) -> None:
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(atomic.os, "fsync", disk_full)
    with pytest.raises(FormatError, match="cannot write .*No space left on device"):
        write_volume(tmp_path / name, random_volume(1))
    assert target.read_bytes() == good
    assert not [p for p in tmp_path.iterdir() if p.name.endswith(".tmp")]


# --- R3 fuzz ---------------------------------------------------------------------------------------------------

FUZZ_LIMIT = 64 * 1024
VALID_R3 = r3_bytes(random_volume(4, (2, 3, 4)))


@pytest.fixture(scope="module")
def fuzz_path(tmp_path_factory) -> Path:
    return tmp_path_factory.mktemp("r3-fuzz") / "fuzz.r3"  # one file, rewritten by every example


def check_r3(path: Path, data: bytes) -> None:
    """Valid data parses into exactly what its header describes; anything else raises FormatError."""
    path.write_bytes(data)
    try:
        result = read_volume(path, max_bytes=FUZZ_LIMIT)
    except FormatError as exc:
        assert path.name in str(exc)
        return
    w, h, d = struct.unpack("<HHH", data[2:8])
    assert data[:2] == b"R3" and result.shape == (d, h, w, 4) and result.dtype == np.uint8
    assert result.nbytes <= FUZZ_LIMIT and result.tobytes() == data[8:]


@settings(max_examples=300, deadline=1000)  # ms: a hang fails the test
@given(st.binary(max_size=300))
def test_r3_fuzz_arbitrary_bytes(fuzz_path, data):
    check_r3(fuzz_path, data)
    check_r3(fuzz_path, b"R3" + data)


@settings(max_examples=300, deadline=1000)  # ms: a hang fails the test
@given(
    cut=st.integers(0, len(VALID_R3)),
    flips=st.lists(st.tuples(st.integers(0, 7), st.integers(0, 255)), max_size=3),
    tail=st.binary(max_size=8),
)
def test_r3_fuzz_mutations_of_a_valid_file(fuzz_path, cut, flips, tail):
    data = bytearray(VALID_R3)
    for index, value in flips:  # header bytes: magic and sizes
        data[index] = value
    check_r3(fuzz_path, bytes(data[:cut]) + tail)
