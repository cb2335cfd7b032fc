"""2D lighting verbs: exact effects, refusals that change nothing, undo of a drag in one step, scene
files, samples, a recorded demo replayed in a fresh editor, and the headless renderer's contract."""
import json
import subprocess
import sys

import numpy as np
import pytest

from app.console.demo import VirtualClock
from app.editor import Editor
from app.resources import SCENES


@pytest.fixture
def editor():
    e = Editor(configs=False)
    assert e.execute("workspace lighting2d") and e.execute("lighting.clear")
    return e


def errors(editor) -> list[str]:
    return [line.text for line in editor.console.log if line.level == "error"]


def test_lights_and_hulls_are_edited_by_commands(editor):
    assert editor.execute("light.add point 10 20")
    assert editor.execute("light.set 0 radius 12.5; light.set 0 color 1 0.5 0.25; light.set 0 shadow_type occluded")
    light = editor.workspaces["lighting2d"].scene.lights[0]
    assert light.position == (10, 20) and light.radius == 12.5 and light.color == (1, 0.5, 0.25)
    assert light.shadow_type == "occluded"
    assert editor.execute("hull.add 0 0 10 0 10 10 0 10; hull.set 0 rotation 0.5; hull.move 0 3 4")
    hull = editor.workspaces["lighting2d"].scene.hulls[0]
    assert hull.valid and hull.position == (3, 4) and hull.rotation == 0.5
    assert editor.execute("hull.vertex 0 2 20 20; hull.insert 0 1 5 -5; hull.delete 0 0")
    edited = editor.workspaces["lighting2d"].scene.hulls[0]  # a new hull: the one before stays as it was
    assert edited.points.tolist() == [[5, -5], [10, 0], [20, 20], [0, 10]]
    assert hull.points.tolist() == [[0, 0], [10, 0], [10, 10], [0, 10]]
    assert (edited.position, edited.rotation) == (hull.position, hull.rotation)
    assert editor.execute("light.add spot 0 0; light.add textured 5 5 builtin:flame")
    lights = editor.workspaces["lighting2d"].scene.lights
    assert lights[1].origin == (0.0, 0.5) and lights[2].texture == "builtin:flame"


@pytest.mark.parametrize("line, needle", [
    ("light.set 0 radius -1", "light radius must be >= 0"),
    ("light.set 0 scale -5 5", "light scale must be >= 0"),
    ("light.set 0 intensity -0.5", "light intensity must be >= 0"),
    ("light.set 0 color 2 0 0", "within 0..1"),
    ("light.set 0 kind laser", "light kind must be one of"),
    ("light.set 0 warmth 3", "no property 'warmth'"),
    ("light.set 7 radius 1", "no light 7"),
    ("light.add textured 0 0 missing.png", "cannot read image"),
    ("hull.set 0 scale -1 1", "hull scale must be >= 0"),
    ("hull.add 0 0 1", "give points as"),
    ("hull.delete 0 9", "no vertex 9"),
    ("hull.add 0 0 nan 1 2 2", "must be finite"),
    ("ambient 0 0 3", "within 0..1"),
    ("lighting.view 0 0 0", "height > 0"),
    ("r_shadowMethod magic", "r_shadowMethod must be one of"),
    ("lighting.sample nowhere", "no sample scene"),
    # what no scene file holds (app/io/lighting2d_scene.py), so every scene made by commands saves and loads again
    ("light.add point 2e6 0", "light position must be within -1e+06..1e+06"),
    ("light.set 0 scale 1e7 1", "light scale must be within -1e+06..1e+06"),
    ("light.set 0 ignored_hulls 4096", "hull numbers 0..4095"),
    ("hull.add 0 0 1e300 0 0 1", "hull points must be within -1e+06..1e+06"),
    ("hull.vertex 0 1 0 -1e9", "hull points must be within -1e+06..1e+06"),
    ("hull.set 0 rotation 1e12", "hull rotation must be within -1e+06..1e+06"),
    ("lighting.view 0 0 1e7", "the view must be within -1e+06..1e+06"),
    ("lighting.background " + "x" * 1025, "at most 1024 characters"),
])
def test_bad_arguments_are_refused_and_change_nothing(editor, line, needle):
    editor.execute("light.add point 0 0; hull.add 0 0 10 0 10 10")
    before = editor.digest()
    assert not editor.execute(line)
    assert editor.digest() == before
    assert any(needle in text for text in errors(editor)), errors(editor)


def test_invalid_hulls_are_kept_marked_and_reported(editor):
    assert editor.execute("hull.add 0 0 10 10 10 0 0 10")  # a bow tie
    hull = editor.workspaces["lighting2d"].scene.hulls[0]
    assert not hull.valid and "cross" in hull.invalid_reason
    assert any("invalid and ignored" in line.text for line in editor.console.log)
    assert editor.execute("hull.vertex 0 1 10 0; hull.vertex 0 2 10 10")  # untangled by editing a vertex
    assert editor.workspaces["lighting2d"].scene.hulls[0].valid


