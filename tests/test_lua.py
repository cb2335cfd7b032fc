"""Lua scripting: the console API, the sandbox, the budgets, and one clear error line per failure."""
import json
import subprocess
import sys
import time
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from lupa import LuaRuntime

from app.console.console import Console
from app.console.lua import LINE_LIMIT, OUTPUT_LIMIT, LuaScripting
from app.console.lua_patterns import PATTERNS
from app.console.registry import SCRIPTS, CommandError, Cvar

ROOT = Path(__file__).parent.parent


def make_console() -> Console:
    c = Console()
    c.calls = []  # every handler appends (name, args) here
    c.registry.command("snow.add", "x:float y:float [radius:float]", allow=SCRIPTS)(
        lambda *a: c.calls.append(("snow.add", a)))
    c.registry.command("say", "words...", allow=SCRIPTS)(lambda words: c.calls.append(("say", words)))

    def fail():
        raise CommandError("the model says no")

    c.registry.command("fail", allow=SCRIPTS)(fail)
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


def run_python(code: str, *args: str) -> str:
    """Run code in a fresh Python process, where a hang fails the test instead of stalling the
    run: its output."""
    done = subprocess.run([sys.executable, "-c", code, *args], cwd=ROOT, capture_output=True, text=True, timeout=60)
    assert done.returncode == 0, done.stderr
    return done.stdout


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
    ("coroutine.close(coroutine.create(print))", "attempt to call a nil value (field 'close')"),
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
    assert not run("loop.lua", f"local x = 1\n{source}")  # the message below says the budget stopped it
    assert errors(console) == ["lua: loop.lua:2: instruction budget exceeded"]
    assert run("next.lua", "print('still working')")
    assert infos(console) == ["still working"]


def test_console_calls_count_against_the_budget(console):
    lua = LuaScripting(console, instruction_budget=1_000_000)
    assert not lua.run_string("while true do cmd.say('x') end", "spam.lua")
    assert errors(console) == ["lua: spam.lua:1: instruction budget exceeded"]
    assert 500 < len(console.calls) <= 1000


def test_commands_an_alias_runs_count_against_the_budget(console):
    """One call into the console may run many commands (an alias): each is charged as a call of its own."""
    console.registry.set_alias("hundred", ";".join(["say x"] * 100))
    lua = LuaScripting(console, instruction_budget=1_000_000)
    assert not lua.run_string("while true do cmd.hundred() end", "alias.lua")
    assert errors(console) == ["lua: alias.lua:1: instruction budget exceeded"]
    assert 500 < len(console.calls) <= 1000  # as many commands as calling `say` itself would have bought


def test_a_slow_command_stops_the_script_right_after_it(console):
    """The clock is read after each console call, not only every thousand instructions."""
    console.registry.command("slow", allow=SCRIPTS)(lambda: time.sleep(0.3))
    lua = LuaScripting(console, time_limit=0.2)
    assert not lua.run_string("cmd.slow()\ncmd.say('after')", "slow.lua")
    assert errors(console) == ["lua: slow.lua:1: time limit exceeded (0.2 s)"]
    assert console.calls == []


def test_loop_over_c_functions_hits_the_time_limit(console):
    # Few instructions, much work in C per instruction: the budget alone would take minutes.
    lua = LuaScripting(console, time_limit=0.2)
    assert not lua.run_string("local s = string.rep('a', 5000)\nwhile true do s:gsub('a', 'b') end", "gsub.lua")
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
    out = run_python(_FULL_HEAP)
    assert out.startswith("['10000\\t") and out.strip().endswith("'next']"), out


_GUARDED = """
import json, sys
from app.console.lua import LuaScripting
from tests.test_lua import make_console, errors

sources, limits = json.loads(sys.argv[1])
results = []
for source in sources:
    console = make_console()
    lua = LuaScripting(console, **limits)
    lua.run_string(source, "loop.lua")
    assert lua.run_string("print('still working')", "next.lua")
    results.append(errors(console))
print(json.dumps(results))
"""


def run_guarded(sources: list[str], **limits) -> list[list[str]]:
    """Run scripts in a fresh process (see run_python: a hang is its timeout), each with a new console and
    runtime: the error lines of each. Each runtime must still work afterwards."""
    return json.loads(run_python(_GUARDED, json.dumps([sources, limits])))


