"""Mouse and keys of the 2D lighting workspace, each edit turned into one console command.

Select mode: click a light (its icon) or a hull to select it; drag it to move it; drag the selection's round
handle to rotate it, its square corner handle to scale it, a hull's vertex handles to move vertices;
double-click a hull's edge to insert a vertex; right-click a vertex to delete it; Delete removes the
selection. Empty space: left drag pans; right/middle drag pans too; the wheel zooms about the cursor.
Draw mode (key h or the panel's button): each click adds a point, clicking the first point, a
double-click, Enter or a right click closes the hull (one `hull.draw`: its origin at its centroid, where its
handles are), Escape cancels.
"""
from __future__ import annotations

import math

import numpy as np
from PySide6.QtCore import Qt

from app.gl.lighting2d.overlay import HANDLE_PX, ICON_PX, handles
from app.views.tool import ViewportTool

PICK_PX = 8.0
ZOOM_STEP = 1.15


def _local(hull, x: float, y: float) -> tuple[float, float] | None:
    """World point -> the hull's local coordinates (None when a scale of 0 makes it undefined)."""
    sx, sy = hull.scale
    if sx == 0 or sy == 0:
        return None
    c, s = math.cos(hull.rotation), math.sin(hull.rotation)
    dx, dy = x - hull.position[0], y - hull.position[1]
    return (c * dx + s * dy) / sx + hull.origin[0], (-s * dx + c * dy) / sy + hull.origin[1]


def _segment_distance(p, a, b) -> float:
    ab = b - a
    t = np.clip(np.dot(p - a, ab) / max(np.dot(ab, ab), 1e-300), 0.0, 1.0)
    return float(np.linalg.norm(p - (a + t * ab)))


