"""Caches and the user folder are input too (issue 26): what the editor reads back at its start (the last bench
results, its autosaves, its noise textures, window.ini, the console history) is parsed as someone else's file. A
malformed one is said and skipped or made again, never a failed start; a FIFO, a folder or a link where a file or
a folder of the editor's should be is refused; nothing is deleted through a link; and recovery offers only what
the editor itself autosaved, whose first Save asks where."""
import json
import os
import subprocess
import sys
import textwrap

import numpy as np
import pytest
from PySide6.QtWidgets import QMessageBox

from app.bench import report
from app.bench.harness import Row
from app.editor import Editor
from app.console.demo import VirtualClock
from app.io.clouds import noise_cache
from app.io.autosave import file_digest
from app.io.clouds.textures import RECIPES, noise_dir, noise_textures
from dialogs import NoDialogs, answer, showed
from test_exec_cli import ROOT
from tests.test_window_documents import CRASHING_SESSION

Button = QMessageBox.StandardButton


@pytest.fixture
def cache(tmp_path, monkeypatch):
    """A cache folder of the test's own."""
    monkeypatch.setenv("SHADELAB_CACHE_DIR", str(tmp_path / "cache"))
    (tmp_path / "cache").mkdir()
    return tmp_path / "cache"


def errors(window) -> list[str]:
    return [line.text for line in window.editor.console.log if line.level == "error"]


def no_internal_error(window) -> None:
    assert not any("internal error" in e or "Traceback" in e for e in errors(window))


def tree(folder) -> list[str]:
    """Everything under `folder`, links as links, with file contents."""
    found = []
    for root, dirs, names in os.walk(folder):
        for name in sorted(dirs + names):
            path = os.path.join(root, name)
            kind = "link" if os.path.islink(path) else "dir" if os.path.isdir(path) else open(path).read()
            found.append(f"{os.path.relpath(path, folder)}: {kind}")
    return sorted(found)


# ---- the bench dock's last results ----------------------------------------------------------------------------


def bench_csv(cache, cut: str) -> None:
    rows = [Row("snowflake", "gs", "level", float(k), "1 flake", 64, 64, 0.5 + k, 0.4, 3, 1e-8, 2e-8)
            for k in range(4)]
    (cache / "bench").mkdir()
    report.write_csv(cache / "bench" / "snowflake.csv", rows)
    text = (cache / "bench" / "snowflake.csv").read_text()
    text = text[:-20] if cut == "cut" else text.replace(",level,2,", ",level,nan,")  # the last row cut; a NaN knob
    (cache / "bench" / "snowflake.csv").write_text(text)


@pytest.mark.parametrize("cut, reason", [
    ("cut", "snowflake.csv:5: the row is cut short (no gpu_ms_median, runs, rmse, max_abs_error)"),
    ("nan", "snowflake.csv:4: knob must be a finite number, got nan"),
])
def test_a_malformed_bench_csv_in_the_cache_is_said_and_the_editor_starts(make_window, cache, cut, reason):
    """A truncated CSV stopped the editor from starting (TypeError)."""
    bench_csv(cache, cut)
    window = make_window()  # the snowflake workspace: its dock reads the CSV at start
    dock = window.bench
    assert dock.status.text().startswith("cannot read snowflake.csv: ") and reason in dock.status.text()
    assert dock.pages.currentWidget() is dock.hint and "Run quick bench" in dock.hint.text()  # makes it again
    no_internal_error(window)


# ---- FIFOs where files should be, through the editor's real start ---------------------------------------------


def test_fifos_in_place_of_cached_and_kept_files_neither_hang_nor_stop_the_start(tmp_path):
    """A FIFO in the cache hung the start (open() waits for a writer). Here one stands in for the bench results,
    window.ini, the console history, a crashed session's lock and another's manifest."""
    cache, config = tmp_path / "cache", tmp_path / "config"
    for folder in (cache / "bench", config, cache / "autosave" / "1-2", cache / "autosave" / "3-4"):
        folder.mkdir(parents=True)
    for fifo in (cache / "bench" / "snowflake.csv", config / "window.ini", config / "history",
                 cache / "autosave" / "1-2" / "lock", cache / "autosave" / "3-4" / "autosave.json"):
        os.mkfifo(fifo)
    log = tmp_path / "log.txt"
    run = subprocess.run([sys.executable, "-m", "app", "--cmd", f"condump {log}", "--size", "640x480",
                          "--screenshot", str(tmp_path / "shot.png")], capture_output=True, text=True, timeout=120,
                         env={**os.environ, "PYTHONPATH": ROOT, "SHADELAB_CACHE_DIR": str(cache),
                              "SHADELAB_CONFIG_DIR": str(config)})
    assert run.returncode == 0, run.stderr
    assert "Traceback" not in run.stderr and (tmp_path / "shot.png").is_file()
    said = log.read_text()
    assert (f"the console history {config / 'history'} is not read: is a FIFO (named pipe), not a regular file"
            in said)
    assert f"{config / 'window.ini'}: is a FIFO (named pipe), not a regular file; the window's layout" in said
    assert os.listdir(cache / "autosave" / "1-2") == ["lock"]  # passed over, left as it was
    assert not (cache / "autosave" / "3-4").exists()  # nothing to recover there: gone, its FIFO unlinked


