"""app.io.png through Pillow: every image comes back RGBA uint8, top row first; bad bytes and huge images are
refused with an OSError that says why."""
import io
import struct
import zlib

import numpy as np
import pytest
from PIL import Image

from app.io import png
from app.io.png import decode_png, encode_png, read_png, write_png

RNG = np.random.default_rng(7)
RGBA = RNG.integers(0, 256, (7, 5, 4), dtype=np.uint8)


def saved(image: Image.Image, image_format: str = "PNG", **options) -> bytes:
    buffer = io.BytesIO()
    image.save(buffer, image_format, **options)
    return buffer.getvalue()


def png_header(width: int, height: int, idat: bytes = b"") -> bytes:
    """A PNG signature and IHDR (8-bit RGBA) claiming width x height, then idat's bytes as its only IDAT."""
    def chunk(kind: bytes, data: bytes) -> bytes:
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))

    ihdr = struct.pack(">IIBBBBB", width, height, 8, 6, 0, 0, 0)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", idat) + chunk(b"IEND", b"")


def test_round_trip_keeps_every_byte_and_the_top_row_first(tmp_path):
    data = encode_png(RGBA)
    assert data.startswith(b"\x89PNG")
    np.testing.assert_array_equal(np.asarray(Image.open(io.BytesIO(data))), RGBA)  # row 0 is the file's top row
    np.testing.assert_array_equal(decode_png(data), RGBA)
    write_png(tmp_path / "a.png", RGBA[:, ::-1])  # any strides
    out = read_png(tmp_path / "a.png")
    assert out.dtype == np.uint8 and out.shape == (7, 5, 4)
    np.testing.assert_array_equal(out, RGBA[:, ::-1])
    assert [p.name for p in tmp_path.iterdir()] == ["a.png"]  # no temporary file left beside it


def test_encode_refuses_what_is_not_rgba():
    with pytest.raises(ValueError, match="height, width, 4"):
        encode_png(RGBA[..., :3])


GREY = RGBA[..., 0].copy()
RGB = RGBA[..., :3].copy()


def rgba_of(rgb: np.ndarray, alpha=255) -> np.ndarray:
    out = np.empty(rgb.shape[:2] + (4,), np.uint8)
    out[..., :3] = rgb if rgb.ndim == 3 else rgb[..., None]
    out[..., 3] = alpha
    return out


@pytest.mark.parametrize("image, expected", [
    (Image.fromarray(RGB), rgba_of(RGB)),
    (Image.fromarray(GREY), rgba_of(GREY)),
    (Image.merge("LA", [Image.fromarray(GREY), Image.fromarray(RGBA[..., 3].copy())]), rgba_of(GREY, RGBA[..., 3])),
    (Image.fromarray(GREY > 127), rgba_of(np.where(GREY > 127, 255, 0).astype(np.uint8))),
], ids=["rgb", "grey", "grey-alpha", "one-bit"])
def test_alpha_less_and_grey_images_come_back_rgba(image, expected):
    out = decode_png(saved(image))
    assert out.dtype == np.uint8
    np.testing.assert_array_equal(out, expected)


def test_palette_images_come_back_rgba_with_their_transparency():
    palette = Image.fromarray(RGB).quantize(16)
    expected = np.asarray(palette.convert("RGBA")).copy()
    np.testing.assert_array_equal(decode_png(saved(palette)), expected)
    expected[np.asarray(palette) == 3, 3] = 0
    np.testing.assert_array_equal(decode_png(saved(palette, transparency=3)), expected)


def test_sixteen_bit_grey_is_scaled_to_eight_bits_not_clipped():
    grey16 = np.array([[0, 128, 129, 32896, 65535], [257, 514, 1000, 40000, 65407]], np.uint16)
    out = decode_png(saved(Image.fromarray(grey16)))
    np.testing.assert_array_equal(out[..., 0], np.rint(grey16 / 257).astype(np.uint8))
    np.testing.assert_array_equal(out[..., 1], out[..., 0])
    assert (out[..., 3] == 255).all()
    keyed = decode_png(saved(Image.fromarray(grey16), transparency=40000))
    np.testing.assert_array_equal(keyed[..., 3], np.where(grey16 == 40000, 0, 255))


@pytest.mark.parametrize("image_format", ["BMP", "GIF", "TGA", "TIFF", "PPM"])
def test_other_lossless_formats_read_too(image_format):
    image = Image.fromarray(RGB).quantize(64).convert("RGB") if image_format == "GIF" else Image.fromarray(RGB)
    np.testing.assert_array_equal(decode_png(saved(image, image_format)), rgba_of(np.asarray(image)))


@pytest.mark.parametrize("data", [b"", b"hello", b"\x89PNG\r\n\x1a\n", saved(Image.fromarray(RGB))[:40]])
def test_bytes_that_are_no_image_are_an_os_error(data):
    with pytest.raises(OSError, match="^not an image Pillow can read$"):
        decode_png(data)


def test_a_damaged_image_is_an_os_error_not_a_crash():
    data = saved(Image.fromarray(RGB), "JPEG")
    with pytest.raises(OSError, match="damaged"):
        decode_png(data[:200])
    with pytest.raises(OSError, match="damaged"):
        decode_png(png_header(5, 7, b"not zlib data"))


def test_formats_outside_the_list_are_not_opened():
    with pytest.raises(OSError, match="not an image Pillow can read"):
        decode_png(saved(Image.fromarray(RGB), "PCX"))


@pytest.mark.filterwarnings("ignore::PIL.Image.DecompressionBombWarning")  # Image.open's, for 10000^2
@pytest.mark.parametrize("side", [8193, 10_000, 20_000, 1 << 30])
def test_a_huge_image_is_refused_from_its_header(side):
    """8193^2 is over MAX_PIXELS, 10000^2 over Pillow's warning bound, 20000^2 over its error bound: all refused."""
    with pytest.raises(OSError, match=rf"{side}x{side} image is over the limit of {png.MAX_PIXELS} pixels"
                       "|decompression bomb"):
        decode_png(png_header(side, side))


def test_the_pixel_bound_is_checked_before_decoding(monkeypatch):
    monkeypatch.setattr(png, "MAX_PIXELS", 34)
    with pytest.raises(OSError, match="a 5x7 image is over the limit of 34 pixels"):
        decode_png(encode_png(RGBA))
    monkeypatch.setattr(png, "MAX_PIXELS", 35)
    np.testing.assert_array_equal(decode_png(encode_png(RGBA)), RGBA)


def test_read_png_names_the_file_it_could_not_read(tmp_path):
    with pytest.raises(OSError, match=r"cannot read image .*missing\.png: No such file or directory"):
        read_png(tmp_path / "missing.png")
    (tmp_path / "junk.png").write_bytes(b"junk")
    with pytest.raises(OSError, match=r"cannot read image .*junk\.png: not an image Pillow can read"):
        read_png(tmp_path / "junk.png")
