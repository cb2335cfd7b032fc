"""Lines over the lit 2D scene: each light's icon at its centre, every hull's outline (faint; invalid hulls in red),
the debug wireframe (brighter outlines, light quads, emitting discs), the editor's selection with its handles and
the hull being drawn, its rubber band to the cursor. Only the
hulls and light icons in view are looked at (the scene index finds the hulls), so what lies far away costs a
frame nothing; and the lines are built and uploaded only when the scene, the view or the selection changed, so
a still frame (the lightmap drawn again under them) only draws them."""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from app.gl.core.lines2d import Lines2D
from app.model.camera2d import Camera2D
from app.model.lighting2d.scene import Scene2D
from app.model.lighting2d.index import SceneIndex, light_quad

INVALID = (1.0, 0.2, 0.2, 1.0)
WIRE = (0.9, 0.9, 0.9, 0.8)
LIGHT = (1.0, 0.85, 0.3, 0.9)
SELECTED = (0.3, 0.9, 1.0, 1.0)
BAND = (0.3, 0.9, 1.0, 0.55)   # the hull being drawn, from its last point to the cursor
HULL = (0.85, 0.85, 0.9, 0.45)  # every valid hull's outline, faint: hulls cast shadows but are not lit
ICON = (1.0, 0.75, 0.1, 1.0)
ICON_SHADE = (0.1, 0.08, 0.05, 1.0)
HANDLE_PX = 5.0     # half-size of a vertex handle, in pixels
ROTATE_PX = 40.0    # the rotation handle's distance from the centre, in pixels
ICON_PX = 10.0      # a light icon's radius (its rays' tips), in pixels: the tool picks a light within it


def loop(points: np.ndarray) -> np.ndarray:
    """A closed outline as segments (n, 2, 2)."""
    return np.stack([points, np.roll(points, -1, axis=0)], axis=1)


def circle(cx: float, cy: float, r: float, n: int = 48) -> np.ndarray:
    a = np.linspace(0, 2 * math.pi, n, endpoint=False)
    return loop(np.stack([cx + r * np.cos(a), cy + r * np.sin(a)], axis=1))


def square(x: float, y: float, half: float) -> np.ndarray:
    return loop(np.array([(x - half, y - half), (x + half, y - half), (x + half, y + half), (x - half, y + half)]))


def _icon() -> tuple[np.ndarray, np.ndarray]:
    """A sun about (0, 0) in pixels: (its lines, their dark rim), so it shows on light and dark."""
    a = np.arange(8) * math.pi / 4
    ray = np.stack([np.cos(a), np.sin(a)], axis=1)
    lines = np.concatenate([circle(0, 0, 0.45 * ICON_PX, 16), np.stack([0.65 * ICON_PX * ray, ICON_PX * ray], axis=1)])
    rim = np.concatenate([circle(0, 0, 0.45 * ICON_PX - 1, 16), circle(0, 0, 0.45 * ICON_PX + 1, 16)])
    return lines, rim


ICON_LINES, ICON_RIM = _icon()


def light_icons(centres: np.ndarray, unit: float) -> tuple[np.ndarray, np.ndarray]:
    """Suns at `centres` (n, 2), `unit` world units a pixel: (their lines, their rims), one icon after another."""
    place = np.asarray(centres, dtype=np.float64).reshape(-1, 1, 1, 2)
    return ((place + unit * ICON_LINES).reshape(-1, 2, 2), (place + unit * ICON_RIM).reshape(-1, 2, 2))


def icons_in(scene: Scene2D, unit: float, x0: float, y0: float, x1: float, y1: float) -> np.ndarray:
    """The centres (n, 2) of the lights whose icon (rim included) meets the rectangle."""
    centres = np.array([light.position for light in scene.lights], dtype=np.float64).reshape(-1, 2)
    reach = (ICON_PX + 1) * unit
    x, y = centres[:, 0], centres[:, 1]
    return centres[(x >= x0 - reach) & (x <= x1 + reach) & (y >= y0 - reach) & (y <= y1 + reach)]


def handles(scene: Scene2D, selection, unit: float) -> dict[str, np.ndarray]:
    """Where the editor's handles are, in world units, for the view and the hit tests alike:
    'centre' (x, y), 'rotate' (x, y), 'vertices' (n, 2) for hulls, 'scale' (x, y)."""
    kind, index = selection
    if kind == "light":
        light = scene.lights[index]
        x, y = light.position
        return {"centre": np.array([x, y]),
                "rotate": np.array([x + ROTATE_PX * unit * math.cos(light.rotation),
                                    y + ROTATE_PX * unit * math.sin(light.rotation)]),
                "scale": light_quad(light)[2]}
    hull = scene.hulls[index]
    x, y = hull.position
    world = hull.world()
    return {"centre": np.array([x, y]), "vertices": world,
            "rotate": np.array([x + ROTATE_PX * unit * math.cos(hull.rotation),
                                y + ROTATE_PX * unit * math.sin(hull.rotation)]),
            "scale": world.max(axis=0) + 2 * HANDLE_PX * unit}


@dataclass
class OverlayStats:
    """What the overlay's last frame did: a still frame builds and uploads nothing."""
    layers_built: int = 0       # layers (the scene's, the selection's) whose lines were built again
    segments_uploaded: int = 0  # line segments written to the GPU
    icons: int = 0              # light icons the frame draws (those in view)


