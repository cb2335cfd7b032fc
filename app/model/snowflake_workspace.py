"""The snowflake workspace's state: the Koch scene, its 2D view and its undo history."""
from __future__ import annotations

from typing import Callable

import numpy as np

from app.model.camera2d import Camera2D
from app.model.framing import in_view_2d, view_2d
from app.model.history import SnapshotHistory
from app.model.snowflake import SnowflakeScene, default_scene
from app.model.workspace import Workspace, short_hash


class SnowflakeWorkspace(Workspace):
    name = "snowflake"

    def __init__(self) -> None:
        self.scene: SnowflakeScene = default_scene()
        self.camera = Camera2D()
        self.history = SnapshotHistory(lambda: self.scene, self._restore)  # a frozen scene is its own snapshot

    def _restore(self, scene: SnowflakeScene) -> None:
        self.scene = scene

    def version(self) -> tuple:
        return self.scene, self.camera.key()

    def document_model(self) -> tuple[object, None]:
        return self.scene, None  # a new scene after each edit: the scene is its own version

    def digest(self) -> dict[str, str]:
        return {"snowflake": self.scene.digest(), "snowflake.camera": short_hash(*self.camera.key())}

    def _bounds(self) -> tuple[np.ndarray, np.ndarray] | None:
        flakes = self.scene.flakes
        if not flakes:
            return None
        centres = np.array([(f.x, f.y) for f in flakes])
        radii = np.array([f.radius for f in flakes])[:, None]  # a Koch flake stays within its triangle's circle
        return (centres - radii).min(0), (centres + radii).max(0)

    def frame_commands(self, aspect: float) -> list[str]:
        bounds = self._bounds()
        if bounds is None:
            return []
        cx, cy, height = view_2d(*bounds, aspect)
        return [f"snow.view {cx!r} {cy!r} {height!r}"]

    def load_frame_commands(self, aspect: float) -> list[str]:
        bounds = self._bounds()
        if bounds is None or in_view_2d(self.camera.key(), *bounds, aspect):
            return []
        return self.frame_commands(aspect)

    def opening_commands(self, snapshot: Callable[[], str]) -> list[str]:
        """Commands that rebuild the scene and its view exactly (floats as repr). The level goes first: each flake
        then adds to a count that never passes the segment budget at that level, as the whole scene keeps to it."""
        scene, cam = self.scene, self.camera
        return ["snow.clear", f"snow.level {scene.level!r}",
                *(f"snow.add {f.x!r} {f.y!r} {f.radius!r}" for f in scene.flakes),
                f"snow.view {cam.cx!r} {cam.cy!r} {cam.height!r}"]
