"""Lua scripting for the console, sandboxed: scripts come from others. No Qt, no GL.

Tex3Dtrace scripted its console in Lua; Shadelab does the same. A script can do what a user can
type in the console, nothing more: every change goes through `Console.execute`, so it is logged
and recorded like typed input.

Script API
----------
``cmd.<name>(args...)``
    Runs a registered console command (or alias, or sets/prints a cvar, as typing it would).
    Dotted names index naturally: ``cmd.snow.add(0, 0.5)`` runs ``snow.add 0 0.5``;
    ``cmd["snow.add"](0, 0.5)`` is the same. Arguments become text: integers as integers,
    floats with enough digits to round-trip exactly (``0.1`` -> ``0.1``), booleans as ``1``/``0``,
    strings quoted when needed. Tables, functions and nil are refused. If the command fails, the
    script stops with ``command failed: <line>`` (the console has already logged why); an unknown
    name stops it with ``unknown command 'x'``.
``exec("console line")``
    Runs a raw console line (``;`` separates commands); stops the script if any command failed.
``cvar.<name>`` / ``cvar["<name>"]``
    The cvar's typed value (number, string or boolean), or nil if there is no such cvar.
``cvar.<name> = value``
    Sets it through the console (converted to text as for ``cmd``); a refused value stops the
    script with the cvar's message and leaves the value unchanged.
``print(...)``
    Writes its arguments (tostring'd, tab-separated) to the console log as one line.
``load(chunk [, chunkname])``
    Compiles source text (never bytecode), given whole or as the pieces a reader function
    returns, into a function that sees this script's globals.
Standard library
    ``assert error ipairs next pairs pcall xpcall select tonumber tostring type rawequal rawlen
    rawget rawset setmetatable getmetatable``; ``string`` (no ``dump``), ``table``, ``math``,
    ``utf8``, ``coroutine`` (no ``close``); ``time.clock()`` and ``time.time()``
    (``os.clock``/``os.time``). ``setmetatable`` refuses ``__gc`` (finalizers run with hooks off,
    outside every limit). Not available: ``io os package require debug dofile loadfile
    collectgarbage`` and anything Python.

Limits
------
Each run gets fresh globals (nothing leaks from one script to the next) and these limits:

- a budget of Lua instructions (default 50 million, a few tenths of a second of plain Lua here;
  each call into the console costs `CONSOLE_CALL_COST` of it, reading a cvar `CVAR_READ_COST`):
  ``instruction budget exceeded``;
- a time limit (default 5 s), for loops whose work is in C functions (``gsub`` over a long string,
  ``table.insert`` at the front of a long table): ``time limit exceeded (5 s)``;
- a memory cap (default 64 MiB): ``out of memory (limit 64 MiB)``; a script source may be at
  most half of it;
- console output: `OUTPUT_LIMIT` (1 MiB) of printed lines and command lines in all, `LINE_LIMIT`
  (64 KiB) in one line, which is refused whole, never cut: ``output limit exceeded (1 MiB)``,
  ``printed line too long (70000 bytes; limit 64 KiB)``, ``command line too long (...)``. What
  commands print in reply is theirs, not counted.

The count hook checks the budget and the clock every `HOOK_PERIOD` instructions, so a single C
call runs whole between two checks. The C functions scripts get do work about linear in their
data, which the memory cap bounds, except the pattern functions (``string.find match gmatch
gsub``), whose matcher backtracks: they are replaced by bounded ones (`app.console.lua_patterns`).
A call whose worst case in C could pass `WORK_LIMIT` steps (about a millisecond) runs in a Lua
port of the matcher instead, under the hook. At 60 to 100 instructions per backtracking step
there, a call that backtracks over a few thousand bytes can spend the budget where C would have
taken tens of milliseconds.

Reaching a limit stops the run for good: from then on every instruction fails, so ``pcall``
catching the error gains the script nothing, and a message handler is not called. A stack
overflow (C or Lua) stops it the same way, since calling the hook can itself fail for want of
stack, and code there would run unwatched. Every error a script can catch is seen first (by the
message handler of every ``pcall`` and ``xpcall``, and by ``coroutine.resume``), before the
stack unwinds and ``__close`` metamethods run; ``coroutine.close`` runs them where nothing could
see, so it is not provided, and a reader function given to ``load`` is called by the sandbox, not
inside ``load``.

A script that fails stops, and the console gets one error line naming the script, the line and
the reason, e.g. ``lua: cube.lua:12: attempt to call a nil value (global 'foo')``; where the
script caught its stop and ended, the line is left out. A script cannot run another script
(through a console command that does), since that would reset its budget.

Sandbox design: the Python callbacks are upvalues of the Lua closures made by `_SETUP`, which runs
once per runtime with the full standard library; scripts get only the environment table `new_env`
builds, so without ``debug`` they cannot reach those upvalues. Callbacks take and return only
strings, numbers and booleans, and never raise (lupa would hand the script the Python exception
object as the error value): they return ``false, message`` and the Lua side raises the error.

lupa (2.8) pushes a callback's results onto the Lua stack unprotected: a memory error there leaves
the GIL taken and hangs the process, and one while pushing a call's arguments aborts it. So each
callback lifts the memory cap just enough for its results, the Lua side restores it right after,
and a script source may use at most half the cap.
"""
from __future__ import annotations