@pytest.mark.parametrize("source", [
    # A message handler runs where the error was raised: here inside the count hook, hooks off.
    "xpcall(function() while true do end end, function() while true do end end)",
    "xpcall(function() xpcall(function() while true do end end, function() while true do end end) end,"
    " function() while true do end end)",
    # After an ordinary error the handler runs hooked, and the budget stops it.
    "xpcall(error, function() while true do end end)",
    "xpcall(function() error({}) end, function() while true do end end)",
    # __close metamethods that loop, run while the error unwinds.
    "pcall(function() local x <close> = setmetatable({}, {__close = function() while true do end end})"
    " while true do end end)",
    # Stopped inside a coroutine (whose hook then never returned), the script must not carry on.
    "local co = coroutine.create(function() local x <close> = setmetatable({}, {__close = function()"
    " while true do end end}) while true do end end) coroutine.resume(co) coroutine.close(co)",
    "coroutine.resume(coroutine.create(function() while true do end end))",
])
def test_the_error_machinery_cannot_outrun_the_budget(source):
    [errs] = run_guarded([f"local x = 1\n{source}"], instruction_budget=2_000_000)
    # A script that ended after its stop was caught has no line left to blame.
    assert errs in (["lua: loop.lua:2: instruction budget exceeded"], ["lua: loop.lua: instruction budget exceeded"])


_AT_THE_C_STACK_LIMIT = """
local function spin() while true do end end
local mt = {}
local obj = setmetatable({}, mt)
local function boom() local a <close> = obj; local b <close> = obj; spin() end
mt.__close = boom
local function at(depth) if depth == 0 then %s end pcall(at, depth - 1) end
at(%d)
"""


@pytest.mark.parametrize("body", [
    "string.gsub('x', 'x', function() while true do pcall(spin) end end)",  # pcall where it cannot yield
    "string.gsub('x', 'x', function() while true do xpcall(spin, print) end end)",
    "while true do load(spin) end",
    "string.gsub('x', 'x', function() pcall(boom) end)",  # each failing __close opens two more
])
def test_code_at_the_c_stack_limit_is_stopped(body):
    # At the limit there is no C stack left to call the count hook: each call of it fails with a
    # "C stack overflow" error instead. Somewhere in this range of depths lies the limit.
    sources = [_AT_THE_C_STACK_LIMIT % (body, depth) for depth in range(170, 200)]
    for [line] in run_guarded(sources, instruction_budget=1_000_000):
        assert line.endswith(("instruction budget exceeded", "stack overflow")), line


def test_a_stack_overflow_stops_the_script(run, console):
    # Catching it would let the script loop where the count hook cannot be called. (Large frames
    # reach Lua's stack limit before the memory cap.)
    frame = ", ".join(f"v{i}" for i in range(150))
    assert not run("deep.lua",
                   f"local function f() local {frame} = 1 return 1 + f() end\nprint(pcall(f))\nprint('after')")
    assert errors(console) == ["lua: deep.lua:2: stack overflow"]
    assert infos(console) == []


def test_load_reads_a_reader_function(run, console):
    assert run("reader.lua", """
        local parts, i = {"return ", "1 + ", "2"}, 0
        local f = load(function() i = i + 1 return parts[i] end)
        assert(f() == 3)
        print(load(function() error("torn", 0) end))
        print(load(function() return {} end))
        print(pcall(function() error("plain") end))
    """)
    assert infos(console) == ["nil\ttorn", "nil\treader function must return a string",
                              "false\treader.lua:7: plain"]


def test_a_long_line_stops_the_script(console):
    lua = LuaScripting(console)
    assert not lua.run_string("for i = 1, 2000 do print(string.rep('x', 2^20)) end", "spam.lua")
    assert errors(console) == ["lua: spam.lua:1: printed line too long (1048576 bytes; limit 64 KiB)"]
    assert infos(console) == []


