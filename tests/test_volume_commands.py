"""The volume verbs through the console: exact effects, clear refusals, files, demos with a snapshot."""
import numpy as np
import pytest

from app.commands import volume, volume_labels
from app.console.console import Console
from app.console.demo import VirtualClock
from app.console.registry import CommandError
from app.editor import Editor
from app.model.volume.workspace import VolumeWorkspace


@pytest.fixture
def editor(volume_editor):
    assert volume_editor.execute("new 8 6 4")
    return volume_editor


def voxels(editor):
    return editor.workspaces["volume"].volume.voxels


def history(editor):
    return editor.workspaces["volume"].volume.history


def last_error(editor):
    return [line.text for line in editor.console.log if line.level == "error"][-1]


def test_default_volume_is_coords3d():
    e = Editor()
    assert voxels(e).size == (64, 64, 64)
    data = voxels(e).data
    assert tuple(data[0, 0, 63]) == (255, 0, 0, 255) and tuple(data[63, 63, 0]) == (0, 255, 255, 255)


def test_voxel_stroke_fill_rotate(editor):
    v = voxels(editor)
    assert editor.execute("voxel 1 2 3 10 20 30 40")
    assert tuple(v.data[3, 2, 1]) == (10, 20, 30, 40)
    assert editor.execute("stroke y 1 1 255 0 0 255 0 0 7 0")  # axis y: u = x, v = z
    assert (v.data[0, 1, :, 0] == 255).all() and v.data[1:, 1, :, 3].sum() == 0
    assert editor.execute("fill z 0 0 5 0 0 255 255")
    assert (v.data[0, 2:, :, 2] == 255).all() and (v.data[0, 1, :, 0] == 255).all()
    assert editor.execute("rotate z")
    assert v.size == (6, 8, 4)
    assert editor.execute("undo; undo")
    assert v.size == (8, 6, 4) and v.data[0, 2:, :, 2].sum() == 0


def test_fill_tolerance_takes_in_similar_colours_and_undoes(editor):
    v = voxels(editor)
    assert editor.execute("sample coords3d")  # a gradient: an exact fill takes one voxel
    base = v.digest()
    for line, filled in (("fill z 5 32 32 250 250 250 128", 1), ("fill z 5 32 32 250 250 250 128 0", 1),
                         ("fill z 5 32 32 250 250 250 128 10", 25), ("fill z 5 32 32 250 250 250 128 255", 4096)):
        assert editor.execute(line)
        assert np.count_nonzero((v.data == (250, 250, 250, 128)).all(-1)) == filled, line
        assert editor.execute("undo") and v.digest() == base


def test_a_load_opens_the_painter_on_the_middle_slice(editor):
    view = editor.workspaces["volume"].view
    assert editor.execute("slice z 3; sample cornell_box 24")
    assert (view.axis, view.index) == ("z", 12)
    assert editor.execute("slice y 2; new 8 40 2")  # a new volume keeps the slice
    assert (view.axis, view.index) == ("y", 2)
    assert editor.execute("save tall.npy; slice y 0; sample coords3d 16")
    assert (view.axis, view.index) == ("y", 8)
    assert editor.execute("load tall.npy")  # 40 voxels high: slice 0 of a file is often empty
    assert (view.axis, view.index) == ("y", 20)
    assert editor.execute("slice x 0; undo")  # back to the sample: the slice is kept within it
    assert (view.axis, view.index) == ("x", 0)


@pytest.mark.parametrize("line, needle", [
    ("voxel 8 0 0 1 1 1 1", ""),
    ("voxel 0 0 0 256 0 0 255", "0..255"),
    ("stroke w 0 1 1 1 1 1 0 0", "axis must be x, y or z"),
    ("stroke z 0 1 1 1 1 1 0", "x1 y1"),
    ("stroke z 9 1 1 1 1 1 0 0", ""),
    ("fill z 0 99 0 1 1 1 1", ""),
    ("fill z 0 0 0 1 1 1 1 256", "fill tolerance must be within 0..255"),
    ("fill z 0 0 0 1 1 1 1 -1", "fill tolerance must be within 0..255"),
    ("fill_tolerance 300", ""),
    ("rotate q", "axis must be"),
    ("new 0 4 4", ""),
    ("new 5000 5000 5000", ""),
    ("sample teapot", "no sample 'teapot'"),
    ("sample coords3d 4", "within 8.."),
    ("slice z 4", "outside 0..3"),
    ("redo", "nothing to redo"),
])
def test_bad_arguments_change_nothing(editor, line, needle):
    before = (voxels(editor).digest(), history(editor).undo_depth)
    assert not editor.execute(line)
    assert needle in last_error(editor)
    assert (voxels(editor).digest(), history(editor).undo_depth) == before


def test_undo_until_nothing_is_left(editor):
    Editor.execute(editor, "voxel 0 0 0 1 2 3 4")
    while history(editor).undo_depth:
        assert editor.execute("undo")
    assert not editor.execute("undo") and "nothing to undo" in last_error(editor)
    assert voxels(editor).size == (64, 64, 64)  # back to the default, before `new`


@pytest.mark.parametrize("name", ["v.r3", "v.npy", "v.tif", "v.nrrd", "v_%02i.png"])
def test_save_and_load_every_format(editor, tmp_path, name):
    editor.execute("stroke z 1 2 9 99 199 255 0 0 7 5")
    digest = voxels(editor).digest()
    assert editor.execute(f"save {tmp_path / name}")
    assert editor.execute("new 3 3 3")
    assert editor.execute(f"load {tmp_path / name}")
    assert voxels(editor).digest() == digest