import os
import re
import time
from pathlib import Path
from typing import Any, Callable

from lupa import LuaError, LuaRuntime

from app.console.console import Console
from app.console.quoting import join
from app.console.lua_patterns import PATTERNS, WORK_LIMIT
from app.console.registry import CommandError
from app.io.regular_file import read_regular_bytes

HOOK_PERIOD = 1000  # instructions between budget checks: finer costs speed, coarser costs accuracy
# Python work is charged in instructions too, so a runaway loop of console calls also stops: at the
# default budget a script gets 50,000 console calls (command, exec, cvar set, print), about 1 s of
# bare console time here, and 500,000 cvar reads.
CONSOLE_CALL_COST = 1000
CVAR_READ_COST = 100
# Console output a run may make: printed lines and command lines, each echoed into the log. Past
# either limit the script stops, as at the budget (a longer line is refused, not cut).
OUTPUT_LIMIT = 2**20  # bytes in all
LINE_LIMIT = 64 * 2**10  # bytes in one line
BYTECODE_SIGNATURE = b"\x1bLua"
BUDGET_MESSAGE = "instruction budget exceeded"
_LUA_OOM = "not enough memory"
_PUSH_SLACK = 64 * 2**10  # room for the Lua stack and string headers when a callback's results are pushed
_INT64 = range(-(2**63), 2**63)
_CHUNK_NAME = "=(lua sandbox)"  # both chunks: an error blaming them is moved to the script's line

