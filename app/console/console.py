"""The console: parses command lines, runs them through the registry, keeps the log. No Qt."""
from __future__ import annotations

import re
import traceback
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

from app.console.budget import DEFAULT_SECONDS, RunBudget
from app.console.quoting import join
from app.console.registry import SCRIPTS, CommandError, Registry, Reported, check_text

MAX_LOG = 10_000  # lines kept; the oldest go first...
MAX_LOG_CHARS = 4 * 2**20  # ...and at most this much text
MAX_LOG_LINE = 16 * 2**10  # a longer printed line is cut here: a text view lays out whole lines
MAX_DEPTH = 32  # aliases and exec'd files calling each other: stop a loop, not a deep script
MAX_LINE = 256 * 2**10  # characters in one console line (a long stroke is a few thousand)
MAX_WORD = 64 * 2**10  # characters in one argument
MAX_EXPANDED = 20_000  # commands one alias or config file may run, nested ones included
MAX_WAIT_CHAIN = 10_000  # `wait`s that follow one another (an alias that waits and calls itself)
MAX_WAITING = 1_000  # lines waiting for their frame at once


class RunawayError(CommandError):
    """An alias or config ran more commands than any honest one does: the whole line stops."""


@dataclass(frozen=True)
class Origin:
    """Who wrote the commands that run now, when it is not the user typing them (docs/architecture.md rule 6).
    `home`: the folder of the file that runs (a demo's snapshot beside it may be read)."""

    kind: str  # "lua", "demo", "config", "bind" or "alias"
    home: Path | None = None

    def who(self) -> str:
        return {"lua": "a Lua script", "demo": "a demo", "config": "a config file", "bind": "a key binding",
                "alias": "an alias"}[self.kind]


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


# One piece of a word, as POSIX shlex reads it: plain characters, a backslash escape, a single- or a
# double-quoted string, blanks between words, or a quote/backslash with nothing to close it.
_PIECE = re.compile(r"""([^ \t\r\n'"\\]+)|\\(.)|'([^']*)'|"((?:[^"\\]|\\.)*)"|([ \t\r\n]+)|(.)""", re.S)
_DOUBLE_QUOTED_ESCAPE = re.compile(r'\\(["\\])')  # inside "...", only \" and \\ are escapes
_PLAIN, _ESCAPED, _SINGLE, _DOUBLE, _BLANK, _STRAY = range(1, 7)


def split_words(text: str) -> list[str]:
    """shlex.split(text) in linear time (shlex grows each word a character at a time: quadratic)."""
    words: list[str] = []
    word: list[str] | None = None  # None between words; a quoted '' still makes an (empty) word
    for piece in _PIECE.finditer(text):
        kind, value = piece.lastindex, piece.group(piece.lastindex)
        if kind == _BLANK:
            if word is not None:
                words.append("".join(word))
            word = None
        elif kind == _STRAY:
            raise ValueError("No escaped character" if value == "\\" else "No closing quotation")
        else:
            word = [] if word is None else word
            word.append(_DOUBLE_QUOTED_ESCAPE.sub(r"\1", value) if kind == _DOUBLE else value)
    if word is not None:
        words.append("".join(word))
    return words


def split_commands(line: str) -> list[list[str]]:
    """'a 1; b "x;y"' -> [['a', '1'], ['b', 'x;y']]: ';' separates commands outside quotes."""
    line = strip_comment(line)
    cuts = [i for i, ch in _outside_quotes(line) if ch == ";"]
    parts = [line[a + 1:b] for a, b in zip([-1, *cuts], [*cuts, len(line)])]
    try:
        commands = [split_words(part) for part in parts]
    except ValueError as exc:  # unbalanced quotes
        raise CommandError(f"cannot parse {_shown(line)}: {exc}") from None
    for words in commands:
        long = next((w for w in words if len(w) > MAX_WORD), None)
        if long is not None:
            raise CommandError(f"an argument of {len(long)} characters (at most {MAX_WORD})")
    return [c for c in commands if c]


def _shown(line: str, limit: int = 200) -> str:
    """A line as an error message quotes it: cut short."""
    return repr(line) if len(line) <= limit else f"{line[:limit]!r}... ({len(line)} characters)"


