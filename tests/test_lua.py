"""Lua scripting: the console API, the sandbox, the budgets, and one clear error line per failure."""
import subprocess
import sys
import time
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from lupa import LuaRuntime

from app.console.console import Console
from app.console.lua import LuaScripting
from app.console.registry import CommandError, Cvar


def make_console() -> Console:
    c = Console()
    c.calls = []  # every handler appends (name, args) here
    c.registry.command("snow.add", "x:float y:float [radius:float]")(lambda *a: c.calls.append(("snow.add", a)))
    c.registry.command("say", "words...")(lambda words: c.calls.append(("say", words)))

    def fail():
        raise CommandError("the model says no")

    c.registry.command("fail")(fail)
    c.registry.add_cvar(Cvar("cl_steps", int, 64, min=1, max=4096))
    c.registry.add_cvar(Cvar("r_name", str, "x"))
    c.registry.add_cvar(Cvar("r_on", bool, False))
    c.registry.add_cvar(Cvar("r_scale", float, 0.5))
    return c


@pytest.fixture
def console():
    return make_console()


@pytest.fixture
def lua(console):
    return LuaScripting(console)


@pytest.fixture
def run(lua, tmp_path):
    """run(name, source) writes the script to a file and runs it, as a user's script would be."""

    def run(name: str, source: str) -> bool:
        path = tmp_path / name
        path.write_text(source, encoding="utf-8")
        return lua.run_file(path)

    return run


def errors(console):
    return [line.text for line in console.log if line.level == "error"]


def infos(console):
    return [line.text for line in console.log if line.level == "info"]


def snapshot(console):
    reg = console.registry
    return sorted(reg.commands), {name: cvar.value for name, cvar in reg.cvars.items()}, list(console.calls)


# -- the console API ---------------------------------------------------------------------------


def test_commands_get_exact_values(run, console):
    assert run("snow.lua", """
        cmd.snow.add(0, 0.5)
        cmd["snow.add"](1, 2, 0.25)
        cmd.snow.add(0.1, 0.1 + 0.2)
        exec("snow.add 3 4")
    """)
    assert console.calls == [
        ("snow.add", (0.0, 0.5)),
        ("snow.add", (1.0, 2.0, 0.25)),
        ("snow.add", (0.1, 0.1 + 0.2)),  # 0.30000000000000004: needs all 17 digits
        ("snow.add", (3.0, 4.0)),
    ]
    inputs = [line.text for line in console.log if line.level == "input"]
    assert inputs[:3] == ["] snow.add 0 0.5", "] snow.add 1 2 0.25", "] snow.add 0.1 0.30000000000000004"]


def test_strings_booleans_and_integers_become_words(run, console):
    assert run("say.lua", """cmd.say("a b", true, false, 7, "it's", "", "x;y", "http://x", -0.0)""")
    assert console.calls == [("say", ["a b", "1", "0", "7", "it's", "", "x;y", "http://x", "-0.0"])]


@pytest.mark.parametrize("call, needle", [
    ("cmd.say({})", "cmd.say: argument 1 is a table (only strings, numbers and booleans)"),
    ("cmd.say('a', nil)", "cmd.say: argument 2 is a nil (only strings, numbers and booleans)"),
    ("cmd.say(print)", "cmd.say: argument 1 is a function (only strings, numbers and booleans)"),
    ("exec({})", "exec: expects a console line (string)"),
    ("cmd.nope(1)", "unknown command 'nope'"),
    ("cmd.snow.add('x', 1)", "command failed: snow.add x 1"),
    ('cmd.say("\\255")', "b'\\xff' is not UTF-8 text"),
])
def test_bad_calls_stop_the_script(run, console, call, needle):
    assert not run("bad.lua", f"cmd.say('before')\n{call}\ncmd.say('after')")
    assert errors(console)[-1] == f"lua: bad.lua:2: {needle}"
    assert console.calls == [("say", ["before"])]


def test_failing_command_stops_the_script(run, console):
    assert not run("stop.lua", "cmd.snow.add(1, 1)\ncmd.fail()\ncmd.snow.add(2, 2)")
    assert console.calls == [("snow.add", (1.0, 1.0))]
    assert errors(console) == ["fail: the model says no", "lua: stop.lua:2: command failed: fail"]


def test_exec_failure_stops_the_script(run, console):
    assert not run("exec.lua", "exec('snow.add 1 1; fail')\ncmd.snow.add(2, 2)")
    assert console.calls == [("snow.add", (1.0, 1.0))]
    assert errors(console)[-1] == "lua: exec.lua:1: command failed: snow.add 1 1; fail"


