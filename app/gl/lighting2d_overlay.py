"""Lines over the lit 2D scene: each light's icon at its centre and invalid hulls in red (always), the debug
wireframe (hull outlines, light quads, emitting discs) and the editor's selection with its handles. Only the
hulls in view are looked at (the scene index finds them), so hulls far away cost a frame nothing."""
from __future__ import annotations

import math

import numpy as np

from app.gl.lines2d import Lines2D
from app.model.camera2d import Camera2D
from app.model.lighting2d import Scene2D
from app.model.lighting2d_index import SceneIndex, light_quad

INVALID = (1.0, 0.2, 0.2, 1.0)
WIRE = (0.9, 0.9, 0.9, 0.8)
LIGHT = (1.0, 0.85, 0.3, 0.9)
SELECTED = (0.3, 0.9, 1.0, 1.0)
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


def light_icon(x: float, y: float, unit: float) -> tuple[np.ndarray, np.ndarray]:
    """A sun at (x, y), `unit` world units a pixel: (its lines, their dark rim), so it shows on light and dark."""
    a = np.arange(8) * math.pi / 4
    ray = np.stack([np.cos(a), np.sin(a)], axis=1)
    centre = np.array([x, y])
    lines = np.concatenate([circle(x, y, 0.45 * ICON_PX * unit, 16),
                            np.stack([centre + 0.65 * ICON_PX * unit * ray, centre + ICON_PX * unit * ray], axis=1)])
    rim = np.concatenate([circle(x, y, (0.45 * ICON_PX - 1) * unit, 16), circle(x, y, (0.45 * ICON_PX + 1) * unit, 16)])
    return lines, rim


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


class Lighting2DOverlay:
    def __init__(self, ctx, shaders) -> None:
        self.lines = Lines2D(ctx, shaders)
        self.hulls_seen = 0  # hulls the last frame looked at (those in view)

    def draw(self, fbo, scene: Scene2D, index: SceneIndex, camera: Camera2D, flip_y: bool, debug: bool,
             selection=None, pending=None) -> None:
        """`index` is the scene's index for its current version (the renderer's)."""
        unit = camera.world_per_pixel(fbo.size[1])
        groups: list[tuple[tuple, list[np.ndarray]]] = [(INVALID, []), (WIRE, []), (LIGHT, []), (ICON_SHADE, []),
                                                        (ICON, []), (SELECTED, [])]
        invalid, wire, lights, rims, icons, selected = (g[1] for g in groups)
        for light in scene.lights:
            lines, rim = light_icon(*light.position, unit)
            icons.append(lines)
            rims.append(rim)
        seen = index.outlines_in(*camera.view_rect(*fbo.size))  # the view is symmetric about cy: flip_y too
        self.hulls_seen = len(seen)
        for i in seen:
            hull = scene.hulls[i]
            target = invalid if not hull.valid else (wire if debug else None)
            if target is not None:
                target.append(loop(hull.world()) if len(hull.points) > 2 else hull.world()[None])
        if debug:
            for light in scene.lights:
                lights.append(loop(light_quad(light)))
                lights.append(circle(*light.position, max(light.radius, 3 * unit)))
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
        for color, parts in groups:
            if parts:
                segments = np.concatenate(parts)
                if flip_y:
                    segments = segments.copy()
                    segments[..., 1] = 2 * camera.cy - segments[..., 1]
                self.lines.upload(segments)
                self.lines.draw(fbo, camera, color)

    @staticmethod
    def _valid(scene: Scene2D, selection) -> bool:
        kind, index = selection
        return 0 <= index < len(scene.lights if kind == "light" else scene.hulls)
