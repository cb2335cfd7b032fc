"""The editor's state without any window: the console and the workspaces, none of them by name.

Both hosts drive one of these: the Qt main window and the headless `shadelab render/exec/bench`.
"""
from __future__ import annotations

from pathlib import Path
from typing import Any, Callable

from app.commands import core
from app.commands.workspaces import COMMANDS
from app.console import builtins, files
from app.console.binds import Binds
from app.console.console import Console
from app.console.demo import Clock, MonotonicClock
from app.console.demos import Demos, snapshot_path
from app.console.quoting import quote
from app.console.registry import SCRIPTS
from app.model.workspace import Workspace, Workspaces
from app.model.workspaces import DEFAULT_WORKSPACE, WORKSPACES

START_CONFIGS = ("default.cfg", "shadelab.cfg")


class Editor:
    """`clock` times demos (a virtual one in tests); `frame` draws one frame for timedemo."""

    def __init__(self, clock: Clock | None = None, frame: Callable[[], None] | None = None,
                 configs: bool = True) -> None:
        self.console = Console()
        self.binds = Binds()
        self.lua = builtins.register(self.console, self.binds)
        self.workspaces = Workspaces([info.state() for info in WORKSPACES], DEFAULT_WORKSPACE)
        self.demos = Demos(self.console, clock or MonotonicClock(), self.opening_commands, frame)
        self.documents = core.register(self.console, self.workspaces)
        for state in self.workspaces:
            checks = self.demos.arg_checks.scoped(state.name)
            COMMANDS[state.name].register(self.console, state, checks)
            checks.reshaped_by(state.name, *core.REPLACING)  # a demo's checks cannot know what a file holds
        self.documents.track()
        self.demos.snapshot_suffixes = self.documents.written_suffixes()
        if configs:
            self.run_start_configs()
        self.documents.forget_changes()  # the scenes an editor starts on are no one's unsaved work

    def run_start_configs(self) -> None:
        """default.cfg and shadelab.cfg from the resources, then the user's archived config."""
        for name in START_CONFIGS:
            builtins.exec_file(self.console, name, trusted=True)
        if files.user_config().is_file():
            builtins.exec_file(self.console, str(files.user_config()), trusted=True)

    def execute(self, line: str) -> bool:
        return self.console.execute(line)

    @property
    def workspace(self) -> str:
        """The current workspace's name (the `workspace` command changes it)."""
        return self.workspaces.name

    @property
    def current(self) -> Workspace:
        return self.workspaces.current

    def render_settings(self) -> Any:
        """The current workspace's renderer settings, from the cvars and its view."""
        return COMMANDS[self.workspace].render_settings(self.console, self.current)

    def frame_budget_ms(self) -> float:
        """How long a frame may take while the user drags, orbits or plays (r_frameBudget)."""
        return self.console.registry.cvars["r_frameBudget"].value

    def version(self) -> tuple:
        """Changes whenever anything a host draws changed: redraw when it differs."""
        return self.workspace, self.current.version(), self.console.registry.cvar_changes

    def digest(self) -> dict[str, str]:
        return core.digest(self.console, self.workspaces)

    def opening_commands(self, demo_path: Path) -> list[str]:
        """Commands that rebuild the current state from any other: a demo's opening lines. Each workspace's
        block runs in that workspace (its command names are scoped to it); big state goes into a snapshot
        file beside the demo."""
        lines = []
        for state in self.workspaces:
            lines.append(f"workspace {state.name}")
            lines += state.opening_commands(lambda suffix=None, state=state: self._snapshot(state, demo_path, suffix))
        # the settings a demo may set; the user's own (scr_budget) are not the demo's to carry
        lines += [c.assignment() for _name, c in sorted(self.console.registry.cvars.items()) if c.allow == SCRIPTS]
        lines.append(f"workspace {self.workspace}")
        return lines

    @staticmethod
    def _snapshot(state: Workspace, demo_path: Path, suffix: str | None = None) -> str:
        path = snapshot_path(demo_path, suffix or state.files.suffixes[0])
        state.files.save(str(path))
        return quote(str(path.resolve()))