def test_window_ini_values_of_the_wrong_type_are_passed_over(make_window, user_config_dir):
    """restoreGeometry of a text value raised TypeError: a failed start."""
    user_config_dir.mkdir()
    (user_config_dir / "window.ini").write_text("[window]\ngeometry=hello\nstate=42\n[recent]\n"
                                                "files=/a.json, relative.json, /b\\x1b[2J.json\n")
    window = make_window()
    assert window.menus.recent.paths() == ["/a.json"]
    no_internal_error(window)


# ---- noise textures --------------------------------------------------------------------------------------------


def test_noise_textures_of_nan_with_a_good_digest_are_rebuilt_with_a_message(make_window, cache):
    """Accepted before: the digest only shows a file is whole, and the clouds came out wrong without a word."""
    version, shape, _within, _build = RECIPES["shape"]
    path = noise_cache.cache_path("shape", noise_dir(), version)
    path.parent.mkdir(parents=True)
    path.write_bytes(noise_cache.encode(np.full(shape, np.nan, dtype=np.float32)))
    window = make_window()
    assert window.run("workspace clouds")
    said = [e for e in errors(window) if "noise cache" in e]
    assert said == [f"rebuilding the noise cache {path}: {np.prod(shape)} values are NaN or infinite"]
    made = noise_textures(cache_dir=noise_dir()).shape
    assert np.isfinite(made).all() and 0.0 <= made.min() and made.max() <= 1.0
    assert np.array_equal(noise_cache.decode(path.read_bytes(), shape, np.dtype(np.float32), (0.0, 1.0)), made)


# ---- the autosave folder ---------------------------------------------------------------------------------------


def test_autosave_as_a_file_turns_autosave_off_with_a_message(make_window, cache):
    """NotADirectoryError at start before."""
    (cache / "autosave").write_text("mine")
    window = make_window()
    assert f"autosave is off this session: {cache / 'autosave'} is a regular file, not a folder" in errors(window)[0]
    window.run("snow.add 0.5 0.5")
    assert window.autosave.save() == 0 and (cache / "autosave").read_text() == "mine"
    no_internal_error(window)


def test_autosave_as_a_link_to_a_users_folder_deletes_nothing_there(make_window, cache, tmp_path):
    """Recovery deleted every folder the link led to, whatever the user answered."""
    mine = tmp_path / "mine"
    for folder in ("123-456", "photos", "999-1"):
        (mine / folder).mkdir(parents=True)
        (mine / folder / "keep.txt").write_text(folder)
    (cache / "autosave").symlink_to(mine)
    before = tree(mine)
    with NoDialogs() as dialogs:
        window = make_window()
        window.run("snow.add 0.5 0.5")
        assert window.autosave.save() == 0
        window.close()
    assert dialogs.came == []  # nothing offered, so nothing to answer
    assert f"{cache / 'autosave'} is a symbolic link, not a folder" in errors(window)[0]
    assert tree(mine) == before


def test_links_in_the_autosave_folder_are_never_followed(make_window, cache, tmp_path):
    """A session folder that is a link is passed over; one that holds a link loses the link, not what it names."""
    mine = tmp_path / "mine"
    (mine / "sub").mkdir(parents=True)
    (mine / "secret.json").write_text("mine")
    (cache / "autosave" / "5-6").mkdir(parents=True)
    (cache / "autosave" / "5-6" / "snowflake.json").symlink_to(mine / "secret.json")
    (cache / "autosave" / "5-6" / "sub").symlink_to(mine / "sub")
    (cache / "autosave" / "7-8").symlink_to(mine)
    before = tree(mine)
    with NoDialogs() as dialogs:
        window = make_window()
        window.close()
    assert dialogs.came == [] and tree(mine) == before
    assert sorted(os.listdir(cache / "autosave")) == ["7-8"]  # 5-6 went, and the link 7-8 was not entered
    no_internal_error(window)


# ---- recovery offers only what the editor autosaved ------------------------------------------------------------


