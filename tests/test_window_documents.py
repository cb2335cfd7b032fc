"""Documents in the window under Xvfb: the title names the file and marks unsaved changes; a sample, Open or New
over unsaved changes asks to save, discard or cancel, an edit undo takes back (clear, reset) never asks, and
closing asks once for every changed scene; File > Open and Save As dialogs are filtered by the workspace's
formats and start in the folder last used; `shadelab FILE` opens the file in its workspace; and a crashed
session's autosave is offered back at the next start."""
import os
import subprocess
import sys
import textwrap

import numpy as np
from PySide6.QtCore import QPoint, Qt
from PySide6.QtWidgets import QMessageBox

from app.console.demo import VirtualClock
from app.editor import Editor
from app.io import snowflake_scene
from app.io.volume_formats import read_volume_file
from app.resources import SCENES
from app.views.application import startup_command
from app.views.main_window import MainWindow
from dialogs import NoDialogs, answer, said, showed

Button = QMessageBox.StandardButton
STAR = SCENES / "f_concave_star.json"


def shown_title(window):
    """The title as the window manager gets it ([*] made a star, or nothing)."""
    return window.windowHandle().title()


def saved_flakes(tmp_path, name="flakes.json"):
    """A snowflake file with two flakes, written by the editor itself."""
    editor = Editor(clock=VirtualClock(), configs=False)
    assert editor.execute("snow.clear") and editor.execute("snow.add 0 0") and editor.execute("snow.add 1 1 0.2")
    assert editor.execute(f"scene.save {tmp_path / name}")
    return tmp_path / name


