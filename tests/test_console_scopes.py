"""Commands scoped to a workspace: one bare name per workspace, resolved by the current one; `workspace:name`
exact; claims that keep every bare name unambiguous; demo checks per workspace; help, cmdlist, completion."""
import pytest

from app.console import builtins, demo
from app.console.binds import Binds
from app.console.completion import complete
from app.console.console import Console
from app.console.demo import ArgChecks, DemoError
from app.console.registry import CommandError, Cvar

HEADER = "shadelab-demo 1\n"


def make_console() -> Console:
    """Workspaces a and b each with their own `light.add` (different arguments), `orbit` only in b, a global
    `workspace` that switches the scope as the editor's does, and the builtins (help, cmdlist, alias...)."""
    c = Console()
    builtins.register(c, Binds())
    c.calls = []
    reg = c.registry

    @reg.command("workspace", "name", "Switch the workspace")
    def workspace(name: str) -> None:
        reg.scope = name

    a, b = reg.scoped("a"), reg.scoped("b")
    a.command("light.add", "x:float y:float", "Add a 2D light")(lambda x, y: c.calls.append(("a", x, y)))
    b.command("light.add", "x:float y:float z:float", "Add a 3D light")(lambda *xyz: c.calls.append(("b", *xyz)))
    b.command("orbit", "yaw:float", "Turn the camera", completer=lambda p: [w for w in ("left", "right")
                                                                              if w.startswith(p)])(
        lambda yaw: c.calls.append(("orbit", yaw)))
    return c


@pytest.fixture
def console():
    return make_console()


def errors(console):
    return [line.text for line in console.log if line.level == "error"]


def out(console):
    return console.log[-1].text


@pytest.mark.parametrize("scope, line, call", [
    ("a", "light.add 1 2", ("a", 1.0, 2.0)),
    ("b", "light.add 1 2 3", ("b", 1.0, 2.0, 3.0)),
    (None, "light.add 1 2", ("a", 1.0, 2.0)),  # no workspace: the one that registered the name first
    ("c", "light.add 1 2", ("a", 1.0, 2.0)),   # a workspace without its own: the same
    ("a", "b:light.add 1 2 3", ("b", 1.0, 2.0, 3.0)),  # qualified: exact, whatever the scope
    (None, "a:light.add 1 2", ("a", 1.0, 2.0)),
    ("a", "orbit 90", ("orbit", 90.0)),  # only b has it: it keeps working from a
])
def test_a_bare_name_runs_the_current_workspaces_command(console, scope, line, call):
    console.registry.scope = scope
    assert console.execute(line), errors(console)
    assert console.calls == [call]


def test_a_qualified_name_never_falls_back(console):
    assert not console.execute("a:orbit 90")
    assert errors(console)[-1] == "a:orbit: unknown command 'a:orbit'"
    assert not console.execute("nothing")
    assert errors(console)[-1] == "nothing: unknown command 'nothing'"


def test_arguments_bind_to_the_resolved_command(console):
    console.registry.scope = "b"
    assert not console.execute("light.add 1 2")
    assert "missing <z>; usage: light.add <x> <y> <z>" in errors(console)[-1]
    assert console.calls == []


def test_the_table_is_keyed_by_command_key_and_resolves_lookups(console):
    reg = console.registry
    keys = list(reg.commands)
    assert keys[-3:] == ["a:light.add", "b:light.add", "b:orbit"] and len(reg.commands) == len(keys)
    reg.scope = "b"
    assert reg.commands["light.add"].key == "b:light.add" and reg.commands.get("orbit").scope == "b"
    assert "light.add" in reg.commands and "a:light.add" in reg.commands and "c:light.add" not in reg.commands
    assert reg.commands.get("nothing") is None
    assert reg.resolve("light.add", "a").key == "a:light.add" and reg.resolve("light.add", None).key == "a:light.add"
    assert {key: c.key for key, c in reg.commands.items()}["a:light.add"] == "a:light.add"  # iteration is exact


@pytest.mark.parametrize("register", [
    lambda reg: reg.command("light.add")(print),             # a global command named like a scoped one
    lambda reg: reg.add_cvar(Cvar("light.add", int, 0)),    # a cvar
    lambda reg: reg.set_alias("orbit", "echo x"),           # an alias
    lambda reg: reg.set_alias("b:orbit", "echo x"),         # a name that is a command's key
    lambda reg: reg.scoped("a").command("echo")(print),      # a scoped command named like a global one
    lambda reg: reg.scoped("a").command("cl_x")(print),      # ... like a cvar
    lambda reg: reg.scoped("a").command("myalias")(print),   # ... like an alias
    lambda reg: reg.scoped("a").command("light.add")(print),  # a key registered twice
    lambda reg: reg.scoped("a:b").command("x")(print),       # ':' separates workspace and name
    lambda reg: reg.scoped("a").command("x:y")(print),
    lambda reg: reg.scoped("a b").command("x")(print),
])
def test_claims_keep_every_bare_name_unambiguous(console, register):
    reg = console.registry
    reg.add_cvar(Cvar("cl_x", int, 0))
    reg.set_alias("myalias", "echo x")
    before = (list(reg.commands), dict(reg.cvars), dict(reg.aliases))
    with pytest.raises(ValueError):
        register(reg)
    assert (list(reg.commands), dict(reg.cvars), dict(reg.aliases)) == before