def plant(folder, manifest: dict) -> None:
    """A session folder as someone else made it: a snowflake scene and a manifest."""
    folder.mkdir(parents=True)
    (folder / "snowflake.json").write_text(json.dumps({"format": "shadelab.snowflake", "version": 1,
                                                       "flakes": [{"x": 0, "y": 0}]}))
    scene = {"workspace": "snowflake", "file": "snowflake.json", "sha256": file_digest(folder / "snowflake.json"),
             **manifest.pop("scene", {})}
    (folder / "autosave.json").write_text(json.dumps({"format": "shadelab.autosave", "version": 2,
                                                      "scenes": [scene], **manifest}))


def test_a_planted_manifest_is_passed_over_and_nothing_is_written_where_it_names(make_window, cache, tmp_path):
    """A planted manifest's `original` named ~/.ssh/authorized_keys, and the next Save wrote there."""
    keys = tmp_path / "home" / ".ssh" / "authorized_keys"
    keys.parent.mkdir(parents=True)
    keys.write_text("ssh-ed25519 AAAA me\n")
    autosave = cache / "autosave"
    plant(autosave / "100-1", {"scene": {"original": str(keys)}})  # no signature
    plant(autosave / "100-2", {"scene": {"original": str(keys)}, "signature": "0" * 64})
    (autosave / "100-3").mkdir()
    (autosave / "100-3" / "autosave.json").write_text('{"format": "shadelab.autosave", "version": 1, "scenes": '
                                                      '[{"workspace": "snowflake", "file": "x.json"}]}')  # before 26
    with NoDialogs() as dialogs:
        window = make_window()
        before = window.editor.digest()["snowflake"]
    assert dialogs.came == []  # nothing offered back
    passed = sorted(e for e in errors(window) if "is passed over" in e)
    assert [e.split(": ", 2)[1] for e in passed] == [f"{autosave / f'100-{i}'} is passed over" for i in (1, 2, 3)]
    assert "missing signature" in passed[0] and "is not signed by this editor's key" in passed[1]
    assert "unsupported version 1" in passed[2]
    assert window.editor.digest()["snowflake"] == before
    assert keys.read_text() == "ssh-ed25519 AAAA me\n"
    assert os.listdir(autosave) == [window.autosave.folder.name]




def test_a_recovered_scenes_first_save_asks_where(qtbot, cache, tmp_path):
    """The editor's own autosave is offered back; its first Save is a Save As that offers the original file, and
    a plain scene.save refuses, so nothing is written there unasked."""
    path = tmp_path / "flakes.json"
    editor = Editor(clock=VirtualClock(), configs=False)
    assert editor.execute("snow.clear") and editor.execute("snow.add 0 0") and editor.execute(f"scene.save {path}")
    saved = path.read_text()
    crash = subprocess.run([sys.executable, "-c", textwrap.dedent(CRASHING_SESSION.format(path=path))],
                           capture_output=True, text=True, timeout=120, env={**os.environ, "PYTHONPATH": ROOT})
    assert crash.returncode == 3, crash.stderr
    from app.views.main_window import MainWindow

    seen = answer(Button.Yes)
    window = MainWindow()
    qtbot.addWidget(window, before_close_func=lambda w: setattr(w.editor.documents, "confirm", None))
    window.show()
    qtbot.waitUntil(lambda: len(seen) == 1)
    qtbot.waitUntil(lambda: window.windowHandle().title().startswith("flakes.json*"))
    assert not window.run("scene.save")
    assert "the scene was recovered from an autosave: give the file to save it to" in errors(window)[-1]
    seen = answer(None)
    window.run("ui.save")  # File > Save: Save As, cancelled
    assert showed(seen) == [str(tmp_path)] and path.read_text() == saved
    seen = answer(tmp_path / "kept.json")
    assert window.run("ui.save")  # the user says where
    assert len(seen) == 1 and "0.25" in (tmp_path / "kept.json").read_text() and path.read_text() == saved
    assert window.run("snow.add 0 0.5") and window.run("scene.save")  # saved since: a plain Save writes again
    assert "0.5" in (tmp_path / "kept.json").read_text() and path.read_text() == saved
    no_internal_error(window)


def test_recover_typed_with_an_original_never_saves_there_unasked(tmp_path):
    keys = tmp_path / "authorized_keys"
    keys.write_text("ssh-ed25519 AAAA me\n")
    editor = Editor(clock=VirtualClock(), configs=False)
    assert editor.execute(f"scene.save {tmp_path / 'a.json'}")
    assert editor.execute(f"recover {tmp_path / 'a.json'} {keys}")
    assert editor.documents.path(editor.current) == str(keys)  # the title names it...
    assert not editor.execute("scene.save")  # ...and a plain save does not write it
    assert keys.read_text() == "ssh-ed25519 AAAA me\n"
    assert editor.documents.suggested_path(editor.current) == str(keys)  # Save As offers it, the user decides
