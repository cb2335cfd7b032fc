"""The child process that runs console scripts (app/console/lua_sandbox.py), from the console's side.

The console sends it a script to run, answers its requests (run a line, read or set a cvar, print)
and kills it when the run passes its time limit: a C function (``table.move`` over 2^40 indices),
the compiler (``a or a or ...``, quadratic) or the garbage collector (chains through weak-key
tables, quadratic) cannot be stopped from inside Lua, but a process can be. docs/console.md gives
the measurements behind this design.

Messages are JSON arrays, each framed by its length (4 bytes, little-endian); the console waits for
them with `select` (POSIX pipes). Workers are shared by every `LuaScripting` of this process and kept
between runs; one is started ahead of need (and right after a kill), so a run seldom waits for a
start-up (~25 ms).
"""
from __future__ import annotations

import atexit
import json
import os
import select
import struct
import subprocess
import sys
from pathlib import Path
from typing import Any

_HEADER = struct.Struct("<I")
_ROOT = Path(__file__).resolve().parents[2]  # the folder holding the `app` package
START_TIMEOUT = 60.0  # seconds a new worker may take to be ready (a loaded machine; the first import)


class Channel:
    """Framed JSON messages over a pair of pipe ends."""

    def __init__(self, read_fd: int, write_fd: int) -> None:
        self.read_fd = read_fd
        self.write_fd = write_fd

    def send(self, message: list) -> None:
        data = json.dumps(message).encode("ascii")  # ensure_ascii: lone surrogates travel escaped
        view = memoryview(_HEADER.pack(len(data)) + data)
        while view:
            view = view[os.write(self.write_fd, view):]

    def receive(self, timeout: float | None = None) -> list | None:
        """The next message; None if none began within `timeout` seconds. EOFError once the other side
        is gone."""
        if timeout is not None and not select.select([self.read_fd], [], [], max(0.0, timeout))[0]:
            return None
        (size,) = _HEADER.unpack(self._read(_HEADER.size))
        return json.loads(self._read(size))

    def _read(self, size: int) -> bytes:
        parts = []
        while size:
            part = os.read(self.read_fd, min(size, 1 << 20))
            if not part:
                raise EOFError("the other side closed the pipe")
            parts.append(part)
            size -= len(part)
        return b"".join(parts)


class Worker:
    """One child process running the sandbox."""

    def __init__(self) -> None:
        # -m from the folder holding `app`: the child imports lupa and the sandbox, never Qt.
        self.process = subprocess.Popen([sys.executable, "-m", "app.console.lua_sandbox"], cwd=_ROOT,
                                        stdin=subprocess.PIPE, stdout=subprocess.PIPE)
        self.channel = Channel(self.process.stdout.fileno(), self.process.stdin.fileno())
        self.ready = False

    def wait_ready(self) -> str | None:
        """None once the child is ready; else why it is not (it is killed then)."""
        if not self.ready:
            try:
                message = self.channel.receive(START_TIMEOUT)
            except (EOFError, OSError, ValueError):
                message = ["failed"]
            if message != ["ready"]:
                self.kill()
                return "cannot start the Lua interpreter" + ("" if message else " (it did not answer)")
            self.ready = True
        return None

    def alive(self) -> bool:
        return self.process.poll() is None

    def kill(self) -> None:
        if self.alive():
            self.process.kill()
        self.process.wait()
        for pipe in (self.process.stdin, self.process.stdout):
            try:
                pipe.close()
            except OSError:  # a write the child never read: nothing to flush to a dead process
                pass

    def exit_status(self) -> Any:
        return self.process.poll()


_idle: list[Worker] = []


def take() -> Worker:
    """A worker for one run: an idle one, else a new one (maybe still starting)."""
    while _idle:
        worker = _idle.pop()
        if worker.alive():
            return worker
        worker.kill()
    return Worker()


def give_back(worker: Worker) -> None:
    """After a run: keep a live worker for the next run; replace a dead one."""
    if worker.alive() and not _idle:
        _idle.append(worker)
    else:
        worker.kill()
        prepare()


def prepare() -> None:
    """Start a worker ahead of need, so the next run does not wait for one."""
    if not _idle:
        _idle.append(Worker())


@atexit.register
def _close_idle() -> None:
    while _idle:
        _idle.pop().kill()
