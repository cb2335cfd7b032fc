"""Where File > Open and Save As start (issue 25; they started in the folder Shadelab ran from): in the folder a
file was last opened from or saved to, kept in window.ini between runs, else the user's documents folder (their
home without one). window.ini is input: anything it names that is not a folder there now is passed over."""
import pytest

from app.resources import SCENES
from dialogs import answer, showed


@pytest.fixture
def home(tmp_path, monkeypatch):
    """A home of the test's own with a Documents folder: Qt's documents folder is $HOME/Documents where
    $XDG_CONFIG_HOME/user-dirs.dirs names none."""
    home = tmp_path / "home"
    (home / "Documents").mkdir(parents=True)
    monkeypatch.setenv("HOME", str(home))
    monkeypatch.setenv("XDG_CONFIG_HOME", str(home / ".config"))
    return home


def started_in(window, line: str, *answers) -> str:
    """The folder the dialog `line` opens starts in (answered with `answers`, cancelled without)."""
    seen = answer(*(answers or (None,)))
    window.run(line)
    return showed(seen)[0]


def test_the_dialogs_start_in_documents_then_where_a_file_was_last_opened_or_saved(make_window, home, tmp_path):
    window = make_window()
    assert started_in(window, "ui.open") == str(home / "Documents")
    work = tmp_path / "work"
    work.mkdir()
    assert started_in(window, "ui.saveas", work / "flakes") == str(home / "Documents")
    assert (work / "flakes.json").is_file()
    assert started_in(window, "ui.open") == str(work)
    assert window.run(f"open {SCENES / 'f_concave_star.json'}")  # a shipped sample's folder is not the user's
    assert started_in(window, "ui.saveas") == str(work)  # nor does Save As of a sample start beside it
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    assert window.run(f"scene.save {elsewhere / 'star.json'}")  # typed: the user's own line
    again = make_window()  # the next run
    assert started_in(again, "ui.open") == str(elsewhere)


def test_what_a_script_saves_does_not_move_the_dialogs(make_window, home, tmp_path):
    window = make_window()
    script = tmp_path / "saves.cfg"
    script.write_text("scene.save from_a_script.json\n")
    assert window.run(f"exec {script}")
    saved = window.editor.documents.path(window.editor.current)
    assert saved.endswith("from_a_script.json")  # where the script's writes may go, not where the user works
    assert started_in(window, "ui.open") == str(home / "Documents")


@pytest.mark.parametrize("kept", ["{tmp}/a_file.txt", "{tmp}/gone", "relative/folder", "@Invalid()", "{tmp}, {tmp}",
                                  "@ByteArray(\\0\\0)", ""])
def test_a_folder_window_ini_names_that_is_none_is_passed_over(make_window, home, tmp_path, user_config_dir, kept):
    (tmp_path / "a_file.txt").write_text("not a folder")
    user_config_dir.mkdir(parents=True, exist_ok=True)
    (user_config_dir / "window.ini").write_text(f"[files]\nfolder={kept.format(tmp=tmp_path)}\n")
    window = make_window()
    assert started_in(window, "ui.open") == str(home / "Documents")
    (home / "Documents").rmdir()
    assert started_in(window, "ui.open") == str(home)  # no documents folder: home
