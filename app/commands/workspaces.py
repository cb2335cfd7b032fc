"""The commands layer's mapping: each workspace's verbs, and how its renderer's settings are built from
the cvars and its view (a renderer never reads the console)."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable

from app.commands import clouds, lighting2d, lights3d, snowflake, volume
from app.console.console import Console
from app.console.demo import ArgChecks
from app.model.workspace import Workspace, WorkspaceMapping


def no_settings(console: Console, state: Workspace) -> None:
    return None


@dataclass(frozen=True)
class WorkspaceCommands:
    register: Callable[[Console, Any, ArgChecks], None]  # (console, the workspace's state, its demo checks)
    render_settings: Callable[[Console, Any], Any] = no_settings


COMMANDS: dict[str, WorkspaceCommands] = WorkspaceMapping("COMMANDS (app/commands/workspaces.py)", {
    "lighting2d": WorkspaceCommands(lighting2d.register, lighting2d.render_settings),
    "volume": WorkspaceCommands(volume.register, volume.render_settings),
    "clouds": WorkspaceCommands(clouds.register, clouds.render_settings),
    "lights3d": WorkspaceCommands(lights3d.register, lights3d.render_settings),
    "snowflake": WorkspaceCommands(snowflake.register),
})
