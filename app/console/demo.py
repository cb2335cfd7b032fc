"""Demos: console commands with their time offsets, recorded and replayed (Tex3Dtrace's timed replay).

File format (plain text, editable):

    shadelab-demo 1
    # comments and blank lines are ignored
    0.000 snow.clear
    0.000 snow.add 0 0 0.5
    1.250 snow.level 3

The first line names the format and its version. Each other line is a time in seconds from the start
(never decreasing) and one console command. Recording starts with commands that rebuild the state the
editor was in, so a demo replayed in a fresh editor ends in the recorded state.
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable, Protocol

from app.console.console import Console, split_commands
from app.console.registry import Command, CommandError, Registry
from app.io.atomic import write_text
from app.io.regular_file import read_regular_bytes

MAGIC = "shadelab-demo"
VERSION = 1
# Bounds that keep every due time a host computes (start + time / speed) a number it can sleep until.
MAX_TIME = 86_400.0  # seconds: a day
SLICE_S = 0.05  # what one update may spend running due commands before the host gets the thread back
MIN_SPEED, MAX_SPEED = 1 / 64, 64.0
MAX_BYTES = 16 << 20  # an hour of drags recorded at 60 lines a second is about 20 MB: cut a longer one


class Clock(Protocol):
    def now(self) -> float: ...


class MonotonicClock:
    def now(self) -> float:
        return time.monotonic()


class VirtualClock:
    """A clock that moves only when told: tests and headless replays that must not sleep."""

    def __init__(self, start: float = 0.0) -> None:
        self.t = start

    def now(self) -> float:
        return self.t

    def advance(self, seconds: float) -> None:
        self.t += seconds


@dataclass(frozen=True)
class Event:
    time: float
    line: str


class DemoError(ValueError):
    pass


def parse(text: str, source: str = "demo") -> list[Event]:
    """Every line is checked before any runs, so a bad demo changes nothing."""
    lines = text.splitlines()
    if not lines or lines[0].split()[:1] != [MAGIC]:
        raise DemoError(f"{source}: not a demo (the first line must be '{MAGIC} {VERSION}')")
    header = lines[0].split()
    if len(header) != 2 or header[1] != str(VERSION):
        raise DemoError(f"{source}:1: unsupported demo version {' '.join(header[1:])!r} (this build plays {VERSION})")
    events: list[Event] = []
    for number, raw in enumerate(lines[1:], start=2):
        line = raw.strip()
        if not line or line.startswith("#"):
            continue
        stamp, _, command = line.partition(" ")
        try:
            t = float(stamp)
        except ValueError:
            raise DemoError(f"{source}:{number}: expected '<seconds> <command>', got {line!r}") from None
        if not 0 <= t <= MAX_TIME or (events and t < events[-1].time):
            raise DemoError(f"{source}:{number}: time {stamp} must be within 0..{MAX_TIME:g} s "
                            "and not before the line above")
        if not command.strip():
            raise DemoError(f"{source}:{number}: no command after the time")
        events.append(Event(t, command.strip()))
    return events


ArgCheck = Callable[..., object]
EVERY_MODEL = "*"


class ArgChecks:
    """Value checks a demo runs before any of its commands, beyond names and argument types.

    For a command (by its key: `workspace:name` if scoped) or a cvar name, a function of its bound
    arguments (for a cvar, of its parsed value) that raises CommandError or ValueError where running the
    command now would be refused, changing nothing: a voxel outside the volume, a slice index past its
    depth, a light that does not exist. The command modules register them (the registry's Command has no
    place for one yet); handlers call the same function first, so a check cannot drift from what the
    command accepts. A workspace's module registers through `scoped(workspace)`, as its commands are.

    A check that reads a model's current shape names that model (a workspace name). Once the demo has
    run a command that may reshape it (`new`, `light.add`, `undo`...: see `reshaped_by`), the checker
    cannot know the new shape and skips that model's checks for the rest of the demo; playback then
    stops at the first command that fails."""

    def __init__(self) -> None:
        self._checks: dict[str, tuple[ArgCheck, str | None]] = {}
        self._reshapers: dict[str, set[str]] = {}

    def add(self, name: str, model: str | None = None) -> Callable[[ArgCheck], ArgCheck]:
        """Decorator: `check` validates the arguments of global command (or cvar) `name`, reading `model`'s shape."""
        def register(check: ArgCheck) -> ArgCheck:
            self._checks[name] = (check, model)
            return check
        return register

    def scoped(self, scope: str) -> ScopedArgChecks:
        """The checks of workspace `scope`'s commands (registered through `registry.scoped(scope)`)."""
        return ScopedArgChecks(self, scope)

    def keys(self) -> list[str]:
        """The command keys and cvar names checked: each should name one the registry has (tests assert it,
        so a command moved into a workspace does not leave its check behind under the bare name)."""
        return sorted(self._checks)

    def reshaped_by(self, model: str, *names: str) -> None:
        """These commands may change `model`'s shape (sizes, counts), so later checks of it cannot be trusted.
        By bare name: every workspace's command of the name counts (more skipped checks, never a wrong one)."""
        for name in names:
            self._reshapers.setdefault(name, set()).add(model)

    def run(self, key: str, values: list, unknown: set[str]) -> None:
        """Check one command (`key`: the resolved Command's key, or a cvar's name) unless its model's shape
        is `unknown`; then add what it reshapes to `unknown`."""
        check, model = self._checks.get(key, (None, None))
        if check is not None and not {model, EVERY_MODEL} & unknown:
            check(*values)
        unknown |= self._reshapers.get(key.rpartition(":")[2], set())  # kept by bare name


