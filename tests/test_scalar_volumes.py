"""Scalar volumes in the editor: 16-bit and float files load through a transfer function (window and colour map),
the window changes without reloading, each change is one undo step, malformed files change nothing, and a window
change uploads the volume once. (Painting a scan paints labels over it: tests/test_volume_labels.py.)"""
from __future__ import annotations

import gzip
import tracemalloc

import nrrd
import numpy as np
import pytest
import tifffile

from app.console.demo import VirtualClock
from app.editor import Editor
from app.gl.volume.raytracer import RayTracer
from app.gl.core.shaders import ShaderLibrary
from app.io.volume_formats import read_volume
from app.model.volume import voxels as voxels_model
from app.model.volume.render_modes import TraceSettings
from app.model.volume.scalars import COLORMAPS, TransferFunction, colour, default_window
from app.model.volume.view import VolumeView
from app.model.volume.volume import Volume
from app.resources import SHADERS

SHAPE = (16, 18, 20)  # depth, height, width: no two sides alike
# Per dtype: the background (the volume's minimum), the first object value and the step between object values.
# The object holds 101 values base + k * step, k = 0..100, so its 1st and 99th percentiles are k = 1 and k = 99.
PHANTOMS = {
    "int8": (-128, -50, 1),
    "uint16": (0, 1000, 7),
    "int16": (-3024, -1000, 20),
    "uint32": (0, 1_000_000, 1000),
    "int32": (-2_000_000, -500_000, 10_000),
    "float32": (-1.0, 0.5, 0.25),
    "float64": (-1e3, -2.0, 0.125),
}


def phantom(dtype: str) -> np.ndarray:
    background, base, step = PHANTOMS[dtype]
    values = np.full(SHAPE, background, dtype)
    spots = np.random.default_rng(3).choice(values.size, 101, replace=False)
    values.reshape(-1)[spots] = base + step * np.arange(101)
    return values


def grey(values: np.ndarray, low: float, high: float) -> np.ndarray:
    """The grey colour map's RGBA, computed directly: level = round(255 t), t the place in the window, alpha = level."""
    t = np.clip((values.astype(np.float64) - low) / (high - low), 0.0, 1.0)
    t[np.isnan(t)] = 0.0
    level = np.floor(t * 255 + 0.5).astype(np.uint8)
    return np.stack([level] * 4, axis=-1)


def volume(editor: Editor) -> Volume:
    return editor.workspaces["volume"].volume


def errors(editor: Editor) -> list[str]:
    return [line.text for line in editor.console.log if line.level == "error"]


def infos(editor: Editor) -> list[str]:
    return [line.text for line in editor.console.log if line.level == "info"]


WRITERS = {
    "npy": lambda path, values: np.save(path, values),
    "nrrd": lambda path, values: nrrd.write(str(path), values, {"encoding": "gzip"}, index_order="C"),
    "raw.nrrd": lambda path, values: nrrd.write(str(path), values, {"encoding": "raw"}, index_order="C"),
    "tif": lambda path, values: tifffile.imwrite(path, values, photometric="minisblack"),
}


def load(editor: Editor, tmp_path, values: np.ndarray, name: str) -> Volume:
    """Write values to tmp_path/name in the format of its extension, load it in the editor; the volume."""
    WRITERS[name.partition(".")[2]](tmp_path / name, values)
    assert editor.execute(f"load {name}")
    return volume(editor)


@pytest.mark.parametrize("dtype", sorted(PHANTOMS))
@pytest.mark.parametrize("kind", sorted(WRITERS))
def test_each_dtype_and_format_loads_through_the_default_window(volume_editor, tmp_path, dtype, kind):
    values = phantom(dtype)
    vol = load(volume_editor, tmp_path, values, f"scan.{kind}")
    np.testing.assert_array_equal(vol.voxels.scalars.values, values)
    assert vol.voxels.scalars.values.dtype == values.dtype and vol.voxels.size == SHAPE[::-1]
    _background, base, step = PHANTOMS[dtype]
    assert vol.voxels.scalars.transfer == TransferFunction(base + step, base + 99 * step, "grey")  # percentiles 1, 99
    expected = grey(values, base + step, base + 99 * step)
    # 16-bit values are placed in float32: a level exactly between two may round the other way
    assert np.abs(vol.voxels.data.astype(int) - expected).max() <= 1
    assert (vol.voxels.data[values == values.min()] == 0).all()  # the background is transparent
    assert f"window {base + step:g}..{base + 99 * step:g}" in infos(volume_editor)[-1]


