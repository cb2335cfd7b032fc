"""What the 2D renderer asks of a scene, answered once per scene (a scene is a value: an edit makes another
one): the hulls that can cast into a light's reach (through a grid index), the outlines the editor's overlay
draws in the view and the tool's clicks test, each light's bounds, and whether its centre is inside a hull
(then Penumbra does not draw it)."""
from __future__ import annotations

import math

import numpy as np

from app.model.lighting2d.scene import Light, Scene2D, distance_to_convex, inside_convex
from app.model.lighting2d.spatial import GridIndex

CORNERS = np.array([(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)])


def light_quad(light: Light) -> np.ndarray:
    """The light's quad corners in world space (4, 2)."""
    c, s = math.cos(light.rotation), math.sin(light.rotation)
    local = (CORNERS - light.origin) * light.scale
    return local @ np.array([[c, s], [-s, c]]) + light.position


def light_bounds(light: Light) -> tuple[float, float, float, float]:
    quad = light_quad(light)
    (x0, y0), (x1, y1) = quad.min(axis=0), quad.max(axis=0)
    return float(x0), float(y0), float(x1), float(y1)


class SceneIndex:
    def __init__(self, scene: Scene2D) -> None:
        self.scene = scene
        # every hull with an outline (invalid and disabled ones too: the overlay draws them); only the
        # enabled valid ones cast shadows
        self.outlined = np.array([i for i, h in enumerate(scene.hulls) if len(h.points) >= 2], np.int64)
        self.casting = np.array([scene.hulls[i].enabled and scene.hulls[i].valid for i in self.outlined], bool)
        boxes = np.array([scene.hulls[i].bounds() for i in self.outlined]).reshape(-1, 4)
        self.grid = GridIndex(boxes)

    def is_for(self, scene: Scene2D) -> bool:
        """Whether this index answers for `scene`: the very scene it was built for (an edited one is another)."""
        return self.scene is scene

    def outlines_in(self, x0: float, y0: float, x1: float, y1: float) -> list[int]:
        """Indices (into scene.hulls) of hulls with an outline whose bounds meet the rectangle."""
        return self.outlined[self.grid.query(x0, y0, x1, y1)].tolist()

    def hulls_in(self, x0: float, y0: float, x1: float, y1: float, ignored=()) -> list[int]:
        """Indices (into scene.hulls) of shadow-casting hulls whose bounds meet the rectangle."""
        found = self.grid.query(x0, y0, x1, y1)
        found = self.outlined[found[self.casting[found]]].tolist()
        return [i for i in found if i not in ignored] if ignored else found

    def reach(self, light: Light) -> tuple[float, float, float, float]:
        """Where a hull can shadow this light's quad: the quad grown by the emitting disc."""
        x0, y0, x1, y1 = light_bounds(light)
        r = light.radius
        return x0 - r, y0 - r, x1 + r, y1 + r

    def casters(self, light: Light) -> list[int]:
        return self.hulls_in(*self.reach(light), ignored=set(light.ignored_hulls))

    def centre_blocked(self, light: Light) -> bool:
        """The light's centre inside (or on the edge of, within 1e-9 relative) a hull it does not ignore."""
        x, y = light.position
        point = np.array([[x, y]])
        return any(inside_convex(point, piece, 1e-9)[0]
                   for i in self.hulls_in(x, y, x, y, ignored=set(light.ignored_hulls))
                   for piece in self.scene.hulls[i].world_pieces())

    def disc_touched(self, light: Light) -> bool:
        """Does a hull piece meet the light's emitting disc? (then shadows are no longer angular intervals)"""
        if light.radius <= 0:
            return False
        x, y, r = *light.position, light.radius
        centre = np.array([[x, y]])
        return any(distance_to_convex(centre, piece)[0] <= r
                   for i in self.hulls_in(x - r, y - r, x + r, y + r, ignored=set(light.ignored_hulls))
                   for piece in self.scene.hulls[i].world_pieces())


class SceneIndexes:
    """One scene's index at a time, built again only after the scene changed. The 2D workspace holds one, so
    that its frame and its tool's clicks share each build (10,000 hulls take milliseconds to index)."""

    def __init__(self) -> None:
        self._index: SceneIndex | None = None

    def get(self, scene: Scene2D) -> SceneIndex:
        if self._index is None or not self._index.is_for(scene):
            self._index = SceneIndex(scene)
        return self._index