def test_cvars_read_typed_values(run):
    assert run("read.lua", """
        assert(cvar.cl_steps == 64 and math.type(cvar.cl_steps) == "integer")
        assert(cvar.r_scale == 0.5 and math.type(cvar.r_scale) == "float")
        assert(cvar.r_name == "x")
        assert(cvar.r_on == false)
        assert(cvar.nope == nil and cvar["snow.add"] == nil)
    """)


def test_cvars_write_through_the_console(run, console):
    assert run("write.lua", """
        cvar.cl_steps = 128
        cvar.r_name = "hello world"
        cvar.r_on = true
        cvar["r_scale"] = 0.1
        assert(cvar.cl_steps == 128 and cvar.r_on == true)
    """)
    values = {name: cvar.value for name, cvar in console.registry.cvars.items()}
    assert values == {"cl_steps": 128, "r_name": "hello world", "r_on": True, "r_scale": 0.1}
    inputs = [line.text for line in console.log if line.level == "input"]
    assert inputs == ["] cl_steps 128", "] r_name 'hello world'", "] r_on 1", "] r_scale 0.1"]


@pytest.mark.parametrize("assignment, needle", [
    ("cvar.cl_steps = 5000", "cl_steps must be within 1..4096, got 5000"),
    ("cvar.cl_steps = 2.5", "cl_steps takes a int, got '2.5'"),
    ("cvar.cl_steps = {}", "cvar.cl_steps: argument 1 is a table (only strings, numbers and booleans)"),
    ("cvar.nope = 1", "unknown cvar 'nope'"),
])
def test_refused_cvar_write_stops_the_script(run, console, assignment, needle):
    assert not run("set.lua", f"print('before')\n{assignment}\nprint('after')")
    assert errors(console) == [f"lua: set.lua:2: {needle}"]
    assert console.registry.cvars["cl_steps"].value == 64
    assert infos(console) == ["before"]


def test_print_goes_to_the_log(run, console):
    assert run("print.lua", "print('a', 1, nil, true, 0.5, {} ~= nil)\nprint()")
    assert infos(console) == ["a\t1\tnil\ttrue\t0.5\ttrue", ""]


def test_coroutines_work(run, console):
    assert run("gen.lua", """
        local gen = coroutine.wrap(function() for i = 1, 3 do coroutine.yield(i) end end)
        print(gen(), gen(), gen())
    """)
    assert infos(console) == ["1\t2\t3"]


# -- the sandbox -------------------------------------------------------------------------------


@pytest.mark.parametrize("snippet, needle", [
    ('os.execute("x")', "attempt to index a nil value (global 'os')"),
    ('io.open("/etc/passwd")', "attempt to index a nil value (global 'io')"),
    ('require("os")', "attempt to call a nil value (global 'require')"),
    ("debug.sethook()", "attempt to index a nil value (global 'debug')"),
    ('dofile("x")', "attempt to call a nil value (global 'dofile')"),
    ('loadfile("x")', "attempt to call a nil value (global 'loadfile')"),
    ("load(string.dump(function() end))", "attempt to call a nil value (field 'dump')"),
    ("string.dump(print)", "attempt to call a nil value (field 'dump')"),
    ('("").dump(print)', "attempt to call a nil value"),
    ('assert(load("\\27Lua"))', "attempt to load a binary chunk (mode is 't')"),
    ('python.eval("1")', "attempt to index a nil value (global 'python')"),
    ("collectgarbage()", "attempt to call a nil value (global 'collectgarbage')"),
    ("package.loaded.os.exit()", "attempt to index a nil value (global 'package')"),
    ("getmetatable(cmd).__index('x')", "attempt to index a boolean value"),
    ('getmetatable("").__index.upper = nil', "attempt to index a boolean value"),
    ("setmetatable(cmd, {})", "cannot change a protected metatable"),
    ("cmd.__class__()", "unknown command '__class__'"),
    ("cmd.snow.add.__globals__()", "unknown command 'snow.add.__globals__'"),
    ("cvar.__dict__.cl_steps = 1", "attempt to index a nil value (field '__dict__')"),
    ("cmd.fail = print", "this table is read-only"),
    ("setmetatable({}, {__gc = function() end})", "__gc metamethods are not allowed in scripts"),
])
def test_sandbox_refuses(run, console, snippet, needle):
    before = snapshot(console)
    assert not run("evil.lua", f"local x = 1\n{snippet}\ncmd.say('escaped')")
    [line] = errors(console)
    assert line.startswith("lua: evil.lua:2: ") and needle in line
    assert snapshot(console) == before