# Runs once per LuaRuntime with the full standard library; returns `run(source, chunkname)`.
_SETUP = r"""
local py_command, py_execute, py_cvar_get, py_cvar_set, py_print, py_relimit, py_overtime, BUDGET,
      PERIOD, CALL_COST, READ_COST, BUDGET_MESSAGE, TIME_MESSAGE, PATTERNS = ...
local error, ipairs, pairs, tostring, type, rawget, setmetatable, load, xpcall =
      error, ipairs, pairs, tostring, type, rawget, setmetatable, load, xpcall
local sethook, getinfo, concat, pack, create, resume, status = debug.sethook, debug.getinfo,
      table.concat, table.pack, coroutine.create, coroutine.resume, coroutine.status
local find, gsub = string.find, string.gsub  -- the C functions, for this chunk's own messages
local SELF = debug.getinfo(1, "S").source  -- this chunk (and PATTERNS'): errors blaming it are moved to the script
local BLAMES_SELF = "^" .. gsub(SELF:sub(2), "%p", "%%%0") .. ":%d+: "

-- Strings share one metatable whose __index is the real string library: strip dump from it, make
-- its pattern functions the bounded ones (lua_patterns.py), and lock the metatable so a script can
-- neither reach dump nor change string methods for later runs.
string.dump = nil
for name, fn in pairs(PATTERNS) do string[name] = fn end
getmetatable("").__metatable = false
_G.python, package.loaded.python = nil, nil  -- lupa registers it even without eval/builtins

local used, stopped = 0, nil  -- instructions charged to this run; why it is being stopped, once it is

local function hook()
  used = used + PERIOD
  -- The clock catches loops over C functions (gsub, table.insert on long data...): cheap in
  -- instructions, not in time. py_overtime returns a boolean: pushing it allocates nothing.
  if not stopped then stopped = used > BUDGET and BUDGET_MESSAGE or py_overtime() and TIME_MESSAGE end
  if stopped then
    -- From now on every instruction of this thread fails, so a pcall (or resume, or load reader)
    -- that caught the error cannot loop on: the script unwinds to the runner.
    sethook(hook, "", 1)
    error(stopped, 2)
  end
end

-- Called from a wrapper called by the script: level 3 is the script. No 1-instruction mode here
-- (it would trip on this very function); the thread's next hook call switches it on.
local function charge(cost)
  used = used + cost
  if not stopped and used > BUDGET then stopped = BUDGET_MESSAGE end
  if stopped then error(stopped, 3) end
end

-- Same level rule as charge. A callback refusing with `stop` (an output limit) ends the run as the
-- budget does. `nested`: the commands a console call ran besides its own (an alias's), each charged as
-- a call of the script's own. The clock is read after every console call: one slow command (a smooth
-- of a large volume) must stop the script at once, not a thousand instructions later.
local function raise_unless(ok, message, stop, nested)
  if nested then used = used + nested * CALL_COST end
  if not stopped then stopped = used > BUDGET and BUDGET_MESSAGE or py_overtime() and TIME_MESSAGE end
  if stop and not stopped then stopped = message end
  if stopped then error(stopped, 3) end
  if not ok then error(message, 3) end
end

local function relimited(...)
  py_relimit()  -- the callback lifted the memory cap for its results (see the module docstring)
  return ...
end

local function python(fn, ...)  -- every call into Python goes through here
  return relimited(fn(...))
end

local function check_values(what, args)
  for i = 1, args.n do
    local t = type(args[i])
    if t ~= "string" and t ~= "number" and t ~= "boolean" then
      error(what .. ": argument " .. i .. " is a " .. t .. " (only strings, numbers and booleans)", 3)
    end
  end
end

local function read_only() error("this table is read-only", 2) end

local function hooked(co)
  sethook(co, hook, "", PERIOD)
  return co
end

local function results_or_error(ok, ...)
  if ok then return ... end
  error((...), 0)
end

-- Every error a script can catch passes through here before the stack unwinds (and __close
-- metamethods run): it is the message handler of the script's pcall and xpcall, and resume checks
-- what killed a coroutine. A stack overflow stops the run, because it may be the count hook failing
-- to be called (no C stack or Lua stack left for the call): code at that depth runs unwatched.
-- Once the run is stopped, this thread goes to 1-instruction mode at once; it would not wait for
-- a hook call, which may be failing. Returns whether the run is stopped.
local function watch(e)
  if not stopped and type(e) == "string" and find(e, "stack overflow", 1, true) then
    stopped = find(e, "C stack overflow", 1, true) and "C stack overflow" or "stack overflow"
  end
  if stopped then sethook(hook, "", 1) end
  return stopped
end

local function on_error(e)
  watch(e)
  return e
end

local function safe_pcall(f, ...)
  return xpcall(f, on_error, ...)
end

-- Lua calls a message handler where the error was raised: inside the count hook, hooks off, when
-- the hook stops the run or could not be called. Those are the errors watch stops at; the
-- script's handler sees only the others, with hooks on.
local function safe_xpcall(f, handler, ...)
  if type(handler) ~= "function" then xpcall(f, handler) end  -- raises xpcall's own argument error
  return xpcall(f, function(e)
    if watch(e) then return e end
    return handler(e)
  end, ...)
end

local function resumed(ok, ...)
  if not ok then watch((...)) end
  return ok, ...
end

local function safe_resume(co, ...)
  return resumed(resume(co, ...))
end

-- Coroutines get the count hook too (hooks are per thread). A new coroutine is charged a full
-- period up front: it may run that long before its first check, and a loop making many short
-- ones must not escape the budget. There is no coroutine.close: it runs __close metamethods in a
-- thread where none of the above can watch them (a coroutine the hook stopped has hooks off for
-- good, as the hook never returned).
local safe_coroutine = {
  create = function(f)
    charge(PERIOD)
    return hooked(create(f))
  end,
  wrap = function(f)
    charge(PERIOD)
    local co = hooked(create(f))
    return function(...) return results_or_error(safe_resume(co, ...)) end
  end,
  resume = safe_resume,
}
for _, name in ipairs({"yield", "status", "running", "isyieldable"}) do
  safe_coroutine[name] = coroutine[name]
end

local function safe_setmetatable(t, mt)
  -- Finalizers run with hooks off, outside any budget; Lua only honours __gc present at this call.
  if type(mt) == "table" and rawget(mt, "__gc") ~= nil then
    error("__gc metamethods are not allowed in scripts", 2)
  end
  return setmetatable(t, mt)
end

-- load calls a reader function inside its own protected call, which would catch (and unwind past)
-- errors unwatched: read the pieces here instead, as load does.
local function read_all(reader)
  local pieces = {}
  while true do
    local piece = reader()
    if piece == nil or piece == "" then return concat(pieces) end
    if type(piece) ~= "string" then error("reader function must return a string", 0) end
    pieces[#pieces + 1] = piece
  end
end

local function loader(env)
  return function(chunk, chunkname)
    if type(chunk) == "function" then
      local ok, source = safe_pcall(read_all, chunk)
      if not ok then return nil, source end
      return load(source, chunkname or "=(load)", "t", env)
    end
    return load(chunk, chunkname, "t", env)
  end
end

local function safe_print(...)
  local args = pack(...)
  for i = 1, args.n do args[i] = tostring(args[i]) end
  charge(CALL_COST)
  raise_unless(python(py_print, concat(args, "\t", 1, args.n)))
end

local function exec(line)
  if type(line) ~= "string" then error("exec: expects a console line (string)", 2) end
  charge(CALL_COST)
  raise_unless(python(py_execute, line))
end

local function new_cmd()
  local proxies = {}  -- per run, so rawset on a proxy cannot leak into the next script
  local function proxy(name)
    local p = proxies[name]
    if not p then
      p = setmetatable({}, {
        __index = function(_, key)
          if type(key) ~= "string" then error("cmd." .. name .. ": command names are strings", 2) end
          return proxy(name .. "." .. key)
        end,
        __call = function(_, ...)
          local args = pack(...)
          check_values("cmd." .. name, args)
          charge(CALL_COST)
          raise_unless(python(py_command, name, ...))
        end,
        __newindex = read_only,
        __metatable = false,
      })
      proxies[name] = p
    end
    return p
  end
  return setmetatable({}, {
    __index = function(_, key)
      if type(key) ~= "string" then error("cmd: command names are strings", 2) end
      return proxy(key)
    end,
    __newindex = read_only,
    __metatable = false,
  })
end

local function new_cvar()
  return setmetatable({}, {
    __index = function(_, name)
      if type(name) ~= "string" then return nil end
      charge(READ_COST)
      return python(py_cvar_get, name)
    end,
    __newindex = function(_, name, value)
      if type(name) ~= "string" then error("cvar: names are strings", 2) end
      check_values("cvar." .. name, pack(value))
      charge(CALL_COST)
      raise_unless(python(py_cvar_set, name, value))
    end,
    __metatable = false,
  })
end

local SAFE_GLOBALS = {
  assert = assert, error = error, ipairs = ipairs, next = next, pairs = pairs, pcall = safe_pcall,
  xpcall = safe_xpcall, select = select, tonumber = tonumber, tostring = tostring, type = type,
  rawequal = rawequal, rawlen = rawlen, rawget = rawget, rawset = rawset,
  getmetatable = getmetatable, setmetatable = safe_setmetatable, print = safe_print, exec = exec,
  _VERSION = _VERSION,
}
local LIBRARIES = {
  string = string, table = table, math = math, utf8 = utf8, coroutine = safe_coroutine,
  time = {clock = os.clock, time = os.time},
}

local function copy(t)
  local c = {}
  for k, v in pairs(t) do c[k] = v end
  return c
end

local function new_env()
  local env = copy(SAFE_GLOBALS)
  for name, lib in pairs(LIBRARIES) do env[name] = copy(lib) end  -- copies: edits stay in this run
  env.cmd, env.cvar, env._G = new_cmd(), new_cvar(), env
  env.load = loader(env)
  return env
end

-- The error message of a failed script run in thread co. Never calls a script's __tostring (the
-- hook is off out here). A C function called by a wrapper above blames the wrapper's line; the
-- dead coroutine's stack is intact, so blame the innermost script line instead.
local function describe(co, err)
  local t = type(err)
  if t ~= "string" and t ~= "number" then return "(error object is a " .. t .. " value)" end
  err = tostring(err)
  if not find(err, BLAMES_SELF) then return err end
  err = gsub(err, BLAMES_SELF, "", 1)
  local level = 0
  repeat
    local info = getinfo(co, level, "Sl")
    if info and info.source ~= SELF and info.currentline > 0 then
      return info.short_src .. ":" .. info.currentline .. ": " .. err
    end
    level = level + 1
  until not info
  return err
end

-- Returns true, or false, kind ("syntax" or "error") and a message.
return function(source, chunkname)
  local env = new_env()
  local fn, err = load(source, chunkname, "t", env)
  if not fn then return false, "syntax", err end
  used, stopped = 0, nil
  -- The script runs in its own coroutine so that the hook (and its 1-instruction mode once the
  -- budget is spent) never applies to this runner.
  local co = hooked(create(fn))
  local ok, result = resume(co)
  if not ok then
    result = describe(co, result)
  elseif status(co) ~= "dead" then
    ok, result = false, "attempt to yield from outside a coroutine"
  end
  -- A stopped run failed, even where the script caught the error and ended before its own next
  -- hook call (the stop was in a coroutine or a message handler).
  if stopped and (ok or not find(result, stopped, 1, true)) then ok, result = false, stopped end
  if ok then return true end
  return false, "error", result
end
"""