def test_console_commands_refuse_scoped_names_too(console):
    assert not console.execute("set light.add 1")
    assert "'light.add' is a command, not a cvar" in errors(console)[-1]
    assert not console.execute("alias orbit echo")
    assert "already registered" in errors(console)[-1]


def test_the_same_bare_name_in_a_third_workspace_is_allowed(console):
    console.registry.scoped("c").command("light.add", "", "Add a cloud light")(lambda: console.calls.append("c"))
    console.registry.scope = "c"
    assert console.execute("light.add") and console.calls == ["c"]


def test_a_scoped_view_delegates_everything_else(console):
    view = console.registry.scoped("a")
    view.add_cvar(Cvar("r_thing", int, 3))
    assert console.registry.cvars["r_thing"].value == 3 and view.cvars is console.registry.cvars
    console.registry.scope = "b"
    assert view.scope == "b"  # the current workspace, not the view's
    assert view.commands["light.add"].key == "b:light.add"


# ---- cvar choices -------------------------------------------------------------------------------------

def test_cvar_choices_refuse_other_values(console):
    cvar = console.registry.add_cvar(Cvar("r_method", str, "exact", choices=("exact", "jitter", "blur")))
    assert console.execute("r_method jitter") and cvar.value == "jitter"
    assert not console.execute("r_method magic") and cvar.value == "jitter"
    assert errors(console)[-1] == "r_method: r_method must be one of exact, jitter, blur, got 'magic'"
    assert not console.execute("set r_method magic")
    console.execute("help r_method")
    assert out(console).startswith("r_method (str, one of exact|jitter|blur, now jitter, default exact)")
    with pytest.raises(CommandError, match="must be one of"):
        Cvar("r_bad", str, "other", choices=("exact",))  # the default too


def test_a_set_value_outside_the_choices_gives_way_to_the_default(console):
    assert console.execute("set r_method magic")  # before the cvar exists (a config ran first)
    cvar = console.registry.add_cvar(Cvar("r_method", str, "exact", choices=("exact", "jitter")))
    assert cvar.value == "exact"


def test_a_demo_checks_cvar_choices(console):
    console.registry.add_cvar(Cvar("r_method", str, "exact", choices=("exact", "jitter")))
    with pytest.raises(DemoError, match="r_method must be one of exact, jitter, got 'magic'"):
        demo.check(console, demo.parse(HEADER + "0 set r_method magic\n"))


# ---- demos --------------------------------------------------------------------------------------------

def scoped_checks(seen: list) -> ArgChecks:
    """Checks that note which workspace's check ran, and refuse x < 0 (a's) or z < 0 (b's)."""
    checks = ArgChecks()

    @checks.scoped("a").add("light.add")
    def a_check(x, y):
        seen.append(("a", x))
        if x < 0:
            raise CommandError("a refuses x < 0")

    @checks.scoped("b").add("light.add")
    def b_check(x, y, z):
        seen.append(("b", z))
        if z < 0:
            raise CommandError("b refuses z < 0")

    return checks


def test_a_demo_is_checked_in_the_workspace_each_line_runs_in(console):
    seen = []
    console.registry.scope = "b"  # the checker starts where the console is
    text = HEADER + "0 light.add 0 1 2\n0 workspace a\n0 light.add 3 4\n0.5 b:light.add 5 6 7\n" \
                    "1 workspace b; light.add 8 9 10\n"
    demo.check(console, demo.parse(text), arg_checks=scoped_checks(seen))
    assert seen == [("b", 2.0), ("a", 3.0), ("b", 7.0), ("b", 10.0)]
    assert console.registry.scope == "b"  # checking ran nothing


@pytest.mark.parametrize("line, message", [
    ("0 workspace a\n0 light.add -1 0\n", "a refuses x < 0"),
    ("0 workspace b\n0 light.add 0 0 -1\n", "b refuses z < 0"),
    ("0 workspace a\n0 light.add 0 0 -1\n", "too many arguments"),  # a's arguments, not b's
    ("0 light.add -1 0\n", "a refuses x < 0"),  # scope None: the first-registered
    ("0 workspace a\n0 b:light.add 0 0 -1\n", "b refuses z < 0"),
    ("0 workspace a\n0 a:orbit 1\n", "unknown command 'a:orbit'"),
])
def test_a_demo_line_is_refused_by_its_workspaces_check(console, line, message):
    with pytest.raises(DemoError, match=message):
        demo.check(console, demo.parse(HEADER + line), arg_checks=scoped_checks([]))


def test_a_bare_name_check_never_stands_in_for_a_workspaces(console):
    checks = ArgChecks()
    checks.add("light.add")(lambda *args: pytest.fail("the bare name's check ran for a:light.add"))
    demo.check(console, demo.parse(HEADER + "0 light.add 1 2\n0 a:light.add 1 2\n"), arg_checks=checks)