def test_the_window_changes_without_reloading_and_each_change_is_one_undo_step(volume_editor, tmp_path):
    values = phantom("int16")
    vol = load(volume_editor, tmp_path, values, "ct.nrrd")
    (tmp_path / "ct.nrrd").unlink()  # nothing is read again
    loaded, depth = vol.voxels.data.copy(), vol.history.undo_depth
    assert volume_editor.execute("vol.window -1000 20")  # 255 levels over 1020: exact quarters
    np.testing.assert_array_equal(vol.voxels.data, grey(values, -1000, 20))
    assert volume_editor.execute("vol.colormap viridis")
    viridis = COLORMAPS["viridis"]
    assert tuple(vol.voxels.data[values >= 20][0]) == (*viridis[-1][1], 255)  # at the top of the window: opaque
    assert tuple(vol.voxels.data[values <= -1000][0]) == (*viridis[0][1], 0)  # at the bottom: transparent
    windowed = vol.voxels.data.copy()
    assert vol.history.undo_depth == depth + 2
    assert volume_editor.execute("undo") and volume_editor.execute("undo")
    np.testing.assert_array_equal(vol.voxels.data, loaded)
    assert vol.voxels.scalars.transfer == TransferFunction(*default_window(values))
    assert volume_editor.execute("redo") and volume_editor.execute("redo")
    np.testing.assert_array_equal(vol.voxels.data, windowed)
    assert volume_editor.execute("vol.window.auto")
    assert vol.voxels.scalars.transfer == TransferFunction(*default_window(values), "viridis")
    np.testing.assert_array_equal(vol.voxels.scalars.values, values)


def test_a_window_step_keeps_no_voxels(volume_editor, tmp_path):
    vol = load(volume_editor, tmp_path, phantom("float32"), "v.npy")
    held = vol.history.nbytes
    for low in range(10):
        assert volume_editor.execute(f"vol.window {low * 0.1} 30")
    assert vol.history.nbytes == held  # the colours are made again from the scalars, not stored


def test_the_history_counts_a_scalar_step_the_same_going_out_as_coming_in():
    vol = Volume.new(2, 2, 2)
    vol.replace_scalars(phantom("float64"))  # its step holds the 2x2x2 image; undone, it holds the scalar volume
    vol.paint.stroke_label("z", 0, 3, 1, [(1, 1)])  # its step holds the labels it changed
    assert vol.history.undo() and vol.history.undo()
    vol.paint.set_voxel(0, 0, 0, (1, 2, 3, 255))  # drops both redo steps
    assert vol.history.nbytes == sum(step.nbytes for step in vol.history._undo) == 4  # the one voxel


def test_window_and_colour_map_refusals_change_nothing(volume_editor, tmp_path):
    vol = load(volume_editor, tmp_path, phantom("uint16"), "v.npy")
    before = (vol.voxels.digest(), vol.history.undo_depth)
    for line, needle in (("vol.window 5 5", "low must be below its high"), ("vol.window 9 2", "below"),
                         ("vol.window 3", "low and high"), ("vol.window 1 inf", "finite"),
                         ("vol.colormap jet", "grey, hot, bone, viridis")):
        assert not volume_editor.execute(line)
        assert needle in errors(volume_editor)[-1]
    assert (vol.voxels.digest(), vol.history.undo_depth) == before
    assert volume_editor.execute("vol.window")  # shows it
    assert infos(volume_editor)[-1] == "window 1007..1693 of uint16 scalars 0..1700, colour map grey"


def test_nan_is_transparent_and_infinities_clamp(volume_editor, tmp_path):
    values = phantom("float32")
    values[0, 0, :3] = (np.nan, np.inf, -np.inf)
    vol = load(volume_editor, tmp_path, values, "v.nrrd")
    assert vol.voxels.scalars.transfer == TransferFunction(0.75, 25.25)  # the finite values' percentiles
    assert [tuple(c) for c in vol.voxels.data[0, 0, :3]] == [(0, 0, 0, 0), (255, 255, 255, 255), (0, 0, 0, 0)]
    assert volume_editor.execute("vol.window")
    assert "float32 scalars -inf..inf" in infos(volume_editor)[-1]