def _text(value: Any) -> str:
    """A Lua value as console text: exact for floats, 1/0 for booleans."""
    if isinstance(value, bool):
        return "1" if value else "0"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        return repr(value)  # shortest text that round-trips exactly
    if isinstance(value, bytes):
        return _decode(value)
    raise TypeError(f"cannot pass a {type(value).__name__}")


def _decode(value: bytes) -> str:
    try:
        return value.decode("utf-8")
    except UnicodeDecodeError:
        raise ValueError(f"{value[:40]!r} is not UTF-8 text") from None


def _to_lua(value: Any) -> bool | int | float | bytes | None:
    """Only plain values cross into Lua: a str would arrive as a Python object (encoding=None)."""
    if isinstance(value, bool | float):
        return value
    if isinstance(value, int):
        return value if value in _INT64 else float(value)
    if isinstance(value, str):
        return value.encode("utf-8", "surrogateescape")
    return None


def _refuse_attribute(obj: Any, name: Any, value: Any = None) -> Any:
    raise AttributeError("Python objects are not accessible from Lua")


class LuaScripting:
    """Runs Lua scripts against a console, each in a fresh sandbox environment."""

    def __init__(
        self,
        console: Console,
        instruction_budget: int = 50_000_000,
        memory_limit: int = 64 * 2**20,
        time_limit: float = 5.0,
    ) -> None:
        self.console = console
        self.instruction_budget = instruction_budget
        self.memory_limit = memory_limit
        self.time_limit = time_limit
        self._running = False
        self._deadline = 0.0
        self._output = 0  # bytes of console output this run has made
        self._lua, self._run = self._new_runtime()

    def run_file(self, path: str | os.PathLike) -> bool:
        """Read a script (UTF-8 text) and run it; False, with one console error line, on any failure."""
        name = Path(path).name
        try:
            data = read_regular_bytes(path, self.memory_limit // 2)  # more could not be pushed (see above)
        except OSError as exc:
            return self._fail(name, f"cannot read {os.fspath(path)}: {exc.strerror or exc}")
        if not data.startswith(BYTECODE_SIGNATURE):  # checked first so bytecode gets the clearer refusal
            try:
                data = data.decode("utf-8-sig").encode("utf-8")  # validates, drops a BOM
            except UnicodeDecodeError as exc:
                return self._fail(name, f"not UTF-8 text (byte {exc.start})")
        return self._execute(data, name)

    def run_string(self, source: str, name: str = "(console)") -> bool:
        try:
            data = source.encode("utf-8")
        except UnicodeEncodeError as exc:
            return self._fail(name, f"not UTF-8 text ({exc.reason})")
        return self._execute(data, name)

    # -- running ------------------------------------------------------------------------------

    def _new_runtime(self) -> tuple[LuaRuntime, Any]:
        lua = LuaRuntime(
            encoding=None,  # strings cross as bytes; decoding is ours, so bad UTF-8 cannot raise in lupa
            register_eval=False,
            register_builtins=False,
            unpack_returned_tuples=True,
            max_memory=self.memory_limit,
            attribute_handlers=(_refuse_attribute, _refuse_attribute),
        )
        callbacks = (self._command, self._exec, self._cvar_get, self._cvar_set, self._print)
        patterns = lua.execute(PATTERNS, WORK_LIMIT, name=_CHUNK_NAME, mode="t")
        run = lua.execute(
            _SETUP,
            *(self._callback(lua, fn) for fn in callbacks),
            lambda: lua.set_max_memory(self.memory_limit),
            lambda: time.monotonic() > self._deadline,
            self.instruction_budget,
            HOOK_PERIOD,
            CONSOLE_CALL_COST,
            CVAR_READ_COST,
            BUDGET_MESSAGE.encode(),
            f"time limit exceeded ({self.time_limit:g} s)".encode(),
            patterns,
            name=_CHUNK_NAME,
            mode="t",
        )
        return lua, run

    def _callback(self, lua: LuaRuntime, fn: Callable[..., Any]) -> Callable[..., Any]:
        """Never raises into Lua (lupa would hand the script the Python exception object), and makes
        room for its results under the memory cap (see the module docstring)."""

        def call(*args: Any) -> Any:
            try:
                result = fn(*args)
            except (TypeError, ValueError) as exc:  # our converters refusing a value: a message for the user
                result = False, str(exc).encode("utf-8", "replace")
            except Exception as exc:  # a bug: still a Lua error, never a traceback through Lua
                result = False, f"internal error: {type(exc).__name__}: {exc}".encode("utf-8", "replace")
            size = sum(len(v) for v in (result if isinstance(result, tuple) else (result,)) if isinstance(v, bytes))
            lua.set_max_memory(max(self.memory_limit, lua.get_memory_used() + size + _PUSH_SLACK))
            return result

        return call

    def _execute(self, source: bytes, name: str) -> bool:
        if source.startswith(BYTECODE_SIGNATURE):
            return self._fail(name, "precompiled Lua bytecode is refused; run the source text instead")
        if len(source) > self.memory_limit // 2:  # pushing it could fail outside Lua's protection
            return self._fail(name, f"script too large ({len(source) / 2**20:.1f} MiB)")
        if self._running:  # a nested run would reset the budget of the script that started it
            return self._fail(name, "cannot run a script from inside a script")
        self._running = True
        self._deadline = time.monotonic() + self.time_limit
        self._output = 0
        try:
            result = self._run(source, b"=" + name.encode("utf-8", "replace"))  # True or (False, kind, message)
        except LuaError as exc:  # the runner itself failed, not the script
            return self._fail(name, self._reason(str(exc) or _LUA_OOM))
        finally:
            self._running = False
            self._lua.set_max_memory(self.memory_limit)  # in case the script stopped before a relimit
            self._lua.gccollect()  # a failed script may leave up to the whole memory cap as garbage
        if result is True:
            return True
        _, kind, message = result
        text = self._reason(message.decode("utf-8", "replace"))
        if kind == b"syntax":
            text = re.sub(r"^(.*?:\d+): (?!syntax error)", r"\1: syntax error: ", text, count=1, flags=re.S)
        if not text.startswith(f"{name}:"):
            text = f"{name}: {text}"
        self.console.error(f"lua: {text}")
        return False

    def _reason(self, message: str) -> str:
        if message == _LUA_OOM:
            return f"out of memory (limit {self.memory_limit / 2**20:g} MiB)"
        return message

    def _fail(self, name: str, reason: str) -> bool:
        self.console.error(f"lua: {name}: {reason}")
        return False

    # -- callbacks (Lua -> Python): plain values in; (True,) or (False, message) out ------------

    def _spend_output(self, size: int, what: str) -> tuple | None:
        """Charge `size` bytes of console output to the run: None, or the refusal that stops it."""
        if size > LINE_LIMIT:
            return False, f"{what} too long ({size} bytes; limit {LINE_LIMIT // 2**10} KiB)".encode(), True
        if self._output + size > OUTPUT_LIMIT:
            return False, f"output limit exceeded ({OUTPUT_LIMIT // 2**20} MiB)".encode(), True
        self._output += size
        return None

    def _run_line(self, line: str) -> tuple:
        refused = self._spend_output(len(line.encode()), "command line")
        if refused:
            return refused
        before = self.console.commands_run
        ok = self.console.execute(line)
        nested = max(0, self.console.commands_run - before - 1)  # the call itself is charged already
        if ok:
            return True, None, None, nested
        return False, f"command failed: {line}".encode(), None, nested

    def _command(self, name: bytes, *args: Any) -> tuple:
        command = _decode(name)
        if command not in self.console.registry.names(qualified=True):
            return False, f"unknown command {command!r}".encode()
        return self._run_line(join([command, *map(_text, args)]))

    def _exec(self, line: bytes) -> tuple:
        return self._run_line(_decode(line))

    def _cvar_get(self, name: bytes) -> bool | int | float | bytes | None:
        cvar = self.console.registry.cvars.get(name.decode("utf-8", "replace"))
        return None if cvar is None else _to_lua(cvar.value)

    def _cvar_set(self, name: bytes, value: Any) -> tuple:
        cvar = self.console.registry.cvars.get(_decode(name))
        if cvar is None:
            return False, f"unknown cvar {name.decode()!r}".encode()
        text = _text(value)
        try:
            cvar.parse(text)  # validate here so the script's error carries the cvar's own message
        except (CommandError, ValueError) as exc:
            return False, str(exc).encode()
        return self._run_line(join([cvar.name, text]))

    def _print(self, text: bytes) -> tuple:
        refused = self._spend_output(len(text), "printed line")
        if refused:
            return refused
        self.console.print(text.decode("utf-8", "replace"))
        return (True,)
