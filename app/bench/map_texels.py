"""How many shadow-map texels a screen pixel gets, and the scenes where a map fitted to the whole scene left its
shadows none (issue 29): the measure behind docs/lights3d.md's map section, scripts/shadow_map_texels.py's table
and tests/test_shadow_map_fitting.py.

texels_per_pixel: over the pixels a light faces and reaches (the reference's `facing`), the area in texels of a
screen pixel's footprint in the map (the tile the light pass reads for that pixel: |det| of the texel position's
derivative across the pixel, from its right and lower neighbours on the same object), median. Over 1 a pixel
reads a texel of its own; at 0.01 one texel spreads over 100 pixels, and a shadow narrower than it is lost.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from app.gl.lights3d.shadow_map import MapViews
from app.model.lights3d.scene import Light3D, Lights3DCamera, Object3D, Scene3D, default_scene

SUN = Light3D("directional", (0, 120, 0), (-0.3, -1.0, 0.5), (0.35, 0.3, 0.25), shadow="map")


@dataclass(frozen=True)
class HardCase:
    name: str
    scene: Scene3D
    light: int                  # the light judged
    camera: Lights3DCamera = field(default_factory=lambda: Lights3DCamera(distance=250.0))  # the scene up close


def _mapped(scene: Scene3D) -> Scene3D:
    for i in range(len(scene.lights)):
        scene = scene.with_light(i, shadow="map")
    return scene


def hard_cases() -> tuple[HardCase, ...]:
    """The issue's: a box 20,000 units off beside the default scene under a sun (and one 20,000 units up the sun's
    rays, its shadow in view), the default spot widened to 89.9 degrees (up close, and seen whole from the default
    camera), the default point light moved 9,400 units away (range 10,000: the most a light takes); and the
    default scene with a sun, each of its lights judged. The camera is 250 units from the scene's middle but where
    said."""
    default = _mapped(default_scene().add_light(SUN))
    away = np.array([0.5, 0.8, 0.33]) / np.linalg.norm([0.5, 0.8, 0.33])
    one = default_scene()
    sun = np.asarray(SUN.direction)
    wide = _mapped(Scene3D(one.objects, (one.lights[1],)).with_light(0, angle=89.9))
    return (
        HardCase("far box, directional", _mapped(Scene3D(one.objects + (Object3D("box", (10.0, 10.0, 10.0),
                                                                                   (20000.0, 5.0, 0.0)),), (SUN,))), 0),
        HardCase("far box up the sun", _mapped(Scene3D(one.objects + (Object3D("box", (10.0, 10.0, 10.0), tuple(
            np.array([-40.0, 5.0, 60.0]) - 20000.0 * sun)),), (SUN,))), 0),  # its shadow beside the box's
        HardCase("spot of 89.9 deg", wide, 0),
        HardCase("spot of 89.9 deg, all", wide, 0, Lights3DCamera()),  # the cone's receivers too wide for one view
        HardCase("point 9,400 away", _mapped(Scene3D(one.objects, (one.lights[0],)).with_light(
            0, position=tuple(9400.0 * away), range=10000.0)), 0),
        *(HardCase(f"default, {light.kind}", default, i) for i, light in enumerate(default.lights)),
    )


def footprints(views: MapViews, light_position, map_size: int, position: np.ndarray, object_id: np.ndarray,
               judged: np.ndarray) -> np.ndarray:
    """The texels each judged pixel's footprint covers in the tile it reads (`position` (H, W, 3) the surface's
    world points, `object_id` (H, W) whose they are, `judged` (H, W) the pixels counted), those with a right and
    a lower neighbour on the same object."""
    here = judged[:-1, :-1] & (object_id[:-1, :-1] == object_id[:-1, 1:]) & (object_id[:-1, :-1] ==
                                                                             object_id[1:, :-1])
    centre, right, below = (position[:-1, :-1][here], position[:-1, 1:][here], position[1:, :-1][here])
    tiles = views.tiles_of(centre, light_position)
    t0, tx, ty = (views.texels(p, tiles, map_size) for p in (centre, right, below))
    ax, ay = tx - t0, ty - t0
    return np.abs(ax[:, 0] * ay[:, 1] - ax[:, 1] * ay[:, 0])


def texels_per_pixel(views: MapViews, light_position, map_size: int, position: np.ndarray, object_id: np.ndarray,
                     judged: np.ndarray) -> float:
    """The median of footprints(...); nan where no pixel is judged."""
    areas = footprints(views, light_position, map_size, position, object_id, judged)
    return float(np.median(areas)) if len(areas) else float("nan")