def test_a_drag_is_one_undo_step_and_undo_redo_restore(editor):
    editor.execute("light.add point 0 0")
    start = editor.digest()
    for x in range(1, 30):
        editor.execute(f"light.move 0 {x} {x}")
    moved = editor.digest()
    assert editor.execute("undo") and editor.digest() == start
    assert editor.execute("redo") and editor.digest() == moved
    editor.execute("light.set 0 radius 3; hull.add 0 0 5 0 5 5")
    assert editor.execute("undo; undo") and editor.digest() == moved


def test_an_edit_puts_a_new_scene_in_place_and_undo_the_snapshot_itself(editor):
    """Undo's snapshots are the frozen scenes themselves, never copies: an edit leaves the one before untouched."""
    state = editor.workspaces["lighting2d"]
    editor.execute("light.add point 0 0; hull.add 0 0 10 0 10 10 0 10; light.set 0 ignored_hulls 0")
    before = state.scene
    digest, points = before.digest(), before.hulls[0].points.copy()
    edits = ("light.move 0 5 5", "light.set 0 color 1 0 0", "hull.move 0 3 4", "hull.set 0 rotation 1",
             "hull.vertex 0 1 20 0", "hull.insert 0 1 5 -5", "hull.delete 0 0", "ambient 0 0 1",
             "lighting.background builtin:white", "lighting.normalmap builtin:bumps", "hull.remove 0", "lighting.clear")
    for line in edits:
        assert editor.execute(line), errors(editor)
    assert state.scene is not before and before.digest() == digest
    assert before.lights[0].position == (0, 0) and before.lights[0].ignored_hulls == (0,)
    np.testing.assert_array_equal(before.hulls[0].points, points)
    for _ in edits:
        assert editor.execute("undo")
    assert state.scene is before


def test_scene_files_round_trip_and_malformed_ones_change_nothing(editor, tmp_path):
    editor.execute("lighting.sample g_overlapping_hulls; lighting.view 12 34 300")
    path = tmp_path / "scene.json"
    assert editor.execute(f"scene.save {path}")
    saved = editor.digest()
    editor.execute("lighting.clear")
    assert editor.execute(f"scene.load {path}")
    assert editor.digest() == saved and editor.workspaces["lighting2d"].camera.cx == 12
    bad = tmp_path / "bad.json"
    data = json.loads(path.read_text())
    data["lights"][0]["radius"] = -3
    bad.write_text(json.dumps(data))
    for text in (json.dumps(data), "{", json.dumps({**data, "version": 9}),
                 json.dumps({**data, "hulls": [{"pts": []}]})):
        bad.write_text(text)
        assert not editor.execute(f"scene.load {bad}")
        assert editor.digest() == saved


def test_every_sample_scene_loads(editor):
    names = sorted(p.stem for p in SCENES.glob("*.json"))
    assert len(names) == 13 and [n[0] for n in names] == list("abcdefghijklm")
    for name in names:
        assert editor.execute(f"lighting.sample {name}")
        assert all(h.valid for h in editor.workspaces["lighting2d"].scene.hulls)


def test_a_recorded_demo_replays_to_the_same_scene(tmp_path):
    clock = VirtualClock()
    recorded = Editor(clock=clock, configs=False)
    recorded.execute("workspace lighting2d")
    demo = tmp_path / "edit.demo"
    recorded.execute(f"record {demo}")
    for line in ("light.add spot 30 40", "light.set 1 cone_decay 2.5", "hull.add 0 0 40 0 20 30",
                 "hull.set 3 rotation 0.25", "light.move 0 -100 -90", "ambient 0.2 0.1 0.3", "r_shadowMethod jitter"):
        clock.advance(0.1)
        assert recorded.execute(line)
    recorded.execute("stop")
    fresh = Editor(clock=clock, configs=False)
    fresh.execute("lighting.clear")
    fresh.execute(f"play {demo}")
    for _ in range(50):
        clock.advance(0.1)
        fresh.demos.update()
    assert fresh.digest() == recorded.digest()


def test_headless_render_takes_the_shadow_method(tmp_path):
    out = {m: tmp_path / f"{m}.png" for m in ("penumbra", "exact")}
    for method, png in out.items():
        done = subprocess.run([sys.executable, "-c", "from app.cli import main; raise SystemExit(main())", "render",
                               "lighting2d", "--scene", str(SCENES / "g_overlapping_hulls.json"),
                               "--cmd", f"r_shadowMethod {method}", "--size", "96x64", "--out", str(png)],
                              capture_output=True, text=True, timeout=120)
        assert done.returncode == 0, done.stderr
    from app.io.png import read_png
    a, b = (read_png(p).astype(int) for p in out.values())
    assert a.shape == (64, 96, 4) and np.abs(a - b).max() > 40  # penumbra over-darkens the overlap
