"""Mouse of the clouds workspace, turned into commands: drag to look around, the wheel to climb or sink
(through the layer and above it). While the winds blow or a weather blends in, the clock runs."""
from __future__ import annotations

import time

from PySide6.QtCore import Qt, QTimer

from app.model.clouds.scene import FOV_Y_DEG, clamp_altitude
from app.views.tool import ViewportTool

CLIMB = 1.2        # altitude factor per wheel notch
TICK_MS = 33       # the clock's pace while the sky moves


class CloudsTool(ViewportTool):
    KEYS = "Drag to look around the sky; the wheel climbs or descends."

    def __init__(self, viewport, state, run) -> None:
        super().__init__(viewport, state, run)
        self._drag = None  # (start pixel, yaw, pitch)
        self._last_tick = None
        self.clock = QTimer(viewport, interval=TICK_MS, timeout=self._tick)
        self.clock.start()

    def press(self, event) -> None:
        if event.button() == Qt.MouseButton.LeftButton:
            self._drag = (event.position(), self.state.view.yaw, self.state.view.pitch)

    def move(self, event) -> None:
        if self._drag is None:
            return
        start, yaw, pitch = self._drag
        d = event.position() - start
        per_pixel = FOV_Y_DEG / max(self.viewport.height(), 1)  # the sky follows the mouse
        pitch = min(max(pitch + d.y() * per_pixel, -90.0), 90.0)
        self.run(f"camera.look {(yaw + d.x() * per_pixel) % 360:.3f} {pitch:.3f}")

    def release(self, event) -> None:
        self._drag = None

    def wheel(self, event) -> None:
        notches = event.angleDelta().y() / 120
        altitude = clamp_altitude(self.state.view.altitude * CLIMB ** notches)
        if altitude != self.state.view.altitude:
            self.run(f"camera.alt {altitude:.1f}")

    def tool_name(self) -> str:
        return "look around (drag), climb (wheel)"

    def render_mode(self) -> str:
        s = self.settings()
        return f"{s.integration} integration, {s.steps} steps, 1/{s.downsample} buffer"

    def _tick(self) -> None:
        """Real time passes for the wind and the weather blend, only while this workspace is in view."""
        now = time.monotonic()
        last, self._last_tick = self._last_tick, now
        if self.viewport.tool is not self or not self.viewport.isVisible() or not self.state.animating():
            return
        if last is not None:
            self.state.advance(min(now - last, 0.25))  # a stalled frame does not jump the sky
            self.viewport.update_full()