def test_no_python_object_is_reachable(run, console):
    # Walk everything a script can reach (values, keys, metatables, string methods): all plain Lua.
    assert run("walk.lua", """
        local seen, todo, found = {}, {_G, getmetatable(""), cmd.snow, cmd.snow.add}, {}
        while #todo > 0 do
          local v = table.remove(todo)
          if type(v) == "userdata" then found[#found + 1] = tostring(v) end
          if type(v) == "table" and not seen[v] then
            seen[v] = true
            todo[#todo + 1] = getmetatable(v)
            for k, x in pairs(v) do todo[#todo + 1] = k; todo[#todo + 1] = x end
          end
        end
        print(#found)
    """)
    assert infos(console) == ["0"]


def test_bytecode_file_is_refused(lua, console, tmp_path):
    bytecode = LuaRuntime(encoding=None).eval("string.dump(function() return 1 end)")
    assert bytecode.startswith(b"\x1bLua")
    (tmp_path / "compiled.luac").write_bytes(bytecode)
    assert not lua.run_file(tmp_path / "compiled.luac")
    assert errors(console) == ["lua: compiled.luac: precompiled Lua bytecode is refused; run the source text instead"]
    assert not lua.run_string(bytecode.decode("latin-1"), "s.lua")  # as a string: not valid UTF-8 for Lua either
    assert len(errors(console)) == 2


def test_unreadable_and_non_utf8_files(lua, console, tmp_path):
    assert not lua.run_file(tmp_path / "missing.lua")
    (tmp_path / "latin.lua").write_bytes(b"print('caf\xe9')")
    assert not lua.run_file(tmp_path / "latin.lua")
    assert errors(console)[0].startswith("lua: missing.lua: cannot read")
    assert errors(console)[1] == "lua: latin.lua: not UTF-8 text (byte 10)"


@pytest.mark.parametrize("source", [
    "while true do end",
    "while true do pcall(function() while true do end end) end",  # catching the error must not help
    "while true do load(function() while true do end end) end",  # nor catching it in a load reader
    "coroutine.wrap(function() while true do end end)()",
    "while true do coroutine.resume(coroutine.create(function() while true do end end)) end",
    "while true do coroutine.resume(coroutine.create(function() end)) end",  # many short coroutines
    "local function f() return f() end f()",
])
def test_runaway_script_is_stopped(run, console, source):
    start = time.perf_counter()
    assert not run("loop.lua", f"local x = 1\n{source}")
    assert time.perf_counter() - start < 1.5  # about 0.15 s here
    assert errors(console) == ["lua: loop.lua:2: instruction budget exceeded"]
    assert run("next.lua", "print('still working')")
    assert infos(console) == ["still working"]


def test_console_calls_count_against_the_budget(console):
    lua = LuaScripting(console, instruction_budget=1_000_000)
    assert not lua.run_string("while true do cmd.say('x') end", "spam.lua")
    assert errors(console) == ["lua: spam.lua:1: instruction budget exceeded"]
    assert 500 < len(console.calls) <= 1000


def test_loop_over_c_functions_hits_the_time_limit(console):
    # Few instructions, much work in C per instruction: the budget alone would take minutes.
    lua = LuaScripting(console, time_limit=0.2)
    start = time.perf_counter()
    assert not lua.run_string("local s = string.rep('a', 5000)\nwhile true do s:gsub('a', 'b') end", "gsub.lua")
    assert time.perf_counter() - start < 1.0
    assert errors(console) == ["lua: gsub.lua:2: time limit exceeded (0.2 s)"]


@pytest.mark.parametrize("source", [
    "local t = {} for i = 1, 1e9 do t[i] = i end",
    "local s = 'x' while true do s = s .. s end",
    "local s = string.rep('x', 2^20) local t = {} for i = 1, 1e6 do t[i] = s .. i end",
])
def test_memory_bomb_is_stopped(run, console, source):
    assert not run("bomb.lua", source)
    assert errors(console) == ["lua: bomb.lua: out of memory (limit 64 MiB)"]
    assert run("next.lua", "local t = {} for i = 1, 1e5 do t[i] = i end print(#t)")
    assert infos(console) == ["100000"]


def test_huge_source_is_refused(lua, console):
    assert not lua.run_string("--" + "x" * (40 * 2**20), "huge.lua")
    assert errors(console) == ["lua: huge.lua: script too large (40.0 MiB)"]
    assert lua.run_string("print('ok')")
    assert infos(console) == ["ok"]