class Console:
    """Single door for state changes: every edit is a line executed here (docs/architecture.md rule 1).

    Listeners: `log_listeners` see every log line; `executed_listeners` every command that succeeded;
    `record_listeners` only those that change state by themselves (what a demo must replay).
    """

    def __init__(self, registry: Registry | None = None) -> None:
        self.registry = registry or Registry()
        self.log: list[LogLine] = []
        self.printed = 0  # lines ever printed: a view shows the last `printed - seen` of the log
        self.clears = 0  # times `clear` emptied the log
        self._log_chars = 0
        self.log_listeners: list[Callable[[LogLine], None]] = []
        self.executed_listeners: list[Callable[[str], None]] = []
        self.record_listeners: list[Callable[[str], None]] = []
        self.quit_listeners: list[Callable[[], None]] = []
        self.file_runners: dict[str, Callable[[str], bool]] = {}  # ".lua" -> run that file
        self.batch_listeners: list[Callable[[bool], None]] = []  # True: a script starts, False: it ended
        self._batch_depth = 0
        # (frames left, commands, how many waits led here) after `wait`
        # (frames left, commands, how many waits led here, who wrote them, their run's budget) after `wait`: a
        # waited line runs later with the trust and the budget of the run that waited
        self.waiting: list[tuple[int, list[list[str]], int, tuple[Origin, ...], RunBudget | None]] = []
        self._wait_chain = 0  # the chain length of the waited-for line running now
        self._depth = 0
        self.origins: list[Origin] = []  # innermost last; empty while the user's own lines run
        self.budget: RunBudget | None = None  # the untrusted run's, while one runs
        self.budget_seconds = DEFAULT_SECONDS  # a new run's time budget (scr_budget, the user's alone)
        self._expanding = 0  # run_lines nesting, and the commands run since the outermost began
        self._expanded = 0
        self.commands_run = 0  # every command dispatched, nested ones too: what a script's budget is charged
        self._recorded_args: list[str] | None = None  # set by the command running now: see record_args
        # (kind "read" or "write", the name given) -> the path the command gets: the file policy (files.py)
        self.file_policy: Callable[[str, str], str] | None = None

    @property
    def trusted(self) -> bool:
        """The commands running now are the user's own (typed, from the command line or a dialog)."""
        return not self.origins

    @contextmanager
    def untrusted(self, kind: str, home: Path | None = None, budget: RunBudget | None = None):
        """Commands run inside come from a script, demo, config, bind or alias: files.py confines them, and the
        outermost one's `budget` (a new one unless given: a demo keeps its own over every update) bounds them."""
        with self._running_as(Origin(kind, home), budget):
            yield

    @contextmanager
    def _running_as(self, origin: Origin | None, budget: RunBudget | None = None):
        if origin is None:  # the editor's own lines
            yield
            return
        outermost = not self.origins
        if outermost:
            self.budget = budget or RunBudget(self.budget_seconds)
            self.budget.enter()
        self.origins.append(origin)
        try:
            yield
        finally:
            self.origins.pop()
            if outermost:
                self.budget.leave()
                self.budget = None

    @contextmanager
    def as_user(self):
        """Commands run inside are the user's own, whatever runs now: what the user chose in a dialog (a file,
        "save") that a key's bind opened. Only a host's dialogs use it; scripts cannot reach it."""
        outer, self.origins = self.origins, []
        try:
            yield
        finally:
            self.origins = outer

    def run_lines(self, lines, label: str, origin: Origin | None, on_failure=None) -> bool:
        """Run the lines an alias or a config file holds, as `origin`; False if any failed (each reported
        through on_failure(number, line), the rest still run). With everything they run in turn, at most
        MAX_EXPANDED commands: past that the outermost alias or config stops, with one message."""
        outermost = self._expanding == 0
        if outermost:
            self._expanded = 0
        self._expanding += 1
        ok = True
        try:  # origin None: the editor's own lines (its start configs), with the user's trust
            with self._running_as(origin):
                for number, line in enumerate(lines, start=1):
                    if not self.execute(line, echo=False):
                        ok = False
                        if on_failure is not None:
                            on_failure(number, line)
        except RunawayError as exc:
            if not outermost:
                raise
            self.error(f"{label}: {exc}")
            return False
        finally:
            self._expanding -= 1
        return ok

    def record_args(self, args: list[str]) -> None:
        """The command running now is recorded (and told to executed_listeners) with `args` for the typed ones:
        with the defaults it chose written out, so a replay does not depend on what it read to choose them."""
        self._recorded_args = list(args)

    def print(self, text: str, level: str = "info") -> None:
        if len(text) > MAX_LOG_LINE:
            text = f"{text[:MAX_LOG_LINE]}... ({len(text) - MAX_LOG_LINE} more characters not shown)"
        line = LogLine(level, text)
        if self.budget is not None:
            self.budget.printed += len(text)
        self.log.append(line)
        self.printed += 1
        self._log_chars += len(text)
        drop = 0
        while len(self.log) - drop > MAX_LOG or self._log_chars > MAX_LOG_CHARS:
            self._log_chars -= len(self.log[drop].text)
            drop += 1
        del self.log[:drop]
        for listener in self.log_listeners:
            listener(line)

    def error(self, text: str) -> None:
        self.print(text, "error")

    def clear(self) -> None:
        self.log.clear()
        self._log_chars = 0
        self.clears += 1

    def execute(self, line: str, echo: bool | None = True) -> bool:
        """Run every command on the line; False if any failed (the later ones still run).
        echo None: echo unless every command is a quiet one (what a drag sends many times a second)."""
        line = line.strip()
        if not strip_comment(line).strip():
            return True
        try:
            if len(line) > MAX_LINE:
                raise CommandError(f"a line of {len(line)} characters (at most {MAX_LINE})")
            check_text("a console line", line)
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
                    self.waiting.append((frames, commands[i + 1:], self._wait_chain + 1, tuple(self.origins),
                                         self.budget))
                return ok
            ok = self._run(words) and ok
        return ok

    def frame(self) -> bool:
        """Advance one frame: run the commands whose `wait` is over. Hosts call this per frame."""
        due, self.waiting = self.waiting, []
        ok = True
        for frames, commands, chain, origins, budget in due:
            if frames > 1:
                self.waiting.append((frames - 1, commands, chain, origins, budget))
                continue
            if budget is not None and budget.told:
                continue  # its run was stopped (and said so): what it left waiting goes too
            self._wait_chain = chain
            outer_origins, outer_budget = self.origins, self.budget
            self.origins, self.budget = list(origins), budget
            if budget is not None:
                budget.enter()
            try:
                ok = self._run_all(commands) and ok
            finally:
                if budget is not None:
                    budget.leave()
                self.origins, self.budget = outer_origins, outer_budget
                self._wait_chain = 0
        return ok

    def _wait_frames(self, words: list[str]) -> int | None:
        try:
            frames = int(words[1]) if len(words) > 1 else 1
            if not 1 <= frames <= 100_000 or len(words) > 2:
                raise ValueError
        except ValueError:
            self.error("wait: usage: wait [frames], frames within 1..100000")
            return None
        if self._wait_chain >= MAX_WAIT_CHAIN:
            return self._refuse_wait(f"{MAX_WAIT_CHAIN} waits in a row (an alias that waits and calls itself?); "
                                     "stopped")
        if len(self.waiting) >= MAX_WAITING:
            return self._refuse_wait(f"{MAX_WAITING} lines are waiting already; refused")
        return frames

    def _refuse_wait(self, why: str) -> None:
        """Say it once: an untrusted run that overflows the waits is stopped whole (what it left waiting goes)."""
        if self.budget is None:
            self.error(f"wait: {why}")
        elif not self.budget.told:
            self.budget.stopped, self.budget.told = f"wait: {why}; the run is stopped", True
            self.error(self.budget.stopped)
        return None

    def _run(self, words: list[str]) -> bool:
        name, args = words[0], words[1:]
        if self._depth >= MAX_DEPTH:
            message = f"nested more than {MAX_DEPTH} deep (an alias or exec that calls itself?)"
            if self._expanding:
                raise RunawayError(message)
            self.error(f"{name}: {message}")
            return False
        self._depth += 1
        outer, self._recorded_args = self._recorded_args, None
        try:
            if self._expanding:
                self._expanded += 1
                if self._expanded > MAX_EXPANDED:
                    raise RunawayError(f"more than {MAX_EXPANDED} commands from one alias or config "
                                       "(one that calls itself?); stopped")
            self.commands_run += 1
            self._within_budget()
            recorded = self._dispatch(name, args)
            if self._recorded_args is not None:
                words = [name, *self._recorded_args]
        except RunawayError:  # unwinds to the outermost alias or config (run_lines): one message, not thousands
            raise
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
            self._recorded_args = outer
        if recorded is None:
            return False
        text = join(words)
        for listener in self.executed_listeners:
            listener(text)
        if recorded:
            for listener in self.record_listeners:
                listener(text)
        return True

    def _within_budget(self) -> None:
        """Refuse every command of an untrusted run past its budget: an alias or config unwinds whole, a script
        or a demo sees its command fail and stops; one message says why."""
        why = None if self.budget is None else self.budget.exhausted()
        if why is None:
            return
        if self._expanding:
            raise RunawayError(why)
        if self.budget.told:
            raise Reported(why)
        self.budget.told = True
        raise CommandError(why)

    def _refuse(self, name: str) -> None:
        """A user-only command or cvar asked for by untrusted content: the one place capabilities are enforced."""
        if not self.trusted:
            raise CommandError(f"{self.origins[-1].who()} may not run {name}: it is the user's own "
                               "(type it yourself)")

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
            if cvar.allow != SCRIPTS:
                self._refuse(name)
            cvar.set(args[0], trusted=self.trusted)
            return True
        cmd = reg.commands.get(name)  # resolved in the current workspace
        if cmd is not None:
            if cmd.allow != SCRIPTS:
                self._refuse(name)
            values = cmd.bind(args)
            for i, param in enumerate(cmd.params[:len(values)]):
                if param.file and self.file_policy is not None:
                    values[i] = self.file_policy(param.file, values[i])
            cmd.handler(*values)
            return cmd.recorded
        if name in reg.aliases:
            if args:
                raise CommandError(f"alias {name} takes no arguments")
            ok = self.run_lines([reg.aliases[name]], f"alias {name}", Origin("alias"))
            return None if not ok else False
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
