"""A save never makes folders: every command that writes a file, and `render --out`, refuses a path whose
folder does not exist and leaves no folder behind. The user folder is the exception (Shadelab's own, made
when first written), and `bench --out DIR` names a folder of outputs, which it makes."""
import shlex

import pytest

from app import cli
from app.console import files
from app.editor import Editor

WRITERS = {"condump": "log.txt", "writeconfig": "mine.cfg", "save": "v.r3", "record": "take"}


@pytest.fixture
def editor(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    return Editor(configs=False)


def errors(editor) -> str:
    return "\n".join(line.text for line in editor.console.log if line.level == "error")


@pytest.mark.parametrize("command", sorted(WRITERS))
def test_a_typed_write_into_a_missing_folder_is_refused(editor, tmp_path, command):
    editor.execute("workspace volume")  # `save` is the volume's
    target = tmp_path / "no" / "such" / WRITERS[command]
    assert not editor.execute(f"{command} {shlex.quote(str(target))}")
    assert f"there is no folder {target.parent} (make it first)" in errors(editor)
    assert not (tmp_path / "no").exists() and editor.demos.recorder is None


@pytest.mark.parametrize("workspace", [s.name for s in Editor(configs=False).workspaces if s.files is not None])
def test_scene_save_into_a_missing_folder_is_refused_in_every_workspace(editor, tmp_path, workspace):
    editor.execute(f"workspace {workspace}")
    target = tmp_path / "no" / f"scene{editor.current.files.suffixes[0]}"
    assert not editor.execute(f"scene.save {shlex.quote(str(target))}")
    assert "there is no folder" in errors(editor) and not target.parent.exists()
    target.parent.mkdir()
    assert editor.execute(f"scene.save {shlex.quote(str(target))}") and target.is_file()  # once it exists


def test_an_untrusted_write_makes_the_sandbox_but_no_folder_inside_it(editor, tmp_path):
    script = tmp_path / "s.cfg"
    script.write_text("condump sub/log.txt\n")
    assert not editor.execute(f"exec {script}")
    assert "there is no folder" in errors(editor) and not (files.sandbox_dir() / "sub").exists()
    script.write_text("condump log.txt\n")
    assert editor.execute(f"exec {script}")
    assert (files.sandbox_dir() / "log.txt").is_file()


def test_render_out_into_a_missing_folder_is_refused_before_any_work(tmp_path, capsys):
    out = tmp_path / "no" / "a.png"
    assert cli.main(["render", "snowflake", "--size", "64x64", "--out", str(out)]) == 1
    assert f"shadelab render: cannot write {out}: there is no folder {out.parent}" in capsys.readouterr().err
    assert not out.parent.exists()