_FULL_HEAP = '''
from app.console.lua import LuaScripting
from tests.test_lua import make_console, infos

console = make_console()
console.registry.cvars["r_name"].value = "y" * 10000
lua = LuaScripting(console)
lua.run_string("""
  local keep, nope = {}, cmd.nope
  for _, size in ipairs({2^20, 2^16, 2^12, 2^8, 16, 1}) do  -- fill the heap to the last bytes
    pcall(function() while true do keep = {keep, string.rep("z", size)} end end)
  end
  local name = cvar.r_name  -- 10 kB pushed by Python into a full heap
  local ok, err = pcall(nope)  -- and an error message
  keep = nil
  print(#name, err)
""")
lua.run_string("print('next')")
print(infos(console))
'''


def test_callbacks_survive_a_full_heap():
    # lupa hangs the process if it cannot push a callback's result: run this where a hang is a timeout.
    done = subprocess.run([sys.executable, "-c", _FULL_HEAP], cwd=Path(__file__).parent.parent,
                          capture_output=True, text=True, timeout=60)
    assert done.returncode == 0, done.stderr
    assert done.stdout.startswith("['10000\\t") and done.stdout.strip().endswith("'next']"), done.stdout


# -- error reporting ---------------------------------------------------------------------------


def test_syntax_error_names_file_and_line(run, console):
    assert not run("bad.lua", "cmd.say('a')\n\nx = = 1")
    assert errors(console) == ["lua: bad.lua:3: syntax error: unexpected symbol near '='"]
    assert console.calls == []  # nothing ran


@pytest.mark.parametrize("call, reason", [
    ("foo()", "attempt to call a nil value (global 'foo')"),
    # errors raised by C functions behind the sandbox's wrappers still blame the script's line
    ("coroutine.create(1)", "bad argument #1 to 'create' (function expected, got number)"),
    ("setmetatable(1, {})", "bad argument #1 to 'setmetatable' (table expected, got number)"),
    ("print(setmetatable({}, {__tostring = function() return {} end}))", "'__tostring' must return a string"),
])
def test_runtime_error_names_file_and_line(run, console, call, reason):
    assert not run("cube.lua", f"local a = 1\n{call}")
    assert errors(console) == [f"lua: cube.lua:2: {reason}"]


@pytest.mark.parametrize("source, reason", [
    ("error({})", "(error object is a table value)"),
    ("error('plain', 0)", "plain"),
    ("coroutine.yield(1)", "attempt to yield from outside a coroutine"),
    ("error(setmetatable({}, {__tostring = function() while true do end end}))", "(error object is a table value)"),
])
def test_errors_without_position_still_name_the_script(lua, console, source, reason):
    assert not lua.run_string(source)
    assert errors(console) == [f"lua: (console): {reason}"]


def test_globals_do_not_leak_between_runs(lua):
    assert lua.run_string("leak = 1; string.upper = nil; table.extra = 1; rawset(cmd, 'x', 2); rawset(cvar, 'y', 3)")
    assert lua.run_string("""
        assert(leak == nil and string.upper and table.extra == nil)
        assert(rawget(cmd, 'x') == nil and rawget(cvar, 'y') == nil)
        assert(("a"):upper() == "A")
    """)


def test_a_script_cannot_run_a_script(console, lua):
    results = []  # what the inner run returned
    console.registry.command("script", "source")(lambda source: results.append(lua.run_string(source, "inner.lua")))
    assert lua.run_string("cmd.script('print(1)')", "outer.lua")  # the command itself succeeds...
    assert results == [False]  # ...but the inner run was refused: it would reset the outer budget
    assert errors(console) == ["lua: inner.lua: cannot run a script from inside a script"]
    assert console.execute("script 'print(2)'")  # outside a script it runs
    assert results == [False, True] and infos(console) == ["2"]


def test_a_semicolon_word_arrives_intact(lua, console):
    assert lua.run_string('cmd.say(";")')
    assert console.calls == [("say", [";"])]


@settings(max_examples=300, deadline=None)
@given(st.text(st.characters(blacklist_categories=["Cs"])))
def test_any_text_arrives_intact(text):
    console = make_console()
    literal = "".join(f"\\{b}" for b in text.encode("utf-8"))  # Lua decimal escapes: any bytes, no quoting
    assert LuaScripting(console).run_string(f'cmd.say("{literal}")\ncvar.r_name = "{literal}"'), errors(console)
    assert console.calls == [("say", [text])]
    assert console.registry.cvars["r_name"].value == text
