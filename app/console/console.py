"""The console: parses command lines, runs them through the registry, keeps the log. No Qt."""
from __future__ import annotations

import shlex
import traceback
from contextlib import contextmanager
from dataclasses import dataclass
from typing import Callable

from app.console.registry import CommandError, Registry, Reported

MAX_LOG = 10_000  # lines kept; the oldest go first
MAX_DEPTH = 32  # aliases and exec'd files calling each other: stop a loop, not a deep script


@dataclass(frozen=True)
class LogLine:
    level: str  # "input", "info" or "error"
    text: str


def _outside_quotes(line: str):
    """Yield (index, char) for the characters of `line` that stand outside quotes."""
    quote, escaped = None, False
    for i, ch in enumerate(line):
        if escaped:  # a backslash-escaped character, as shlex reads it
            escaped = False
        elif ch == "\\" and quote != "'":
            escaped = True
        elif quote:
            quote = None if ch == quote else quote
        elif ch in "\"'":
            quote = ch
        else:
            yield i, ch


def strip_comment(line: str) -> str:
    """Drop a `//` comment that starts outside quotes, as Quake configs write them."""
    for i, _ch in _outside_quotes(line):
        if line.startswith("//", i):
            return line[:i]
    return line


def split_commands(line: str) -> list[list[str]]:
    """'a 1; b "x;y"' -> [['a', '1'], ['b', 'x;y']]: ';' separates commands outside quotes."""
    line = strip_comment(line)
    cuts = [i for i, ch in _outside_quotes(line) if ch == ";"]
    parts = [line[a + 1:b] for a, b in zip([-1, *cuts], [*cuts, len(line)])]
    try:
        commands = [shlex.split(part) for part in parts]
    except ValueError as exc:  # unbalanced quotes
        raise CommandError(f"cannot parse {line!r}: {exc}") from None
    return [c for c in commands if c]


class Console:
    """Single door for state changes: every edit is a line executed here (DESIGN.md rule 1).

    Listeners: `log_listeners` see every log line; `executed_listeners` every command that succeeded;
    `record_listeners` only those that change state by themselves (what a demo must replay).
    """

    def __init__(self, registry: Registry | None = None) -> None:
        self.registry = registry or Registry()
        self.log: list[LogLine] = []
        self.log_listeners: list[Callable[[LogLine], None]] = []
        self.executed_listeners: list[Callable[[str], None]] = []
        self.record_listeners: list[Callable[[str], None]] = []
        self.quit_listeners: list[Callable[[], None]] = []
        self.file_runners: dict[str, Callable[[str], bool]] = {}  # ".lua" -> run that file
        self.batch_listeners: list[Callable[[bool], None]] = []  # True: a script starts, False: it ended
        self._batch_depth = 0
        self.waiting: list[tuple[int, list[list[str]]]] = []  # (frames left, commands) after `wait`
        self._depth = 0

    def print(self, text: str, level: str = "info") -> None:
        line = LogLine(level, text)
        self.log.append(line)
        if len(self.log) > MAX_LOG:
            del self.log[: len(self.log) - MAX_LOG]
        for listener in self.log_listeners:
            listener(line)

    def error(self, text: str) -> None:
        self.print(text, "error")

    def clear(self) -> None:
        self.log.clear()

    def execute(self, line: str, echo: bool | None = True) -> bool:
        """Run every command on the line; False if any failed (the later ones still run).
        echo None: echo unless every command is a quiet one (what a drag sends many times a second)."""
        line = line.strip()
        if not strip_comment(line).strip():
            return True
        try:
            commands = split_commands(line)
        except CommandError as exc:
            if echo:
                self.print(f"] {line}", "input")
            self.error(str(exc))
            return False
        if echo or (echo is None and not all(self._quiet(words[0]) for words in commands)):
            self.print(f"] {line}", "input")
        return self._run_all(commands)

    def _quiet(self, name: str) -> bool:
        cmd = self.registry.commands.get(name)
        return cmd is not None and cmd.quiet

    def _run_all(self, commands: list[list[str]]) -> bool:
        ok = True
        for i, words in enumerate(commands):
            if words[0] == "wait":  # the rest of the line runs `frames` frames later
                frames = self._wait_frames(words)
                if frames is None:
                    return False
                if commands[i + 1:]:
                    self.waiting.append((frames, commands[i + 1:]))
                return ok
            ok = self._run(words) and ok
        return ok

    def frame(self) -> bool:
        """Advance one frame: run the commands whose `wait` is over. Hosts call this per frame."""
        due, self.waiting = self.waiting, []
        ok = True
        for frames, commands in due:
            if frames <= 1:
                ok = self._run_all(commands) and ok
            else:
                self.waiting.append((frames - 1, commands))
        return ok

    def _wait_frames(self, words: list[str]) -> int | None:
        try:
            frames = int(words[1]) if len(words) > 1 else 1
            if not 1 <= frames <= 100_000 or len(words) > 2:
                raise ValueError
        except ValueError:
            self.error("wait: usage: wait [frames], frames within 1..100000")
            return None
        return frames

    def _run(self, words: list[str]) -> bool:
        name, args = words[0], words[1:]
        if self._depth >= MAX_DEPTH:
            self.error(f"{name}: nested more than {MAX_DEPTH} deep (an alias or exec that calls itself?)")
            return False
        self._depth += 1
        try:
            recorded = self._dispatch(name, args)
        except Reported:
            return False
        except (CommandError, ValueError) as exc:  # model validation errors are ValueErrors
            self.error(f"{name}: {exc}")
            return False
        except Exception:  # a bug in a handler must not take the editor down
            self.error(f"{name}: internal error\n{traceback.format_exc(limit=3)}")
            return False
        finally:
            self._depth -= 1
        if recorded is None:
            return False
        text = shlex.join(words)
        for listener in self.executed_listeners:
            listener(text)
        if recorded:
            for listener in self.record_listeners:
                listener(text)
        return True

    def _dispatch(self, name: str, args: list[str]) -> bool | None:
        """Run one command; True if it should be recorded, None if it failed (already logged)."""
        reg = self.registry
        if name in reg.cvars:
            cvar = reg.cvars[name]
            if not args:
                self.print(f'"{name}" is "{cvar.text()}" (default "{cvar.default}")')
                return False
            if len(args) > 1:
                raise CommandError(f"{name} takes one value; quote it if it has spaces")
            cvar.set(args[0])
            return True
        if name in reg.commands:
            cmd = reg.commands[name]
            cmd.handler(*cmd.bind(args))
            return cmd.recorded
        if name in reg.aliases:
            if args:
                raise CommandError(f"alias {name} takes no arguments")
            return None if not self.execute(reg.aliases[name], echo=False) else False
        runner = next((r for suffix, r in self.file_runners.items() if name.endswith(suffix)), None)
        if runner is not None and not args:
            return None if not runner(name) else False
        raise CommandError(f"unknown command {name!r}")

    @contextmanager
    def batch(self):
        """Commands run inside form one batch (a script): models may undo them as one step."""
        self._batch_depth += 1
        if self._batch_depth == 1:
            for listener in self.batch_listeners:
                listener(True)
        try:
            yield
        finally:
            self._batch_depth -= 1
            if self._batch_depth == 0:
                for listener in self.batch_listeners:
                    listener(False)

    def request_quit(self) -> None:
        for listener in self.quit_listeners:
            listener()
