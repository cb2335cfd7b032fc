"""Weather maps, their blend, blue noise, cirrus and weather PNGs: tileable, deterministic per seed, in range; the
blend linear and without jumps; bad files refused with a WeatherError and nothing else."""
from __future__ import annotations

import io
import itertools
import struct
import zlib

import numpy as np
import pytest
from PIL import Image

from app.io.clouds.weather_image import WeatherError, load_weather, save_weather
from app.model.clouds import noise as cn
from app.model.clouds.blue_noise import blue_noise
from app.model.clouds.weather import WeatherBlend, resample, weather_map


def seam_ratio(a: np.ndarray, axis: int) -> float:
    """Mean |difference| across the wrap seam (last texel to first) over the mean between interior neighbours."""
    n = a.shape[axis]
    seam = np.abs(np.take(a, 0, axis) - np.take(a, n - 1, axis)).mean()
    inner = np.abs(np.diff(a, axis=axis)).mean()
    return float(seam / inner) if inner > 0 else float(seam > 0) * np.inf


@pytest.fixture(scope="module")
def weather64():
    return weather_map(seed=3, size=64)


# Weather maps


def test_weather_map_shape_dtype_and_ranges(weather64):
    assert weather64.shape == (64, 64, 3) and weather64.dtype == np.float32
    assert weather64.min() >= 0.0 and weather64.max() <= 1.0
    for channel in range(3):
        assert weather64[..., channel].std() > 0.01, channel  # none of them flat


@pytest.mark.parametrize("channel", [0, 1, 2])
def test_weather_map_wraps(weather64, channel):
    for axis in range(2):
        assert seam_ratio(weather64[..., channel], axis) < 1.5, axis


def test_the_seam_ratio_catches_a_map_that_does_not_wrap():
    half = weather_map(seed=3, size=128)[:64, :64, 0]  # a piece of a tiling map does not tile
    assert max(seam_ratio(half, axis) for axis in range(2)) > 2


def test_weather_map_is_the_same_for_a_seed_and_differs_between_seeds(weather64):
    assert np.array_equal(weather64, weather_map(seed=3, size=64))
    other = weather_map(seed=4, size=64)
    for channel in range(2):  # rain may be 0 in both where a map has no rain cell nearby
        assert not np.allclose(weather64[..., channel], other[..., channel])


def test_weather_map_progress_rises_to_exactly_one():
    seen: list[float] = []
    weather_map(seed=0, size=32, progress=seen.append)
    assert len(seen) >= 3
    assert all(0 < a <= b for a, b in itertools.pairwise(seen))
    assert seen[-1] == 1.0


@pytest.mark.parametrize("size", [0, 1, 48])
def test_weather_map_sizes_are_powers_of_two(size):
    with pytest.raises(ValueError, match="power of two"):
        weather_map(seed=0, size=size)


def test_resample_keeps_a_map_averages_blocks_and_stays_tileable(weather64):
    assert np.array_equal(resample(weather64, 64), weather64)
    blocks = np.random.default_rng(0).random((4, 4, 3), dtype=np.float32)
    np.testing.assert_allclose(resample(np.repeat(np.repeat(blocks, 8, 0), 8, 1), 4), blocks, atol=1e-6)
    small = resample(weather64, 16)
    np.testing.assert_allclose(small, weather64.reshape(16, 4, 16, 4, 3).mean(axis=(1, 3)), atol=1e-6)
    for size in (24, 128):  # shrinking by a fraction; growing
        a = resample(weather64, size)
        assert a.shape == (size, size, 3) and a.dtype == np.float32
        assert weather64.min() <= a.min() and a.max() <= weather64.max()
        for channel, axis in itertools.product(range(3), range(2)):
            assert seam_ratio(a[..., channel], axis) < 1.5, (size, channel, axis)
    with pytest.raises(ValueError):
        resample(np.zeros((16, 8, 3)), 16)


# The noises it is made of


@pytest.mark.parametrize("frequency", [1, 2, 5, (3, 7)])
def test_simplex_wraps_and_stays_about_within_one(frequency):
    a = cn.simplex(48, frequency, np.random.default_rng(2))  # any size: no blocked lattice
    assert a.shape == (48, 48) and a.dtype == np.float32
    assert np.abs(a).max() <= 1.05 and a.std() > 0.1
    for axis in range(2):
        assert seam_ratio(a, axis) < 1.5, axis