class ScopedArgChecks:
    """`checks.scoped("volume")`: `add` registers under `volume:name`, the key of that workspace's command."""

    def __init__(self, checks: ArgChecks, scope: str) -> None:
        self._checks, self._scope = checks, scope

    def add(self, name: str, model: str | None = None) -> Callable[[ArgCheck], ArgCheck]:
        return self._checks.add(f"{self._scope}:{name}", model)

    def reshaped_by(self, model: str, *names: str) -> None:
        self._checks.reshaped_by(model, *names)


@dataclass
class _Seen:
    """What the checker knows of the state a demo builds as it goes."""
    scope: str | None  # the workspace the next line runs in (`workspace NAME` switches it)
    scope_known: bool = True  # False once a line ran commands unseen (an alias, a script): they may switch it
    cvars: set[str] = field(default_factory=set)  # made by the demo's own `set`: typed only when it runs
    aliases: set[str] = field(default_factory=set)  # made by the demo's own `alias`
    unknown: set[str] = field(default_factory=set)  # models whose shape an earlier command may have changed


def check(console: Console, events: list[Event], source: str = "demo", arg_checks: ArgChecks | None = None) -> None:
    """Refuse commands the console does not know, whose arguments cannot bind, or whose values it would
    refuse now (cvars by their type and range, commands by `arg_checks`), before any runs. Names resolve
    in the workspace the demo will be in at that line: the current one, until it switches."""
    checks, seen = arg_checks or ArgChecks(), _Seen(console.registry.scope)
    for event in events:
        try:
            for words in split_commands(event.line):
                _check_command(console, checks, words, seen)
        except (CommandError, ValueError) as exc:  # model refusals are ValueErrors
            raise DemoError(f"{source}: at {event.time:.3f} s: {event.line!r}: {exc}") from None


def _check_command(console: Console, checks: ArgChecks, words: list[str], seen: _Seen) -> None:
    reg = console.registry
    name, args = words[0], words[1:]
    if name in ("set", "seta") and len(args) == 2:
        if args[0] in reg.cvars:
            checks.run(args[0], [reg.cvars[args[0]].parse(args[1])], seen.unknown)
        else:
            seen.cvars.add(args[0])
    elif name == "alias" and args:
        seen.aliases.add(args[0])
    if name in seen.cvars:
        return
    if name in seen.aliases or name in reg.aliases or any(name.endswith(s) for s in console.file_runners):
        seen.unknown.add(EVERY_MODEL)  # it runs commands the checker does not see
        seen.scope_known = False
    elif (command := reg.resolve(name, seen.scope)) is not None:
        if not seen.scope_known and command.scope is not None and command.key != name:
            command = _any_binding(reg, command, args)
        checks.run(command.key, command.bind(args), seen.unknown)
        if not command.recorded:  # a query, or a runner of others (exec, lua): assume the worst
            seen.unknown.add(EVERY_MODEL)
            seen.scope_known = False
        elif command.key == "workspace" and args:
            seen.scope, seen.scope_known = args[0], True
    elif name in reg.cvars:
        if len(args) == 1:
            checks.run(name, [reg.cvars[name].parse(args[0])], seen.unknown)
    elif name != "wait":
        raise CommandError(f"unknown command {name!r}")


