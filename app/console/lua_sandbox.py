"""The interpreter of console scripts: a sandboxed Lua runtime, in a child process of its own.

`LuaScripting` (app/console/lua.py, which documents the script API and the limits) starts this
module as ``python -m app.console.lua_sandbox`` through `app.console.lua_process`, sends it scripts
and answers its requests; the console itself stays in the parent. Past a run's time limit the
parent kills this process, whatever it is doing; the limits below stop a run from inside first,
with a message naming the script's line.

Limits from inside
------------------
The count hook checks the budget and the clock every `HOOK_PERIOD` instructions, so a single C
call runs whole between two checks (the parent's kill stops one that never ends). The pattern
functions (``string.find match gmatch gsub``) backtrack in C: they are replaced by bounded ones
(`app.console.lua_patterns`). A call whose worst case in C could pass `WORK_LIMIT` steps (about a
millisecond) runs in a Lua port of the matcher instead, under the hook. At 60 to 100 instructions
per backtracking step there, a call that backtracks over a few thousand bytes can spend the budget
where C would have taken tens of milliseconds.

Reaching a limit stops the run for good: from then on every instruction fails, so ``pcall``
catching the error gains the script nothing, and a message handler is not called. A stack
overflow (C or Lua) stops it the same way, since calling the hook can itself fail for want of
stack, and code there would run unwatched. Every error a script can catch is seen first (by the
message handler of every ``pcall`` and ``xpcall``, and by ``coroutine.resume``), before the
stack unwinds and ``__close`` metamethods run; ``coroutine.close`` runs them where nothing could
see, so it is not provided, and a reader function given to ``load`` is called by the sandbox, not
inside ``load``.

Sandbox design: the Python callbacks are upvalues of the Lua closures made by `_SETUP`, which runs
once per runtime with the full standard library; scripts get only the environment table `new_env`
builds, so without ``debug`` they cannot reach those upvalues. Callbacks take and return only
strings, numbers and booleans, and never raise (lupa would hand the script the Python exception
object as the error value): they return ``false, message`` and the Lua side raises the error.

lupa (2.8) pushes a callback's results onto the Lua stack unprotected: a memory error there leaves
the GIL taken and hangs the process, and one while pushing a call's arguments aborts it. So each
callback lifts the memory cap just enough for its results, the Lua side restores it right after,
and a script source may use at most half the cap. (Should it happen anyway, it happens here, not
in the editor: the parent kills a hung process at the time limit and reports one that died.)

Messages (JSON arrays; `app.console.lua_process` frames them). From the parent:
``["run", source, chunkname, budget, memory_limit, time_limit, time_message]``, answered by
``["done", ok, kind, message]``. Meanwhile this process asks, and waits for each answer:
``["command", name, line, error]`` and ``["exec", line]`` (answer ``[ok, message, stop, nested]``),
``["set", name, text, error]`` (the same), ``["cvar", name]`` (answer ``[value]``) and
``["print", text]`` (answer ``[ok, message, stop]``). A conversion that failed here travels as
`error`, so the parent still answers an unknown name first.
"""
from __future__ import annotations

import os
import signal
import sys
import threading
import time
from typing import Any, Callable

from lupa import LuaError, LuaRuntime

from app.console.lua_patterns import PATTERNS, WORK_LIMIT
from app.console.lua_process import Channel
from app.console.quoting import join

HOOK_PERIOD = 1000  # instructions between budget checks: finer costs speed, coarser costs accuracy
# Python work is charged in instructions too, so a runaway loop of console calls also stops: at the
# default budget a script gets 50,000 console calls (command, exec, cvar set, print), about 4 s of
# bare console time here (each a round trip to the editor's process), and 500,000 cvar reads.
CONSOLE_CALL_COST = 1000
CVAR_READ_COST = 100
BUDGET_MESSAGE = "instruction budget exceeded"
LUA_OOM = "not enough memory"
_PUSH_SLACK = 64 * 2**10  # room for the Lua stack and string headers when a callback's results are pushed
_INT64 = range(-(2**63), 2**63)
_CHUNK_NAME = "=(lua sandbox)"  # both chunks: an error blaming them is moved to the script's line

