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
from dataclasses import dataclass
from pathlib import Path
from typing import Callable, Protocol

from app.console.console import Console, split_commands
from app.console.registry import CommandError
from app.io.atomic import write_text

MAGIC = "shadelab-demo"
VERSION = 1
# Bounds that keep every due time a host computes (start + time / speed) a number it can sleep until.
MAX_TIME = 86_400.0  # seconds: a day
MIN_SPEED, MAX_SPEED = 1 / 64, 64.0


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


def check(console: Console, events: list[Event], source: str = "demo") -> None:
    """Refuse commands the console does not know or whose arguments cannot bind, before any runs."""
    reg = console.registry
    created: set[str] = set()  # names a `set` or `alias` earlier in the demo will make
    for event in events:
        try:
            for words in split_commands(event.line):
                name, args = words[0], words[1:]
                if name in ("set", "seta", "alias") and args:
                    created.add(args[0])
                if name in created or any(name.endswith(s) for s in console.file_runners):
                    continue
                if name in reg.commands:
                    reg.commands[name].bind(args)
                elif name in reg.cvars:
                    if len(args) == 1:
                        reg.cvars[name].parse(args[0])
                elif name not in reg.aliases and name != "wait":
                    raise CommandError(f"unknown command {name!r}")
        except CommandError as exc:
            raise DemoError(f"{source}: at {event.time:.3f} s: {event.line!r}: {exc}") from None


def load(console: Console, path: Path) -> list[Event]:
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise DemoError(f"cannot read {path}: {exc}") from None
    events = parse(text, path.name)
    check(console, events, path.name)
    return events


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
        self.failed = 0
        self.start = clock.now()
        self.paused_at: float | None = None

    @property
    def done(self) -> bool:
        return self.index >= len(self.events)

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

    def update(self) -> None:
        """Run every command whose time has come."""
        if self.paused_at is not None:
            return
        elapsed = self.elapsed()
        while not self.done and self.events[self.index].time <= elapsed:
            line = self.events[self.index].line
            self.index += 1
            if not self.console.execute(line):
                self.failed += 1
        if self.done:
            self.on_done()
