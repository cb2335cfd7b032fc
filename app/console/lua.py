"""Lua scripting for the console, sandboxed: scripts come from others. No Qt, no GL.

Tex3Dtrace scripted its console in Lua; Shadelab does the same. A script can do what a user can
type in the console, nothing more: every change goes through `Console.execute`, so it is logged
and recorded like typed input.

Script API
----------
``cmd.<name>(args...)``
    Runs a registered console command (or sets/prints a cvar, as typing its name would).
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
    Compiles source text (never bytecode) into a function that sees this script's globals.
Standard library
    ``assert error ipairs next pairs pcall xpcall select tonumber tostring type rawequal rawlen
    rawget rawset setmetatable getmetatable``; ``string`` (no ``dump``), ``table``, ``math``,
    ``utf8``, ``coroutine``; ``time.clock()`` and ``time.time()`` (``os.clock``/``os.time``).
    ``setmetatable`` refuses ``__gc`` (finalizers would run outside the instruction budget).
    Not available: ``io os package require debug dofile loadfile collectgarbage`` and anything
    Python.

Limits
------
Each run gets fresh globals (nothing leaks from one script to the next), a budget of Lua
instructions (default 50 million, about a second; each call into the console costs
`CONSOLE_CALL_COST` of it, reading a cvar `CVAR_READ_COST`) and a memory cap (default 64 MiB).
A script that exceeds either, or raises an error, stops; the console gets one error line naming
the script, the line and the reason, e.g. ``lua: cube.lua:12: attempt to call a nil value
(global 'foo')``. Lua pattern matching runs in C, outside the instruction budget: a pathological
pattern on a long subject can still take a long time.

Sandbox design: the Python callbacks are upvalues of the Lua closures made by `_SETUP`, which runs
once per runtime with the full standard library; scripts get only the environment table `new_env`
builds, so without ``debug`` they cannot reach those upvalues. Callbacks take and return only
strings, numbers and booleans, and never raise (lupa would hand the script the Python exception
object as the error value): they return ``false, message`` and the Lua side raises the error.
"""
from __future__ import annotations

import os
import re
import shlex
from pathlib import Path
from typing import Any, Callable

from lupa import LuaError, LuaRuntime

from app.console.console import Console
from app.console.registry import CommandError

HOOK_PERIOD = 1000  # instructions between budget checks: finer costs speed, coarser costs accuracy
# Python work is charged in instructions too, so a runaway loop of console calls also stops: at the
# default budget a script gets 50,000 console calls (command, exec, cvar set, print), about 1 s of
# bare console time here, and 500,000 cvar reads.
CONSOLE_CALL_COST = 1000
CVAR_READ_COST = 100
BYTECODE_SIGNATURE = b"\x1bLua"
BUDGET_MESSAGE = "instruction budget exceeded"
_LUA_OOM = "not enough memory"
_INT64 = range(-(2**63), 2**63)

