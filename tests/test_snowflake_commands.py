"""Snowflake verbs through the console, and scene files: refused input changes nothing."""
import json

import pytest

from app.editor import Editor
from app.io import snowflake_scene


@pytest.fixture
def editor():
    return Editor()


def last_error(editor):
    return [line.text for line in editor.console.log if line.level == "error"][-1]


def test_default_scene_is_embedded(editor):
    assert editor.workspace == "snowflake"
    assert len(editor.workspaces["snowflake"].scene.flakes) == 7 and editor.workspaces["snowflake"].scene.level == 4


def test_edit_commands(editor):
    e = editor
    assert e.execute("snow.clear; snow.add 0.5 -0.25 0.2; snow.add 1 1")
    assert [(f.x, f.y, f.radius) for f in e.workspaces["snowflake"].scene.flakes] == [(0.5, -0.25, 0.2), (1, 1, 0.3)]
    assert e.execute("snow.move 1 -1 2; snow.remove 0")
    assert [(f.x, f.y) for f in e.workspaces["snowflake"].scene.flakes] == [(-1, 2)]
    assert e.execute("snow.level 2.5; snow.step 0.25")
    assert e.workspaces["snowflake"].scene.level == 2.75
    assert e.execute("snow.step 100")
    assert e.workspaces["snowflake"].scene.level == 8


@pytest.mark.parametrize("line, needle", [
    ("snow.level 9", "within 0..8"),
    ("snow.level -1", "within 0..8"),
    ("snow.add 0 0 -1", "radius must be > 0"),
    ("snow.move 99 0 0", "no flake 99"),
    ("snow.remove -1", "no flake -1"),
    ("snow.view 0 0 0", "height must be > 0"),
    ("snow.add 2e6 0", "within -1e+06..1e+06"),
    ("snow.move 0 0 -1e300", "within -1e+06..1e+06"),
    ("workspace nowhere", "no workspace"),
])
def test_bad_arguments_change_nothing(editor, line, needle):
    before = (editor.digest(), editor.version(), editor.workspaces["snowflake"].camera.height)
    assert not editor.execute(line)
    assert needle in last_error(editor)
    assert (editor.digest(), editor.version(), editor.workspaces["snowflake"].camera.height) == before


def test_digest_tracks_state(editor):
    d0 = editor.digest()
    editor.execute("snow.add 0 0")
    assert editor.digest() != d0
    editor.execute("snow.remove 7")
    assert editor.digest() == d0
    editor.execute("digest")
    assert [line.text for line in editor.console.log[-len(d0):]] == [f"{k} {v}" for k, v in d0.items()]


def test_scene_round_trip(editor, tmp_path):
    path = tmp_path / "scene.json"
    editor.execute("snow.level 3.5")
    assert editor.execute(f'scene.save "{path}"')
    other = Editor()
    other.execute("snow.clear")
    assert other.execute(f'scene.load "{path}"')
    assert other.digest() == editor.digest()
    assert not list(tmp_path.glob(".*tmp"))  # the atomic write left no temp file


@pytest.mark.parametrize("content, needle", [
    ("{not json", "not valid JSON"),
    ('{"format": "other", "version": 1, "flakes": []}', "not a shadelab.snowflake file"),
    ('{"format": "shadelab.snowflake", "version": 9, "flakes": []}', "unsupported version 9"),
    ('{"format": "shadelab.snowflake", "version": 1, "level": 12, "flakes": []}', "level: must be within 0..8, got 12"),
    ('{"format": "shadelab.snowflake", "version": 1, "flakes": {}}', "flakes: expected a list, got an object"),
    ('{"format": "shadelab.snowflake", "version": 1, "flakes": [{"x": 0, "y": 0}, {"x": 1}]}', "flakes[1]: missing y"),
    ('{"format": "shadelab.snowflake", "version": 1, "flakes": [{"x": 0, "y": 0, "radius": -2}]}',
     "flakes[0].radius: must be > 0"),
])
def test_malformed_scene_refused_before_the_model_is_touched(editor, tmp_path, content, needle):
    path = tmp_path / "bad.json"
    path.write_text(content)
    before = editor.digest()
    assert not editor.execute(f'scene.load "{path}"')
    assert needle in last_error(editor)
    assert editor.digest() == before


def test_missing_scene_file(editor, tmp_path):
    assert not editor.execute(f'scene.load "{tmp_path / "none.json"}"')
    assert "cannot read" in last_error(editor)


def test_saved_file_is_documented_format(editor, tmp_path):
    path = tmp_path / "s.json"
    snowflake_scene.save(path, editor.workspaces["snowflake"].scene)
    data = json.loads(path.read_text())
    assert data["format"] == "shadelab.snowflake" and data["version"] == 1 and len(data["flakes"]) == 7


def test_every_snowflake_edit_is_one_undo_step_and_undo_stays_in_the_workspace(editor):
    def scene():  # each edit puts a new frozen scene in place
        return editor.workspaces["snowflake"].scene

    volume_before = editor.workspaces["volume"].volume.voxels.digest()
    start = scene().digest()
    steps = ["snow.add 0.5 0.5 0.2", "snow.level 3", "snow.step 0.25", "snow.remove 0", "snow.clear"]
    states = []
    for line in steps:
        states.append(scene().digest())
        assert editor.execute(line)
    for index in range(3):  # the moves of one drag: one step
        assert editor.execute(f"snow.add {index} 0 0.1")
    states.append(scene().digest())
    for x in (0.1, 0.2, 0.3):
        assert editor.execute(f"snow.move 0 {x} 0")
    assert scene().flakes[0].x == 0.3
    assert editor.execute("undo") and scene().digest() == states[-1]
    for _ in range(3):
        assert editor.execute("undo")  # the three adds
    for expected in reversed(states[:-1]):
        assert editor.execute("undo") and scene().digest() == expected
    assert scene().digest() == start
    assert not editor.execute("undo")  # nothing left here; the volume's edits are not reached
    assert editor.workspaces["volume"].volume.voxels.digest() == volume_before
    assert editor.execute("redo") and scene().digest() == states[1]
    first = scene()
    assert editor.execute("snow.level 1") and editor.execute("undo") and scene() is first  # the snapshot itself


def test_undo_in_the_snowflake_leaves_voxel_edits_alone(editor):
    assert editor.execute("voxel 1 1 1 255 0 0 255")  # a volume edit, typed while the snowflake is in view
    painted = editor.workspaces["volume"].volume.voxels.digest()
    assert not editor.execute("undo")
    assert editor.workspaces["volume"].volume.voxels.digest() == painted
    assert editor.execute("workspace volume; undo") and editor.workspaces["volume"].volume.voxels.digest() != painted