def test_malformed_file_is_refused_and_nothing_changes(editor, tmp_path):
    (tmp_path / "bad.r3").write_bytes(b"R3" + bytes([8, 0, 8, 0, 8, 0]) + b"\0" * 100)
    before = (voxels(editor).digest(), history(editor).undo_depth)
    assert not editor.execute(f"load {tmp_path / 'bad.r3'}")
    assert "truncated" in last_error(editor)
    assert (voxels(editor).digest(), history(editor).undo_depth) == before


def test_demo_of_an_edited_volume_starts_from_a_snapshot(editor, tmp_path):
    clock = editor.demos.clock
    editor.execute("voxel 2 2 2 9 9 9 255")
    editor.execute("record edits")
    clock.advance(0.5)
    editor.execute("stroke z 2 1 255 0 0 255 0 0 7 5; rotate x")
    editor.execute("stop")
    assert (tmp_path / "edits.start.r3").exists()
    fresh = Editor(clock=VirtualClock())
    assert fresh.execute(f"timedemo {tmp_path / 'edits'}")
    assert voxels(fresh).digest() == voxels(editor).digest()
    assert fresh.digest() == editor.digest()


def test_stroke_preview_leaves_one_undo_step(editor):
    depth = history(editor).undo_depth
    editor.execute("stroke.preview z 0 1 255 0 0 255 0 0 3 0")
    editor.execute("stroke.preview z 0 1 255 0 0 255 0 0 3 0 3 3")
    assert voxels(editor).data[0, 3, 3, 3] == 255
    editor.execute("stroke z 0 1 255 0 0 255 0 0 3 0 3 3")
    assert history(editor).undo_depth == depth + 1
    editor.execute("stroke.preview z 1 1 255 0 0 255 0 0")
    editor.execute("stroke.cancel")
    assert voxels(editor).data[1].sum() == 0 and history(editor).undo_depth == depth + 1


def test_pick_sets_the_brush(editor):
    editor.execute("voxel 1 1 1 12 34 56 78; pick 1 1 1")
    assert editor.workspaces["volume"].view.brush == (12, 34, 56, 78)


def test_cube_lua_draws_a_cube_open_on_one_side():
    e = Editor()
    assert e.execute("workspace volume; cube.lua")  # undo below acts on the workspace in view
    data = voxels(e).data
    n = voxels(e).size[0]
    solid = data[..., 3] > 0
    assert solid[:, 0, :].all() and solid[:, -1, :].all() and solid[:, :, 0].all() and solid[:, :, -1].all()
    assert solid[-1].all() and not solid[0, 1:-1, 1:-1].any()  # back closed, front open
    assert not solid[1:-1, 1:-1, 1:-1].any() and n == 32
    assert e.execute("undo") and voxels(e).size == (64, 64, 64)


def test_a_preview_never_mixes_with_the_history(editor):
    v = voxels(editor)
    editor.execute("stroke.preview z 0 1 255 0 0 255 2 2; voxel 7 5 0 0 255 0 255; stroke.cancel")
    assert tuple(v.data[0, 5, 7]) == (0, 255, 0, 255) and v.data[0, 2, 2, 3] == 0
    editor.execute("stroke.preview z 0 1 255 0 0 255 3 3; stroke.cancel")
    assert not editor.execute("redo") and v.data[0, 3, 3, 3] == 0


def test_undo_inside_a_script_keeps_earlier_edits_apart(editor, tmp_path):
    editor.execute("voxel 0 0 0 255 0 0 255")
    (tmp_path / "s.lua").write_text("cmd.voxel(1,0,0,9,9,9,255)\ncmd.voxel(2,0,0,9,9,9,255)\ncmd.undo()\n"
                                    "cmd.voxel(3,0,0,9,9,9,255)\n")
    assert editor.execute(f"lua {tmp_path / 's.lua'}")
    assert editor.execute("undo")  # the script's edits, as one
    assert tuple(voxels(editor).data[0, 0, 0]) == (255, 0, 0, 255)
    assert voxels(editor).data[0, 0, 1:4, 3].sum() == 0


def test_undo_that_shrinks_the_volume_keeps_the_slice_inside(editor):
    editor.execute("new 8 8 40; slice z 39; undo")
    assert voxels(editor).size == (8, 6, 4) and editor.workspaces["volume"].view.index == 3


def test_small_cornell_name_keeps_its_walls():
    e = Editor()
    e.execute("sample cornell_name 16")
    green = np.array([40, 170, 60, 255])
    assert (voxels(e).data[:-1, 1:-1, -1] == green).all()  # no letter wrapped onto the right wall


def test_a_command_is_a_function_that_runs_alone():
    """No console dispatch: each verb takes the workspace's context and does its work."""
    ctx = volume.Ctx(Console(), VolumeWorkspace())
    volume.new(ctx, 4, 3, 2)
    volume.voxel(ctx, 3, 2, 1, 10, 20, 30, 255)
    volume.rotate(ctx, "z")
    voxels = ctx.state.volume.voxels
    assert voxels.size == (3, 4, 2) and voxels.pick(0, 3, 1) == (10, 20, 30, 255)
    assert ctx.state.volume.history.undo_name() == "Rotate"
    with pytest.raises(CommandError, match="outside 0..1 along z"):
        volume.slice_args(ctx, "z", 2)


def test_every_declared_command_is_registered_in_the_workspace(editor):
    registry = editor.console.registry
    scoped = {key for key in registry.commands if key.startswith("volume:")}
    assert scoped == {f"volume:{d.name}" for d in volume.COMMANDS.declared + volume_labels.COMMANDS.declared}
    # as many as the closure registered (none lost in the move), vol.spacing, vol.iso, vol.opacity (.preview, .reset)
    # and vol.preset
    assert len(volume.COMMANDS.declared) == 37
