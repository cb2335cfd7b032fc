"""The editor's workspaces, in switcher order; one is current at a time."""
from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class WorkspaceInfo:
    name: str
    title: str
    built: bool = False  # False until its issue lands: the switcher shows it disabled


WORKSPACES = (
    WorkspaceInfo("lighting2d", "2D lighting", built=True),
    WorkspaceInfo("volume", "Volume", built=True),
    WorkspaceInfo("clouds", "Clouds"),
    WorkspaceInfo("lights3d", "3D lights"),
    WorkspaceInfo("snowflake", "Snowflake", built=True),
)
NAMES = tuple(w.name for w in WORKSPACES)
