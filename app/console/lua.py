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
- a time limit (default 5 s), wall clock, whatever the script is doing: ``time limit exceeded (5 s)``.
  Lua runs in a child process (`app.console.lua_sandbox`), which stops a script at the limit from
  inside when it can (the message then names the line) and is killed `KILL_GRACE` later when it
  cannot (a C call such as ``table.move(a, 1, 1 << 40, 1, b)``, compiling, collecting garbage);
- a memory cap (default 64 MiB): ``out of memory (limit 64 MiB)``; a script source may be at
  most half of it;
- console output: `OUTPUT_LIMIT` (1 MiB) of printed lines and command lines in all, `LINE_LIMIT`
  (64 KiB) in one line, which is refused whole, never cut: ``output limit exceeded (1 MiB)``,
  ``printed line too long (70000 bytes; limit 64 KiB)``, ``command line too long (...)``. What
  commands print in reply is theirs, not counted.

A script that fails stops, and the console gets one error line naming the script, the line and
the reason, e.g. ``lua: cube.lua:12: attempt to call a nil value (global 'foo')``; where the
script caught its stop and ended, or was killed, the line is left out. A script cannot run another
script (through a console command that does), since that would reset its budget.
"""
from __future__ import annotations

import os
import re
import time
from pathlib import Path

from app.console import lua_process
from app.console.console import Console
from app.console.lua_sandbox import LUA_OOM
from app.console.quoting import join
from app.console.registry import CommandError
from app.io.regular_file import read_regular_bytes

# Console output a run may make: printed lines and command lines, each echoed into the log. Past
# either limit the script stops, as at the budget (a longer line is refused, not cut).
OUTPUT_LIMIT = 2**20  # bytes in all
LINE_LIMIT = 64 * 2**10  # bytes in one line
BYTECODE_SIGNATURE = b"\x1bLua"
KILL_GRACE = 0.2  # seconds past the time limit before a run that did not stop itself is killed


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
        self._output = 0  # bytes of console output this run has made
        lua_process.prepare()

    def run_file(self, path: str | os.PathLike) -> bool:
        """Read a script (UTF-8 text) and run it; False, with one console error line, on any failure."""
        name = Path(path).name
        try:
            data = read_regular_bytes(path, self.memory_limit // 2)  # more could not be pushed into Lua
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

    @property
    def time_message(self) -> str:
        return f"time limit exceeded ({self.time_limit:g} s)"

    def _execute(self, source: bytes, name: str) -> bool:
        if source.startswith(BYTECODE_SIGNATURE):
            return self._fail(name, "precompiled Lua bytecode is refused; run the source text instead")
        if len(source) > self.memory_limit // 2:  # pushing it could fail outside Lua's protection
            return self._fail(name, f"script too large ({len(source) / 2**20:.1f} MiB)")
        if self._running:  # a nested run would reset the budget of the script that started it
            return self._fail(name, "cannot run a script from inside a script")
        self._running = True
        self._output = 0
        worker = lua_process.take()
        try:
            ok, kind, message = self._run(worker, source.decode("utf-8"), name)
        finally:
            self._running = False
            lua_process.give_back(worker)
        if ok:
            return True
        text = self._reason(message)
        if kind == "syntax":
            text = re.sub(r"^(.*?:\d+): (?!syntax error)", r"\1: syntax error: ", text, count=1, flags=re.S)
        if not text.startswith(f"{name}:"):
            text = f"{name}: {text}"
        self.console.error(f"lua: {text}")
        return False

    def _run(self, worker: lua_process.Worker, source: str, name: str) -> list:
        """Run a script in `worker`, answering its requests until it is done: [ok, kind, message]. A
        worker that outlives the time limit by `KILL_GRACE`, or dies, is killed and the run fails."""
        failed = worker.wait_ready()
        if failed:
            return [False, "error", failed]
        deadline = time.monotonic() + self.time_limit
        answers = {"command": self._command, "exec": self._run_line, "set": self._cvar_set,
                   "cvar": self._cvar_get, "print": self._print}
        try:
            worker.channel.send(["run", source, "=" + name, self.instruction_budget, self.memory_limit,
                                 self.time_limit, self.time_message])
            while True:
                request = worker.channel.receive(deadline - time.monotonic() + KILL_GRACE)
                if request is None:  # stuck where nothing inside could stop it (a C call, the compiler)
                    worker.kill()
                    return [False, "error", self.time_message]
                if request[0] == "done":
                    return request[1:]
                worker.channel.send(answers[request[0]](*request[1:]))
        except (EOFError, OSError, ValueError, KeyError, TypeError):  # it died, or talks nonsense
            worker.kill()
            return [False, "error", f"the Lua interpreter stopped unexpectedly (exit status {worker.exit_status()})"]
        except BaseException:  # interrupted mid-run (Ctrl+C): the worker would take our next message as an answer
            worker.kill()
            raise

    def _reason(self, message: str) -> str:
        if message == LUA_OOM:
            return f"out of memory (limit {self.memory_limit / 2**20:g} MiB)"
        return message

    def _fail(self, name: str, reason: str) -> bool:
        self.console.error(f"lua: {name}: {reason}")
        return False

    # -- requests from the script: plain values in, plain values out -------------------------

    def _spend_output(self, size: int, what: str) -> list | None:
        """Charge `size` bytes of console output to the run: None, or the refusal that stops it."""
        if size > LINE_LIMIT:
            return [False, f"{what} too long ({size} bytes; limit {LINE_LIMIT // 2**10} KiB)", True, 0]
        if self._output + size > OUTPUT_LIMIT:
            return [False, f"output limit exceeded ({OUTPUT_LIMIT // 2**20} MiB)", True, 0]
        self._output += size
        return None

    def _run_line(self, line: str) -> list:
        """[ok, message, stop, nested]: `nested`, the commands it ran besides its own (an alias's)."""
        refused = self._spend_output(len(line.encode("utf-8", "surrogatepass")), "command line")
        if refused:
            return refused
        before = self.console.commands_run
        ok = self.console.execute(line)
        nested = max(0, self.console.commands_run - before - 1)  # the call itself is charged already
        return [True, None, None, nested] if ok else [False, f"command failed: {line}", None, nested]

    def _command(self, name: str, line: str | None, error: str | None) -> list:
        if name not in self.console.registry.names(qualified=True):
            return [False, f"unknown command {name!r}", None, 0]
        if error is not None:
            return [False, error, None, 0]
        return self._run_line(line)

    def _cvar_get(self, name: str) -> list:
        cvar = self.console.registry.cvars.get(name)
        return [None if cvar is None else cvar.value]

    def _cvar_set(self, name: str, text: str | None, error: str | None) -> list:
        cvar = self.console.registry.cvars.get(name)
        if cvar is None:
            return [False, f"unknown cvar {name!r}", None, 0]
        if error is not None:
            return [False, error, None, 0]
        try:
            cvar.parse(text)  # validate here so the script's error carries the cvar's own message
        except (CommandError, ValueError) as exc:
            return [False, str(exc), None, 0]
        return self._run_line(join([cvar.name, text]))

    def _print(self, text: str) -> list:
        refused = self._spend_output(len(text.encode("utf-8", "surrogatepass")), "printed line")
        if refused:
            return refused[:3]
        self.console.print(text)
        return [True, None, None]
