"""The Quake command set, config files and completion, on a real Editor's console."""
import pytest

from app.console import files
from app.console.completion import complete
from app.editor import Editor


@pytest.fixture
def editor(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    return Editor()


def out(editor):
    return editor.console.log[-1].text


def errors(editor):
    return [line.text for line in editor.console.log if line.level == "error"]


def test_start_configs_set_seed_cvars_and_binds(editor):
    cvars = editor.console.registry.cvars
    assert cvars["cl_steps"].value == 128 and cvars["cl_steps"].type is int and cvars["cl_steps"].archive
    assert cvars["cl_distanceScale"].type is float
    assert editor.binds.lookup("snowflake", "w") == "snow.step 0.25"
    assert editor.binds.lookup("volume", "w") == "orbit.step 0 0 -0.25"
    assert editor.binds.lookup("clouds", "w") is None
    assert errors(editor) == []


def test_set_seta_reset_toggle(editor):
    e = editor
    assert e.execute("set r_name hello; seta r_count 3; set r_flag 0")
    reg = e.console.registry
    assert (reg.cvars["r_name"].type, reg.cvars["r_count"].type) == (str, int)
    assert reg.cvars["r_count"].archive and not reg.cvars["r_name"].archive
    assert e.execute("r_count 5") and reg.cvars["r_count"].value == 5
    assert not e.execute("r_count five") and reg.cvars["r_count"].value == 5
    assert e.execute("reset r_count") and reg.cvars["r_count"].value == 3
    assert e.execute("toggle r_count 3 7 9") and reg.cvars["r_count"].value == 7
    assert e.execute("toggle r_count 3 7 9; toggle r_count 3 7 9") and reg.cvars["r_count"].value == 3
    assert not e.execute("toggle r_count") and "give the values" in errors(e)[-1]
    assert not e.execute("set snow.add 1") and "is a command" in errors(e)[-1]


def test_registered_cvar_takes_over_a_set_one(editor):
    from app.console.registry import Cvar

    editor.execute("set r_later 12")
    cvar = editor.console.registry.add_cvar(Cvar("r_later", float, 1.0))
    assert cvar.value == 12.0 and cvar.type is float


def test_lists_and_help(editor):
    e = editor
    e.execute("cvarlist cl_")
    assert out(e) == "4 cvars"
    e.execute("cmdlist snow.")
    assert out(e) == "8 commands"
    e.execute("help snow.add")
    assert out(e).startswith("[snowflake] snow.add <x> <y> [<radius>]:")
    e.execute("help cl_steps")
    assert "now 128" in out(e)
    assert not e.execute("help nothing")


def test_echo_alias_and_loops(editor):
    e = editor
    assert e.execute('alias grow "snow.step 1; echo grown"')
    level = e.workspaces["snowflake"].scene.level
    assert e.execute("grow")
    assert e.workspaces["snowflake"].scene.level == level + 1 and out(e) == "grown"
    e.execute("alias loop loop")
    assert not e.execute("loop")
    assert "nested more than" in errors(e)[-1]
    assert not e.execute("alias snow.add x") and "already registered" in errors(e)[-1]


def test_wait_defers_the_rest_of_the_line(editor):
    e = editor
    level = e.workspaces["snowflake"].scene.level
    assert e.execute("snow.step 1; wait 2; snow.step 1")
    assert e.workspaces["snowflake"].scene.level == level + 1
    e.console.frame()
    assert e.workspaces["snowflake"].scene.level == level + 1
    e.console.frame()
    assert e.workspaces["snowflake"].scene.level == level + 2 and not e.console.waiting
    assert not e.execute("wait many")


@pytest.mark.parametrize("workspace, line, said", [
    ("volume", "bind F5", "F5 is bound to 'mode 5' in volume"),
    ("volume", "bind c", "c is bound to 'ui.background' in volume (elsewhere: painter:c 'ui.brushcolor')"),
    ("snowflake", "bind F5", "F5 is not bound in snowflake (elsewhere: volume:F5 'mode 5')"),
    ("snowflake", "bind volume:f5", "volume:F5 is bound to 'mode 5'"),
    ("clouds", "bind F12", "F12 is bound to 'digest'"),
])
def test_bind_alone_says_what_the_key_runs_in_this_workspace(editor, workspace, line, said):
    """default.cfg binds F5 in the volume workspace only: `bind F5` there finds it."""
    editor.execute(f"workspace {workspace}")
    assert editor.execute(line) and out(editor) == said


def test_bind_unbind_bindlist(editor):
    e = editor
    assert e.execute("bind F5 snow.level 3")  # unquoted words are joined, as in Quake
    assert e.binds.lookup("snowflake", "F5") == "snow.level 3"
    assert e.execute('bind snowflake:f5 "snow.level 4"')
    assert e.binds.lookup("snowflake", "F5") == "snow.level 4" and e.binds.lookup("clouds", "F5") == "snow.level 3"
    e.execute("bind F5")  # in the snowflake workspace, its own bind runs
    assert out(e) == "F5 is bound to 'snow.level 4' in snowflake (elsewhere: 'snow.level 3'; volume:F5 'mode 5')"
    assert not e.execute("bind NOTAKEY x") and "no key called" in errors(e)[-1]
    assert e.execute("unbind F5") and not e.execute("unbind F5")
    e.execute("bindlist")
    assert any(line.text == "bind snowflake:F5 'snow.level 4'" for line in e.console.log)


def test_exec_reports_the_failing_line_and_runs_the_rest(editor, tmp_path):
    (tmp_path / "mine.cfg").write_text("// comment\nsnow.level 2\nsnow.level banana\nsnow.step 1\n")
    assert not editor.execute("exec mine.cfg")
    assert editor.workspaces["snowflake"].scene.level == 3
    assert "exec: mine.cfg:3: snow.level banana" in errors(editor)
    assert not editor.execute("exec none.cfg") and "cannot find none.cfg" in errors(editor)[-1]


def test_writeconfig_round_trip(editor, tmp_path):
    e = editor
    e.execute("seta r_keep 7; set r_lose 1; bind x snow.clear; alias hi 'echo hi'; cl_steps 256")
    assert e.execute("writeconfig")
    text = files.user_config().read_text()
    assert "seta r_keep 7" in text and "r_lose" not in text and "seta cl_steps 256" in text
    again = Editor()  # a new start reads the user config after the defaults
    reg = again.console.registry
    assert reg.cvars["r_keep"].value == 7 and reg.cvars["cl_steps"].value == 256
    assert again.binds.lookup("", "x") == "snow.clear" and reg.aliases["hi"] == "echo hi"


def test_condump_and_clear(editor, tmp_path):
    editor.execute("echo first line")
    assert editor.execute("condump dump.txt")
    assert "first line" in (tmp_path / "dump.txt").read_text()
    editor.execute("clear")
    assert editor.console.log == []


def test_quit_tells_the_host(editor):
    told = []
    editor.console.quit_listeners.append(lambda: told.append(True))
    editor.execute("quit")
    assert told == [True]


@pytest.mark.parametrize("line, expected_line, expected", [
    ("snow.ad", "snow.add ", []),
    ("snow.", "snow.", ["snow.add", "snow.clear", "snow.level", "snow.list", "snow.move", "snow.remove",
                        "snow.step", "snow.view"]),
    ("cl_sh", "cl_shadowSteps ", ["cl_shadowSteps = 20"]),
    ("cl_s", "cl_s", ["cl_sampleRange = 1", "cl_shadowSteps = 20", "cl_steps = 128"]),
    ("bind F1", "bind F1", ["F1", "F10", "F11", "F12"]),
    ("bind pg", "bind PG", ["PGDN", "PGUP"]),
    ("bind x snow.cl", "bind x snow.clear ", ["snow.clear"]),
    ("exec shade", "exec shadelab.cfg ", ["shadelab.cfg"]),
    ("play snow", "play snowflake_tour.demo ", ["snowflake_tour.demo"]),
    ("lua ri", "lua ring.lua ", ["ring.lua"]),
    ("snow.add 1 ", "snow.add 1 ", []),
])
def test_completion(editor, line, expected_line, expected):
    result = complete(editor.console.registry, line)
    assert result.line == expected_line
    if expected:
        assert result.candidates == expected


@pytest.mark.parametrize("arg, line", [
    ("my.cfg", "exec my.cfg"), ("ring.lua", "lua ring.lua"), ("tour.demo", "play tour.demo"),
    ("scene one.json", "open 'scene one.json'"), ("head.r3", "open head.r3"),  # in the file's own workspace
])
def test_first_argument_of_the_editor(arg, line):
    from app.views.application import startup_command

    assert startup_command(arg) == line


def test_an_unbound_default_stays_unbound_after_a_restart(editor):
    assert editor.execute("unbind volume:m; writeconfig")
    assert Editor().binds.lookup("volume", "m") is None


def test_completion_never_drops_the_typed_letter(editor):
    assert complete(editor.console.registry, "bind f").line == "bind f"