@pytest.mark.parametrize("values, window", [
    (np.full((2, 3, 4), 7, np.int16), (7, 8)),  # one value: the window starts there
    (np.arange(24, dtype=np.uint16).reshape(2, 3, 4) % 2, (0, 1)),  # a mask: its two values
    (np.full((2, 3, 4), np.nan, np.float32), (0, 1)),  # no value at all
])
def test_the_default_window_of_degenerate_volumes(values, window):
    assert default_window(values) == window


def test_rotations_turn_the_scalars_with_the_voxels(volume_editor, tmp_path):
    values = phantom("uint16")
    vol = load(volume_editor, tmp_path, values, "v.npy")
    depth = vol.history.undo_depth
    for turn, axis in enumerate("xyz"):
        low = 1000 + turn
        assert volume_editor.execute(f"vol.window {low} {low + 255 * 4}")
        assert volume_editor.execute(f"rotate {axis}")
        # the turned scalars give the turned colours: they turned the same way
        np.testing.assert_array_equal(vol.voxels.data, grey(vol.voxels.scalars.values, low, low + 255 * 4))
    for _ in range(6):
        assert volume_editor.execute("undo")
    assert vol.history.undo_depth == depth
    np.testing.assert_array_equal(vol.voxels.scalars.values, values)


def malformed_files(tmp_path) -> list[tuple[str, str]]:
    """(file name, what the refusal says) for scalar files that must not load."""
    header = "NRRD0004\ntype: {type}\ndimension: 3\nsizes: 4 3 2\nencoding: {encoding}\n{extra}\n"
    files = {
        "noendian.nrrd": (header.format(type="short", encoding="raw", extra="").encode() + bytes(48), "endian"),
        "int64.nrrd": (header.format(type="int64", encoding="raw", extra="endian: little\n").encode() + bytes(192),
                       "int64"),
        "short.nrrd": (header.format(type="float", encoding="raw", extra="endian: little\n").encode() + bytes(95),
                       "truncated"),
        "long.nrrd": (header.format(type="ushort", encoding="gzip", extra="endian: big\n").encode()
                      + gzip.compress(bytes(49)), "more than the 48 bytes"),
    }
    for name, (data, _needle) in files.items():
        (tmp_path / name).write_bytes(data)
    np.save(tmp_path / "int64.npy", np.zeros((2, 3, 4), np.int64))
    np.save(tmp_path / "pairs.npy", np.zeros((2, 3, 4, 2), np.int16))
    tifffile.imwrite(tmp_path / "rgb16.tif", np.zeros((2, 3, 4, 3), np.uint16), photometric="rgb")
    return [(name, needle) for name, (_data, needle) in files.items()] + [
        ("int64.npy", "int64"), ("pairs.npy", "not a scalar volume"), ("rgb16.tif", "not a scalar volume")]


def test_malformed_scalar_files_are_refused_and_change_nothing(volume_editor, tmp_path):
    vol = load(volume_editor, tmp_path, phantom("int16"), "good.npy")
    before = (vol.voxels.digest(), vol.history.undo_depth, vol.voxels.scalars)
    for name, needle in malformed_files(tmp_path):
        assert not volume_editor.execute(f"load {name}")
        assert name in errors(volume_editor)[-1] and needle in errors(volume_editor)[-1], errors(volume_editor)[-1]
        assert (vol.voxels.digest(), vol.history.undo_depth, vol.voxels.scalars) == before


def test_a_scalar_volume_over_the_memory_limit_is_refused_before_reading(volume_editor, tmp_path, monkeypatch):
    values = phantom("float64")
    WRITERS["nrrd"](tmp_path / "big.nrrd", values)
    monkeypatch.setattr(voxels_model, "MAX_BYTES", values.size * 12 - 1)  # room for its colours, not its scalars too
    before = volume(volume_editor).voxels.digest()
    assert not volume_editor.execute("load big.nrrd")
    assert "its scalars and their colours" in errors(volume_editor)[-1]
    assert volume(volume_editor).voxels.digest() == before
    with pytest.raises(voxels_model.VolumeError, match="RGBA data, scalars and labels"):
        volume(volume_editor).replace_scalars(values)
    monkeypatch.setattr(voxels_model, "MAX_BYTES", values.size * 13 - 1)  # no room for a label a voxel
    assert not volume_editor.execute("load big.nrrd")
    assert "RGBA data, scalars and labels" in errors(volume_editor)[-1]
    assert volume(volume_editor).voxels.digest() == before
    monkeypatch.setattr(voxels_model, "MAX_BYTES", values.size * 13)
    assert volume_editor.execute("load big.nrrd")


