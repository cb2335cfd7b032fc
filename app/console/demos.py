"""The demo commands: record, stop, play, pause, timedemo. The host drives playback with update()."""
from __future__ import annotations

import os
import time
from pathlib import Path
from typing import Callable

from app.console import demo, files
from app.console.command_set import CommandSet, Context
from app.console.console import Console
from app.console.budget import RunBudget
from app.console.registry import SCRIPTS, CommandError
from app.console.text import count
from app.io.atomic import name_max

DEMO_SUFFIX = ".demo"
COMMANDS = CommandSet(None)


def _demo_path(name: str) -> str:
    return name if name.endswith(DEMO_SUFFIX) else name + DEMO_SUFFIX


def snapshot_path(demo_path: Path, suffix: str) -> Path:
    """Where a recording keeps a scene too big for its lines, in the format of `suffix`: beside the demo."""
    return demo_path.with_suffix(".start" + suffix)


class Demos:
    """At most one recording and one playback at a time.

    `preamble(demo_path)` gives the commands that rebuild the current state (a recording starts with
    them; it may write files beside the demo);
    `frame()` draws one frame, for timedemo (None: the host draws nothing, only commands are timed).
    `snapshot_suffixes`: the formats of the snapshots a preamble may write (snapshot_path), whose names a
    recording's name must leave room for.
    """

    def __init__(self, console: Console, clock: demo.Clock, preamble: Callable[[Path], list[str]],
                 frame: Callable[[], None] | None = None) -> None:
        self.console, self.clock, self.preamble, self.frame = console, clock, preamble, frame
        self.recorder: demo.Recorder | None = None
        self.player: demo.Player | None = None
        self._home: Path | None = None  # the folder of the demo playing: its lines may read beside it
        self._budget: RunBudget | None = None  # the demo playing's, over all its updates
        self.arg_checks = demo.ArgChecks()  # the command modules add theirs; every demo is checked with them
        self.snapshot_suffixes: tuple[str, ...] = ()
        COMMANDS.register(console.registry, Context(console, self))

    @property
    def playing(self) -> bool:
        return self.player is not None

    def update(self) -> None:
        """Hosts call this often while playing (a Qt timer; the headless loop after sleeping). A demo's
        lines run untrusted: they read only beside it, in the user folder and the resources."""
        if self.player is not None:
            with self.console.untrusted("demo", self._home, self._budget):
                self.player.update()

    def _load(self, name: str) -> tuple[list[demo.Event], Path]:
        path = files.find(_demo_path(name), self.console)
        if path is None:
            raise CommandError(f"cannot find {_demo_path(name)}")
        try:
            with self.console.untrusted("demo", path.parent):  # its checks read what its lines would
                return demo.load(self.console, path, self.arg_checks), path.parent
        except demo.DemoError as exc:
            raise CommandError(str(exc)) from None

    def _finished(self, name: str) -> None:
        player, self.player = self.player, None
        if player is None:
            return
        if player.failed_at is None:
            self.console.print(f"demo finished: {count(len(player.events), 'command')}")
        else:
            self.console.error(f"{_demo_path(name)}: {demo.stopped(player.events, player.failed_at)}")

    def stop_all(self) -> None:
        """Stop playback and save a recording in progress (also on quit)."""
        if self.player is not None:
            self.player = None
            self.console.print("playback stopped")
        if self.recorder is not None:
            recorder, self.recorder = self.recorder, None
            try:
                self.console.print(f"recorded {count(recorder.stop(), 'command')} to {recorder.path}")
            except OSError as exc:  # a full disk, a folder gone since
                self.console.error(f"cannot write the demo {recorder.path}: {exc.strerror or exc}; the recording "
                                   "is lost")

    def _check_names(self, path: Path) -> None:
        """Refuse a recording whose file, or a snapshot beside it, would have a longer name than the folder's
        file system takes: found at `record`, not when the recording is saved at `stop`."""
        limit = name_max(path.parent)
        names = [path.name, *(snapshot_path(path, s).name for s in self.snapshot_suffixes)]
        longest = max(names, key=lambda n: len(os.fsencode(n)))
        size = len(os.fsencode(longest))
        if size > limit:
            suffix = longest.removeprefix(path.stem)
            room = limit - len(os.fsencode(suffix))
            raise CommandError(f"too long a name: with {suffix} (a snapshot it may write beside the demo) it has "
                               f"{size} bytes, more than the {limit} a file name may have here; give at most {room} "
                               f"bytes before {DEMO_SUFFIX}")


