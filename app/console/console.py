"""The console: parses command lines, runs them through the registry, keeps the log. No Qt."""
from __future__ import annotations

import shlex
import traceback
from dataclasses import dataclass
from typing import Callable

from app.console.registry import CommandError, Registry


@dataclass(frozen=True)
class LogLine:
    level: str  # "input", "info" or "error"
    text: str


def split_commands(line: str) -> list[list[str]]:
    """'a 1; b "x;y"' -> [['a', '1'], ['b', 'x;y']]: ';' separates commands outside quotes."""
    lexer = shlex.shlex(line, posix=True, punctuation_chars=";")
    lexer.whitespace_split = True
    lexer.commenters = ""
    commands: list[list[str]] = [[]]
    try:
        for token in lexer:
            if token and set(token) == {";"}:
                commands.append([])
            else:
                commands[-1].append(token)
    except ValueError as exc:  # unbalanced quotes
        raise CommandError(f"cannot parse {line!r}: {exc}") from None
    return [c for c in commands if c]


class Console:
    """Single door for state changes: every edit is a line executed here (DESIGN.md rule 1)."""

    def __init__(self, registry: Registry | None = None) -> None:
        self.registry = registry or Registry()
        self.log: list[LogLine] = []
        self.log_listeners: list[Callable[[LogLine], None]] = []
        self.executed_listeners: list[Callable[[str], None]] = []

    def print(self, text: str, level: str = "info") -> None:
        line = LogLine(level, text)
        self.log.append(line)
        for listener in self.log_listeners:
            listener(line)

    def error(self, text: str) -> None:
        self.print(text, "error")

    def execute(self, line: str, echo: bool = True) -> bool:
        """Run every command on the line; False if any failed (the later ones still run)."""
        line = line.strip()
        if not line or line.startswith("//"):
            return True
        if echo:
            self.print(f"] {line}", "input")
        try:
            commands = split_commands(line)
        except CommandError as exc:
            self.error(str(exc))
            return False
        ok = True
        for words in commands:
            ok = self._run(words) and ok
        return ok

    def _run(self, words: list[str]) -> bool:
        name, args = words[0], words[1:]
        reg = self.registry
        try:
            if name in reg.cvars:
                cvar = reg.cvars[name]
                if not args:
                    self.print(f'"{name}" is "{cvar.text()}" (default "{cvar.default}")')
                    return True
                if len(args) > 1:
                    raise CommandError(f"{name} takes one value; quote it if it has spaces")
                cvar.set(args[0])
            elif name in reg.commands:
                cmd = reg.commands[name]
                cmd.handler(*cmd.bind(args))
            else:
                raise CommandError(f"unknown command {name!r}")
        except (CommandError, ValueError) as exc:  # model validation errors are ValueErrors
            self.error(f"{name}: {exc}")
            return False
        except Exception:  # a bug in a handler must not take the editor down
            self.error(f"{name}: internal error\n{traceback.format_exc(limit=3)}")
            return False
        text = shlex.join(words)
        for listener in self.executed_listeners:
            listener(text)
        return True