class _Layer:
    """Lines of several colours in one buffer, built and uploaded again only when their key changed."""

    def __init__(self, ctx, shaders) -> None:
        self.lines = Lines2D(ctx, shaders)
        self.key = None
        self.spans: list[tuple[tuple, int, int]] = []  # (colour, first segment, segments)

    def update(self, key, build, camera: Camera2D, flip_y: bool, stats: OverlayStats) -> None:
        """`build()` gives [(colour, [segments (n, 2, 2), ...]), ...], called only when `key` changed."""
        if key == self.key:
            return
        groups = [(color, np.concatenate(parts)) for color, parts in build() if parts]
        segments = np.concatenate([s for _, s in groups]) if groups else np.zeros((0, 2, 2))
        if flip_y:  # the view is mirrored about cy
            segments[..., 1] = 2 * camera.cy - segments[..., 1]
        starts = np.cumsum([0] + [len(s) for _, s in groups])
        self.spans = [(color, int(first), len(s)) for (color, s), first in zip(groups, starts)]
        self.lines.upload(segments)
        self.key = key
        stats.layers_built += 1
        stats.segments_uploaded += len(segments)

    def draw(self, fbo, camera: Camera2D) -> None:
        for color, first, count in self.spans:
            self.lines.draw(fbo, camera, color, first, count)


class Lighting2DOverlay:
    def __init__(self, ctx, shaders) -> None:
        self._scene_layer = _Layer(ctx, shaders)      # icons, invalid hulls, the wireframe
        self._selection_layer = _Layer(ctx, shaders)  # the selection, its handles, the hull being drawn
        self.hulls_seen = 0  # hulls the last built frame looked at (those in view)
        self.stats = OverlayStats()

    def draw(self, fbo, scene: Scene2D, index: SceneIndex, camera: Camera2D, flip_y: bool, debug: bool,
             selection=None, pending=None, cursor=None, marks: bool = True) -> None:
        """`index` is the scene's index (the renderer's): a new one means a new scene (an edit makes one), so it
        keys the layers with the view. Without `marks`, the debug wireframe alone (no icons, outlines, selection):
        the scene as `shadelab render` draws it."""
        unit = camera.world_per_pixel(fbo.size[1])
        view = camera.view_rect(*fbo.size)  # the view is symmetric about cy: flip_y too
        frame = (index, camera.key(), tuple(fbo.size), flip_y)
        self.stats = OverlayStats(icons=self.stats.icons)
        self._scene_layer.update((*frame, debug, marks), lambda: self._scene_lines(scene, index, unit, view, debug,
                                                                                   marks), camera, flip_y, self.stats)
        self._scene_layer.draw(fbo, camera)
        if marks:
            self._selection_layer.update((*frame, selection, tuple(pending or ()), cursor if pending else None),
                                         lambda: self._selection_lines(scene, unit, selection, pending, cursor),
                                         camera, flip_y, self.stats)
            self._selection_layer.draw(fbo, camera)

    def _scene_lines(self, scene: Scene2D, index: SceneIndex, unit: float, view, debug: bool, marks: bool = True):
        invalid, outlines, lights = [], [], []
        icons, rims = light_icons(icons_in(scene, unit, *view) if marks else np.zeros((0, 2)), unit)
        self.stats.icons = len(icons) // len(ICON_LINES)
        seen = index.outlines_in(*view) if marks or debug else []
        self.hulls_seen = len(seen)
        for i in seen:
            hull = scene.hulls[i]
            target = outlines if hull.valid else invalid
            target.append(loop(hull.world()) if len(hull.points) > 2 else hull.world()[None])
        if debug:
            for light in scene.lights:
                lights.append(loop(light_quad(light)))
                lights.append(circle(*light.position, max(light.radius, 3 * unit)))
        return [(INVALID, invalid), (WIRE if debug else HULL, outlines), (LIGHT, lights), (ICON_SHADE, [rims]),
                (ICON, [icons])]

    def _selection_lines(self, scene: Scene2D, unit: float, selection, pending, cursor=None):
        selected, band = [], []
        if selection is not None and self._valid(scene, selection):
            h = handles(scene, selection, unit)
            kind, index = selection
            if kind == "light":
                light = scene.lights[index]
                selected.append(circle(*light.position, max(light.radius, 6 * unit)))
                selected.append(loop(light_quad(light)))
            else:
                selected.append(loop(h["vertices"]))
                selected += [square(x, y, HANDLE_PX * unit) for x, y in h["vertices"]]
                selected.append(square(*h["scale"], HANDLE_PX * unit))
            selected.append(np.array([[h["centre"], h["rotate"]]]))
            selected.append(circle(*h["rotate"], HANDLE_PX * unit, 12))
        if pending:
            points = np.asarray(pending, dtype=np.float64)
            if len(points) > 1:
                selected.append(np.stack([points[:-1], points[1:]], axis=1))
            selected += [square(x, y, HANDLE_PX * unit) for x, y in points]
            if cursor is not None:  # the rubber band: to the cursor, and back to the first point once it closes
                band.append(np.array([[points[-1], cursor]]))
                if len(points) >= 2:
                    band.append(np.array([[cursor, points[0]]]))
        return [(SELECTED, selected), (BAND, band)]

    @staticmethod
    def _valid(scene: Scene2D, selection) -> bool:
        kind, index = selection
        return 0 <= index < len(scene.lights if kind == "light" else scene.hulls)
