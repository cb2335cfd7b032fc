"""One budget per untrusted run (docs/architecture.md rule 6): a demo, a config or a script, with everything it runs
inside it (scripts, aliases, waited lines), spends one allowance of time and of console output. Time counts while
its commands run, not while a demo waits for its next event; past the allowance every command of the run is
refused, so the run stops with one message."""
from __future__ import annotations

import time

DEFAULT_SECONDS = 30.0  # scr_budget's default
OUTPUT_CHARS = 4 << 20  # what one run may print to the console log


class RunBudget:
    def __init__(self, seconds: float = DEFAULT_SECONDS, output_chars: int = OUTPUT_CHARS) -> None:
        self.seconds, self.output_chars = seconds, output_chars
        self.spent = 0.0   # seconds spent in the run's commands, over every time it was entered
        self.printed = 0   # characters it printed
        self._entered: float | None = None  # when the run was entered this time, while it runs
        self.told = False  # the stop was said once: the commands refused after it stay quiet
        self.stopped: str | None = None  # why the run was stopped for good, whatever its time and output

    def enter(self) -> None:
        self._entered = time.monotonic()

    def leave(self) -> None:
        if self._entered is not None:
            self.spent += time.monotonic() - self._entered
            self._entered = None

    def used(self) -> float:
        return self.spent + (0.0 if self._entered is None else time.monotonic() - self._entered)

    def remaining(self) -> float:
        return max(0.0, self.seconds - self.used())

    def exhausted(self) -> str | None:
        """Why the run must stop, or None."""
        if self.stopped is not None:
            return self.stopped
        if self.used() > self.seconds:
            return f"the run's time budget of {self.seconds:g} s is spent (scr_budget); stopped"
        if self.printed > self.output_chars:
            return f"the run printed more than {self.output_chars >> 20} MiB; stopped"
        return None
