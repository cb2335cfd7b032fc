"""Scene JSON files (2D lighting and snowflake) against hostile input: every field's type, length and
range is checked on load, the refusal names the field by its JSON path, and nothing changes."""
import json
import os

import pytest

from app.editor import Editor
from app.io import json_file, snowflake_scene
from app.io import lighting2d_scene as scene2d
from app.resources import SCENES

SAMPLE = json.loads((SCENES / "j_concave_three_lights.json").read_text())  # three lights, three hulls


@pytest.fixture
def editor():
    return Editor(configs=False)


def refused(editor, workspace, path, needle):
    """scene.load refuses with `needle` in its message, the digest stays, and no handler crashed."""
    assert editor.execute(f"workspace {workspace}")
    before = editor.digest()
    assert not editor.execute(f'scene.load "{path}"')
    log = [line.text for line in editor.console.log]
    assert "internal error" not in "\n".join(log)
    errors = [line.text for line in editor.console.log if line.level == "error"]
    assert needle in errors[-1], errors[-1]
    assert editor.digest() == before


def scene_with(keys: tuple, value) -> dict:
    """The sample scene with the field at `keys` (a JSON path as a tuple) set to `value`."""
    data = json.loads(json.dumps(SAMPLE))
    node = data
    for key in keys[:-1]:
        node = node[key]
    node[keys[-1]] = value
    return data


@pytest.mark.parametrize("change, needle", [
    ((("lights", 2, "position"), [1, 2, 3, 4]), "lights[2].position: expected 2 numbers, got 4"),
    ((("lights", 0, "scale"), []), "lights[0].scale: expected 2 numbers, got 0"),
    ((("lights", 1, "texture"), 7), "lights[1].texture: expected a string or null, got a number"),
    ((("lights", 0, "kind"), "laser"), "lights[0].kind: must be one of point, spot, textured, got 'laser'"),
    ((("lights", 0, "enabled"), 1), "lights[0].enabled: expected true or false, got a number"),
    ((("lights", 0, "radius"), 1e300), "lights[0].radius: must be within -1e+06..1e+06, got 1e+300"),
    ((("lights", 0, "radius"), -3), "lights[0]: light radius must be >= 0, got -3"),
    ((("lights", 0, "ignored_hulls"), [5000]), "lights[0].ignored_hulls[0]: must be within 0..4095, got 5000"),
    ((("hulls", 1, "points"), [[0, 0], [1]]), "hulls[1].points[1]: expected 2 numbers, got 1"),
    ((("hulls", 0, "points"), []), "hulls[0].points: expected 1 to 4096 points, got 0"),
    ((("hulls", 0, "spin"), 1), "hulls[0]: unknown keys: spin"),
    ((("view",), [0, 0, 500, 1]), "view: expected 3 numbers, got 4"),
    ((("ambient",), "dark"), "ambient: expected a list, got a string"),
    ((("background",), ""), "background: expected 1 to 1024 characters, got 0"),
    ((("background",), "x" * 5000), "background: expected 1 to 1024 characters, got 5000"),
    ((("background",), "/dev/zero"), "background: cannot read image /dev/zero: is a device, not a regular file"),
    ((("normal_map",), "/"), "normal_map: cannot read image /: is a folder, not a regular file"),
    ((("lights",), [{}] * (scene2d.MAX_LIGHTS + 1)), "lights: expected at most 256 lights, got 257"),
])
def test_a_2d_scene_with_a_bad_field_is_refused_by_its_path(editor, tmp_path, change, needle):
    path = tmp_path / "bad.json"
    path.write_text(json.dumps(scene_with(*change)))
    refused(editor, "lighting2d", path, needle)


def test_a_texture_that_is_a_fifo_is_refused_without_blocking(editor, tmp_path):
    fifo = tmp_path / "pipe.png"
    os.mkfifo(fifo)
    path = tmp_path / "bad.json"
    data = scene_with(("lights", 0, "texture"), str(fifo))
    data["lights"][0]["kind"] = "textured"
    path.write_text(json.dumps(data))
    refused(editor, "lighting2d", path,
            f"lights[0].texture: cannot read image {fifo}: is a FIFO (named pipe), not a regular file")


HEADER = '{"format": "shadelab.snowflake", "version": 1, '


