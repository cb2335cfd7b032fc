"""Volume readers/writers: round trips, variants, malformed files, atomic saves and an R3 fuzz."""
from __future__ import annotations

import bz2
import gzip
import io
import struct
from pathlib import Path

import nrrd
import numpy as np
import pytest
import tifffile
from hypothesis import given, settings
from hypothesis import strategies as st
from PIL import Image

from app.io import atomic
from app.io.volume_formats import SUPPORTED, FormatError, read_volume, write_volume

SHAPE = (3, 7, 5)  # depth, height, width: no two sides alike, so a transposed read cannot pass


def random_volume(seed: int = 0, shape: tuple[int, int, int] = SHAPE) -> np.ndarray:
    return np.random.default_rng(seed).integers(0, 256, shape + (4,), dtype=np.uint8)


def assert_volume(result: np.ndarray, shape: tuple[int, int, int] = SHAPE) -> None:
    assert result.dtype == np.uint8 and result.shape == shape + (4,) and result.flags.c_contiguous


def r3_bytes(volume: np.ndarray) -> bytes:
    d, h, w, _ = volume.shape
    return b"R3" + struct.pack("<HHH", w, h, d) + volume.tobytes()


# --- round trips -----------------------------------------------------------------------------------------------


@pytest.mark.parametrize("name", ["v.r3", "v.raw", "v.npy", "v.tif", "v.tiff", "v.nrrd", "s_%i.png", "s_%d.tga", "s_%03i.PNG"])
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
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s_0.png", "s_1.png", "s_2.png"]
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
    tifffile.imwrite(tmp_path / "planar.tif", planar, photometric="rgb", planarconfig="separate", extrasamples=["unassalpha"])
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
    # 20 bytes claiming 256 GiB: the limit is reported, not the (also true) truncation, so nothing was read or allocated.
    path = write_file(tmp_path / "huge.r3", b"R3" + struct.pack("<HHH", 4096, 4096, 4096) + bytes(12))
    message = refused(path, "4096x4096x4096", "size limit", str(4096**3 * 4))
    assert "truncated" not in message
    refused(write_file(tmp_path / "small.r3", r3_bytes(random_volume())), "size limit", max_bytes=419)
    assert read_volume(tmp_path / "small.r3", max_bytes=420).shape == SHAPE + (4,)


def test_npy_refusals(tmp_path):
    refused(write_file(tmp_path / "junk.npy", b"not numpy at all"), "not a valid .npy")
    np.save(tmp_path / "u16.npy", GREY.astype(np.uint16))
    refused(tmp_path / "u16.npy", "uint16", "8-bit")
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
    np.lib.format.write_array_header_1_0(header, {"descr": "|u1", "fortran_order": False, "shape": (4096, 4096, 4096, 4)})
    refused(write_file(tmp_path / "huge.npy", header.getvalue()), "size limit")


def test_tiff_refusals(tmp_path):
    refused(write_file(tmp_path / "junk.tif", b"II*\x00garbage"), "not a valid TIFF")
    tifffile.imwrite(tmp_path / "u16.tif", GREY.astype(np.uint16), photometric="minisblack")
    refused(tmp_path / "u16.tif", "uint16", "convert it to 8-bit")
    tifffile.imwrite(tmp_path / "hyper.tif", np.zeros((2, 3, 7, 5), np.uint8), photometric="minisblack")
    refused(tmp_path / "hyper.tif", "not a single stack")
    tifffile.imwrite(tmp_path / "big.tif", random_volume(), photometric="rgb")
    refused(tmp_path / "big.tif", "size limit", max_bytes=100)
    tifffile.imwrite(tmp_path / "inverted.tif", GREY, photometric="miniswhite")
    refused(tmp_path / "inverted.tif", "MINISWHITE")


def test_nrrd_refusals(tmp_path):
    refused(write_file(tmp_path / "junk.nrrd", b"\x00" * 100), "not a NRRD file")
    refused(write_file(tmp_path / "noend.nrrd", b"NRRD0004\ntype: uchar"), "header is truncated")
    refused(write_file(tmp_path / "bad.nrrd", b"NRRD0004\ndimension: three\n\n"), "not a valid NRRD header")
    header = "NRRD0004\ntype: {type}\ndimension: 3\nsizes: 5 7 3\nencoding: raw\n{extra}\n"
    raw = header.format(type="uchar", extra="").encode()
    refused(write_file(tmp_path / "short.nrrd", raw + bytes(104)), "truncated", "expected 105", "found 104")
    refused(write_file(tmp_path / "long.nrrd", raw + bytes(106)), "trailing", "found 106")
    short16 = header.format(type="short", extra="").encode() + bytes(210)
    refused(write_file(tmp_path / "short16.nrrd", short16), "short", "8-bit")
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
