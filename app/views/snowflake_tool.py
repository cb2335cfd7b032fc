"""Mouse and keys of the snowflake workspace, each turned into a console command.

Left click on empty space adds a flake, left drag moves one, right click removes one,
middle or right drag pans, the wheel zooms about the cursor, w/s change the level.
"""
from __future__ import annotations

from PySide6.QtCore import Qt

from app.views.tool import ViewportTool

PICK_PIXELS = 12
ZOOM_STEP = 1.15


class SnowflakeTool(ViewportTool):
    KEYS = ("Click to add a flake, drag one to move it, right-click one to remove it; right or middle drag pans, "
            "the wheel zooms.")

    def __init__(self, viewport, state, run) -> None:
        super().__init__(viewport, state, run)
        self._drag: int | None = None  # flake being moved
        self._pan_from = None  # (pixel, camera centre) of a pan in progress
        self._moved = False

    def _world(self, event) -> tuple[float, float]:
        p = event.position()
        cam = self.state.camera
        return cam.to_world(p.x(), p.y(), self.viewport.width(), self.viewport.height())

    def _pick(self, x: float, y: float) -> int | None:
        slack = PICK_PIXELS * self.state.camera.world_per_pixel(self.viewport.height())
        return self.state.scene.pick(x, y, slack)

    def press(self, event) -> None:
        x, y = self._world(event)
        self._moved = False
        if event.button() == Qt.MouseButton.LeftButton:
            self._drag = self._pick(x, y)
            if self._drag is None:
                self.run(f"snow.add {x:.4f} {y:.4f}")
        elif event.button() in (Qt.MouseButton.MiddleButton, Qt.MouseButton.RightButton):
            cam = self.state.camera
            self._pan_from = (event.position(), (cam.cx, cam.cy))

    def move(self, event) -> None:
        if self._drag is not None:
            x, y = self._world(event)
            self._moved = True
            self.run(f"snow.move {self._drag} {x:.4f} {y:.4f}")
        elif self._pan_from is not None:
            start, (cx, cy) = self._pan_from
            d = event.position() - start
            if abs(d.x()) + abs(d.y()) < 3 and not self._moved:
                return
            self._moved = True
            cam = self.state.camera
            units = cam.world_per_pixel(self.viewport.height())
            self.run(f"snow.view {cx - d.x() * units:.5f} {cy + d.y() * units:.5f} {cam.height:.5f}")

    def release(self, event) -> None:
        if event.button() == Qt.MouseButton.RightButton and not self._moved:
            i = self._pick(*self._world(event))
            if i is not None:
                self.run(f"snow.remove {i}")
        self._drag = None
        self._pan_from = None

    def hover(self, event) -> str:
        x, y = self._world(event)
        flake = self._pick(x, y)
        return f"x {x:.3f}  y {y:.3f}" + (f"   flake {flake}" if flake is not None else "")

    def tool_name(self) -> str:
        return "add, move (left) and remove (right) flakes"

    def render_mode(self) -> str:
        return f"geometry shader, level {self.state.scene.level:g}"

    def wheel(self, event) -> None:
        """Zoom keeping the world point under the cursor in place."""
        cx, cy, h = self.state.camera.zoomed_about(*self._world(event), event.angleDelta().y() / 120,
                                                             ZOOM_STEP)
        self.run(f"snow.view {cx:.5f} {cy:.5f} {h:.5f}")
