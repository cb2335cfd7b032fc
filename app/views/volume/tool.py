"""Mouse of the volume workspace's 3D view: left drag orbits, the wheel moves closer; with the slice
picker open, hovering highlights the slice under the cursor and a click edits it."""
from __future__ import annotations

import numpy as np
from PySide6.QtCore import Qt

from app.console.text import number
from app.model.volume.render_modes import MODES
from app.model.volume.pick import first_hit
from app.model.volume.view import AXIS_INDEX
from app.views.tool import ViewportTool

DEGREES_PER_PIXEL = 0.4


class VolumeTool(ViewportTool):
    KEYS = ("Drag to orbit the volume, the wheel moves closer or away. Paint in the slice painter of the left "
            "dock: q/e previous and next slice, 1-4 brush size, c brush colour, u/r undo and redo, a/d/w/s pan, "
            "h/j shrink and grow the drawing.")

    def __init__(self, viewport, state, run) -> None:
        super().__init__(viewport, state, run)
        self.picker_axis: str | None = None  # set while the slice picker is open
        self.on_pick = lambda axis, index: None
        self._drag = None

    def voxel_under(self, event) -> tuple[int, int, int] | None:
        """The first voxel with alpha > 0 under the cursor, else where the ray enters the box (None: it misses)."""
        vp, view = self.viewport, self.state.view
        p = event.position()
        origin, direction = view.camera.ray(p.x(), p.y(), vp.width(), vp.height())
        return first_hit(self.state.volume.voxels, np.asarray(origin), np.asarray(direction))

    def slice_under(self, event) -> int | None:
        hit = self.voxel_under(event)
        return None if hit is None else hit[AXIS_INDEX[self.picker_axis]]

    def press(self, event) -> None:
        if event.button() != Qt.MouseButton.LeftButton:
            return
        if self.picker_axis is not None:
            index = self.slice_under(event)
            if index is not None:
                self.on_pick(self.picker_axis, index)
            return
        cam = self.state.view.camera
        self._drag = (event.position(), cam.yaw, cam.pitch)

    def move(self, event) -> None:
        if self._drag is not None:
            start, yaw, pitch = self._drag
            d = event.position() - start
            pitch = min(max(pitch + d.y() * DEGREES_PER_PIXEL, -85.0), 85.0)
            self.run(f"orbit {yaw - d.x() * DEGREES_PER_PIXEL:.2f} {pitch:.2f}")
        elif self.picker_axis is not None:
            index = self.slice_under(event)
            target = f"slice.highlight {self.picker_axis} {index}" if index is not None else "slice.highlight"
            if (self.picker_axis, index) != self.state.view.highlight:
                self.run(target)

    def release(self, _event) -> None:
        self._drag = None

    def wheel(self, event) -> None:
        self.run(f"orbit.step 0 0 {-0.25 * event.angleDelta().y() / 120:g}")

    def hover(self, event) -> str:
        hit = self.voxel_under(event)
        if hit is None:
            return ""
        r, g, b, a = self.state.volume.voxels.pick(*hit)
        where = f"voxel {hit[0]} {hit[1]} {hit[2]}"
        if not a:
            return f"{where} (the ray enters the box there, meeting no voxel)"
        value = self.state.volume.voxels.scalar_at(*hit)
        return f"{where}   rgba {r} {g} {b} {a}" + ("" if value is None else f"   value {number(value)}")

    def tool_name(self) -> str:
        return f"slice picker ({self.picker_axis})" if self.picker_axis else "orbit"

    def render_mode(self) -> str:
        settings = self.settings()
        if settings.scalar_mode != "colour" and self.state.volume.voxels.scalars is not None:
            return settings.scalar_mode + (f" {number(settings.iso)}" if settings.scalar_mode == "iso" else "")
        mode = self.state.view.mode
        return f"mode {mode}: {MODES[mode].name}"