def test_simplex_is_one_function_sampled_at_texel_centres():
    """Texel j of 16 and texel 3j + 1 of 48 share a centre, (2j + 1) / 32 of the tile: the same value there."""
    small, large = (cn.simplex(n, (2, 3), np.random.default_rng(0)) for n in (16, 48))
    np.testing.assert_allclose(large[1::3, 1::3], small, atol=1e-6)


def brute_force_worley_2d(size: int, frequency: int, seed: int) -> np.ndarray:
    points = np.random.default_rng(seed).random((frequency, frequency, 2), dtype=np.float32).astype(np.float64)
    cells = np.stack(np.meshgrid(np.arange(frequency), np.arange(frequency), indexing="ij"), axis=-1)
    features = (cells + points).reshape(-1, 2)
    centres = (np.stack(np.meshgrid(np.arange(size), np.arange(size), indexing="ij"), axis=-1) + 0.5)
    d = (centres * frequency / size).reshape(-1, 1, 2) - features[None]
    d -= frequency * np.round(d / frequency)
    return np.minimum(np.sqrt((d ** 2).sum(-1)).min(1), 1.0).reshape(size, size)


@pytest.mark.parametrize("frequency", [1, 2, 4, 8])
def test_2d_worley_equals_a_brute_force_search(frequency):
    got = cn.worley(16, frequency, np.random.default_rng(5), dim=2)
    np.testing.assert_allclose(got, brute_force_worley_2d(16, frequency, 5), atol=1e-5)


def test_stretched_perlin_wraps_with_its_own_period_per_axis():
    a = cn.perlin(64, (16, 2), np.random.default_rng(0), dim=2)
    for axis in range(2):
        assert seam_ratio(a, axis) < 1.5
    assert np.abs(np.diff(a, axis=0)).mean() > 4 * np.abs(np.diff(a, axis=1)).mean()  # finer across y


# Cirrus


def test_cirrus_is_tileable_in_range_and_the_same_for_a_seed():
    a = cn.cirrus_noise(64, seed=1)
    assert a.shape == (64, 64) and a.dtype == np.float32
    assert a.min() == 0.0 and a.max() == 1.0
    for axis in range(2):
        assert seam_ratio(a, axis) < 1.5, axis
    assert np.array_equal(a, cn.cirrus_noise(64, seed=1))
    assert not np.allclose(a, cn.cirrus_noise(64, seed=2))
    assert np.abs(np.diff(a, axis=0)).mean() > 2 * np.abs(np.diff(a, axis=1)).mean()  # streaks along x


def test_cirrus_progress_rises_to_exactly_one():
    seen: list[float] = []
    cn.cirrus_noise(32, progress=seen.append)
    assert all(0 < a <= b for a, b in itertools.pairwise(seen)) and seen[-1] == 1.0


# The blend


def maps(n: int = 4) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    rng = np.random.default_rng(0)
    return tuple(rng.random((n, n, 3), dtype=np.float32) for _ in range(3))


def test_a_new_blend_starts_at_the_old_map_and_rises_linearly_to_the_new():
    a, b, _ = maps()
    blend = WeatherBlend(a)
    assert blend.weight(0.0) == 1.0 and blend.done(0.0)
    assert np.array_equal(blend.current(5.0), a)
    version = blend.version
    blend.begin(b, clock=10.0, duration=4.0)
    assert blend.version != version
    old, new = blend.maps
    assert np.array_equal(old, a) and np.array_equal(new, b)
    assert [blend.weight(t) for t in (0.0, 10.0, 11.0, 12.0, 13.0, 14.0, 99.0)] == [0, 0, 0.25, 0.5, 0.75, 1, 1]
    assert not blend.done(13.9) and blend.done(14.0)
    np.testing.assert_allclose(blend.current(11.0), 0.75 * a + 0.25 * b, rtol=1e-6)


def test_interrupting_a_blend_starts_from_what_is_on_screen():
    a, b, c = maps()
    blend = WeatherBlend(a)
    blend.begin(b, clock=0.0, duration=10.0)
    before = blend.current(3.0)
    blend.begin(c, clock=3.0, duration=5.0)
    old, new = blend.maps
    w = blend.weight(3.0)
    shown = old * np.float32(1 - w) + new * np.float32(w)  # what the shader's mix draws on the next frame
    np.testing.assert_allclose(shown, before, rtol=0, atol=1e-7)
    np.testing.assert_allclose(old, 0.7 * a + 0.3 * b, atol=1e-6)
    assert np.array_equal(new, c) and blend.weight(5.5) == 0.5