Ctx = Context[Demos]


def _demo_files(ctx: Ctx, prefix: str) -> list[str]:
    return files.complete(prefix, (DEMO_SUFFIX,))


@COMMANDS.command("record", "demo", "Record every command with its time into a .demo file (stop ends it)",
                  recorded=False, allow=SCRIPTS)
def record(ctx: Ctx, name: str) -> None:
    demos = ctx.state
    if demos.recorder is not None:
        raise CommandError(f"already recording {demos.recorder.path}; stop first")
    path = files.writable(ctx.console, _demo_path(name))
    demos._check_names(path)
    try:
        preamble = demos.preamble(path)
    except OSError as exc:
        raise CommandError(f"cannot write the demo's snapshot beside {path}: {exc.strerror or exc}") from None
    demos.recorder = demo.Recorder(ctx.console, demos.clock, path, preamble)
    ctx.console.print(f"recording to {path}")


@COMMANDS.command("stop", "", "Stop recording (the demo is saved) and playback", recorded=False, allow=SCRIPTS)
def stop(ctx: Ctx) -> None:
    if ctx.state.recorder is None and ctx.state.player is None:
        raise CommandError("nothing is recording or playing")
    ctx.state.stop_all()


@COMMANDS.command("play", "demo [speed:float]", "Replay a demo at its recorded times (speed 2 = twice as fast)",
                  recorded=False, completer=_demo_files, allow=SCRIPTS)
def play(ctx: Ctx, name: str, speed: float = 1.0) -> None:
    demos = ctx.state
    if demos.player is not None:
        raise CommandError("a demo is already playing; stop it first")
    demo.check_speed(speed)  # before reading the file: a refused speed needs no file
    events, demos._home = demos._load(name)
    demos._budget = RunBudget(ctx.console.budget_seconds)
    demos.player = demo.Player(ctx.console, demos.clock, events, speed, on_done=lambda: demos._finished(name))
    ctx.console.print(f"playing {_demo_path(name)}: {count(len(events), 'command')}, "
                      f"{events[-1].time / speed if events else 0:.1f} s")
    demos.update()


@COMMANDS.command("pause", "", "Pause or resume the demo playing", recorded=False, allow=SCRIPTS)
def pause(ctx: Ctx) -> None:
    player = ctx.state.player
    if player is None:
        raise CommandError("no demo is playing")
    if player.paused_at is None:
        player.pause()
        ctx.console.print("paused")
    else:
        player.resume()
        ctx.console.print("resumed")


@COMMANDS.command("timedemo", "demo", "Replay a demo as fast as possible, a frame per time step, and "
                  "print frames per second", recorded=False, completer=_demo_files, allow=SCRIPTS)
def timedemo(ctx: Ctx, name: str) -> None:
    console, frame = ctx.console, ctx.state.frame
    events, home = ctx.state._load(name)
    frames = 0
    start = time.perf_counter()
    budget = RunBudget(console.budget_seconds)  # one for the whole demo, as it plays
    for i, event in enumerate(events):
        with console.untrusted("demo", home, budget):
            ok = console.execute(event.line, echo=False)
        if not ok:  # it logged why; the rest relied on it
            raise CommandError(f"{_demo_path(name)}: {demo.stopped(events, i)}")
        if i + 1 == len(events) or events[i + 1].time != event.time:
            if frame is not None:
                frame()
            frames += 1
    seconds = max(time.perf_counter() - start, 1e-9)
    drawn = "" if frame is not None else " (commands only, nothing drawn)"
    console.print(f"timedemo {_demo_path(name)}: {frames} frames in {seconds:.3f} s = "
                  f"{frames / seconds:.1f} frames/s{drawn}")