def test_the_title_names_the_file_and_marks_unsaved_changes(make_window, qtbot, tmp_path):
    window = make_window()
    assert shown_title(window) == "untitled — Snowflake — Shadelab"
    path = saved_flakes(tmp_path)
    assert window.run(f"open {path}")
    assert window.windowTitle() == "flakes.json[*] — Snowflake — Shadelab" and not window.isWindowModified()
    vp = window.viewport
    qtbot.mouseClick(vp, Qt.MouseButton.LeftButton, pos=QPoint(vp.width() // 4, vp.height() // 4))  # a new flake
    assert len(window.editor.current.scene.flakes) == 3
    assert shown_title(window) == "flakes.json* — Snowflake — Shadelab"
    qtbot.keyClick(window.viewport, Qt.Key.Key_Z, Qt.KeyboardModifier.ControlModifier)
    assert shown_title(window) == "flakes.json — Snowflake — Shadelab"  # undone back to the file: clean
    window.run("workspace volume")
    assert shown_title(window) == "untitled — Volume — Shadelab"


def test_closing_with_unsaved_changes_asks_save_discard_or_cancel(make_window, qtbot, tmp_path):
    window = make_window(asks=True)
    window.run("snow.add 0.4 0.4")
    seen = answer(Button.Cancel)
    window.close()
    assert window.isVisible()  # cancelled: still open, nothing lost
    assert "The Snowflake scene untitled has unsaved changes." in said(seen)[0]
    assert "Save them before closing Shadelab?" in said(seen)[0]
    target = tmp_path / "kept.json"
    seen = answer(Button.Save, target)  # untitled: Save goes on to Save As
    window.close()
    qtbot.waitUntil(lambda: not window.isVisible())
    assert said(seen)[1][0] == "Snowflake files (*.json)"
    flakes, _level = snowflake_scene.load(target)
    assert (0.4, 0.4) in [(f.x, f.y) for f in flakes]


def test_discard_closes_without_writing(make_window, qtbot, tmp_path):
    window = make_window(asks=True)
    path = saved_flakes(tmp_path)
    window.run(f"open {path}")
    before = path.read_bytes()
    window.run("snow.clear")  # an edit undo takes back: never asks
    window.run("snow.add 0 0")
    answer(Button.Discard)
    window.close()
    qtbot.waitUntil(lambda: not window.isVisible())
    assert path.read_bytes() == before


def test_a_sample_over_unsaved_changes_asks_first(make_window, qtbot):
    window = make_window(asks=True)
    window.run("workspace lighting2d")
    window.run("ambient 0.5 0.1 0.1")
    panel = window.workspace_panels["lighting2d"].widget()
    before = window.editor.digest()
    seen = answer(Button.Cancel)
    panel.sample.activated.emit(1)  # the user picks a sample in the panel
    qtbot.waitUntil(lambda: len(seen) == 1)
    assert window.editor.digest() == before
    assert "before lighting.sample a_penumbra_transition?" in said(seen)[0]
    answer(Button.Discard)
    panel.sample.activated.emit(1)
    assert window.editor.digest()["lighting2d"] != before["lighting2d"]
    assert not window.isWindowModified() and shown_title(window) == "untitled — 2D lighting — Shadelab"


def test_a_key_that_loads_a_sample_saves_to_the_file_when_asked(make_window, qtbot, tmp_path):
    """Keys run as binds, confined to the user folder; the file the user chose to save to is theirs."""
    window = make_window(asks=True)
    window.run("workspace volume")
    window.run(f"save {tmp_path / 'mine.r3'}")
    window.run("voxel 1 2 3 255 0 0 255")
    painted = window.editor.digest()["volume"]
    window.viewport.setFocus()
    seen = answer(Button.Save)
    qtbot.keyClick(window.viewport, Qt.Key.Key_9)  # volume:9 is `sample cornell_box`
    assert "The Volume scene mine.r3 has unsaved changes." in said(seen)[0]
    assert window.editor.current.volume.voxels.size == (64, 64, 64) and window.editor.digest()["volume"] != painted
    fresh = Editor(clock=VirtualClock(), configs=False)
    assert fresh.execute(f"open {tmp_path / 'mine.r3'}")
    assert fresh.digest()["volume"] == painted


def test_file_open_is_filtered_by_the_workspace_and_opens_in_the_files_workspace(make_window, qtbot, tmp_path):
    window = make_window()
    window.run("workspace volume")
    window.run(f"save {tmp_path / 'v.r3'}")
    window.run("workspace lighting2d")
    seen = answer(tmp_path / "v.r3")
    window.menus.menus["file"].actions()[1].trigger()  # Open...
    filters = said(seen)[0]
    assert filters[0] == "2D lighting files (*.json)" and filters[1].startswith("Every Shadelab file (*.bmp")
    assert "Volume files (*.r3 " in filters[2] and filters[-1] == "All files (*)"
    assert window.editor.workspace == "volume" and window.workspace_actions["volume"].isChecked()
    assert shown_title(window) == "v.r3 — Volume — Shadelab"
    window.run(f"open {STAR}")
    recent = window.menus.recent_menu
    recent.aboutToShow.emit()
    assert [a.text() for a in recent.actions()[:2]] == [str(STAR), str(tmp_path / "v.r3")]
    recent.actions()[1].trigger()
    assert window.editor.workspace == "volume"
    assert [line.text for line in window.editor.console.log if line.level == "input"][-1] == \
        f"] open {tmp_path / 'v.r3'}"


def test_file_new_and_save(make_window, qtbot, tmp_path):
    window = make_window()
    window.run("workspace lights3d")
    file = window.menus.menus["file"]
    seen = answer(tmp_path / "lights")  # Save on an untitled scene asks where; the suffix comes from the format
    window.menus.save.trigger()
    assert said(seen)[0] == ["3D lights files (*.json)"]
    assert (tmp_path / "lights.json").is_file() and shown_title(window) == "lights.json — 3D lights — Shadelab"
    window.run("light3d.add point")
    window.menus.save.trigger()  # to its file, no dialog
    assert not window.isWindowModified()
    file.actions()[0].trigger()  # New: the default scene, untitled
    assert shown_title(window) == "untitled — 3D lights — Shadelab"
    assert window.editor.current.history.undo_name() == "Reset Scene"


def test_shadelab_with_a_file_opens_it_in_its_workspace(tmp_path):
    """`shadelab scene.json` with a 2D lighting scene and `shadelab v.r3` each end in the file's workspace."""
    assert startup_command(str(STAR)) == f"open {STAR}" and startup_command("x.lua") == "lua x.lua"
    editor = Editor(clock=VirtualClock(), configs=False)
    assert editor.execute("workspace volume") and editor.execute(f"save {tmp_path / 'v.r3'}")
    for path, workspace in ((STAR, "lighting2d"), (tmp_path / "v.r3", "volume")):
        log = tmp_path / f"{workspace}.log"
        run = subprocess.run([sys.executable, "-m", "app", str(path), "--cmd", "workspace", "--cmd",
                              f"condump {log}", "--size", "640x480", "--screenshot", str(tmp_path / "x.png")],
                             capture_output=True, text=True, timeout=120, env={**os.environ, "PYTHONPATH": os.getcwd()})
        assert run.returncode == 0, run.stderr
        text = log.read_text()
        assert f"workspace is {workspace}" in text and "is not a shadelab" not in text


CRASHING_SESSION = """
    import os, sys
    from PySide6.QtWidgets import QApplication
    from app.views.application import set_surface_format
    set_surface_format()
    app = QApplication(sys.argv[:1])
    from app.views.main_window import MainWindow
    window = MainWindow()
    window.run("open {path}")
    window.run("snow.add 0.25 -0.5 0.125")
    assert window.autosave.save() == 1
    print(window.editor.digest()["snowflake"], flush=True)
    os._exit(3)  # a crash: no close, no clean-up
"""


def test_a_crashed_sessions_autosave_is_offered_back(qtbot, tmp_path, monkeypatch):
    monkeypatch.setenv("SHADELAB_CACHE_DIR", str(tmp_path / "cache"))
    path = saved_flakes(tmp_path)
    crash = subprocess.run([sys.executable, "-c", textwrap.dedent(CRASHING_SESSION.format(path=path))],
                           capture_output=True, text=True, timeout=120, env={**os.environ, "PYTHONPATH": os.getcwd()})
    assert crash.returncode == 3, crash.stderr
    autosaved = crash.stdout.split()[-1]
    sessions = list((tmp_path / "cache" / "autosave").iterdir())
    assert len(sessions) == 1 and (sessions[0] / "snowflake.json").is_file()
    seen = answer(Button.Yes)
    window = MainWindow()  # the offer comes once it is up, whether or not it is active yet
    qtbot.addWidget(window, before_close_func=lambda w: setattr(w.editor.documents, "confirm", None))
    window.show()
    qtbot.waitUntil(lambda: len(seen) == 1)
    assert "did not exit cleanly" in said(seen)[0] and "Snowflake: flakes.json" in said(seen)[0]
    assert window.editor.digest()["snowflake"] == autosaved
    assert shown_title(window) == "flakes.json* — Snowflake — Shadelab"  # recovered work is unsaved
    assert [p.name for p in (tmp_path / "cache" / "autosave").iterdir()] == [window.autosave.folder.name]


def test_a_running_sessions_autosave_is_left_alone(make_window, tmp_path, monkeypatch):
    monkeypatch.setenv("SHADELAB_CACHE_DIR", str(tmp_path / "cache"))
    first = make_window()
    first.run("snow.add 0.5 0.5")
    assert first.autosave.save() == 1
    second = make_window()
    assert second.autosave.crashed() == []  # the first one's lock is held
    first.close()
    assert not first.autosave.folder.exists()  # a clean exit leaves nothing to recover
    assert second.autosave.folder.is_dir()


def test_save_as_without_a_suffix_keeps_a_scalar_volume_as_nrrd(make_window, qtbot, tmp_path):
    """Save As adds the suffix of the format that keeps the scene as it stands: a scalar volume's window goes
    into .nrrd (.r3 would keep the colours only)."""
    window = make_window(asks=True)
    source = tmp_path / "ct.npy"
    np.save(source, np.arange(8 * 8 * 8, dtype=np.int16).reshape(8, 8, 8))
    assert window.run("workspace volume") and window.run(f"load {source}") and window.run("vol.window 10 300")
    answer(tmp_path / "kept")
    window.run("ui.saveas")
    kept = read_volume_file(tmp_path / "kept.nrrd")
    assert kept.data.dtype == np.int16 and (kept.transfer.low, kept.transfer.high) == (10.0, 300.0)
    assert not (tmp_path / "kept.r3").exists()


def type_line(qtbot, window, line: str) -> None:
    """Type `line` into the console's command line and press Enter, as a person would."""
    field = window.console_widget.input
    field.setFocus()
    qtbot.waitUntil(field.hasFocus)
    qtbot.keyClicks(field, line)
    qtbot.keyClick(field, Qt.Key.Key_Return)


def test_a_clear_typed_over_unsaved_changes_never_asks(make_window, qtbot, tmp_path):
    """Issue 25: `snow.clear` typed over unsaved changes asked to save with Save focused, and the typing after it
    saved a stray file and lost the next line. Clearing is one undo step: no question, the scene keeps its file
    with unsaved changes, and the next line runs."""
    window = make_window(asks=True)
    path = saved_flakes(tmp_path)
    window.run(f"open {path}")
    window.run("snow.add 0.5 0.5")
    files, saved = sorted(tmp_path.iterdir()), path.read_bytes()
    with NoDialogs() as dialogs:
        type_line(qtbot, window, "snow.clear")
        type_line(qtbot, window, "snow.add 0.25 0.25")
    assert dialogs.came == []
    assert [(f.x, f.y) for f in window.editor.current.scene.flakes] == [(0.25, 0.25)]
    assert shown_title(window) == "flakes.json* — Snowflake — Shadelab"
    assert sorted(tmp_path.iterdir()) == files and path.read_bytes() == saved
    assert window.run("undo") and window.editor.current.history.undo_name() == "Clear Flakes"
    assert window.run("undo") and len(window.editor.current.scene.flakes) == 3  # the file's two and the one added


def changed_scenes(window, tmp_path):
    """Unsaved changes in three workspaces: a shipped 2D lighting sample (saved only through Save As), an untitled
    3D lights scene and a snowflake file. Returns the snowflake file."""
    path = saved_flakes(tmp_path)
    for line in (f"open {STAR}", "ambient 0.5 0.1 0.1", "workspace lights3d", "light3d.add point", f"open {path}",
                 "snow.add 0.4 0.4"):
        assert window.run(line)
    return path


def test_closing_with_several_changed_scenes_asks_once_and_saves_all(make_window, qtbot, tmp_path):
    window = make_window(asks=True)
    flakes = changed_scenes(window, tmp_path)
    seen = answer(Button.Cancel)
    window.close()
    assert window.isVisible() and len(seen) == 1  # one question, not one a scene
    assert said(seen)[0] == ("3 scenes have unsaved changes:\n• 2D lighting: f_concave_star.json\n"
                             "• 3D lights: untitled\n• Snowflake: flakes.json\n\nSave them before closing Shadelab?")
    assert sorted(showed(seen)[0]) == ["Cancel", "Discard All", "Save All"]
    seen = answer(Button.SaveAll, None)  # the sample needs Save As: cancelling it cancels the close
    window.close()
    assert window.isVisible() and said(seen)[1] == ["2D lighting files (*.json)"]
    documents, states = window.editor.documents, window.editor.workspaces
    assert all(documents.modified(states[name]) for name in ("lighting2d", "lights3d", "snowflake"))
    seen = answer(Button.SaveAll, tmp_path / "star", tmp_path / "lights")
    window.close()
    qtbot.waitUntil(lambda: not window.isVisible())
    assert said(seen)[1:] == [["2D lighting files (*.json)"], ["3D lights files (*.json)"]]
    fresh = Editor(clock=VirtualClock(), configs=False)
    for name, file in (("lighting2d", tmp_path / "star.json"), ("lights3d", tmp_path / "lights.json"),
                       ("snowflake", flakes)):
        assert fresh.execute(f"open {file}")
        assert fresh.workspaces[name].document_digest() == states[name].document_digest()


def test_discard_all_closes_without_writing_any(make_window, qtbot, tmp_path):
    window = make_window(asks=True)
    flakes = changed_scenes(window, tmp_path)
    files, saved = sorted(tmp_path.iterdir()), flakes.read_bytes()
    seen = answer(Button.Discard)
    window.close()
    qtbot.waitUntil(lambda: not window.isVisible())
    assert said(seen)[0].startswith("3 scenes have unsaved changes:")
    assert sorted(tmp_path.iterdir()) == files and flakes.read_bytes() == saved