def test_output_stops_at_its_limit(console):
    lua = LuaScripting(console)
    line = 16_000  # under what the log keeps of one line
    assert not lua.run_string(f"for i = 1, 2000 do pcall(print, string.rep('x', {line})) end print('after')",
                              "spam.lua")
    assert errors(console) == ["lua: spam.lua:1: output limit exceeded (1 MiB)"]
    assert [len(text) for text in infos(console)] == [line] * (OUTPUT_LIMIT // line)  # no 'after'


def test_command_lines_count_as_output(console):
    lua = LuaScripting(console)
    assert not lua.run_string(f"exec('say ' .. string.rep('x', {LINE_LIMIT}))", "long.lua")
    assert errors(console) == [f"lua: long.lua:1: command line too long ({LINE_LIMIT + 4} bytes; limit 64 KiB)"]
    assert console.calls == []  # refused before it reached the console
    assert not lua.run_string("print(string.rep('x', 60000))\nwhile true do cmd.say(string.rep('y', 60000)) end",
                              "say.lua")
    assert errors(console)[-1] == "lua: say.lua:2: output limit exceeded (1 MiB)"
    assert len(console.calls) == OUTPUT_LIMIT // 60_004 - 1  # "say " and the word; the print took one


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
    console.registry.command("script", "source", allow=SCRIPTS)(
        lambda source: results.append(lua.run_string(source, "inner.lua")))
    assert lua.run_string("cmd.script('print(1)')", "outer.lua")  # the command itself succeeds...
    assert results == [False]  # ...but the inner run was refused: it would reset the outer budget
    assert errors(console) == ["lua: inner.lua: cannot run a script from inside a script"]
    assert console.execute("script 'print(2)'")  # outside a script it runs
    assert results == [False, True] and infos(console) == ["2"]


def test_a_semicolon_word_arrives_intact(lua, console):
    assert lua.run_string('cmd.say(";")')
    assert console.calls == [("say", [";"])]


@settings(max_examples=300, deadline=None)
@given(st.text(st.characters(blacklist_categories=["Cs", "Cc"], blacklist_characters="\u2028\u2029")))
def test_any_text_arrives_intact(text):
    console = make_console()
    literal = "".join(f"\\{b}" for b in text.encode("utf-8"))  # Lua decimal escapes: any bytes, no quoting
    assert LuaScripting(console).run_string(f'cmd.say("{literal}")\ncvar.r_name = "{literal}"'), errors(console)
    assert console.calls == [("say", [text])]
    assert console.registry.cvars["r_name"].value == text


@pytest.mark.parametrize("char", ["\n", "\r", "\x00", "\x1b", "\u2028"])
def test_control_characters_stop_the_script_and_change_nothing(char):
    """A newline in stored text would come back from config.cfg as a line of the script's own."""
    console = make_console()
    literal = "".join(f"\\{b}" for b in f"a{char}b".encode("utf-8"))
    assert not LuaScripting(console).run_string(f'cvar.r_name = "{literal}"')
    assert "control characters" in errors(console)[0] and console.registry.cvars["r_name"].value != f"a{char}b"


# -- patterns ----------------------------------------------------------------------------------


@pytest.mark.parametrize("call", [
    'string.find(string.rep("a", 40), ".-.-.-.-.-.-.-.-.-.-.-b")',
    '("a"):rep(5000):find("a*a*a*a*a*b")',
    '("a"):rep(3000):match("^(a*)(a*)(a*)b")',
    'for _ in ("a"):rep(3000):gmatch("a*a*a*b") do end',
    '("a"):rep(3000):gsub("a-a-a-b", "")',
    '("ab"):rep(3000):find("(.-)%1%1x")',
    '("("):rep(5000):find("%b()%b()x")',
    '("a"):rep(2^22):find(("a"):rep(2^19) .. "b", 1, true)',  # a plain search compares 2^19 bytes per start
])
def test_pathological_patterns_are_stopped(call):
    # In C each of these runs for minutes to ages, past every limit.
    [errs] = run_guarded([f"local x = 1\n{call}"], instruction_budget=5_000_000)
    assert errs == ["lua: loop.lua:2: instruction budget exceeded"]  # the budget, a count of work, stopped it


def test_scripts_get_the_c_results_from_long_subjects(run, console):
    # Subjects this long go to the Lua port: the C matcher's worst case on them is too long.
    assert run("words.lua", """
        local s = string.rep("word ", 2000) .. "end"
        local n = 0
        for w in s:gmatch("%a+") do n = n + 1 end
        print(n, (s:gsub("%s+", "_")):sub(1, 12), ("  trim me  "):match("^%s*(.-)%s*$"), s:find("(%a+)%s+end"))
        print(("k1=v1, k2=v2"):gsub("(%w+)=(%w+)", "%2=%1"))
    """)
    assert infos(console) == ["2001\tword_word_wo\ttrim me\t9996\t10003\tword", "v1=k1, v2=k2\t2"]


_COMPARE = r"""
local function show(ok, ...)  -- results as text; an error without its position (only the port's has one)
  local out = {ok and "ok" or "error"}
  for i = 1, select("#", ...) do
    local v = select(i, ...)
    if not ok then v = tostring(v):gsub("^.-:%d+: ", "") end
    out[#out + 1] = type(v) .. " " .. tostring(v)
  end
  return table.concat(out, " | ")
end

local function all(iterator)  -- what a gmatch iterator gives, call after call
  local out = {}
  for _ = 1, 50 do
    local r = table.pack(iterator())
    if r[1] == nil then break end
    out[#out + 1] = show(true, table.unpack(r, 1, r.n))
  end
  return table.concat(out, " / ")
end

local REPLACEMENTS = {"<%0>", "%1-%2", "%%", "%", "x%9", 7, {a = "A", ab = false, [1] = 1, b = {}},
                      function(...) return select("#", ...) .. tostring((...)) end, function() return false end}

return function(lib, s, p, init, plain)
  local out = {
    show(pcall(lib.find, s, p, init, plain)),
    show(pcall(lib.match, s, p, init)),
    show(pcall(function() return all(lib.gmatch(s, p, init)) end)),
  }
  for _, repl in ipairs(REPLACEMENTS) do
    out[#out + 1] = show(pcall(lib.gsub, s, p, repl))
    out[#out + 1] = show(pcall(lib.gsub, s, p, repl, 1))
  end
  return table.concat(out, "\n")
end
"""


class PatternLibraries:
    """The C pattern functions, and the bounded ones with no work allowed in C: always the Lua port."""

    def __init__(self) -> None:
        lua = LuaRuntime(encoding=None)
        self.c = lua.globals().string
        self.port = lua.execute(PATTERNS, 0)
        self.compare = lua.execute(_COMPARE)

    def results(self, *args) -> tuple[str, str]:
        c, port = (self.compare(lib, *args).decode("utf-8", "replace") for lib in (self.c, self.port))
        return c, port


@pytest.fixture(scope="module")
def libraries():
    return PatternLibraries()


@pytest.mark.parametrize("s, p, init, plain", [
    (b"hello world", b"o w", None, None),
    (b"hello world", b"(o)(r)", None, None),
    (b"hello", b"()ll()", None, None),
    (b"THE (quick) fox", b"%((%a+)%)", None, None),
    (b"  trim  ", b"^%s*(.-)%s*$", None, None),
    (b"key = value", b"(%w+)%s*=%s*(%w+)", None, None),
    (b"f(a(b)c)d", b"%b()", None, None),
    (b"THE quick", b"%f[%a]%a+", None, None),
    (b"THE quick", b"%f[%A]", None, None),
    (b"abcabc", b"(abc)%1", None, None),
    (b"a.b.c", b".", 2, True),
    (b"a.b.c", b"", 9, True),
    (b"aaa", b"a-b", None, None),
    (b"aaa", b"a?a?a", None, None),
    (b"x]", b"[]]", None, None),
    (b"x]", b"[^]]+", None, None),
    (b"a-b", b"[a-]+", None, None),
    (b"a-b", b"[%a-]+", None, None),
    (b"^x", b"^^x", None, None),
    (b"x$y", b"x$y", None, None),
    (b"abc", b"", 4, None),
    (b"abc", b"", 5, None),
    (b"abc", b"b", -2, None),
    (b"abc", b"b", -10, None),
    (b"\0a\0", b"%z+", None, None),
    (b"\0a\0", b"[\0]", None, None),
    (b"caf\xc3\xa9 ok", b"[\x80-\xff]+", None, None),
    (b"a,b,,c", b"([^,]*)", None, None),
    (b"abc", b"^(a)(b)(c)", None, None),
    (b"abc", b"%", None, None),
    (b"abc", b"[a", None, None),
    (b"abc", b"b%", None, None),  # malformed after a failing item: no error
    (b"abc", b"(a", None, None),
    (b"abc", b"a)", None, None),
    (b"abc", b"%1", None, None),
    (b"abc", b"(a)%2", None, None),
    (b"abc", b"%b(", None, None),
    (b"abc", b"%f", None, None),
    (b"abc", b"(" * 33, None, None),
    (b"a" * 30, b"a?" * 250, None, None),
])
def test_pattern_port_matches_the_c_functions(libraries, s, p, init, plain):
    c, port = libraries.results(s, p, init, plain)
    assert port == c


def test_bounded_functions_read_arguments_as_c_does(libraries):
    for args in [(123, 2, None, None), (12.5, b"%.", b"2", None), (b"abc", b"c", 2.0, 1), (b"x", b"x", None, False)]:
        c, port = libraries.results(*args)
        assert port == c


_TOKENS = ["a", "b", ".", "%a", "%d", "%s", "%w", "%p", "%A", "%S", "%.", "%%", "[ab]", "[^a]", "[a-c]", "[%a_]",
           "[]]", "(", ")", "()", "%1", "%2", "%b()", "%f[%w]", "%f[%W]", "^", "$", "*", "+", "-", "?", "%", "[",
           "\0", "\u00e9"]


@settings(max_examples=500, deadline=None)
@given(
    s=st.text("ab(). 1%-\0\u00e9", max_size=12).map(str.encode),
    p=st.lists(st.sampled_from(_TOKENS), max_size=8).map(lambda tokens: "".join(tokens).encode()),
    init=st.none() | st.integers(-15, 15),
    plain=st.none() | st.booleans(),
)
def test_pattern_port_matches_the_c_functions_everywhere(libraries, s, p, init, plain):
    c, port = libraries.results(s, p, init, plain)
    assert port == c
