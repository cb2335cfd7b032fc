"""What the 3D lights editor draws over the lit scene, in pixels: a marker at each light (a square in its colour,
with a short stroke along a spot's or directional light's direction), the selected item highlighted (a light's
marker ringed, an object's bounding box outlined) and the translate gizmo on it (x, y and z handles in red, green
and blue, where app/model/lights3d/gizmo.py puts them for the tool to hit). Always on top: depth and stencil ignored.

Geometry is built in numpy each frame (a few dozen triangles): world points projected with the camera, strokes
cut where they cross the near plane, anything behind the eye left out."""
from __future__ import annotations

import numpy as np

from app.gl.lights3d.light_reach import box_corners
from app.gl.core.blending import blending
from app.gl.core.stencil import GL, StencilState, stencil_state
from app.gl.core.vertex_arrays import VertexArrays
from app.model.camera3d import OrbitCamera
from app.model.lights3d.scene import Scene3D
from app.model.lights3d.gizmo import Projection, gizmo_axes

PROGRAM = "overlay2d"
STROKE_FRACTION = 0.06   # a light's direction stroke
MARKER_PX = 4.0          # a light marker's half side
HIGHLIGHT = (1.0, 0.85, 0.2, 1.0)
OUTLINE = (0.05, 0.05, 0.05, 1.0)
AXIS_COLOURS = ((0.95, 0.25, 0.25, 1.0), (0.3, 0.9, 0.3, 1.0), (0.35, 0.55, 1.0, 1.0))
ON_TOP = StencilState(write_mask=0, depth_func=GL.GL_ALWAYS, colour_write=True)
BOX_EDGES = [(a, b) for a in range(8) for b in range(8) if a < b and bin(a ^ b).count("1") == 1]


def quad(corners: np.ndarray, colour) -> np.ndarray:
    """Two triangles (6, 6) of corners (4, 2) in order around, each vertex (x, y, r, g, b, a)."""
    c = corners[[0, 1, 2, 0, 2, 3]]
    return np.hstack([c, np.tile(colour, (6, 1))])


def square(centre: np.ndarray, half: float, colour) -> np.ndarray:
    return quad(centre + half * np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]], np.float64), colour)


def stroke(ends: np.ndarray, half_width: float, colour) -> np.ndarray:
    a, b = ends
    d = b - a
    length = np.hypot(*d)
    if length < 1e-9:
        return np.empty((0, 6))
    n = np.array([-d[1], d[0]]) / length * half_width
    return quad(np.array([a + n, b + n, b - n, a - n]), colour)


def light_marks(scene: Scene3D, view: Projection, selected: int | None) -> list[np.ndarray]:
    parts = []
    for i, light in enumerate(scene.lights):
        if not view.in_front(light.position):
            continue
        centre = view.pixels(view.clip(light.position))
        colour = (*np.clip(light.colour, 0.0, 1.0), 1.0)
        if light.kind != "point":
            tip = np.asarray(light.position) + view.world_length(light.position, STROKE_FRACTION) * np.asarray(
                light.direction)
            ends = view.segment(light.position, tip)
            if ends is not None:
                parts += [stroke(ends, 2.0, OUTLINE), stroke(ends, 1.0, colour)]
        if i == selected:
            parts.append(square(centre, MARKER_PX + 4, HIGHLIGHT))
        parts += [square(centre, MARKER_PX + 1, OUTLINE), square(centre, MARKER_PX, colour)]
    return parts


def box_marks(lo, hi, view: Projection) -> list[np.ndarray]:
    corners = box_corners(lo, hi)
    parts = []
    for a, b in BOX_EDGES:
        ends = view.segment(corners[a], corners[b])
        if ends is not None:
            parts.append(stroke(ends, 1.0, HIGHLIGHT))
    return parts


def gizmo_marks(camera: OrbitCamera, size: tuple[int, int], origin) -> list[np.ndarray]:
    segments = gizmo_axes(camera, size, origin)  # the handles the tool hit-tests, in pixels
    if segments is None:
        return []
    parts = []
    for ends, colour in zip(segments, AXIS_COLOURS):
        parts += [stroke(ends, 1.5, colour), square(ends[1], 3.0, colour)]
    return parts


def overlay_vertices(scene: Scene3D, camera: OrbitCamera, size: tuple[int, int], selection) -> np.ndarray:
    """(n, 6) float32 triangle vertices, drawn in order (later ones on top)."""
    view = Projection(camera, size)
    kind, index = selection if selection is not None else (None, None)
    parts = light_marks(scene, view, index if kind == "light" else None)
    if kind == "object":
        parts += box_marks(*scene.objects[index].bounds, view)
    if kind is not None:
        item = scene.objects[index] if kind == "object" else scene.lights[index]
        parts += gizmo_marks(camera, size, item.position)
    return np.concatenate(parts or [np.empty((0, 6))]).astype(np.float32)


class Overlay:
    def __init__(self, ctx, shaders) -> None:
        self.ctx, self.shaders = ctx, shaders
        self.buffer = ctx.buffer(reserve=4096, dynamic=True)
        self._vaos = VertexArrays(lambda program: ctx.vertex_array(
            program, [(self.buffer, "2f 4f", "in_pixel", "in_colour")]))

    def draw(self, fbo, scene: Scene3D, camera: OrbitCamera, selection) -> int:
        """The marks over `fbo` (bound here); returns the triangles drawn."""
        data = overlay_vertices(scene, camera, fbo.size, selection)
        if not len(data):
            return 0
        if data.nbytes > self.buffer.size:
            self.buffer.orphan(data.nbytes)
        self.buffer.write(data)
        program = self.shaders.program(PROGRAM)
        program["u_size"].value = tuple(map(float, fbo.size))
        fbo.use()
        with stencil_state(ON_TOP), blending(False):
            self._vaos.get(program).render(vertices=len(data))
        return len(data) // 3

    def release(self) -> None:
        self._vaos.release()
        self.buffer.release()