# Runs once per LuaRuntime with the full standard library; returns `run(source, chunkname, budget,
# time_message)`.
_SETUP = r"""
local py_command, py_execute, py_cvar_get, py_cvar_set, py_print, py_relimit, py_overtime, PERIOD,
      CALL_COST, READ_COST, BUDGET_MESSAGE, PATTERNS = ...
local BUDGET, TIME_MESSAGE  -- this run's: set by the runner
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
return function(source, chunkname, budget, time_message)
  BUDGET, TIME_MESSAGE = budget, time_message
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


def _lua_answer(answer: list) -> tuple:
    """The parent's answer to a console call as the callback's results: (True, nil, nil, nested) or
    (False, message, stop, nested)."""
    ok, message, stop, *nested = answer
    return ok, None if message is None else message.encode("utf-8", "replace"), stop, *nested


class Sandbox:
    """A Lua runtime that runs scripts, asking the parent over `channel` for everything console."""

    def __init__(self, channel: Channel) -> None:
        self.channel = channel
        self.memory_limit = 64 * 2**20  # this run's; the runtime needs a cap from the start to keep one
        self._deadline = 0.0
        self._cvars: dict[bytes, Any] = {}  # values read since the last console call (only those change them)
        self.lua = LuaRuntime(
            encoding=None,  # strings cross as bytes; decoding is ours, so bad UTF-8 cannot raise in lupa
            register_eval=False,
            register_builtins=False,
            unpack_returned_tuples=True,
            max_memory=self.memory_limit,
            attribute_handlers=(_refuse_attribute, _refuse_attribute),
        )
        lua = self.lua
        callbacks = (self._command, self._exec, self._cvar_get, self._cvar_set, self._print)
        patterns = lua.execute(PATTERNS, WORK_LIMIT, name=_CHUNK_NAME, mode="t")
        self._run = lua.execute(
            _SETUP,
            *(self._callback(fn) for fn in callbacks),
            lambda: lua.set_max_memory(self.memory_limit),
            lambda: time.monotonic() > self._deadline,
            HOOK_PERIOD,
            CONSOLE_CALL_COST,
            CVAR_READ_COST,
            BUDGET_MESSAGE.encode(),
            patterns,
            name=_CHUNK_NAME,
            mode="t",
        )

    def run(self, source: str, chunkname: str, budget: int, memory_limit: int, time_limit: float,
            time_message: str) -> list:
        """Run one script: [ok, kind ("syntax" or "error"), message]."""
        self.memory_limit = memory_limit
        self.lua.set_max_memory(memory_limit)
        self._cvars.clear()
        self._deadline = time.monotonic() + time_limit
        try:
            result = self._run(source.encode("utf-8", "surrogateescape"), chunkname.encode("utf-8", "replace"),
                               budget, time_message.encode())
        except LuaError as exc:  # the runner itself failed, not the script
            return [False, "error", str(exc) or LUA_OOM]
        finally:
            self.lua.set_max_memory(self.memory_limit)  # in case the script stopped before a relimit
            self.lua.gccollect()  # a failed script may leave up to the whole memory cap as garbage
        if result is True:
            return [True, None, None]
        _, kind, message = result
        return [False, kind.decode(), message.decode("utf-8", "replace")]

    def _callback(self, fn: Callable[..., Any]) -> Callable[..., Any]:
        """Never raises into Lua (lupa would hand the script the Python exception object), and makes
        room for its results under the memory cap (see the module docstring)."""
        lua = self.lua

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

    def _ask(self, *request: Any) -> list:
        self.channel.send(list(request))
        return self.channel.receive()

    # -- callbacks (Lua -> Python): plain values in; (True,) or (False, message) out ------------

    def _console_call(self, *request: Any) -> tuple:
        self._cvars.clear()  # a console call may change any cvar
        return _lua_answer(self._ask(*request))

    def _command(self, name: bytes, *args: Any) -> tuple:
        command = _decode(name)
        try:
            line, error = join([command, *map(_text, args)]), None
        except (TypeError, ValueError) as exc:
            line, error = None, str(exc)
        return self._console_call("command", command, line, error)

    def _exec(self, line: bytes) -> tuple:
        return self._console_call("exec", _decode(line))

    def _cvar_get(self, name: bytes) -> bool | int | float | bytes | None:
        if name not in self._cvars:
            self._cvars[name] = _to_lua(self._ask("cvar", name.decode("utf-8", "replace"))[0])
        return self._cvars[name]

    def _cvar_set(self, name: bytes, value: Any) -> tuple:
        try:
            text, error = _text(value), None
        except (TypeError, ValueError) as exc:
            text, error = None, str(exc)
        return self._console_call("set", _decode(name), text, error)

    def _print(self, text: bytes) -> tuple:
        return _lua_answer(self._ask("print", text.decode("utf-8", "replace")))


def _exit_with(parent: int) -> None:
    """Beside the interpreter (lupa lets go of the GIL while Lua runs): a script stuck in C must not
    outlive the editor that started it, should that die before it could kill this process."""
    while os.getppid() == parent:
        time.sleep(1.0)
    os._exit(1)


def main() -> None:
    """Serve runs until the parent closes the pipe."""
    threading.Thread(target=_exit_with, args=(os.getppid(),), daemon=True).start()
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl+C in a terminal is the editor's to handle: it kills us
    protocol = os.dup(1)
    os.dup2(2, 1)  # stray writes to stdout (a warning, a print) must not land in the message stream
    channel = Channel(0, protocol)
    sandbox = Sandbox(channel)
    channel.send(["ready"])
    while True:
        try:
            request = channel.receive()
        except EOFError:
            return
        if request[0] == "run":
            channel.send(["done", *sandbox.run(*request[1:])])


if __name__ == "__main__":
    sys.exit(main())
