"""Mouse and keys of the 3D lights workspace, each edit turned into one console command.

Left press on a handle of the selection's gizmo drags the item along that axis (its moves are one undo step);
a left click elsewhere selects the light or object under the cursor, or nothing; a left drag on empty space,
or a right or middle drag, orbits; the wheel moves closer or away; Delete removes the selection.
"""
from __future__ import annotations

from PySide6.QtCore import Qt

from app.console.text import number
from app.model.camera3d import PITCH_LIMIT
from app.model.lights3d.scene import Lights3DCamera
from app.model.lights3d.gizmo import drag_along, hit_axis, pick_light, pick_object
from app.views.tool import ViewportTool

DEGREES_PER_PIXEL = 0.4
ZOOM_STEP = 1.15    # distance factor per wheel notch
CLICK_PX = 3        # a press that moves less than this is a click, not an orbit
MOVE_VERBS = {"object": "object.move", "light": "light3d.move"}
REMOVE_VERBS = {"object": "object.remove", "light": "light3d.remove"}


class Lights3DTool(ViewportTool):
    KEYS = ("Click an object or a light's marker to select it and drag a gizmo arrow to move it along that axis; "
            "drag elsewhere to orbit, the wheel zooms; Delete removes the selection.")

    def __init__(self, viewport, state, run) -> None:
        super().__init__(viewport, state, run)
        # ("axis", kind, index, origin, axis, press pixel) or ("orbit", press pixel, yaw, pitch, is a left click)
        self._drag = None

    def _size(self) -> tuple[int, int]:
        return self.viewport.width(), self.viewport.height()

    @staticmethod
    def _pixel(event) -> tuple[float, float]:
        p = event.position()
        return p.x(), p.y()

    def press(self, event) -> None:
        button = event.button()
        cam, pixel = self.state.camera, self._pixel(event)
        origin = self.state.selected_position()
        if button == Qt.MouseButton.LeftButton and origin is not None:
            axis = hit_axis(cam, self._size(), origin, *pixel)
            if axis is not None:
                self._drag = ("axis", *self.state.selection, origin, axis, pixel)
                return
        if button in (Qt.MouseButton.LeftButton, Qt.MouseButton.RightButton, Qt.MouseButton.MiddleButton):
            self._drag = ("orbit", pixel, cam.yaw, cam.pitch, button == Qt.MouseButton.LeftButton)

    def move(self, event) -> None:
        if self._drag is None:
            return
        pixel = self._pixel(event)
        if self._drag[0] == "axis":
            _, kind, index, origin, axis, start = self._drag
            moved = drag_along(self.state.camera, self._size(), origin, axis, start, pixel)
            if moved is not None and moved != self.state.item(kind, index).position:
                self.run(f"{MOVE_VERBS[kind]} {index} {' '.join(map(number, moved))}")
            return
        _, (x0, y0), yaw, pitch, click = self._drag
        dx, dy = pixel[0] - x0, pixel[1] - y0
        if click and abs(dx) + abs(dy) < CLICK_PX:
            return  # still a click: the view keeps still
        self._drag = ("orbit", (x0, y0), yaw, pitch, False)
        pitch = min(max(pitch + dy * DEGREES_PER_PIXEL, -PITCH_LIMIT), PITCH_LIMIT)
        self.run(f"view.orbit {yaw - dx * DEGREES_PER_PIXEL:.3f} {pitch:.3f}")

    def release(self, event) -> None:
        drag, self._drag = self._drag, None
        if drag is not None and drag[0] == "orbit" and drag[4]:
            self.run("lights3d.select " + self._under(*self._pixel(event)))

    def _under(self, px: float, py: float) -> str:
        """What a click at the pixel selects, as lights3d.select's words: a light's marker before an object."""
        scene, cam, size = self.state.scene, self.state.camera, self._size()
        light = pick_light(scene, cam, size, px, py)
        if light is not None:
            return f"light {light}"
        obj = pick_object(scene, cam, size, px, py)
        return "none" if obj is None else f"object {obj}"

    def wheel(self, event) -> None:
        cam = self.state.camera
        distance = cam.distance * ZOOM_STEP ** (-event.angleDelta().y() / 120)
        distance = min(max(distance, Lights3DCamera.MIN_DISTANCE), Lights3DCamera.MAX_DISTANCE)
        if distance != cam.distance:
            self.run(f"view.orbit {cam.yaw!r} {cam.pitch!r} {distance:.3f}")

    def tool_name(self) -> str:
        return "select, move (gizmo), orbit"

    def render_mode(self) -> str:
        s = self.settings()
        methods = ", ".join(dict.fromkeys(light.shadow for light in self.state.scene.lights)) or "no lights"
        debug = f", showing {s.debug}" if s.debug != "none" else ""
        return f"shadows: {methods} (maps {s.map_size} px, PCF {s.pcf}){debug}"

    def key(self, event) -> bool:
        """Delete (or Backspace) removes the selection; other keys go to their binds."""
        if event.key() not in (Qt.Key.Key_Delete, Qt.Key.Key_Backspace) or self.state.selection is None:
            return False
        kind, index = self.state.selection
        self.run(f"{REMOVE_VERBS[kind]} {index}")
        return True
