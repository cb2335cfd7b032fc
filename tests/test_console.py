"""The registry and the console: typed arguments, cvars, clear refusals that change nothing."""
import pytest

from app.console.console import Console, split_commands
from app.console.registry import CommandError, Cvar, Registry


@pytest.fixture
def console():
    c = Console()
    calls = []
    c.registry.command("add", "a:int b:int [scale:float]", "Add two numbers")(
        lambda a, b, scale=1.0: calls.append((a + b) * scale))
    c.registry.command("many", "words...")(lambda words: calls.append(words))
    c.registry.add_cvar(Cvar("cl_steps", int, 64, "ray steps", min=1, max=4096))
    c.calls = calls
    return c


def errors(console):
    return [line.text for line in console.log if line.level == "error"]


def test_typed_arguments_and_optional(console):
    assert console.execute("add 2 3")
    assert console.execute("add 2 3 0.5")
    assert console.calls == [5.0, 2.5]


@pytest.mark.parametrize("line, needle", [
    ("add 2", "missing <b>"),
    ("add 2 x", "<b> must be int"),
    ("add 1 2 3 4", "too many arguments"),
    ("add 1 2 nan", "must be finite"),
    ("nope", "unknown command 'nope'"),
    ('add "1 2', "cannot parse"),
])
def test_bad_input_is_refused_with_usage(console, line, needle):
    assert not console.execute(line)
    assert console.calls == []
    assert needle in errors(console)[-1]


def test_variadic_and_quotes(console):
    assert console.execute('many a "b c" d')
    assert console.calls == [["a", "b c", "d"]]


def test_semicolons_separate_commands_outside_quotes():
    assert split_commands('a 1; b "x;y";c') == [["a", "1"], ["b", "x;y"], ["c"]]


def test_later_commands_run_after_a_failure(console):
    assert not console.execute("add 1; add 2 2")
    assert console.calls == [4.0]


def test_cvar_print_set_and_range(console):
    assert console.execute("cl_steps")
    assert '"cl_steps" is "64"' in console.log[-1].text
    assert console.execute("cl_steps 128")
    assert console.registry.cvars["cl_steps"].value == 128
    assert not console.execute("cl_steps 0")
    assert not console.execute("cl_steps many")
    assert console.registry.cvars["cl_steps"].value == 128
    assert "within 1..4096" in errors(console)[0]


def test_cvar_listener_refusal_rolls_back():
    cvar = Cvar("r_level", float, 1.0)

    def refuse(c):
        raise ValueError("the model says no")

    cvar.on_change.append(refuse)
    with pytest.raises(ValueError):
        cvar.set("2")
    assert cvar.value == 1.0


def test_bool_cvar_words():
    cvar = Cvar("r_debug", bool, False)
    cvar.set("on")
    assert cvar.value is True and cvar.text() == "1"
    with pytest.raises(CommandError):
        cvar.set("maybe")


def test_names_are_unique_across_commands_and_cvars():
    reg = Registry()
    reg.add_cvar(Cvar("x", int, 0))
    with pytest.raises(ValueError, match="already registered"):
        reg.command("x")(lambda: None)
    with pytest.raises(ValueError, match="bad console name"):
        reg.command("two words")(lambda: None)


def test_handler_bug_is_logged_and_the_console_survives(console):
    console.registry.command("boom")(lambda: 1 / 0)
    assert not console.execute("boom")
    assert "internal error" in errors(console)[-1] and "ZeroDivisionError" in errors(console)[-1]
    assert console.execute("add 1 1")


def test_executed_listeners_see_only_successful_commands(console):
    seen = []
    console.executed_listeners.append(seen.append)
    console.execute("add 1 2; add x; many 'a b'")
    assert seen == ["add 1 2", "many 'a b'"]


def test_comments_outside_quotes_are_dropped():
    assert split_commands('echo a // the rest') == [["echo", "a"]]
    assert split_commands('echo "http://x" // c') == [["echo", "http://x"]]
    assert Console().execute("// only a comment")


def test_quoted_and_escaped_separators_stay_in_their_word():
    assert split_commands("say ';'; say \";;\"") == [["say", ";"], ["say", ";;"]]
    assert split_commands(r"say a\;b; echo \"x") == [["say", "a;b"], ["echo", '"x']]


def test_quiet_commands_are_echoed_only_when_asked():
    c = Console()
    c.registry.command("drag", "x:int", quiet=True)(lambda x: None)
    c.execute("drag 1", echo=None)
    assert c.log == []
    c.execute("drag 2")  # typed: always echoed
    assert [line.text for line in c.log] == ["] drag 2"]