def test_a_blend_of_no_duration_is_done_at_once_and_maps_are_copies():
    a, b, _ = maps()
    blend = WeatherBlend(a)
    blend.begin(b, clock=2.0, duration=0.0)
    assert blend.weight(2.0) == 1.0 and blend.done(2.0)
    b[:] = 0  # the caller's array, changed after the fact
    assert not np.array_equal(blend.maps[1], b)
    with pytest.raises(ValueError):
        blend.maps[0][0, 0, 0] = 1  # read-only: the version counter is the only way maps change


def test_restoring_a_snapshot_brings_back_the_blend_under_a_new_version():
    a, b, c = maps()
    blend = WeatherBlend(a)
    blend.begin(b, clock=0.0, duration=10.0)
    state, seen = blend.snapshot(), {blend.version}
    blend.begin(c, clock=4.0, duration=1.0)
    seen.add(blend.version)
    blend.restore(state)
    assert blend.version not in seen  # a renderer that uploaded any earlier version uploads again
    assert np.array_equal(blend.maps[0], a)
    assert np.array_equal(blend.maps[1], b) and blend.weight(4.0) == 0.4


@pytest.mark.parametrize("bad", [np.zeros((4, 4, 4)), np.zeros((4, 5, 3)), np.zeros((8, 8, 3))])
def test_a_new_map_of_another_shape_is_refused(bad):
    blend = WeatherBlend(maps()[0])
    with pytest.raises(ValueError):
        blend.begin(bad, clock=0.0, duration=1.0)


def test_a_negative_duration_is_refused():
    blend = WeatherBlend(maps()[0])
    with pytest.raises(ValueError):
        blend.begin(maps()[1], clock=0.0, duration=-1.0)


# Blue noise


@pytest.fixture(scope="module")
def blue64():
    return blue_noise(64, seed=0)


def test_blue_noise_holds_every_rank_once(blue64):
    assert blue64.shape == (64, 64) and blue64.dtype == np.float32
    n = blue64.size
    assert np.array_equal(np.sort(blue64.ravel()), ((np.arange(n) + 0.5) / n).astype(np.float32))
    assert 0 < blue64.min() and blue64.max() < 1


def low_frequency_power(a: np.ndarray) -> float:
    """Mean power of the radial frequencies 1 .. size/8 cycles per tile."""
    size = a.shape[0]
    power = np.abs(np.fft.fft2(a - a.mean())) ** 2
    f = np.fft.fftfreq(size) * size
    r = np.hypot(*np.meshgrid(f, f))
    return float(power[(r > 0) & (r <= size / 8)].mean())


def test_blue_noise_has_little_low_frequency_energy(blue64):
    white = np.random.default_rng(1).permutation(blue64.ravel()).reshape(blue64.shape)
    assert low_frequency_power(blue64) < 0.01 * low_frequency_power(white)


def test_blue_noise_spreads_its_points_evenly_across_the_seam(blue64):
    """The first 10% of ranks: no two closer than 2 pixels, measured round the torus (a seam would break it)."""
    ys, xs = np.nonzero(blue64 < 0.1)
    dy = np.abs(ys[:, None] - ys[None]) % 64
    dx = np.abs(xs[:, None] - xs[None]) % 64
    d = np.hypot(np.minimum(dy, 64 - dy), np.minimum(dx, 64 - dx))
    np.fill_diagonal(d, np.inf)
    assert d.min() >= 2.0


def test_blue_noise_is_the_same_for_a_seed(blue64):
    assert np.array_equal(blue64, blue_noise(64, seed=0))
    assert not np.array_equal(blue_noise(16, seed=0), blue_noise(16, seed=1))


# Weather PNGs


def png_bytes(image: Image.Image) -> bytes:
    buffer = io.BytesIO()
    image.save(buffer, "PNG")
    return buffer.getvalue()


def chunk(kind: bytes, data: bytes) -> bytes:
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))


def raw_png(width: int, height: int, depth: int, colour: int, pixels: bytes = b"") -> bytes:
    header = struct.pack(">IIBBBBB", width, height, depth, colour, 0, 0, 0)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(pixels)) + chunk(b"IEND", b"")