def test_save_writes_the_scalars_where_the_format_holds_them_and_the_colours_elsewhere(volume_editor, tmp_path):
    values = phantom("int16")
    load(volume_editor, tmp_path, values, "in.npy")
    volume_editor.execute("vol.window -1000 20; save out.nrrd; save out.npy; save out.r3")
    np.testing.assert_array_equal(read_volume(tmp_path / "out.nrrd"), values)
    np.testing.assert_array_equal(read_volume(tmp_path / "out.npy"), values)
    np.testing.assert_array_equal(read_volume(tmp_path / "out.r3"), grey(values, -1000, 20))
    assert "the colours of window -1000..20" in infos(volume_editor)[-1]
    assert "the int16 scalars (the window is not kept in the file; .nrrd keeps it)" in infos(volume_editor)[-2]
    assert "the int16 scalars and their window -1000..20, grey" in infos(volume_editor)[-3]


def test_a_scalar_volume_saved_to_nrrd_loads_again_with_its_window(volume_editor, tmp_path):
    values = phantom("float32")
    load(volume_editor, tmp_path, values, "in.npy")
    assert volume_editor.execute("vol.window 0.5 9.125; vol.colormap viridis; save kept.nrrd; sample coords3d 8")
    assert volume_editor.execute("load kept.nrrd")
    vol = volume(volume_editor)
    assert vol.voxels.scalars.transfer == TransferFunction(0.5, 9.125, "viridis")
    np.testing.assert_array_equal(vol.voxels.scalars.values, values)
    assert "window 0.5..9.125 (kept in the file), viridis" in infos(volume_editor)[-1]


def test_an_autosaved_scalar_volume_recovers_as_scalars_with_its_window(volume_editor, tmp_path):
    """The autosave keeps the scalars and the window (an .nrrd, not the .r3 of colours it was), so the recovered
    volume windows again; a tampered window is refused like any malformed file, changing nothing."""
    values = phantom("int16")
    load(volume_editor, tmp_path, values, "ct.npy")
    assert volume_editor.execute("vol.window -990 -20; vol.colormap hot")
    folder = tmp_path / "session"
    assert volume_editor.documents.autosave(folder) == 1
    assert sorted(p.name for p in folder.iterdir()) == ["autosave.json", "volume.nrrd"]
    fresh = Editor(clock=VirtualClock(), configs=False)
    [scene] = fresh.documents.recoverable(folder)
    assert fresh.execute(f"recover {scene.file} {scene.original}"), errors(fresh)
    recovered = volume(fresh)
    np.testing.assert_array_equal(recovered.voxels.scalars.values, values)
    assert recovered.voxels.scalars.transfer == TransferFunction(-990, -20, "hot")
    assert fresh.digest()["volume"] == volume_editor.digest()["volume"]
    assert fresh.documents.path(fresh.current) == str(tmp_path / "ct.npy") and fresh.documents.modified(fresh.current)
    assert fresh.execute("vol.window 0 100") and recovered.voxels.scalars.transfer.low == 0  # still windows

    tampered = (folder / "volume.nrrd").read_bytes().replace(b"-990.0 -20.0 hot", b"-20.0 -990.0 hot")
    (folder / "volume.nrrd").write_bytes(tampered)
    before = fresh.digest()
    assert not fresh.execute(f"recover {scene.file} {scene.original}")
    assert "shadelab_window field: the window's low must be below its high" in errors(fresh)[-1]
    assert fresh.digest() == before

    assert volume_editor.execute("label.voxel 1 1 1 3")  # labels over the scan: kept beside its .nrrd
    assert volume_editor.documents.autosave(folder) == 1
    assert sorted(p.name for p in folder.iterdir()) == ["autosave.json", "volume.nrrd", "volume.seg.nrrd"]
    again = Editor(clock=VirtualClock(), configs=False)
    [scene] = again.documents.recoverable(folder)
    assert again.execute(f"recover {scene.file} {scene.original}"), errors(again)
    assert volume(again).voxels.label_at(1, 1, 1) == 3 and again.digest()["volume"] == volume_editor.digest()["volume"]