# Runs once per LuaRuntime with the full standard library; returns `run(source, chunkname)`.
_SETUP = r"""
local py_command, py_execute, py_cvar_get, py_cvar_set, py_print, BUDGET, PERIOD, CALL_COST, READ_COST,
      BUDGET_MESSAGE = ...
local assert, error, ipairs, next, pairs, pcall, xpcall, select, tonumber, tostring, type =
      assert, error, ipairs, next, pairs, pcall, xpcall, select, tonumber, tostring, type
local rawequal, rawlen, rawget, rawset, setmetatable, getmetatable, load =
      rawequal, rawlen, rawget, rawset, setmetatable, getmetatable, load
local sethook, concat, pack, create, resume, status = debug.sethook, table.concat, table.pack,
      coroutine.create, coroutine.resume, coroutine.status

-- Strings share one metatable whose __index is the real string library: strip dump from it and
-- lock the metatable so a script can neither reach dump nor change string methods for later runs.
string.dump = nil
getmetatable("").__metatable = false
_G.python, package.loaded.python = nil, nil  -- lupa registers it even without eval/builtins

local used, exhausted = 0, false

local function hook()
  used = used + PERIOD
  if exhausted or used > BUDGET then
    exhausted = true
    -- From now on every instruction of this thread fails, so a pcall (or resume, or load reader)
    -- that caught the error cannot loop on: the script unwinds to the runner.
    sethook(hook, "", 1)
    error(BUDGET_MESSAGE, 2)
  end
end

-- Called from a wrapper called by the script: level 3 is the script. No 1-instruction mode here
-- (it would trip on this very function); the thread's next hook call switches it on.
local function charge(cost)
  used = used + cost
  if used > BUDGET then
    exhausted = true
    error(BUDGET_MESSAGE, 3)
  end
end

local function raise_unless(ok, message)  -- same level rule as charge
  if not ok then error(message, 3) end
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

local function wrap_results(ok, ...)
  if ok then return ... end
  error((...), 0)
end

-- Coroutines get the count hook too (hooks are per thread). A new coroutine is charged a full
-- period up front: it may run that long before its first check, and a loop making many short
-- ones must not escape the budget.
local safe_coroutine = {
  create = function(f)
    charge(PERIOD)
    return hooked(create(f))
  end,
  wrap = function(f)
    charge(PERIOD)
    local co = hooked(create(f))
    return function(...) return wrap_results(resume(co, ...)) end
  end,
}
for _, name in ipairs({"resume", "yield", "status", "running", "isyieldable", "close"}) do
  safe_coroutine[name] = coroutine[name]
end

local function safe_setmetatable(t, mt)
  -- Finalizers run with hooks off, outside any budget; Lua only honours __gc present at this call.
  if type(mt) == "table" and rawget(mt, "__gc") ~= nil then
    error("__gc metamethods are not allowed in scripts", 2)
  end
  return setmetatable(t, mt)
end

local function safe_print(...)
  local args = pack(...)
  for i = 1, args.n do args[i] = tostring(args[i]) end
  charge(CALL_COST)
  py_print(concat(args, "\t", 1, args.n))
end

local function exec(line)
  if type(line) ~= "string" then error("exec: expects a console line (string)", 2) end
  charge(CALL_COST)
  raise_unless(py_execute(line))
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
          raise_unless(py_command(name, ...))
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
      return py_cvar_get(name)
    end,
    __newindex = function(_, name, value)
      if type(name) ~= "string" then error("cvar: names are strings", 2) end
      check_values("cvar." .. name, pack(value))
      charge(CALL_COST)
      raise_unless(py_cvar_set(name, value))
    end,
    __metatable = false,
  })
end

local SAFE_GLOBALS = {
  assert = assert, error = error, ipairs = ipairs, next = next, pairs = pairs, pcall = pcall,
  xpcall = xpcall, select = select, tonumber = tonumber, tostring = tostring, type = type,
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
  env.load = function(chunk, chunkname) return load(chunk, chunkname, "t", env) end
  return env
end

local function describe(err)  -- never calls a script's __tostring: the hook is off out here
  local t = type(err)
  if t == "string" or t == "number" then return tostring(err) end
  return "(error object is a " .. t .. " value)"
end

-- Returns true, or false, kind ("syntax" or "error") and a message.
return function(source, chunkname)
  local env = new_env()
  local fn, err = load(source, chunkname, "t", env)
  if not fn then return false, "syntax", err end
  used, exhausted = 0, false
  -- The script runs in its own coroutine so that the hook (and its 1-instruction mode once the
  -- budget is spent) never applies to this runner.
  local co = hooked(create(fn))
  local ok, result = resume(co)
  if not ok then return false, "error", describe(result) end
  if status(co) ~= "dead" then return false, "error", "attempt to yield from outside a coroutine" end
  return true
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


def _guarded(fn: Callable[..., tuple]) -> Callable[..., tuple]:
    """Callbacks never raise into Lua: lupa would pass the script the Python exception object."""

    def call(*args: Any) -> tuple:
        try:
            return fn(*args)
        except Exception as exc:
            return False, f"{type(exc).__name__}: {exc}".encode("utf-8", "replace")

    return call


def _refuse_attribute(obj: Any, name: Any, value: Any = None) -> Any:
    raise AttributeError("Python objects are not accessible from Lua")


class LuaScripting:
    """Runs Lua scripts against a console, each in a fresh sandbox environment."""

    def __init__(self, console: Console, instruction_budget: int = 50_000_000, memory_limit: int = 64 * 2**20) -> None:
        self.console = console
        self.instruction_budget = instruction_budget
        self.memory_limit = memory_limit
        self._running = False
        self._runtime, self._run = self._new_runtime()

    def run_file(self, path: str | os.PathLike) -> bool:
        """Read a script (UTF-8 text) and run it; False, with one console error line, on any failure."""
        name = Path(path).name
        try:
            data = Path(path).read_bytes()
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
        run = lua.execute(
            _SETUP,
            _guarded(self._command),
            _guarded(self._exec),
            self._cvar_get,
            _guarded(self._cvar_set),
            _guarded(self._print),
            self.instruction_budget,
            HOOK_PERIOD,
            CONSOLE_CALL_COST,
            CVAR_READ_COST,
            BUDGET_MESSAGE.encode(),
            name="=(lua sandbox)",
            mode="t",
        )
        return lua, run

    def _execute(self, source: bytes, name: str) -> bool:
        if source.startswith(BYTECODE_SIGNATURE):
            return self._fail(name, "precompiled Lua bytecode is refused; run the source text instead")
        if self._running:  # a nested run would reset the budget of the script that started it
            return self._fail(name, "cannot run a script from inside a script")
        self._running = True
        try:
            result = self._run(source, b"=" + name.encode("utf-8", "replace"))  # True or (False, kind, message)
        except LuaError as exc:  # the runner itself failed (out of memory outside the script): start over
            self._runtime, self._run = self._new_runtime()
            return self._fail(name, self._reason(str(exc) or _LUA_OOM))
        finally:
            self._running = False
            self._runtime.gccollect()  # a failed script may leave up to the whole memory cap as garbage
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

    # -- callbacks (Lua -> Python): plain values in, (ok, message) out ------------------------

    def _run_line(self, line: str) -> tuple:
        if self.console.execute(line):
            return (True,)
        return False, f"command failed: {line}".encode()

    def _command(self, name: bytes, *args: Any) -> tuple:
        command = _decode(name)
        registry = self.console.registry
        if command not in registry.commands and command not in registry.cvars:
            return False, f"unknown command {command!r}".encode()
        return self._run_line(shlex.join([command, *map(_text, args)]))

    def _exec(self, line: bytes) -> tuple:
        return self._run_line(_decode(line))

    def _cvar_get(self, name: bytes) -> bool | int | float | bytes | None:
        cvar = self.console.registry.cvars.get(name.decode("utf-8", "replace"))
        return None if cvar is None else _to_lua(cvar.value)

    def _cvar_set(self, name: bytes, value: Any) -> tuple:
        cvar = self.console.registry.cvars.get(_decode(name))
        if cvar is None:
            return False, f"unknown cvar {_decode(name)!r}".encode()
        text = _text(value)
        try:
            cvar.parse(text)  # validate here so the script's error carries the cvar's own message
        except (CommandError, ValueError) as exc:
            return False, str(exc).encode()
        return self._run_line(shlex.join([cvar.name, text]))

    def _print(self, text: bytes) -> tuple:
        self.console.print(text.decode("utf-8", "replace"))
        return (True,)