@pytest.mark.parametrize("text, needle", [
    (HEADER + '"flakes": [{"x": ' + "9" * 400 + ', "y": 0}]}', "not valid JSON: an integer of 400 digits"),
    (HEADER + '"flakes": [{"x": ' + "9" * 5000 + ', "y": 0}]}', "not valid JSON: an integer of 5000 digits"),
    (HEADER + '"flakes": [{"x": 1e999, "y": 0}]}', "flakes[0].x: must be within -1e+06..1e+06, got inf"),
    (HEADER + '"flakes": [{"x": NaN, "y": 0}]}', "NaN is not a finite number"),
    (HEADER + '"flakes": [{"x": -Infinity, "y": 0}]}', "-Infinity is not a finite number"),
    (HEADER + '"flakes": ' + "[" * 100_000 + "]" * 100_000 + "}", "nested too deeply"),
    (HEADER + '"flakes": [{"x": ' + "[" * 500 + "]" * 500 + ', "y": 0}]}',
     "flakes[0].x: expected a number, got a list"),
    (HEADER + '"flakes": [{"x": 0, "y": 2e6}]}', "flakes[0].y: must be within -1e+06..1e+06, got 2000000.0"),
    (HEADER + '"flakes": [{"x": 0, "y": 0, "radius": 0}]}', "flakes[0].radius: must be > 0 and <= 1e+06, got 0"),
    (HEADER + '"flakes": [{"x": 0, "y": 0, "z": 0}]}', "flakes[0]: unknown keys: z"),
    (HEADER + '"level": true, "flakes": []}', "level: expected a number, got true or false"),
    (HEADER + '"flakes": [' + ", ".join(['{"x": 0, "y": 0}'] * 4097) + "]}",
     "flakes: expected at most 4096 flakes, got 4097"),
    (HEADER + '"flakes": [], "' + "k" * 100 + '": 1}', "(top level): unknown keys: " + "k" * 40 + "..."),
])
def test_a_snowflake_scene_with_hostile_json_is_refused_cleanly(editor, tmp_path, text, needle):
    path = tmp_path / "bad.json"
    path.write_text(text)
    refused(editor, "snowflake", path, needle)


def test_non_utf8_bytes_are_refused(editor, tmp_path):
    path = tmp_path / "bad.json"
    path.write_bytes(b'{"format": "shadelab.snowflake", "version": 1, "flakes": [], "a": "\xff"}')
    refused(editor, "snowflake", path, "is not valid JSON")


@pytest.mark.parametrize("kind", ["device", "fifo", "folder", "large"])
def test_a_scene_path_that_is_no_regular_file_or_too_large_is_refused_unread(editor, tmp_path, kind):
    path = {"device": "/dev/zero", "fifo": tmp_path / "pipe.json", "folder": tmp_path,
            "large": tmp_path / "large.json"}[kind]
    if kind == "fifo":
        os.mkfifo(path)  # no writer: a blocking open would hang here
    if kind == "large":
        path.write_text(HEADER + '"flakes": [], "pad": "' + " " * json_file.MAX_BYTES + '"}')
    needle = {"device": "is a device, not a regular file", "fifo": "is a FIFO (named pipe), not a regular file",
              "folder": "is a folder, not a regular file",
              "large": "the file is over the size limit of 8388608 bytes"}[kind]
    for workspace in ("snowflake", "lighting2d"):
        refused(editor, workspace, path, f"cannot read {path}: {needle}")


def test_the_loaders_raise_their_own_errors_not_internal_ones(tmp_path):
    path = tmp_path / "deep.json"
    path.write_text("[" * 100_000 + "]" * 100_000)
    for loader, error in ((scene2d.load, scene2d.Lighting2DError), (snowflake_scene.load, snowflake_scene.SceneError)):
        with pytest.raises(error, match="nested too deeply"):
            loader(path)


def test_every_sample_scene_still_passes_the_schema():
    for path in SCENES.glob("*.json"):
        scene2d.load(path)


def test_commands_stop_at_the_counts_a_scene_file_holds_so_a_save_always_loads(editor, tmp_path):
    assert editor.execute("workspace lighting2d; lighting.clear")
    for i in range(scene2d.MAX_LIGHTS):
        assert editor.execute(f"light.add point {i} 0")
    assert not editor.execute("light.add point 0 0")
    assert "a scene holds at most 256 of them" in editor.console.log[-1].text
    assert editor.execute("workspace snowflake; snow.clear")
    for i in range(snowflake_scene.MAX_FLAKES):
        assert editor.execute(f"snow.add {i} 0 0.5")
    assert not editor.execute("snow.add 0 0")
    for workspace in ("lighting2d", "snowflake"):
        assert editor.execute(f"workspace {workspace}; scene.save {tmp_path / workspace}.json")
        saved = editor.digest()
        assert editor.execute(f"scene.load {tmp_path / workspace}.json")
        assert editor.digest()[workspace] == saved[workspace]  # the scene; the flakes far off view get framed


def test_the_volume_workspace_scene_files_are_its_volumes(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    editor = Editor(configs=False)
    assert editor.execute("workspace volume; sample cornell_box 16; scene.save box.r3")
    saved = editor.workspaces["volume"].volume.voxels.digest()
    assert editor.execute("new 4 4 4; scene.load box.r3")
    assert editor.workspaces["volume"].volume.voxels.digest() == saved