class Lighting2DTool(ViewportTool):
    KEYS = ("Click a light or hull to select it, drag it to move it; the round handle rotates, the square one scales, "
            "a hull's vertex handles move vertices (double-click an edge to insert one, right-click one to delete it). "
            "h draws a new hull point by point (Enter ends it, Escape drops it); Delete removes the selection. "
            "Drag empty space to pan; the wheel zooms.")

    def __init__(self, viewport, state, run) -> None:
        super().__init__(viewport, state, run)
        self.drawing = False
        self._drag = None      # (kind, data) of the gesture in progress
        self._moved = False

    @property
    def editor(self):
        return self.viewport.editor

    @property
    def selection(self):
        return self.state.selection

    def select(self, selection) -> None:
        self.state.selection = selection
        self.viewport.selection_changed()

    # ---- geometry --------------------------------------------------------------------------------

    def _unit(self) -> float:
        return self.state.camera.world_per_pixel(self.viewport.height())

    def _world(self, event) -> tuple[float, float]:
        p = event.position()
        cam = self.state.camera
        x, y = cam.to_world(p.x(), p.y(), self.viewport.width(), self.viewport.height())
        if self.editor.console.registry.cvars["r_flipY"].value:
            y = 2 * cam.cy - y
        return x, y

    def _hit_handle(self, x: float, y: float):
        """The selection's handle under the cursor: ('rotate'|'scale'|'centre', None) or ('vertex', k)."""
        sel = self.selection
        scene = self.state.scene
        if sel is None or not 0 <= sel[1] < len(scene.lights if sel[0] == "light" else scene.hulls):
            return None
        h = handles(self.state.scene, sel, self._unit())
        reach = (HANDLE_PX + 3) * self._unit()
        p = np.array([x, y])
        for name in ("rotate", "scale"):
            if np.linalg.norm(p - h[name]) <= reach:
                return name, None
        if "vertices" in h:
            d = np.linalg.norm(h["vertices"] - p, axis=1)
            if d.min() <= reach:
                return "vertex", int(d.argmin())
        return None

    def _pick(self, x: float, y: float):
        scene = self.state.scene
        for i in reversed(range(len(scene.lights))):
            light = scene.lights[i]
            if math.dist((x, y), light.position) <= max(light.radius, ICON_PX * self._unit()):  # or its icon
                return "light", i
        # the workspace's index (the frame's too): a click tests only the hulls whose bounds hold it
        for i in reversed(self.state.index().outlines_in(x, y, x, y)):  # ascending: the topmost last
            hull = scene.hulls[i]
            if len(hull.points) >= 3 and hull.contains(x, y):
                return "hull", i
        return None

    # ---- events ------------------------------------------------------------------------------------

    def press(self, event) -> None:
        x, y = self._world(event)
        self._moved = False
        button = event.button()
        if self.drawing:
            if button == Qt.MouseButton.LeftButton:
                pending = self.state.pending
                if len(pending) >= 3 and math.dist(pending[0], (x, y)) <= PICK_PX * self._unit():
                    self.finish_hull()
                else:
                    pending.append((x, y))
                    self.viewport.selection_changed()
            elif button == Qt.MouseButton.RightButton:
                self.finish_hull()
            return
        if button in (Qt.MouseButton.MiddleButton, Qt.MouseButton.RightButton):
            if button == Qt.MouseButton.RightButton and self._delete_vertex(x, y):
                return
            self._start_pan(event)
            return
        if button != Qt.MouseButton.LeftButton:
            return
        handle = self._hit_handle(x, y)
        if handle is not None:
            self._start_handle(handle, x, y)
            return
        picked = self._pick(x, y)
        if picked is not None:
            self.select(picked)
            kind, i = picked
            item = self.state.scene.lights[i] if kind == "light" else self.state.scene.hulls[i]
            self._drag = ("move", (kind, i, item.position, (x, y)))
            return
        self.select(None)
        self._start_pan(event)

    def _start_pan(self, event) -> None:
        cam = self.state.camera
        self._drag = ("pan", (event.position(), (cam.cx, cam.cy)))

    def _start_handle(self, handle, x, y) -> None:
        kind, i = self.selection
        item = self.state.scene.lights[i] if kind == "light" else self.state.scene.hulls[i]
        centre = np.array(item.position)
        start = np.array([x, y]) - centre
        name, vertex = handle
        if name == "rotate":
            self._drag = ("rotate", (kind, i, item.rotation, math.atan2(start[1], start[0])))
        elif name == "scale":
            self._drag = ("scale", (kind, i, item.scale, max(np.linalg.norm(start), 1e-9)))
        else:
            self._drag = ("vertex", (i, vertex))

    def move(self, event) -> None:
        if self.drawing:  # the rubber band from the last point to the cursor
            self.state.pending_cursor = self._world(event)
            if self.state.pending:
                self.viewport.selection_changed()
            return
        if self._drag is None:
            return
        x, y = self._world(event)
        what, data = self._drag
        if what == "pan":
            start, (cx, cy) = data
            d = event.position() - start
            if abs(d.x()) + abs(d.y()) < 3 and not self._moved:
                return
            self._moved = True
            cam = self.state.camera
            units = self._unit()
            dy = -d.y() if self.editor.console.registry.cvars["r_flipY"].value else d.y()
            self.run(f"lighting.view {cx - d.x() * units:.5f} {cy + dy * units:.5f} {cam.height:.5f}")
            return
        self._moved = True
        if what == "move":
            kind, i, (px, py), (sx, sy) = data
            self.run(f"{kind}.move {i} {px + x - sx:.4f} {py + y - sy:.4f}")
        elif what == "rotate":
            kind, i, rotation, angle0 = data
            item = self.state.scene.lights[i] if kind == "light" else self.state.scene.hulls[i]
            angle = math.atan2(y - item.position[1], x - item.position[0])
            self.run(f"{kind}.set {i} rotation {rotation + angle - angle0:.6f}")
        elif what == "scale":
            kind, i, (s0x, s0y), dist0 = data
            item = self.state.scene.lights[i] if kind == "light" else self.state.scene.hulls[i]
            k = math.dist((x, y), item.position) / dist0
            self.run(f"{kind}.set {i} scale {s0x * k:.5f} {s0y * k:.5f}")
        elif what == "vertex":
            i, vertex = data
            local = _local(self.state.scene.hulls[i], x, y)
            if local is not None:
                self.run(f"hull.vertex {i} {vertex} {local[0]:.5f} {local[1]:.5f}")

    def release(self, event) -> None:
        if self._drag is not None and self._drag[0] != "pan":
            self.move(event)  # the release point is where the drag ends, whatever moves were merged
        self._drag = None

    def double_click(self, event) -> None:
        """On the selected hull's edge: insert a vertex there."""
        if self.drawing:
            self.finish_hull()
            return
        sel = self.selection
        if sel is None or sel[0] != "hull":
            return
        x, y = self._world(event)
        hull = self.state.scene.hulls[sel[1]]
        world = hull.world()
        p = np.array([x, y])
        dists = [_segment_distance(p, world[k], world[(k + 1) % len(world)]) for k in range(len(world))]
        k = int(np.argmin(dists))
        local = _local(hull, x, y)
        if dists[k] <= PICK_PX * self._unit() and local is not None:
            self.run(f"hull.insert {sel[1]} {k + 1} {local[0]:.5f} {local[1]:.5f}")

    def _delete_vertex(self, x: float, y: float) -> bool:
        handle = self._hit_handle(x, y)
        if handle is None or handle[0] != "vertex":
            return False
        self.run(f"hull.delete {self.selection[1]} {handle[1]}")
        return True

    def wheel(self, event) -> None:
        cx, cy, h = self.state.camera.zoomed_about(*self._world(event), event.angleDelta().y() / 120,
                                                            ZOOM_STEP, lo=1e-2, hi=1e7)
        self.run(f"lighting.view {cx:.5f} {cy:.5f} {h:.5f}")

    # ---- the status bar ------------------------------------------------------------------------------

    def hover(self, event) -> str:
        """The world point under the cursor and the light reaching it (the lightmap drawn)."""
        x, y = self._world(event)
        light = self.viewport.value_at(event.position())
        value = "" if light is None else f"   light {light[0]:.3f} {light[1]:.3f} {light[2]:.3f}"
        return f"x {x:.2f}  y {y:.2f}{value}"

    def tool_name(self) -> str:
        return "draw hull (click points; Enter, right click or the first point closes)" if self.drawing else "select"

    def render_mode(self) -> str:
        s = self.settings()
        detail = {"jitter": f", {s.samples} samples", "blur": f", blur {s.blur:g}"}.get(s.method, "")
        scale = f", lightmap x{s.lightmap_scale:g}" if s.lightmap_scale != 1 else ""
        return f"{s.method} shadows{detail}{scale}{', wireframe' if s.debug else ''}"

    def key(self, event) -> bool:
        """Keys the tool owns (True when handled): h draw, Enter/Escape end drawing, Delete removes."""
        k = event.key()
        if k == Qt.Key.Key_H and not self.drawing:
            self.start_drawing()
        elif self.drawing and k in (Qt.Key.Key_Return, Qt.Key.Key_Enter):
            self.finish_hull()
        elif self.drawing and k == Qt.Key.Key_Escape:
            self.cancel_drawing()
        elif k in (Qt.Key.Key_Delete, Qt.Key.Key_Backspace) and self.selection is not None:
            kind, i = self.selection
            self.select(None)
            self.run(f"{kind}.remove {i}")
        else:
            return False
        return True

    # ---- drawing a hull ----------------------------------------------------------------------------

    def start_drawing(self) -> None:
        self.drawing = True
        self.state.pending = []
        self.select(None)

    def cancel_drawing(self) -> None:
        self.drawing = False
        self.state.pending, self.state.pending_cursor = [], None
        self.viewport.selection_changed()

    def finish_hull(self) -> None:
        points = self.state.pending
        self.drawing = False
        self.state.pending, self.state.pending_cursor = [], None
        if len(points) >= 3:
            self.run("hull.draw " + " ".join(f"{x:.4f} {y:.4f}" for x, y in points))
            self.select(("hull", len(self.state.scene.hulls) - 1))
        else:
            self.viewport.selection_changed()