def _any_binding(reg: Registry, command: Command, args: list[str]) -> Command:
    """The workspace is unknown here, so a bare name may run any workspace's command of that name: one
    whose arguments bind (else `command`, whose bind then says why not). Its model checks are skipped."""
    for other in reg.commands.values():
        if other.name == command.name and other.scope is not None:
            try:
                other.bind(args)
                return other
            except CommandError:
                pass
    return command


def load(console: Console, path: Path, arg_checks: ArgChecks | None = None) -> list[Event]:
    try:
        text = read_regular_bytes(path, MAX_BYTES).decode("utf-8")
    except OSError as exc:
        raise DemoError(f"cannot read {path}: {exc.strerror}") from None
    except UnicodeDecodeError as exc:
        raise DemoError(f"cannot read {path}: not UTF-8 text (byte {exc.start})") from None
    events = parse(text, path.name)
    check(console, events, path.name, arg_checks)
    return events


def stopped(events: list[Event], index: int) -> str:
    """Why playback ended early: the command at `index` failed, so those after it never ran."""
    event, rest = events[index], len(events) - index - 1
    return (f"stopped at {event.time:.3f} s, command {index + 1} of {len(events)} ({event.line!r}) failed; "
            f"the {rest} after it did not run")


class Recorder:
    """Collects every state-changing command with its time; writes the file at stop()."""

    def __init__(self, console: Console, clock: Clock, path: Path, preamble: list[str]) -> None:
        """`preamble`: the commands that rebuild the state at the start (they run at 0 s)."""
        self.console, self.clock, self.path = console, clock, path
        self.start = clock.now()
        self.events = [Event(0.0, line) for line in preamble]
        console.record_listeners.append(self._record)

    def _record(self, line: str) -> None:
        self.events.append(Event(max(0.0, self.clock.now() - self.start), line))

    def stop(self) -> int:
        self.console.record_listeners.remove(self._record)
        body = "".join(f"{e.time:.3f} {e.line}\n" for e in self.events)
        write_text(self.path, f"{MAGIC} {VERSION}\n# recorded by Shadelab; <seconds> <command>\n{body}")
        return len(self.events)


def check_speed(speed: float) -> None:
    if not MIN_SPEED <= speed <= MAX_SPEED:
        raise DemoError(f"speed must be within 1/{1 / MIN_SPEED:g}..{MAX_SPEED:g}, got {speed:g}")


class Player:
    """Runs a demo's commands when the clock reaches their times (scaled by speed); pausable."""

    def __init__(self, console: Console, clock: Clock, events: list[Event], speed: float = 1.0,
                 on_done: Callable[[], None] = lambda: None) -> None:
        check_speed(speed)
        self.console, self.clock, self.events, self.speed = console, clock, events, speed
        self.on_done = on_done
        self.index = 0
        self.failed_at: int | None = None  # the command that failed and stopped playback
        self.start = clock.now()
        self.paused_at: float | None = None

    @property
    def done(self) -> bool:
        return self.index >= len(self.events) or self.failed_at is not None

    def elapsed(self) -> float:
        now = self.paused_at if self.paused_at is not None else self.clock.now()
        return (now - self.start) * self.speed

    def next_due(self) -> float | None:
        """Clock time at which the next command is due (None when done or paused)."""
        if self.done or self.paused_at is not None:
            return None
        return self.start + self.events[self.index].time / self.speed

    def pause(self) -> None:
        if self.paused_at is None:
            self.paused_at = self.clock.now()

    def resume(self) -> None:
        if self.paused_at is not None:
            self.start += self.clock.now() - self.paused_at
            self.paused_at = None

    def update(self, slice_s: float = SLICE_S) -> None:
        """Run the commands whose time has come, for `slice_s` at most: a host calls again after its other work,
        so many commands due at once never freeze it. Stop at one that fails, whose state the rest relied on."""
        if self.paused_at is not None:
            return
        elapsed = self.elapsed()
        until = time.monotonic() + slice_s
        while not self.done and self.events[self.index].time <= elapsed and time.monotonic() < until:
            if not self.console.execute(self.events[self.index].line):
                self.failed_at = self.index
            self.index += 1
        if self.done:
            self.on_done()
