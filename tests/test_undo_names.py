"""Every undo step has a name (Edit > Undo says "Undo Stroke"): each workspace's edits, a drag as one step,
and undo and redo handing the name across."""
import numpy as np
import pytest

from app.console.demo import VirtualClock
from app.editor import Editor


@pytest.fixture
def editor(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    return Editor(clock=VirtualClock(), configs=False)


def names(editor):
    history = editor.current.history
    return history.undo_name(), history.redo_name()


@pytest.mark.parametrize("workspace, lines, name", [
    ("snowflake", ["snow.add 0 0"], "Add Flake"),
    ("snowflake", ["snow.move 0 0.1 0", "snow.move 0 0.2 0", "snow.move 0 0.3 0"], "Move Flake"),
    ("snowflake", ["snow.level 3"], "Set Level"),
    ("lighting2d", ["light.add point 0 0"], "Add Light"),
    ("lighting2d", ["light.move 0 1 1", "light.move 0 2 2"], "Move Light"),
    ("lighting2d", ["light.set 0 radius 50"], "Set Light radius"),
    ("lighting2d", ["hull.add 0 0 10 0 10 10"], "Add Hull"),
    ("lighting2d", ["hull.vertex 0 0 1 1"], "Move Vertex"),
    ("lighting2d", ["ambient 0.1 0.2 0.3"], "Set Ambient"),
    ("lighting2d", ["lighting.sample a_penumbra_transition"], "Load Scene"),
    ("volume", ["new 8 8 8", "stroke z 0 1 255 0 0 255 0 0 5 5"], "Stroke"),
    ("volume", ["fill z 0 0 0 9 9 9 255"], "Fill"),
    ("volume", ["voxel 1 2 3 9 9 9 255"], "Paint Voxel"),
    ("volume", ["rotate x"], "Rotate"),
    ("volume", ["sample cornell_box 16"], "Sample"),
    ("clouds", ["clouds.set coverage 0.7", "clouds.set coverage 0.8"], "Set coverage"),
    ("clouds", ["sun.dir 10 20"], "Move Sun"),
    ("lights3d", ["object.move 0 1 2 3", "object.move 0 2 2 3"], "Move Object"),
    ("lights3d", ["light3d.set 0 colour 1 0 0"], "Set Light colour"),
    ("lights3d", ["light3d.remove 1"], "Remove Light"),
])
def test_each_edit_names_its_step(editor, workspace, lines, name):
    assert editor.execute(f"workspace {workspace}")
    for line in lines:
        assert editor.execute(line), editor.console.log[-1].text
    assert names(editor) == (name, None)
    assert editor.execute("undo")
    assert names(editor)[1] == name  # redo would take the same step again
    assert editor.execute("redo")
    assert names(editor) == (name, None)


def test_a_script_is_one_named_step_in_the_volume(editor, tmp_path):
    script = tmp_path / "two.lua"
    script.write_text("cmd.voxel(1, 1, 1, 255, 0, 0, 255)\ncmd.voxel(2, 2, 2, 255, 0, 0, 255)\n")
    assert editor.execute("workspace volume") and editor.execute(f"lua {script}")
    assert names(editor) == ("Script", None)


def test_nothing_to_undo_has_no_name(editor):
    assert names(editor) == (None, None)


def test_a_scalar_volumes_load_and_window_are_named(editor, tmp_path):
    np.save(tmp_path / "ramp.npy", np.linspace(0, 1, 8 * 8 * 8, dtype=np.float32).reshape(8, 8, 8))
    assert editor.execute("workspace volume") and editor.execute("load ramp.npy")
    assert names(editor) == ("Load Volume", None)
    assert editor.execute("vol.window 0.2 0.8")
    assert names(editor) == ("Set Window", None)
    assert editor.execute("undo") and names(editor) == ("Load Volume", "Set Window")
