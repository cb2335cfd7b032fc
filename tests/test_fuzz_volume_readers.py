"""Fuzzing every volume reader: EXAMPLES inputs each, half mutated from valid small files (bit flips, byte and
number edits, truncation, junk after the end), half built from generated headers (huge and odd sizes, types,
encodings, tags). Whatever the bytes, a read returns a valid volume within the limit or raises FormatError (any
other exception is an internal error), and the memory it traces stays within PEAK_LIMIT."""
from __future__ import annotations

import bz2
import gzip
import io
import lzma
import math
import shutil
import struct
import tracemalloc
import zlib
from pathlib import Path

import nrrd
import numpy as np
import pytest
import tifffile
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from PIL import Image

from app.io.volume_formats import MAX_SIDE, FormatError, read_volume
from app.model.volume.scalars import SCALAR_TYPES

EXAMPLES = 1000  # per reader
MAX_BYTES = 1 << 20
# Twice the volume, one decoder buffer or LZMA dictionary (each within MAX_BYTES) and a 1 MiB read chunk: the
# most seen is under 3 MiB, inflating NRRD data that was then refused.
PEAK_LIMIT = 3 * MAX_BYTES + (1 << 20)

FUZZ = settings(max_examples=EXAMPLES // 2, deadline=None, suppress_health_check=[HealthCheck.too_slow])


@pytest.fixture(scope="module")
def folder(tmp_path_factory) -> Path:
    return tmp_path_factory.mktemp("fuzz")


def check(folder: Path, files: dict[str, bytes], name: str) -> None:
    """Write files into an emptied folder and read `name`: FormatError, or a valid volume (RGBA, or the scalars of
    a 16-bit or float file), in bounded memory."""
    shutil.rmtree(folder)
    folder.mkdir()
    for file_name, data in files.items():
        (folder / file_name).write_bytes(data)
    tracemalloc.start()
    try:
        volume = read_volume(folder / name, max_bytes=MAX_BYTES)
    except FormatError:
        volume = None
    finally:
        peak = tracemalloc.get_traced_memory()[1]
        tracemalloc.stop()
    assert peak <= PEAK_LIMIT, f"reading traced {peak} bytes"
    if volume is not None and volume.ndim == 3:
        assert volume.dtype in SCALAR_TYPES and volume.dtype.isnative and volume.flags.c_contiguous
        assert all(1 <= n <= MAX_SIDE for n in volume.shape)
        assert volume.size * (4 + volume.itemsize) <= MAX_BYTES  # the scalars and the colours they become
    elif volume is not None:
        assert isinstance(volume, np.ndarray) and volume.dtype == np.uint8 and volume.flags.c_contiguous
        assert volume.ndim == 4 and volume.shape[3] == 4 and all(1 <= n <= MAX_SIDE for n in volume.shape[:3])
        assert volume.nbytes <= MAX_BYTES


# --- mutations of valid files ----------------------------------------------------------------------------------

HUGE_NUMBERS = [b"\xff\xff\xff\xff", b"\xff\xff\xff\x7f", b"\x00\x10\x00\x00", b"\x00\x00\x00\x00", b"\x01\x10"]
HUGE_TEXT = [b"4097", b"65536", b"99999999999999999999", b"-1", b"0", b"1e9"]


@st.composite
def mutated(draw, valid: bytes) -> bytes:
    """Edits mostly in the first 128 bytes, where sizes, offsets and types are; then a cut and some junk."""
    data = bytearray(valid)
    for _ in range(draw(st.integers(0, 6))):
        at = draw(st.integers(0, min(len(data), 128) - 1) | st.integers(0, len(data) - 1))
        edit = draw(st.sampled_from(["flip", "byte", "number", "text"]))
        if edit == "flip":
            data[at] ^= 1 << draw(st.integers(0, 7))
        elif edit == "byte":
            data[at] = draw(st.integers(0, 255))
        else:
            data[at : at + 4] = draw(st.sampled_from(HUGE_NUMBERS if edit == "number" else HUGE_TEXT))
    cut = draw(st.just(len(data)) | st.integers(0, len(data)))
    return bytes(data[:cut]) + draw(st.just(b"") | st.binary(max_size=16))


def rng_volume(shape: tuple[int, ...], seed: int = 0, dtype: str = "uint8") -> np.ndarray:
    return np.random.default_rng(seed).integers(0, 256, shape, dtype=np.uint8).astype(dtype)


def npy_bytes(array: np.ndarray, version: tuple[int, int] | None = None) -> bytes:
    buffer = io.BytesIO()
    if version is None:
        np.save(buffer, array)
    else:
        np.lib.format.write_array(buffer, array, version=version)
    return buffer.getvalue()


def tiff_bytes(array: np.ndarray, **options) -> bytes:
    buffer = io.BytesIO()
    tifffile.imwrite(buffer, array, **options)
    return buffer.getvalue()


def nrrd_bytes(array: np.ndarray, encoding: str) -> bytes:
    buffer = io.BytesIO()
    nrrd.write(buffer, array, {"encoding": encoding}, index_order="C")
    return buffer.getvalue()


def image_bytes(array: np.ndarray, image_format: str) -> bytes:
    buffer = io.BytesIO()
    Image.fromarray(array).save(buffer, image_format)
    return buffer.getvalue()


R3 = [b"R3" + struct.pack("<HHH", 4, 3, 2) + rng_volume((2, 3, 4, 4)).tobytes()]
NPY = [
    npy_bytes(rng_volume((2, 3, 4))),
    npy_bytes(rng_volume((2, 3, 4, 3))),
    npy_bytes(np.asfortranarray(rng_volume((2, 3, 4, 4)))),
    npy_bytes(rng_volume((2, 3, 4)), version=(2, 0)),
    npy_bytes(rng_volume((2, 3, 4), dtype=">i2")),
    npy_bytes(np.asfortranarray(rng_volume((2, 3, 4), dtype="<f8"))),
]
TIFF = [
    tiff_bytes(rng_volume((2, 3, 4)), photometric="minisblack"),
    tiff_bytes(rng_volume((2, 3, 4, 3)), photometric="rgb"),
    tiff_bytes(rng_volume((2, 4, 3, 4)), photometric="rgb", planarconfig="separate", extrasamples=["unassalpha"]),
    tiff_bytes(rng_volume((2, 3, 4)), photometric="minisblack", compression="zlib"),
    tiff_bytes(rng_volume((1, 16, 16)), photometric="minisblack", compression="lzma", tile=(16, 16)),
    tiff_bytes(rng_volume((2, 3, 4), dtype="uint16"), photometric="minisblack"),
    tiff_bytes(rng_volume((2, 3, 4), dtype="float32"), photometric="minisblack", compression="zlib"),
]
NRRD = [nrrd_bytes(rng_volume((2, 3, 4)), "raw"), nrrd_bytes(rng_volume((2, 3, 4, 4)), "gzip"),
        nrrd_bytes(rng_volume((2, 3, 4, 3)), "bzip2"), nrrd_bytes(rng_volume((2, 3, 4), dtype=">i2"), "raw"),
        nrrd_bytes(rng_volume((2, 3, 4), dtype="<f4"), "gzip"), nrrd_bytes(rng_volume((2, 3, 4), dtype="<f8"), "bzip2")]
SLICES = [image_bytes(rng_volume((3, 4, 4)), "PNG"), image_bytes(rng_volume((3, 4)), "PNG"),
          image_bytes(rng_volume((3, 4, 3)), "BMP"), image_bytes(rng_volume((3, 4, 3)), "JPEG"),
          image_bytes(rng_volume((3, 4)), "GIF"), image_bytes(rng_volume((3, 4, 4)), "TGA")]


@pytest.mark.parametrize("name, valid", [("v.r3", R3), ("v.npy", NPY), ("v.tif", TIFF), ("v.nrrd", NRRD)])
@FUZZ
@given(data=st.data())
def test_mutations(folder, name, valid, data):
    check(folder, {name: data.draw(st.sampled_from(valid).flatmap(mutated))}, name)


def series(slices: list[bytes]) -> dict[str, bytes]:
    return {f"s_{z}.png": data for z, data in enumerate(slices)}


@FUZZ
@given(st.lists(st.sampled_from(SLICES).flatmap(mutated), min_size=1, max_size=3))
def test_series_mutations(folder, slices):
    check(folder, series(slices), "s_%i.png")


# --- generated headers -----------------------------------------------------------------------------------------

SIDES = st.sampled_from([0, 1, 2, 3, 4096, 4097, 65535, 2**31, 2**32 + 1, 2**63, -1]) | st.integers(0, 40)


def small_product(sizes) -> int:
    """The number of bytes the sizes declare, or -1 where that is no small whole number."""
    if not all(isinstance(n, int) and 0 <= n < 4096 for n in sizes):
        return -1
    return math.prod(sizes) if math.prod(sizes) <= 4096 else -1


def payload(declared: int):
    """Exactly the declared bytes when that is small, else (and sometimes anyway) a few random ones."""
    exact = st.binary(min_size=declared, max_size=declared) if 0 <= declared <= 4096 else st.nothing()
    return exact | st.binary(max_size=64)


@FUZZ
@given(st.tuples(SIDES, SIDES, SIDES).map(lambda s: tuple(n % 65536 for n in s)).flatmap(
    lambda s: st.tuples(st.just(s), payload(s[0] * s[1] * s[2] * 4))))
def test_r3_headers(folder, case):
    (w, h, d), voxels = case
    check(folder, {"v.r3": b"R3" + struct.pack("<HHH", w, h, d) + voxels}, "v.r3")


NPY_DESCR = {"|u1": 1, "<u1": 1, "|i1": 1, "<u2": 2, ">u2": 2, "<i2": 2, "<f4": 4, ">f8": 8, "<i8": 8, "<c8": 8,
             "<f2": 2, "|b1": 1, "|O": 8, "|V4": 4, "<U3": 12, "|S2": 2, "bogus": 1}  # descr: bytes a voxel


@st.composite
def npy_headers(draw) -> bytes:
    shape = draw(st.lists(SIDES, max_size=5).map(tuple) | st.sampled_from(["(4,)", None, (2.5, 1)]))
    descr = draw(st.sampled_from(sorted(NPY_DESCR)) | st.sampled_from([[("a", "|u1")], 7]))
    header = repr({"descr": descr, "fortran_order": draw(st.sampled_from([False, True, 0, "no"])),
                   "shape": shape}).encode("latin1")
    major = draw(st.sampled_from([1, 2, 3, 0, 255]))
    length = struct.pack("<H" if major == 1 else "<I", len(header) + 1)
    if draw(st.booleans()):  # a length field that lies
        length = draw(st.binary(min_size=len(length), max_size=len(length)))
    product = small_product(shape) if isinstance(shape, tuple) else -1
    voxels = draw(payload(product * NPY_DESCR.get(descr, 1) if isinstance(descr, str) and product >= 0 else product))
    return b"\x93NUMPY" + bytes([major, 0]) + length + header + b"\n" + voxels


@FUZZ
@given(npy_headers())
def test_npy_headers(folder, data):
    check(folder, {"v.npy": data}, "v.npy")


NRRD_FIELDS = st.sampled_from([
    "endian: big", "endian: little", "space: left-posterior-superior", "kinds: domain domain domain",
    "data file: other.raw", "line skip: 1", "byte skip: -1", "spacings: 1 1 1", "space dimension: 3",
    "space directions: (1,0,0) (0,1,0) (0,0,1)", "space origin: (0,0,0)", "# a comment", "key:=value",
    "block size: 3", "centerings: cell cell cell", "units: mm", "labels: a b c", "min: 0", "thicknesses: 1",
    "dimension: 3", "type: float", "encoding: ascii", "sizes: 4096 4096 4096", "bogus field: 1", "sizes:", ":",
])


NRRD_TYPES = {"uchar": 1, "unsigned char": 1, "uint8": 1, "signed char": 1, "short": 2, "ushort": 2, "int": 4,
              "float": 4, "double": 8, "int64": 8, "block": 1, "": 1}


@st.composite
def nrrd_headers(draw) -> bytes:
    sizes = draw(st.lists(SIDES, max_size=5))
    kind = draw(st.sampled_from(sorted(NRRD_TYPES)))
    lines = [
        draw(st.sampled_from(["NRRD0004", "NRRD0001", "NRRD0005", "NRRDxyz"])),
        "type: " + kind,
        "dimension: " + draw(st.sampled_from([str(len(sizes)), "3", "-1", "three", "99999999999"])),
        "sizes: " + " ".join(map(str, sizes)),
        "encoding: " + draw(st.sampled_from(["raw", "gzip", "gz", "bzip2", "bz2", "ascii", "hex", "zip"])),
        *draw(st.sampled_from([["endian: little"], ["endian: big"], ["endian: middle"], []])),  # wider types need one
        *draw(st.lists(NRRD_FIELDS, max_size=3)),
    ]
    lines = draw(st.permutations(lines[1:]).map(lambda rest: lines[:1] + rest))
    product = small_product(sizes)
    voxels = draw(payload(product * NRRD_TYPES[kind] if product >= 0 else -1))
    voxels = draw(st.sampled_from([voxels, gzip.compress(voxels), bz2.compress(voxels), zlib.compress(voxels)]))
    return ("\n".join(lines) + "\n\n").encode() + voxels


@FUZZ
@given(nrrd_headers())
def test_nrrd_headers(folder, data):
    check(folder, {"v.nrrd": data}, "v.nrrd")


# TIFF: an image file header and one IFD of (tag, type, count, value) entries, the image data after it. The values
# make a valid 4x3 greyscale image in one strip, or in one 16x16 tile; 273 and 324 (offsets) point at the data.
TIFF_COMMON = {256: 4, 257: 3, 258: 8, 259: 1, 262: 1, 277: 1, 284: 1, 338: 2, 339: 1}
TIFF_STRIPS = {**TIFF_COMMON, 273: 0, 278: 3, 279: 12}
TIFF_TILES = {**TIFF_COMMON, 322: 16, 323: 16, 324: 0, 325: 256}
TIFF_TYPES = st.sampled_from([3, 4]) | st.sampled_from([1, 2, 5, 7, 16, 0, 99])


def tiff_file(entries: list[tuple[int, int, int, int]], data: bytes, order: str = "<") -> bytes:
    """Little- or big-endian TIFF: header, IFD at 8, data after the IFD (value 0 for 273 and 324 means there)."""
    data_at = 8 + 2 + 12 * len(entries) + 4
    packed = [struct.pack(order + "HHII", tag, kind, count, data_at if tag in (273, 324) and value == 0 else value)
              for tag, kind, count, value in entries]
    magic = b"II*\x00" if order == "<" else b"MM\x00*"
    return magic + struct.pack(order + "IH", 8, len(entries)) + b"".join(packed) + struct.pack(order + "I", 0) + data


# BitsPerSample and SampleFormat (1 uint, 2 int, 3 float)
TIFF_SAMPLES = [(8, 1), (16, 1), (16, 2), (32, 3), (64, 3), (32, 1), (64, 2)]


@st.composite
def tiff_headers(draw) -> bytes:
    entries = []
    bits, sample_format = draw(st.sampled_from(TIFF_SAMPLES))
    size = bits // 8
    layout = draw(st.sampled_from([TIFF_STRIPS, TIFF_TILES]))
    layout = {**layout, 258: bits, 339: sample_format,
              **{tag: layout[tag] * size for tag in (279, 325) if tag in layout}}  # byte counts
    for tag, value in sorted(layout.items()):
        if draw(st.integers(0, 9)) == 0:  # a tag left out
            continue
        edited = draw(st.integers(0, 3)) == 0
        kind = draw(TIFF_TYPES) if edited else 4
        count = draw(SIDES.map(lambda n: n % 2**32)) if edited and draw(st.booleans()) else 1
        entries.append((tag, kind, count, draw(SIDES.map(lambda n: n % 2**32)) if edited else value))
    compression = draw(st.sampled_from([1, 8, 34925, 5, 32773]))
    entries = [(t, k, c, compression if t == 259 and v == 1 else v) for t, k, c, v in entries]
    voxels = draw(payload(12 * size) | payload(256 * size))
    data = {1: voxels, 8: zlib.compress(voxels), 34925: lzma.compress(voxels)}.get(compression, voxels)
    return tiff_file(entries, data, draw(st.sampled_from("<>")))


@FUZZ
@given(tiff_headers())
def test_tiff_headers(folder, data):
    check(folder, {"v.tif": data}, "v.tif")


def png_chunk(kind: bytes, body: bytes) -> bytes:
    return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))


