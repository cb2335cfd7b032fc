"""Commands from scripts, configs, binds and aliases stay in their sandbox (issue 12, B.2-B.5), on a real
Editor's console: the file policy, control characters in stored text, and caps on what one line may cost."""
import os
import shlex

import pytest

from app.console import console as console_module, files
from app.editor import Editor


@pytest.fixture
def editor(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    return Editor(configs=False)


def errors(editor):
    return [line.text for line in editor.console.log if line.level == "error"]


@pytest.fixture
def outside(tmp_path):
    """A folder of the user's that is neither the Shadelab folder nor beside a file that runs."""
    folder = tmp_path / "home"
    folder.mkdir()
    (folder / "secret.cfg").write_text("echo the secret\n")
    return folder


def run_as(editor, origin, line, tmp_path):
    """Run one console line as each untrusted origin would (the line is quoted as text where it must be)."""
    console = editor.console
    scripts = tmp_path / "scripts"  # files that run live here, apart from `outside`
    scripts.mkdir(exist_ok=True)
    if origin == "lua":
        (scripts / "s.lua").write_text(f"exec({line!r})\n")
        return console.execute(f"lua {shlex.quote(str(scripts / 's.lua'))}")
    if origin == "config":
        (scripts / "s.cfg").write_text(line + "\n")
        return console.execute(f"exec {shlex.quote(str(scripts / 's.cfg'))}")
    if origin == "alias":
        console.registry.set_alias("doit", line)
        return console.execute("doit")
    if origin == "demo":
        (scripts / "s.demo").write_text(f"shadelab-demo 1\n0 {line}\n")
        ok = console.execute(f"play {shlex.quote(str(scripts / 's.demo'))}")
        return ok and not editor.demos.playing and not any("stopped at" in e for e in errors(editor))
    assert origin == "bind"  # what MainWindow.run_bind does with a bound key's command
    editor.binds.bind("k", line)
    with console.untrusted("bind"):
        return console.execute(editor.binds.lookup("snowflake", "k"))


ORIGINS = ["lua", "config", "alias", "bind", "demo"]
WRITERS = ["condump {}", "writeconfig {}", "save {}", "scene.save {}", "record {}"]
READERS = ["exec {}", "lua {}", "load {}", "scene.load {}", "play {}", "lighting.background {}"]


@pytest.mark.parametrize("origin", ORIGINS)
@pytest.mark.parametrize("command", WRITERS)
def test_untrusted_lines_write_nowhere_outside_the_sandbox(editor, tmp_path, outside, origin, command):
    for target in (outside / "out.txt", tmp_path / "user-config" / ".." / "home" / "dotdot.txt",
                   files.config_dir() / "config.cfg"):
        assert not run_as(editor, origin, command.format(shlex.quote(str(target))), tmp_path)
        assert not target.exists()
    refusal = "it is the user's own" if command.startswith("writeconfig") else "may write only inside the sandbox"
    assert any(refusal in e for e in errors(editor)), errors(editor)


@pytest.mark.parametrize("origin", ORIGINS)
def test_a_symbolic_link_in_the_sandbox_leads_nowhere_else(editor, tmp_path, outside, origin):
    sandbox = files.sandbox_dir()
    sandbox.mkdir(parents=True, exist_ok=True)
    (sandbox / "link").symlink_to(outside)
    assert not run_as(editor, origin, "condump link/x.txt", tmp_path)
    assert not (outside / "x.txt").exists()


@pytest.mark.parametrize("origin", ORIGINS)
@pytest.mark.parametrize("command", [w for w in WRITERS if not w.startswith(("writeconfig", "record"))])
def test_untrusted_relative_names_land_in_the_sandbox(editor, tmp_path, origin, command):
    name = {"save": "v.r3", "scene.save": "s.json"}.get(command.split()[0], "f.txt")
    assert run_as(editor, origin, command.format(name), tmp_path), errors(editor)
    assert (files.sandbox_dir() / name).is_file()
    assert not (tmp_path / name).exists() and not (files.config_dir() / name).exists()  # nor the user folder


def test_a_sandbox_that_is_a_planted_link_is_refused(editor, tmp_path, outside):
    files.config_dir().mkdir(parents=True, exist_ok=True)
    files.sandbox_dir().symlink_to(outside)
    assert not run_as(editor, "lua", "condump f.txt", tmp_path)
    assert not (outside / "f.txt").exists() and any("not a folder Shadelab made" in e for e in errors(editor))


@pytest.mark.parametrize("origin", ORIGINS)
@pytest.mark.parametrize("command", READERS)
def test_untrusted_lines_read_nothing_outside_their_places(editor, tmp_path, outside, origin, command):
    secret = outside / {"exec": "secret.cfg", "play": "secret.demo", "lighting.background": "secret.png"}.get(
        command.split()[0], "secret.lua")
    secret.write_text("shadelab-demo 1\n0 echo the secret\n" if secret.suffix == ".demo" else "echo the secret\n")
    before = editor.digest()
    assert not run_as(editor, origin, command.format(shlex.quote(str(secret))), tmp_path)
    assert "the secret" not in [line.text for line in editor.console.log]
    refusal = "a demo is already playing" if (origin, command) == ("demo", "play {}") else "may not read"
    assert any(refusal in e for e in errors(editor)), errors(editor)
    assert editor.digest() == before


def test_the_private_key_case(editor, tmp_path, outside):
    """`exec ~/.ssh/id_ed25519` from a script used to echo the key into the log, and condump copied it out."""
    key = outside / "id_ed25519"
    key.write_text("-----BEGIN OPENSSH PRIVATE KEY-----\n")
    assert not run_as(editor, "lua", f"exec {key}; condump {outside / 'leak.txt'}", tmp_path)
    assert "BEGIN OPENSSH" not in "".join(line.text for line in editor.console.log)
    assert not (outside / "leak.txt").exists()


def test_the_user_may_read_and_write_anywhere(editor, tmp_path, outside):
    assert editor.execute(f"exec {outside / 'secret.cfg'}")
    assert editor.execute(f"condump {outside / 'log.txt'}")
    assert "the secret" in (outside / "log.txt").read_text()


def test_untrusted_lines_read_beside_the_file_that_runs_and_the_resources(editor, tmp_path):
    scripts = tmp_path / "scripts"
    scripts.mkdir()
    (scripts / "helper.cfg").write_text("echo beside\n")
    (scripts / "main.lua").write_text("exec('exec helper.cfg')\nexec('exec default.cfg')\n")
    assert editor.execute(f"lua {scripts / 'main.lua'}"), errors(editor)
    assert "beside" in [line.text for line in editor.console.log]


# --- B.3: stored text never carries a second line into config.cfg -----------------------------------------


@pytest.mark.parametrize("line", [
    'alias x "echo hi\ncondump /some/file //"',
    'bind k "echo hi\ncondump /some/file"',
    'set r_text "a\nb"',
    'alias x "echo \u2028condump f"',  # str.splitlines() breaks here too
    'seta r_text "a\x00b"',
])
def test_control_characters_are_refused_in_aliases_binds_and_cvars(editor, line):
    before = (dict(editor.console.registry.aliases), dict(editor.binds.table), set(editor.console.registry.cvars))
    assert not editor.execute(line)
    assert "control characters" in errors(editor)[-1]
    assert before == (dict(editor.console.registry.aliases), dict(editor.binds.table),
                      set(editor.console.registry.cvars))


def test_a_lua_alias_with_a_newline_never_reaches_the_config(editor):
    assert not editor.lua.run_string('cmd.alias("x", "echo hi\\ncondump /some/file //")\n', "evil.lua")
    assert editor.execute("writeconfig")
    written = files.user_config().read_text()
    assert "condump" not in written and "x" not in editor.console.registry.aliases


def test_what_writeconfig_writes_reads_back_the_same(editor):
    assert editor.execute("""alias q "echo 'a b' ; echo \\"//x\\"" ; bind k "echo it's" ; seta r_s 'x y'""")
    assert editor.execute("writeconfig")
    fresh = Editor()  # the start runs the user's config.cfg, as the user's own
    assert not [line.text for line in fresh.console.log if line.level == "error"]
    assert fresh.console.registry.aliases["q"] == editor.console.registry.aliases["q"]
    assert fresh.binds.table == editor.binds.table
    assert fresh.console.registry.cvars["r_s"].value == "x y"


# --- B.4: one console call is bounded -----------------------------------------------------------------------


def test_a_self_doubling_alias_stops_with_one_message(editor):
    assert editor.execute('alias a "a;a"')
    assert not editor.execute("a")
    assert len(errors(editor)) == 1 and errors(editor)[0].startswith("alias a: nested more than 32 deep")
    assert editor.execute('alias b "b2;b2;b2;b2;b2;b2;b2;b2;b2;b2"; alias b2 "b3;b3;b3;b3;b3;b3;b3;b3;b3;b3"')
    assert editor.execute('alias b3 "b4;b4;b4;b4;b4;b4;b4;b4;b4;b4"; alias b4 "b5;b5;b5;b5;b5;b5;b5;b5;b5;b5"')
    assert editor.execute('alias b5 "echo x;echo x;echo x"')  # 30,000 echoes, never deeper than six
    assert not editor.execute("b")
    assert errors(editor)[-1:] == ["alias b: more than 20000 commands from one alias or config (one that calls "
                                  "itself?); stopped"]
    assert editor.execute("echo still here")


def test_a_config_that_execs_itself_twice_stops(editor, tmp_path):
    (tmp_path / "twice.cfg").write_text("exec twice.cfg\nexec twice.cfg\n")
    assert not editor.execute(f"exec {tmp_path / 'twice.cfg'}")
    assert len(errors(editor)) == 1 and "nested more than 32 deep" in errors(editor)[0]


def test_console_work_per_line_is_capped(editor):
    assert not editor.execute("echo " + "A" * (console_module.MAX_LINE + 1))
    assert "at most" in errors(editor)[-1]
    assert not editor.execute("echo " + "A" * (console_module.MAX_WORD + 1))
    assert "an argument of" in errors(editor)[-1]
    assert editor.execute("echo " + "A" * console_module.MAX_WORD)  # just under: fine


def test_a_long_line_from_lua_is_parsed_in_linear_time(editor):
    """cmd.echo(string.rep("A", 2^20)) took 34 s in shlex; the line cap and a linear split bound it."""
    assert not editor.lua.run_string('cmd.echo(string.rep("A", 2^20))', "long.lua")
    assert editor.lua.run_string('cmd.echo(string.rep("A", 60000))', "ok.lua"), errors(editor)


def test_the_split_agrees_with_shlex():
    from hypothesis import given, settings, strategies as st

    @settings(max_examples=2000, deadline=None)
    @given(st.text("ab \t'\"\\;x", max_size=16))
    def agree(text):
        try:
            expected = shlex.split(text)
        except ValueError:
            expected = ValueError
        try:
            got = console_module.split_words(text)
        except ValueError:
            got = ValueError
        assert got == expected

    agree()


def test_a_waiting_alias_loop_stops_at_the_chain_cap(editor, monkeypatch):
    monkeypatch.setattr(console_module, "MAX_WAIT_CHAIN", 50)
    console = editor.console
    assert editor.execute('alias loop "echo x; wait 1; loop"')
    assert editor.execute("loop")
    frames = 0
    while console.waiting and frames < 1000:
        console.frame()
        frames += 1
    assert not console.waiting and frames <= 51
    assert any("50 waits in a row" in e for e in errors(editor))


# --- B.5: the log is bounded in bytes, and one huge line does not freeze the view ---------------------------


def test_the_log_keeps_a_bounded_amount_of_text(editor):
    console = editor.console
    for _ in range(20):
        console.print("x" * 2**20)
    total = sum(len(line.text) for line in console.log)
    assert total <= console_module.MAX_LOG_CHARS
    assert all(len(line.text) <= console_module.MAX_LOG_LINE + 100 for line in console.log)
    assert console.log[-1].text.endswith("more characters not shown)")
    assert console.printed >= 20


def test_dot_dot_from_a_config_cannot_climb_out(editor, tmp_path):
    """A relative name from a config lands in the user folder: no dot-dot or absolute escape survives."""
    (tmp_path / "c.cfg").write_text("condump ../../escape.txt\n")
    assert not editor.execute(f"exec {tmp_path / 'c.cfg'}")
    assert not (tmp_path / "escape.txt").exists() and not os.path.exists(tmp_path.parent / "escape.txt")


def test_configs_demos_and_scripts_are_read_within_a_bound(editor, tmp_path):
    """They are read whole before anything runs: a file of any size would be read into memory first."""
    from app.console import builtins, demo

    (tmp_path / "big.cfg").write_bytes(b"echo x\n" * (builtins.MAX_CONFIG_BYTES // 7 + 1))
    assert not editor.execute(f"exec {tmp_path / 'big.cfg'}")
    assert "over the size limit" in errors(editor)[-1]
    (tmp_path / "big.demo").write_bytes(b"shadelab-demo 1\n" + b"0 echo x\n" * (demo.MAX_BYTES // 9 + 1))
    assert not editor.execute(f"play {tmp_path / 'big.demo'}")
    assert "over the size limit" in errors(editor)[-1]
    (tmp_path / "big.lua").write_bytes(b"--" + b"x" * (editor.lua.memory_limit // 2))
    assert not editor.execute(f"lua {tmp_path / 'big.lua'}")
    assert "over the size limit" in errors(editor)[-1]
    assert "x" not in [line.text for line in editor.console.log]
