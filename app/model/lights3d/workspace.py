"""The 3D lights workspace's state: the scene, the orbit camera, the selected item (the gizmo's) and undo."""
from __future__ import annotations

from dataclasses import astuple, replace
from typing import Callable

import numpy as np

from app.model.framing import box_in_view, orbit_distance
from app.model.history import SnapshotHistory
from app.model.lights3d.scene import Lights3DCamera, Lights3DError, Scene3D, default_scene
from app.model.workspace import Workspace, short_hash

ITEM_KINDS = ("object", "light")
Selection = tuple[str, int] | None  # ("object", i), ("light", i) or nothing


class Lights3DWorkspace(Workspace):
    name = "lights3d"

    def __init__(self) -> None:
        self.scene: Scene3D = default_scene()
        self.camera = Lights3DCamera()
        self.selection: Selection = None  # always names an item the scene holds
        # The scene is a frozen value, so the pair is a whole snapshot. The selection is no undo step of its own
        # but goes with the scene, so undoing a removal selects the item again.
        self.history = SnapshotHistory(lambda: (self.scene, self.selection), self._restore)

    def _restore(self, snapshot: tuple[Scene3D, Selection]) -> None:
        self.scene, self.selection = snapshot

    def items(self, kind: str) -> tuple:
        """The scene's objects or lights."""
        return self.scene.objects if kind == "object" else self.scene.lights

    def item(self, kind: str, index: int):
        """Object or light `index`; Lights3DError if the scene holds no such one."""
        items = self.items(kind)
        if not 0 <= index < len(items):
            raise Lights3DError(f"no {kind} {index} (there {'is' if len(items) == 1 else 'are'} {len(items)})")
        return items[index]

    def checked_selection(self, kind: str, index: int | None = None) -> Selection:
        """(kind, index) naming an object or light the scene holds, None for kind "none"; else Lights3DError."""
        if kind == "none" and index is None:
            return None
        if kind not in ITEM_KINDS or index is None:
            given = kind if index is None else f"{kind} {index}"
            raise Lights3DError(f"select object I, light I or none, got {given!r}")
        self.item(kind, index)
        return kind, index

    def selected_position(self) -> tuple[float, float, float] | None:
        """Where the selected item is (the gizmo's origin), or None."""
        if self.selection is None:
            return None
        return self.item(*self.selection).position

    def remove(self, kind: str, index: int) -> None:
        """Remove object or light `index`; the selection follows the items that stay (none if it was this one)."""
        self.scene = self.scene.remove_object(index) if kind == "object" else self.scene.remove_light(index)
        if self.selection is not None and self.selection[0] == kind:
            selected = self.selection[1]
            self.selection = None if selected == index else (kind, selected - (selected > index))

    def replace(self, scene: Scene3D) -> None:
        """Put a whole scene in place (loaded, or the default one): nothing is selected."""
        self.scene, self.selection = scene, None

    def camera_key(self) -> tuple:
        return astuple(self.camera)

    # ---- the workspace ------------------------------------------------------------------------------

    def version(self) -> tuple:
        return self.scene, self.camera_key(), self.selection

    def digest(self) -> dict[str, str]:
        return {"lights3d": short_hash(self.scene, self.selection), "lights3d.camera": short_hash(*self.camera_key())}

    def document_digest(self) -> str:
        return short_hash(self.scene)  # a selection is no change to the file

    def _bounds(self) -> tuple[np.ndarray, np.ndarray] | None:
        objects = [o for o in self.scene.objects if o.kind != "plane"] or self.scene.objects  # a ground is no subject
        if not objects:
            return None
        corners = np.array([corner for obj in objects for corner in obj.bounds])
        return corners.min(0), corners.max(0)

    def load_frame_commands(self, aspect: float) -> list[str]:
        bounds = self._bounds()
        if bounds is None or box_in_view(self.camera, *bounds, aspect):
            return []
        return self.frame_commands(aspect)

    def frame_commands(self, aspect: float) -> list[str]:
        bounds = self._bounds()
        if bounds is None:
            return []
        lo, hi = bounds
        x, y, z = (float(v) for v in (lo + hi) / 2)
        distance = orbit_distance(replace(self.camera, target=(x, y, z)), lo, hi, aspect)
        cam = self.camera
        return [f"view.target {x!r} {y!r} {z!r}", f"view.orbit {cam.yaw!r} {cam.pitch!r} {distance!r}"]

    def opening_commands(self, snapshot: Callable[[], str]) -> list[str]:
        """Commands that rebuild the scene (from a snapshot file beside the demo unless it is the default one),
        the camera and the selection."""
        if self.scene == default_scene():
            lines = ["lights3d.reset"]
        else:
            lines = [f"scene.load {snapshot()}"]
        cam, selected = self.camera, self.selection
        x, y, z = cam.target
        return lines + [f"view.target {x!r} {y!r} {z!r}", f"view.orbit {cam.yaw!r} {cam.pitch!r} {cam.distance!r}",
                        "lights3d.select " + ("none" if selected is None else f"{selected[0]} {selected[1]}")]
