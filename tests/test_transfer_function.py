"""The opacity curve, the colour maps and the presets through the console: `vol.opacity` sets, shows and refuses
curves whole; each change is one undo step that colours nothing again; a drag's preview is no step; `vol.preset`
sets window, colours and curve at once; demos and .nrrd files keep the curve, and a volume without one keeps the
digest it had before curves."""
import hashlib

import nrrd
import numpy as np
import pytest

from app.console.demo import VirtualClock
from app.editor import Editor
from app.model.volume.phantom import ct_phantom
from app.model.volume.scalars import COLORMAPS, MAX_OPACITY_POINTS, TransferFunction, value_histogram
from app.model.volume.transfer_presets import PRESETS


@pytest.fixture
def ct(volume_editor, tmp_path):
    np.save(tmp_path / "ct.npy", ct_phantom(16))
    assert volume_editor.execute(f"load {tmp_path / 'ct.npy'}")
    return volume_editor


def volume(editor: Editor):
    return editor.workspaces["volume"].volume


def transfer(editor: Editor) -> TransferFunction:
    return volume(editor).voxels.scalars.transfer


def last(editor: Editor) -> str:
    return editor.console.log[-1].text


def test_vol_opacity_sets_and_shows_the_curve_in_one_undo_step(ct):
    start = transfer(ct)
    assert ct.execute("vol.opacity") and "(the ramp over the window" in last(ct)
    assert f"opacity {start.low:g} 0 {start.high:g} 1" in last(ct)
    assert ct.execute("vol.opacity -500 0 200 0.25 900 0.8")
    assert "translucent (now mip)" in last(ct)  # where it draws
    assert transfer(ct) == TransferFunction(start.low, start.high, "grey", ((-500, 0), (200, 0.25), (900, 0.8)))
    assert ct.execute("vol.opacity") and last(ct) == "opacity -500 0 200 0.25 900 0.8 (set)"
    assert volume(ct).history.undo_name() == "Set Opacity"
    assert ct.execute("undo") and transfer(ct) == start
    assert ct.execute("redo") and transfer(ct).points == ((-500, 0), (200, 0.25), (900, 0.8))
    assert ct.execute("vol.window 0 600") and transfer(ct).points == ((-500, 0), (200, 0.25), (900, 0.8))  # data units
    assert ct.execute("vol.opacity.reset") and transfer(ct).points is None
    assert volume(ct).history.undo_name() == "Reset Opacity"
    assert ct.execute("vol.opacity 100 0.5") and transfer(ct).opacity() == ((100, 0.5),)  # one point: constant


@pytest.mark.parametrize("line, message", [
    ("vol.opacity 0 0 100", "pairs, value opacity"),
    ("vol.opacity 100 0 50 1", "values must increase: point 2's 50 comes after 100"),
    ("vol.opacity 100 0 100 1", "values must increase"),
    ("vol.opacity 0 1.5", "point 1's opacity must be within 0..1, got 1.5"),
    ("vol.opacity 0 -0.1", "within 0..1"),
    ("vol.opacity inf 0", "finite"),
    ("vol.opacity " + " ".join(f"{i} 0.5" for i in range(MAX_OPACITY_POINTS + 1)), f"1 to {MAX_OPACITY_POINTS} points"),
    ("vol.preset ct_bones", "no preset 'ct_bones'; choose one of ct_bone, ct_soft_tissue, ct_air, mr_default"),
    ("vol.colormap jet", "magma"),
    ("vol.opacity.preview 5 0 1 1", "values must increase"),
])
def test_bad_input_is_refused_whole_and_changes_nothing(ct, line, message):
    assert ct.execute("vol.opacity -500 0 900 0.8")
    digest, steps, version = ct.digest(), volume(ct).history.undo_depth, ct.version()
    assert not ct.execute(line)
    assert message in last(ct)
    assert ct.digest() == digest and volume(ct).history.undo_depth == steps and ct.version() == version


def test_an_rgba_volume_has_no_curve_to_set(volume_editor):
    for line in ("vol.opacity", "vol.opacity 0 0 1 1", "vol.opacity.reset", "vol.preset ct_bone",
                 "vol.opacity.preview 0 1"):
        assert not volume_editor.execute(line)
        assert "no scalars" in last(volume_editor)


def test_a_curve_colours_nothing_again_but_shows_as_a_new_version(ct):
    voxels = volume(ct).voxels
    version, colours, shown = voxels.version, voxels.data.copy(), ct.version()
    assert ct.execute("vol.opacity 0 0 500 1")
    assert voxels.version == version and np.array_equal(voxels.data, colours)  # nothing to upload again
    assert ct.version() != shown  # but the view draws again
    assert ct.execute("vol.colormap magma")
    assert voxels.version > version and not np.array_equal(voxels.data, colours)


def test_a_preview_shows_the_curve_without_a_step_and_the_drop_is_one(ct):
    start, steps = transfer(ct), volume(ct).history.undo_depth
    assert ct.execute("vol.opacity.preview -500 0 300 0.4")
    assert transfer(ct).points == ((-500, 0), (300, 0.4)) and volume(ct).history.undo_depth == steps
    assert ct.execute("vol.opacity.preview -500 0 350 0.5")
    assert ct.execute("vol.opacity -500 0 400 0.6")
    assert volume(ct).history.undo_depth == steps + 1
    assert ct.execute("undo") and transfer(ct) == start  # back to before the drag, not to a preview
    assert ct.execute("vol.opacity.preview -500 0 300 0.4; stroke.cancel")  # any edit drops a preview first
    assert transfer(ct) == start


