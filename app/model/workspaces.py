"""The model layer's mapping: every workspace, in switcher order, with the class of its state."""
from __future__ import annotations

from app.model.clouds.workspace import CloudsWorkspace
from app.model.lighting2d.workspace import Lighting2DWorkspace
from app.model.lights3d.workspace import Lights3DWorkspace
from app.model.snowflake_workspace import SnowflakeWorkspace
from app.model.volume.workspace import VolumeWorkspace
from app.model.workspace import WorkspaceInfo

WORKSPACES: list[WorkspaceInfo] = [
    WorkspaceInfo("lighting2d", "2D lighting", Lighting2DWorkspace),
    WorkspaceInfo("volume", "Volume", VolumeWorkspace),
    WorkspaceInfo("clouds", "Clouds", CloudsWorkspace),
    WorkspaceInfo("lights3d", "3D lights", Lights3DWorkspace),
    WorkspaceInfo("snowflake", "Snowflake", SnowflakeWorkspace),
]


def names() -> list[str]:
    return [w.name for w in WORKSPACES]


def workspace_title(name: str) -> str:
    """What people call the workspace ("2D lighting")."""
    return next(w.title for w in WORKSPACES if w.name == name)


DEFAULT_WORKSPACE = "snowflake"  # the editor opens on it