def test_a_load_keeps_the_values_it_read_without_a_second_copy(volume_editor, tmp_path):
    """Loading holds the values once (the reader's array is the model's), the colours, and colouring's slabs."""
    values = np.random.default_rng(0).integers(-1000, 1000, (128, 128, 128)).astype(np.int16)  # 4 MiB
    np.save(tmp_path / "big.npy", values)
    colours = np.empty(values.shape + (4,), np.uint8)
    tracemalloc.start()
    try:
        colour(values, TransferFunction(-500, 500), colours)
        slabs = tracemalloc.get_traced_memory()[1]  # colouring's own temporaries
        tracemalloc.reset_peak()
        assert volume_editor.execute("load big.npy")
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < values.nbytes + colours.nbytes + slabs + (1 << 20)  # a second copy would add 4 MiB
    np.testing.assert_array_equal(volume(volume_editor).voxels.scalars.values, values)


def test_replace_scalars_copies_unless_handed_the_array():
    vol, values = Volume.new(2, 2, 2), phantom("uint16")
    vol.replace_scalars(values)
    assert not np.shares_memory(vol.voxels.scalars.values, values) and values.flags.writeable
    vol.replace_scalars(values, copy=False)
    assert np.shares_memory(vol.voxels.scalars.values, values) and not values.flags.writeable  # read-only: the model's
    swapped = phantom("uint16").astype(">u2")
    vol.replace_scalars(swapped, copy=False)  # the model's byte order needs a copy anyway
    assert vol.voxels.scalars.values.dtype.isnative and swapped.flags.writeable
    np.testing.assert_array_equal(vol.voxels.scalars.values, values)


@pytest.mark.parametrize("dtype, window", [("int16", ""), ("float32", "vol.window 0.75 3.125")])
def test_a_demo_recorded_from_a_scalar_volume_replays_to_it(volume_editor, tmp_path, dtype, window):
    load(volume_editor, tmp_path, phantom(dtype), "in.npy")
    volume_editor.execute(f"vol.colormap hot; {window}")  # int16: the default window, whole numbers
    start = volume(volume_editor).voxels.scalars.transfer
    volume_editor.execute("record scan")
    volume_editor.demos.clock.advance(0.5)
    volume_editor.execute("rotate y")
    volume_editor.execute("stop")
    assert (tmp_path / "scan.start.npy").exists() and not (tmp_path / "scan.start.r3").exists()
    (tmp_path / "in.npy").unlink()
    fresh = Editor(clock=VirtualClock())
    assert fresh.execute(f"timedemo {tmp_path / 'scan'}")
    assert volume(fresh).voxels.digest() == volume(volume_editor).voxels.digest()  # covers the scalars and window
    assert volume(fresh).voxels.scalars.transfer == start and start.colormap == "hot"
    assert fresh.digest() == volume_editor.digest()


def test_a_window_change_uploads_the_volume_once(gl, volume_editor, tmp_path):
    vol = load(volume_editor, tmp_path, phantom("int16"), "v.nrrd").voxels
    tracer = RayTracer(gl, ShaderLibrary(gl, [SHADERS]))
    fbo = gl.simple_framebuffer((32, 32))
    settings = TraceSettings(mode=7, steps=32)  # empty-space skipping: the distance field follows the alpha too
    tracer.render(fbo, vol, VolumeView(), settings)
    before = tracer.volume.uploaded_voxels
    volume_editor.execute("vol.window -1000 20")
    for _ in range(3):
        tracer.render(fbo, vol, VolumeView(), settings)
    assert tracer.volume.uploaded_voxels - before == vol.data.shape[0] * vol.data.shape[1] * vol.data.shape[2]
    np.testing.assert_array_equal(tracer.volume.read(), vol.data)
    assert not tracer.distance.stale  # rebuilt exactly for the new alpha, not clamped
    np.testing.assert_array_equal(tracer.distance.field == 0, vol.data[..., 3] > 0)
    fbo.release()