@pytest.mark.parametrize("name", PRESETS)
def test_a_preset_sets_window_colours_and_curve_as_one_step(ct, name):
    steps = volume(ct).history.undo_depth
    before = transfer(ct)
    assert ct.execute(f"vol.preset {name}")
    chosen, now = PRESETS[name], transfer(ct)
    assert now.colormap == name and now.points is not None and volume(ct).history.undo_depth == steps + 1
    assert volume(ct).history.undo_name() == f"Preset {chosen.title}"
    if chosen.relative:  # the MR preset spans the scan's own default window
        assert (now.low, now.high) == (before.low, before.high)
        assert now.points[0][0] == before.low and now.points[-1][0] == before.high
    else:
        assert (now.low, now.high) == chosen.window and now.points == chosen.points
    assert f"{chosen.title}: window " in ct.console.log[-2].text
    assert ct.execute("undo") and transfer(ct) == before


def test_the_new_colour_maps_and_presets_colour_the_volume(ct):
    for name in ("magma", "inferno", "plasma", "ct_bone", "ct_soft_tissue", "ct_air", "mr_default"):
        assert name in COLORMAPS and ct.execute(f"vol.colormap {name}")
        table = transfer(ct).table()
        assert table.shape == (256, 4) and len({tuple(c) for c in table[:, :3]}) > 100  # a smooth ramp of colours
    assert set(PRESETS) <= set(COLORMAPS)  # each preset's colour map is its namesake


def test_a_volume_without_a_curve_keeps_the_digest_it_had_before_curves(ct):
    """The digest hashes the transfer function's repr (app/model/volume/voxels.py): without a curve, the text of
    the dataclass before curves, so old demos replay to their digests."""
    t = transfer(ct)
    assert repr(t) == f"TransferFunction(low={t.low!r}, high={t.high!r}, colormap={t.colormap!r})"
    values = volume(ct).voxels.scalars.values
    h = hashlib.sha256("16x16x16;".encode())
    h.update(f";{values.dtype.str};TransferFunction(low={t.low!r}, high={t.high!r}, colormap='grey');".encode())
    h.update(values.data)
    assert ct.digest()["volume"] == h.hexdigest()[:16]
    assert ct.execute("vol.opacity 0 0 1 1")
    assert ct.digest()["volume"] != h.hexdigest()[:16]
    assert ct.execute("vol.opacity.reset") and ct.digest()["volume"] == h.hexdigest()[:16]


def test_a_demo_replays_the_curve_and_the_preset(ct, tmp_path):
    assert ct.execute("record tf")
    for line in ("vol.preset ct_bone", "vol.opacity 100 0 641 0.5 3071 0.7", "vol.colormap magma",
                 "r_scalarMode translucent"):
        ct.demos.clock.advance(0.25)
        assert ct.execute(line)
    assert ct.execute("stop")
    text = (tmp_path / "tf.demo").read_text()
    assert "vol.preset ct_bone" in text and "vol.opacity 100 0 641 0.5 3071 0.7" in text
    fresh = Editor(clock=VirtualClock())
    assert fresh.execute(f"timedemo {tmp_path / 'tf'}")
    assert fresh.digest() == ct.digest()
    assert transfer(fresh) == transfer(ct)
    # a demo recorded from a volume with a curve opens with it
    assert ct.execute("record again") and ct.execute("stop")
    assert "0.000 vol.opacity 100.0 0.0 641.0 0.5 3071.0 0.7\n" in (tmp_path / "again.demo").read_text()
    again = Editor(clock=VirtualClock())
    assert again.execute(f"timedemo {tmp_path / 'again'}") and transfer(again) == transfer(ct)


def test_an_nrrd_keeps_the_curve_and_refuses_a_bad_one(ct, tmp_path):
    assert ct.execute("vol.opacity -500 0 200.5 0.25 900 0.8")
    assert ct.execute(f"save {tmp_path / 'kept.nrrd'}")
    header = nrrd.read_header(str(tmp_path / "kept.nrrd"))
    assert header["shadelab_opacity"] == "-500.0 0.0 200.5 0.25 900.0 0.8"
    kept = transfer(ct)
    assert ct.execute("sample coords3d 8") and ct.execute(f"load {tmp_path / 'kept.nrrd'}")
    assert transfer(ct) == kept
    data = (tmp_path / "kept.nrrd").read_bytes().replace(b"200.5 0.25", b"200.5 1.25")
    (tmp_path / "bad.nrrd").write_bytes(data)
    digest = ct.digest()
    assert not ct.execute(f"load {tmp_path / 'bad.nrrd'}")
    assert "its shadelab_opacity field: opacity point 2's opacity must be within 0..1" in last(ct)
    assert ct.digest() == digest


def test_the_histogram_counts_the_finite_values():
    values = np.array([0, 1, 1, 2, 2, 2, 3, 3, 3, 3], np.float32).reshape(1, 2, 5)
    edges, counts = value_histogram(values, 4)
    assert edges[0] == 0 and edges[-1] == 3 and counts.tolist() == [1, 2, 3, 4]
    values[0, 0, 0] = np.nan
    assert value_histogram(values, 4)[1].sum() == 9
    edges, counts = value_histogram(np.full((2, 2, 2), 7, np.int16), 8)
    assert (edges[0], edges[-1], counts.sum()) == (6.5, 7.5, 8)
    edges, counts = value_histogram(np.full((2, 2, 2), np.nan, np.float32), 8)
    assert counts.sum() == 0 and len(edges) == 9