def test_a_weather_map_survives_a_png_round_trip(tmp_path):
    a = np.random.default_rng(0).integers(0, 256, (32, 32, 3)).astype(np.float32) / 255
    path = tmp_path / "w.png"
    save_weather(path, a)
    assert np.array_equal(load_weather(path), a)
    with Image.open(path) as image:
        assert image.mode == "RGB" and image.size == (32, 32)
    assert [p.name for p in tmp_path.iterdir()] == ["w.png"]  # no temporary file left


def test_an_rgba_png_and_a_16_bit_rgb_png_are_read(tmp_path):
    rgba = np.random.default_rng(1).integers(0, 256, (16, 16, 4), dtype=np.uint8)
    (tmp_path / "a.png").write_bytes(png_bytes(Image.fromarray(rgba)))
    assert np.array_equal(load_weather(tmp_path / "a.png"), rgba[..., :3] / np.float32(255))
    samples = np.random.default_rng(2).integers(0, 65536, (16, 16, 3)).astype(">u2")
    rows = b"".join(b"\0" + row.tobytes() for row in samples)
    (tmp_path / "b.png").write_bytes(raw_png(16, 16, 16, 2, rows))
    np.testing.assert_allclose(load_weather(tmp_path / "b.png"), samples / 65535, atol=1 / 255 + 1e-6)


def test_a_saved_map_is_clamped_and_a_bad_array_refused(tmp_path):
    save_weather(tmp_path / "w.png", np.full((16, 16, 3), 2.0))
    assert load_weather(tmp_path / "w.png").min() == 1.0
    for bad in (np.zeros((16, 16)), np.zeros((16, 32, 3)), np.zeros((8, 8, 3)), np.full((16, 16, 3), np.nan)):
        with pytest.raises(WeatherError):
            save_weather(tmp_path / "x.png", bad)


def malformed(tmp_path) -> dict[str, object]:
    good = png_bytes(Image.fromarray(np.zeros((32, 32, 3), np.uint8)))
    folder = tmp_path / "folder.png"
    folder.mkdir()
    return {
        "truncated": good[:len(good) // 2],
        "header only": good[:20],
        "text named .png": b"coverage, type, rain\n0.5, 0.5, 0\n",
        "empty": b"",
        "not square": png_bytes(Image.fromarray(np.zeros((16, 32, 3), np.uint8))),
        "too small": png_bytes(Image.fromarray(np.zeros((8, 8, 3), np.uint8))),
        "huge header": raw_png(1 << 20, 1 << 20, 8, 2),
        "huge square under the pixel bound": raw_png(4096, 4096, 8, 2),
        "greyscale": png_bytes(Image.fromarray(np.zeros((32, 32), np.uint8))),
        "palette": png_bytes(Image.fromarray(np.zeros((32, 32, 3), np.uint8)).convert("P")),
        "a JPEG": (lambda b: (Image.new("RGB", (32, 32)).save(b, "JPEG"), b.getvalue())[1])(io.BytesIO()),
        "pixels missing": raw_png(32, 32, 8, 2, b"\0" * 10),
        "bad CRC": good[:29] + bytes([good[29] ^ 0xFF]) + good[30:],
        "missing file": None,
        "a folder": folder,
    }


@pytest.mark.parametrize("case", ["truncated", "header only", "text named .png", "empty", "not square", "too small",
                                  "huge header", "huge square under the pixel bound", "greyscale", "palette",
                                  "a JPEG", "pixels missing", "bad CRC", "missing file", "a folder"])
def test_malformed_files_give_a_weather_error(tmp_path, case):
    content = malformed(tmp_path)[case]
    path = tmp_path / "w.png"
    if isinstance(content, bytes):
        path.write_bytes(content)
    elif content is not None:
        path = content
    with pytest.raises(WeatherError) as caught:
        load_weather(path)
    assert str(caught.value)


def test_damaged_pngs_give_a_weather_error_or_a_map_and_nothing_else(tmp_path):
    good = png_bytes(Image.fromarray(np.random.default_rng(3).integers(0, 256, (16, 16, 3), dtype=np.uint8)))
    rng = np.random.default_rng(4)
    path = tmp_path / "w.png"
    variants = [good[:cut] for cut in range(0, len(good), 7)]
    for _ in range(150):
        data = bytearray(good)
        for at in rng.integers(0, len(good), rng.integers(1, 4)):
            data[at] = rng.integers(0, 256)
        variants.append(bytes(data))
    for data in variants:
        path.write_bytes(data)
        try:
            a = load_weather(path)
        except WeatherError:
            continue
        assert a.shape == (16, 16, 3) and a.dtype == np.float32