@st.composite
def png_headers(draw) -> bytes:
    """A PNG with valid checksums, so the decoder goes past them: any sizes, depths and colour types."""
    width, height = draw(SIDES.map(lambda n: n % 2**31)), draw(SIDES.map(lambda n: n % 2**31))
    depth, colour = draw(st.sampled_from([1, 2, 4, 8, 16, 3])), draw(st.sampled_from([0, 2, 3, 4, 6, 5]))
    ihdr = struct.pack(">IIBBBBB", width, height, depth, colour, 0, 0, draw(st.sampled_from([0, 1])))
    rows = draw(payload(min(width * height * 4 + height, 5000) if width * height < 1000 else -1))
    chunks = [png_chunk(b"IHDR", ihdr)]
    if colour == 3:
        chunks.append(png_chunk(b"PLTE", draw(st.binary(max_size=30))))
    chunks += [png_chunk(b"IDAT", zlib.compress(rows)), png_chunk(b"IEND", b"")]
    return b"\x89PNG\r\n\x1a\n" + b"".join(chunks)


@FUZZ
@given(st.lists(png_headers(), min_size=1, max_size=3))
def test_series_headers(folder, slices):
    check(folder, series(slices), "s_%i.png")


# --- targeted cases --------------------------------------------------------------------------------------------


