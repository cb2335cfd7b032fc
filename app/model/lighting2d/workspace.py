"""The 2D lighting workspace's state: the scene, its view, what the editor draws over it, and undo."""
from __future__ import annotations

import dataclasses
from typing import Callable

import numpy as np

from app.model.camera2d import Camera2D
from app.model.framing import view_2d
from app.model.history import SnapshotHistory
from app.model.lighting2d.scene import Light, Scene2D
from app.model.lighting2d.index import SceneIndex, SceneIndexes
from app.model.workspace import Workspace, short_hash

HULL_KEYS = ("position", "origin", "rotation", "scale", "enabled")


def fmt(value) -> str:
    """A property value as command words (floats exact, booleans 0/1, nothing as `none`)."""
    if isinstance(value, bool):
        return str(int(value))
    if isinstance(value, (tuple, list)):
        return " ".join(fmt(v) for v in value) if value else "none"
    if value is None:
        return "none"
    return repr(value) if isinstance(value, float) else str(value)


def light_commands(index: int, light: Light) -> list[str]:
    """light.set lines that give light `index` every property of `light` (kind first)."""
    names = ("kind", "texture", *(f.name for f in dataclasses.fields(Light) if f.name not in ("kind", "texture")))
    return [f"light.set {index} {name} {fmt(getattr(light, name))}" for name in names
            if name != "texture" or light.texture]


class Lighting2DWorkspace(Workspace):
    name = "lighting2d"

    def __init__(self, scene: Scene2D | None = None) -> None:
        self.scene = scene or Scene2D()
        self.camera = Camera2D(*self.scene.view)
        # what the 2D view draws besides the scene (view state, not model: no command changes it)
        self.selection: tuple[str, int] | None = None
        self.pending: list[tuple[float, float]] = []  # the points of a hull being drawn
        self.pending_cursor: tuple[float, float] | None = None  # where the next point would go (the rubber band)
        # The scene is a frozen value: a snapshot is the scene itself, and restoring one puts it back.
        self.history = SnapshotHistory(lambda: self.scene, self._restore)
        self.indexes = SceneIndexes()

    def index(self) -> SceneIndex:
        """The current scene's index: the renderer's frame and the tool's clicks ask it alike."""
        return self.indexes.get(self.scene)

    def _restore(self, scene: Scene2D) -> None:
        self.scene = scene

    def replace(self, scene: Scene2D) -> None:
        """Put a loaded scene in place (its view becomes the camera's); the history stays, so loading can be
        undone."""
        self.scene = scene
        cam = self.camera
        cam.cx, cam.cy, cam.height = scene.view

    def version(self) -> tuple:
        return self.scene, self.camera.key()  # scenes compare by identity: an edit makes another

    def document_model(self) -> tuple[object, None]:
        return self.scene, None  # a new scene after each edit: the scene is its own version

    def digest(self) -> dict[str, str]:
        return {"lighting2d": self.scene.digest(), "lighting2d.camera": short_hash(*self.camera.key())}

    def load_frame_commands(self, aspect: float) -> list[str]:
        return []  # a 2D scene file keeps the view it was saved with

    def framed_view(self, aspect: float) -> tuple[float, float, float] | None:
        """(centre x, centre y, height) of the view that shows every hull and light whole; None: nothing to show."""
        scene = self.scene
        points = [hull.world() for hull in scene.hulls]
        points += [np.array(light.position) + light.radius * np.array([[-1.0, -1.0], [1.0, 1.0]])
                   for light in scene.lights]
        if not points:
            return None
        every = np.concatenate(points)
        return view_2d(every.min(0), every.max(0), aspect)

    def frame_commands(self, aspect: float) -> list[str]:
        view = self.framed_view(aspect)
        return [] if view is None else ["lighting.view {!r} {!r} {!r}".format(*view)]

    def opening_commands(self, snapshot: Callable[[], str]) -> list[str]:
        """Commands that rebuild the 2D scene and its view exactly (floats as repr)."""
        scene, cam = self.scene, self.camera
        lines = ["lighting.clear", f"ambient {fmt(scene.ambient)}", f"lighting.background {scene.background}",
                 f"lighting.normalmap {scene.normal_map or 'none'}"]
        for i, hull in enumerate(scene.hulls):
            lines.append(f"hull.add {fmt(tuple(hull.points.ravel().tolist()))}")
            lines += [f"hull.set {i} {key} {fmt(getattr(hull, key))}" for key in HULL_KEYS]
        for i, light in enumerate(scene.lights):
            texture = f" {light.texture}" if light.texture else ""
            lines.append(f"light.add {light.kind} {fmt(light.position)}{texture}")
            lines += light_commands(i, light)
        lines.append(f"lighting.view {cam.cx!r} {cam.cy!r} {cam.height!r}")
        return lines
