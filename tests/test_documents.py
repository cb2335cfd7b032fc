"""Documents without a window: `open` picks the workspace a file belongs to, each workspace knows its file and
whether its scene changed since (undo back to the saved state clears it), replacing a scene asks the user's
own lines only, and autosaves list what a crashed session can give back."""
import json
import os

import pytest

from app.console.demo import VirtualClock
from app.editor import Editor
from app.io import autosave
from app.io.autosave import file_digest
from app.resources import SCENES


@pytest.fixture
def editor(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    return Editor(clock=VirtualClock(), configs=False)


def errors(editor):
    return [line.text for line in editor.console.log if line.level == "error"]


def current(editor):
    return editor.documents.path(editor.current), editor.documents.modified(editor.current)


def test_open_picks_the_workspace_of_each_format(editor, tmp_path):
    """A JSON scene opens where its "format" belongs (no longer refused as "not a shadelab.snowflake file"),
    a volume in the volume workspace; each scene is that workspace's document, unchanged."""
    for workspace in ("snowflake", "clouds", "lights3d"):
        assert editor.execute(f"workspace {workspace}") and editor.execute(f"scene.save {workspace}.json")
    assert editor.execute("workspace volume") and editor.execute("sample cornell_box 16")
    assert editor.execute("save box.r3")
    assert editor.execute("workspace snowflake")
    opened = {}
    for path in (SCENES / "f_concave_star.json", tmp_path / "clouds.json", tmp_path / "lights3d.json",
                 tmp_path / "box.r3", tmp_path / "snowflake.json"):
        assert editor.execute(f"open {path}"), errors(editor)
        opened[path.name] = editor.workspace
        assert current(editor) == (str(path), False)
    assert opened == {"f_concave_star.json": "lighting2d", "clouds.json": "clouds", "lights3d.json": "lights3d",
                      "box.r3": "volume", "snowflake.json": "snowflake"}
    assert editor.workspaces["lighting2d"].scene.hulls[0].points.shape[0] > 3  # the star's points
    assert editor.workspaces["volume"].volume.voxels.size == (16, 16, 16)


def test_open_refuses_what_no_workspace_opens_and_changes_nothing(editor, tmp_path):
    (tmp_path / "notes.txt").write_text("hello")
    (tmp_path / "other.json").write_text('{"format": "someone.else", "version": 1}')
    (tmp_path / "broken.json").write_text("{")
    before = editor.digest()
    for name, needle in (("notes.txt", "no workspace opens .txt (they open .bmp"),
                         ("other.json", "is no scene file of any workspace (its format is 'someone.else')"),
                         ("broken.json", "is not valid JSON"), ("missing.json", "cannot read")):
        assert not editor.execute(f"open {tmp_path / name}")
        assert needle in errors(editor)[-1], errors(editor)[-1]
    assert editor.digest() == before and editor.workspace == "snowflake"


def test_unsaved_comes_from_the_model_so_undo_back_clears_it(editor, tmp_path):
    assert current(editor) == (None, False)  # the start-up scene is no one's unsaved work
    assert editor.execute("snow.add 0.5 0.5")
    assert current(editor) == (None, True)
    assert not editor.execute("scene.save")
    assert "the scene is untitled or a shipped sample" in errors(editor)[-1]
    assert editor.execute("scene.save flakes.json")
    assert current(editor) == (str(tmp_path / "flakes.json"), False)
    assert editor.execute("snow.move 0 0.1 0.1") and editor.execute("snow.level 3")
    assert current(editor)[1]
    assert editor.execute("undo") and editor.execute("undo")
    assert current(editor) == (str(tmp_path / "flakes.json"), False)  # back to what the file holds
    assert editor.execute("redo") and current(editor)[1]
    assert editor.execute("scene.save")  # to its own file
    assert current(editor) == (str(tmp_path / "flakes.json"), False)
    assert editor.execute("snow.view 0 0 9")  # the view is not in the file
    assert not current(editor)[1]


def test_a_shipped_sample_opened_and_edited_is_never_saved_over(editor, tmp_path):
    sample = SCENES / "f_concave_star.json"
    shipped = sample.read_bytes()
    assert editor.execute(f"open {sample}") and editor.execute("light.add point 40 60")
    assert current(editor) == (str(sample), True)  # still named for the title
    assert not editor.execute("scene.save")
    assert "a shipped sample: give the file to save it to" in errors(editor)[-1]
    assert sample.read_bytes() == shipped
    assert editor.execute("scene.save mine.json") and current(editor) == (str(tmp_path / "mine.json"), False)


def test_clouds_and_lights3d_count_what_their_files_hold(editor):
    assert editor.execute("workspace lights3d") and editor.execute("lights3d.select light 0")
    assert not editor.documents.modified(editor.current)  # a selection is no change to the file
    assert editor.execute("workspace clouds") and editor.execute("clouds.time 5 40")
    assert not editor.documents.modified(editor.current)  # the wind's clock neither
    assert editor.execute("sun.dir 10 20") and editor.documents.modified(editor.current)


def test_new_and_samples_leave_an_untitled_scene_and_volume_verbs_name_the_file(editor, tmp_path):
    assert editor.execute(f"open {SCENES / 'f_concave_star.json'}")
    assert editor.execute("scene.new")
    assert current(editor) == (None, False)
    assert editor.workspaces["lighting2d"].scene.hulls == ()
    assert editor.execute("lighting.sample a_penumbra_transition")
    assert current(editor) == (None, False)
    assert editor.execute("workspace volume") and editor.execute("save v.r3")  # the volume's own verbs
    assert current(editor) == (str(tmp_path / "v.r3"), False)
    assert editor.execute("voxel 1 1 1 255 0 0 255") and current(editor)[1]
    assert editor.execute("load v.r3")
    assert current(editor) == (str(tmp_path / "v.r3"), False)
    assert editor.execute("scene.new")  # an empty volume of the same size
    assert editor.workspaces["volume"].volume.voxels.size == (64, 64, 64)
    assert not editor.workspaces["volume"].volume.voxels.data.any()
    assert editor.execute("undo")  # New is an undo step like any other
    assert editor.workspaces["volume"].volume.voxels.data.any()


def test_a_volume_found_elsewhere_is_the_document_saved_back_to(editor, tmp_path, user_config_dir):
    """`load v.r3` finds the file in the user folder (or beside a running demo): the document is that file, so
    a plain save writes there, not a new v.r3 in the working folder; scene.load and open name it the same way."""
    user_config_dir.mkdir()
    assert editor.execute("workspace volume") and editor.execute("sample cornell_box 16")
    assert editor.execute(f"save {user_config_dir / 'v.r3'}")
    assert editor.execute("scene.new")
    for line in ("load v.r3", "scene.load v.r3", "open v.r3"):
        assert editor.execute(line), errors(editor)
        assert current(editor) == (str(user_config_dir / "v.r3"), False), line
    assert editor.execute("voxel 1 1 1 255 0 0 255") and editor.execute("scene.save")
    assert not (tmp_path / "v.r3").exists()
    assert editor.execute("scene.new") and editor.execute(f"load {user_config_dir / 'v.r3'}")
    assert editor.workspaces["volume"].volume.voxels.pick(1, 1, 1) == (255, 0, 0, 255)  # the edit went to that file
    demos = tmp_path / "demos"
    demos.mkdir()
    assert editor.execute(f"save {demos / 'start.r3'}")
    (demos / "opens.demo").write_text("shadelab-demo 1\n0.000 workspace volume\n0.000 load start.r3\n")
    assert editor.execute("scene.new") and editor.execute(f"play {demos / 'opens.demo'}"), errors(editor)
    editor.demos.clock.advance(1)
    editor.demos.update()
    assert not editor.demos.playing and current(editor) == (str(demos / "start.r3"), False)


def test_replacing_asks_the_users_own_lines_and_a_cancel_changes_nothing(editor, tmp_path):
    asked = []
    answer = {"go": False}
    editor.documents.confirm = lambda state, doing: asked.append((state.name, doing)) or answer["go"]
    assert editor.execute("lighting2d:lighting.sample a_penumbra_transition")  # unchanged: nothing to ask
    assert editor.execute("workspace lighting2d") and editor.execute("ambient 0.3 0.3 0.3")
    before = editor.digest()
    for line in ("lighting.sample b_light_pass_through", "scene.new", f"open {SCENES / 'f_concave_star.json'}"):
        assert not editor.execute(line)
        assert "cancelled; the unsaved changes are kept" in editor.console.log[-1].text
    assert [doing for _name, doing in asked] == ["lighting.sample b_light_pass_through", "scene.new",
                                                 f"open {SCENES / 'f_concave_star.json'}"]
    assert editor.digest() == before
    script = tmp_path / "sample.cfg"
    script.write_text("lighting.sample b_light_pass_through\n")
    assert editor.execute(f"exec {script}")  # a config is never asked
    assert len(asked) == 3 and editor.digest()["lighting2d"] != before["lighting2d"]
    assert editor.execute("undo") and editor.digest() == before and editor.documents.modified(editor.current)
    answer["go"] = True
    assert editor.execute("lighting.sample b_light_pass_through")
    assert asked[-1] == ("lighting2d", "lighting.sample b_light_pass_through")
    assert not editor.documents.modified(editor.current)


# Per workspace: an edit that makes its scene differ from the one saved, and its verb that empties or resets it.
UNDOABLE_RESETS = {"lighting2d": ("ambient 0.3 0.3 0.3", "lighting.clear"), "snowflake": ("snow.level 2", "snow.clear"),
                   "clouds": ("clouds.set coverage 0.9", "clouds.reset"),
                   "lights3d": ("light3d.add point", "lights3d.reset")}


@pytest.mark.parametrize("workspace", sorted(UNDOABLE_RESETS))
def test_an_edit_undo_takes_back_never_asks_and_keeps_the_file(editor, tmp_path, workspace):
    """Clearing or resetting a scene is one undo step, as clearing a text editor is: no question, the scene keeps
    its file with unsaved changes, and undo brings back the scene as saved."""
    asked = []
    editor.documents.confirm = lambda state, doing: asked.append(doing)  # would cancel, had it been asked
    change, reset = UNDOABLE_RESETS[workspace]
    assert editor.execute(f"workspace {workspace}") and editor.execute(change)
    assert editor.execute(f"scene.save {workspace}.json")
    saved, file = editor.digest()[workspace], str(tmp_path / f"{workspace}.json")
    assert editor.execute(reset), errors(editor)
    assert asked == [] and editor.digest()[workspace] != saved
    assert current(editor) == (file, True)
    assert editor.execute("undo") and editor.digest()[workspace] == saved and current(editor) == (file, False)
    assert editor.execute("redo") and current(editor) == (file, True)  # the reset was one step


def test_autosave_keeps_changed_scenes_and_recoverable_lists_those_newer_than_their_files(editor, tmp_path,
                                                                                         user_config_dir):
    folder = tmp_path / "session"
    assert editor.execute("scene.save flakes.json") and editor.execute("snow.add 0.2 0.2")
    assert editor.execute("workspace lights3d") and editor.execute("light3d.add point")
    assert editor.documents.autosave(folder) == 2
    assert sorted(p.name for p in folder.iterdir()) == ["autosave.json", "lights3d.json", "snowflake.json"]
    fresh = Editor(clock=VirtualClock(), configs=False)
    found = {s.workspace: s for s in fresh.documents.recoverable(folder)}
    assert sorted(found) == ["lights3d", "snowflake"]
    assert found["snowflake"].original == str(tmp_path / "flakes.json") and found["lights3d"].original is None
    assert fresh.execute(f"recover {found['snowflake'].file} {found['snowflake'].original}")
    assert fresh.workspace == "snowflake"
    assert fresh.digest()["snowflake"] == editor.digest()["snowflake"]
    assert fresh.documents.path(fresh.current) == str(tmp_path / "flakes.json")
    assert fresh.documents.modified(fresh.current)  # recovered work is unsaved until saved
    os.utime(tmp_path / "flakes.json", (2e9, 2e9))  # the file was saved after the autosave
    assert [s.workspace for s in fresh.documents.recoverable(folder)] == ["lights3d"]
    assert editor.execute("undo") and editor.execute("workspace snowflake") and editor.execute("undo")
    assert editor.documents.autosave(folder) == 0  # nothing unsaved: the old autosaves go
    assert sorted(p.name for p in folder.iterdir()) == ["autosave.json"]
    scenes = [{"workspace": "snowflake", "file": "../flakes.json", "sha256": file_digest(tmp_path / "flakes.json")}]
    key = autosave.signing_key(user_config_dir / autosave.KEY_FILE)
    (folder / "autosave.json").write_text(json.dumps({"format": autosave.FORMAT, "version": autosave.VERSION,
                                                      "scenes": scenes, "signature": autosave.signature(key, scenes)}))
    assert fresh.documents.recoverable(folder) == []  # signed, and still: a manifest naming a file outside its folder
    assert "'../flakes.json' is not a file name" in fresh.console.log[-1].text


def test_a_demo_that_opens_a_bigger_scene_is_not_refused(editor, tmp_path):
    """The demo checker cannot know what a file holds: after `open`, a flake past the start-up scene's seven
    is not refused before the demo runs."""
    assert editor.execute("snow.clear")
    for i in range(12):
        assert editor.execute(f"snow.add {i} 0 0.1")
    assert editor.execute("scene.save twelve.json")
    (tmp_path / "moved.demo").write_text("shadelab-demo 1\n0.000 workspace snowflake\n0.000 open twelve.json\n"
                                         "0.000 snow.move 11 3 3\n")
    clock = VirtualClock()
    fresh = Editor(clock=clock, configs=False)
    assert len(fresh.workspaces["snowflake"].scene.flakes) == 7
    assert fresh.execute("play moved.demo"), errors(fresh)
    clock.advance(1)
    fresh.demos.update()
    assert not fresh.demos.playing and fresh.workspaces["snowflake"].scene.flakes[11].x == 3


def test_a_camera_drag_hashes_no_scene_again(editor, monkeypatch):
    """The window asks "unsaved?" after every command; a pan or an orbit changes no file, so it rehashes nothing."""
    hashed = []
    for name in ("lighting2d", "volume"):
        state = editor.workspaces[name]
        digest = type(state).document_digest
        monkeypatch.setattr(type(state), "document_digest", lambda s, d=digest: hashed.append(s.name) or d(s))
    assert editor.execute("workspace lighting2d") and editor.execute("light.add point 0 0")
    assert editor.documents.modified(editor.current)
    hashed.clear()
    for x in range(5):
        assert editor.execute(f"lighting.view {x} 0 400") and editor.documents.modified(editor.current)
    assert editor.execute("workspace volume") and not editor.documents.modified(editor.current)
    for yaw in range(5):
        assert editor.execute(f"orbit {10 * yaw} 20") and not editor.documents.modified(editor.current)
    assert hashed.count("lighting2d") == 0 and hashed.count("volume") <= 1
    assert editor.execute("voxel 1 1 1 255 0 0 255") and editor.documents.modified(editor.current)
    assert hashed.count("volume") <= 2  # hashed again once the voxels changed


def test_a_stroke_previewed_under_the_mouse_hashes_the_volume_once_not_per_move(editor, monkeypatch):
    """A preview changes the volume's version at every move; the document's digest (a hash of every voxel) is kept
    by the history instead, so hovering with the brush does not hash the volume each time; an edit, its undo and
    the preview's end each do, and the document is modified exactly while the edit stands."""
    from app.model.volume.voxels import Voxels

    assert editor.execute("workspace volume") and editor.execute("sample cornell_box 16")
    editor.documents.forget_changes()
    hashed = []
    digest = Voxels.digest
    monkeypatch.setattr(Voxels, "digest", lambda self: hashed.append(1) or digest(self))
    for x in range(2, 12):
        assert editor.execute(f"stroke.preview z 8 1 255 0 0 255 {x} 5")
        editor.documents.modified(editor.current)
    assert len(hashed) == 1  # the first preview; the nine after it are the same document state
    assert editor.execute("stroke z 8 1 255 0 0 255 5 5") and current(editor)[1]
    assert editor.execute("undo") and not current(editor)[1]
    assert len(hashed) == 3