@pytest.mark.parametrize("compression, inflate", [(8, zlib.compress), (34925, lzma.compress)])
def test_a_tiff_strip_that_inflates_beyond_its_page_is_refused_without_inflating_it(folder, compression, inflate):
    entries = [(tag, 4, 1, compression if tag == 259 else value) for tag, value in sorted(TIFF_STRIPS.items())]
    bomb = inflate(bytes(64 << 20))  # 64 MiB of zeros in a 4x3 image's strip
    entries = [(t, k, c, len(bomb) if t == 279 else v) for t, k, c, v in entries]
    check(folder, {"v.tif": tiff_file(entries, bomb)}, "v.tif")
    with pytest.raises(FormatError, match="more than its 12 bytes"):
        read_volume(folder / "v.tif")


def test_a_tiff_tile_over_the_limit_is_refused_before_it_is_allocated(folder):
    tiles = {**TIFF_TILES, 322: 1 << 16, 323: 1 << 16}  # 65536 x 65536 tiles for a 4x3 image
    entries = [(tag, 4, 1, value) for tag, value in sorted(tiles.items())]
    check(folder, {"v.tif": tiff_file(entries, bytes(12))}, "v.tif")
    with pytest.raises(FormatError, match="tile"):
        read_volume(folder / "v.tif")


@pytest.mark.parametrize("name, data", [
    ("v.npy", b"\x93NUMPY\x02\x00" + struct.pack("<I", 0xFFFFFFF0) + b"{'descr': '|u1'"),  # a 4 GiB header
    ("s_%i.png", SLICES[0][:33] + struct.pack(">I", 0x7FFFFFF0) + SLICES[0][37:]),  # a 2 GiB image data chunk
])
def test_a_length_field_far_past_the_end_of_the_file_allocates_nothing(folder, name, data):
    """A read of n bytes allocated n before reading: numpy and Pillow ask for as many as a length field says."""
    check(folder, {name.replace("%i", "0"): data}, name)