def test_after_lines_it_cannot_see_the_checker_accepts_any_workspaces_command(console):
    # the alias may switch the workspace, so `light.add x y z` may be b's: not refused for a's arguments
    text = HEADER + "0 workspace a\n0 alias go 'workspace b'\n0 go\n0 light.add 1 2 3\n0 light.add 1 2\n"
    demo.check(console, demo.parse(text), arg_checks=scoped_checks([]))
    with pytest.raises(DemoError, match="too many arguments"):  # a named workspace is known again
        demo.check(console, demo.parse(text + "0 workspace a\n0 light.add 1 2 3\n"), arg_checks=scoped_checks([]))


def test_reshapers_stay_keyed_by_bare_name(console):
    checks, seen = ArgChecks(), []
    checks.scoped("b").reshaped_by("lights3d", "light.add")
    checks.scoped("b").add("orbit", "lights3d")(lambda yaw: seen.append(yaw))
    demo.check(console, demo.parse(HEADER + "0 orbit 1\n0 light.add 1 2\n0 orbit 2\n"), arg_checks=checks)
    assert seen == [1.0]  # a's light.add counts too: a skipped check, never a wrong one
    assert checks.keys() == ["b:orbit"]


def test_a_line_is_recorded_as_typed(console):
    recorded = []
    console.record_listeners.append(recorded.append)
    console.registry.scope = "b"
    assert console.execute("light.add 1 2 3; a:light.add 4 5; workspace a; light.add 6 7")
    assert recorded == ["light.add 1 2 3", "a:light.add 4 5", "workspace a", "light.add 6 7"]


# ---- help, cmdlist, completion, Lua -------------------------------------------------------------------

def test_help_names_the_owning_workspace(console):
    console.registry.scope = "b"
    console.execute("help light.add")
    assert out(console) == "[b] light.add <x> <y> <z>: Add a 3D light (who may run it: the user only)"
    console.execute("help a:light.add")
    assert out(console) == "[a] light.add <x> <y>: Add a 2D light (who may run it: the user only)"
    console.execute("help echo")
    assert out(console) == "echo [<words>...]: Print the words (who may run it: scripts too)"  # global: unmarked
    assert not console.execute("help nothing")
    assert errors(console)[-1] == "help: no command, cvar or alias 'nothing'"


def test_cmdlist_marks_each_workspaces_command(console):
    console.execute("cmdlist light.")
    shown = [line.text for line in console.log[-3:]]
    assert shown[0].startswith("[a] light.add <x> <y>") and shown[0].endswith(" Add a 2D light")
    assert shown[1].startswith("[b] light.add <x> <y> <z>")
    assert shown[2] == "2 commands"
    console.execute("cmdlist b:")
    assert [line.text.split()[:2] for line in console.log[-3:-1]] == [["[b]", "light.add"], ["[b]", "orbit"]]


@pytest.mark.parametrize("line, expected_line, candidates", [
    ("light.a", "light.add ", ["light.add"]),  # a bare name once, however many workspaces have it
    ("orb", "orbit ", ["orbit"]),
    ("b:", "b:", ["b:light.add", "b:orbit"]),  # qualified names once a ':' is typed
    ("a:l", "a:light.add ", ["a:light.add"]),
    ("b:orbit l", "b:orbit left ", ["left"]),  # the qualified command's own completer
    ("help b:o", "help b:orbit ", ["b:orbit"]),
    ("bind x a:li", "bind x a:light.add ", ["a:light.add"]),
])
def test_completion_of_bare_and_qualified_names(console, line, expected_line, candidates):
    result = complete(console.registry, line)
    assert (result.line, result.candidates) == (expected_line, candidates)


def test_names_lists_each_bare_name_once(console):
    names = console.registry.names()
    assert names.count("light.add") == 1 and "orbit" in names and not any(":" in n for n in names)
    assert {"a:light.add", "b:light.add", "b:orbit"} <= set(console.registry.names(qualified=True))


def test_lua_runs_bare_and_qualified_names(console):
    from app.console.lua import LuaScripting

    console.registry.scope = "a"
    assert LuaScripting(console).run_string('cmd["light.add"](1, 2); cmd["b:light.add"](3, 4, 5)', "t.lua")
    assert console.calls == [("a", 1.0, 2.0), ("b", 3.0, 4.0, 5.0)]


# ---- the editor -----------------------------------------------------------------------------------------

def test_every_editor_check_names_a_registered_command_or_cvar(tmp_path, monkeypatch):
    """A command moved into a workspace must take its check along (`checks.scoped(ws).add`): a check left
    under the bare name would never run."""
    from app.editor import Editor

    monkeypatch.chdir(tmp_path)
    editor = Editor(configs=False)
    names = {*editor.console.registry.commands, *editor.console.registry.cvars}  # exact keys: no resolving
    assert [key for key in editor.demos.arg_checks.keys() if key not in names] == []
