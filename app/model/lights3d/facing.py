"""Which faces a light lights: one answer per triangle, from its own plane, that the shadow volumes
(app/gl/lights3d/shadow_volumes.py), the light pass's facing test (resources/shaders/lights3d.shl) and the CPU
reference (app/reference/lights3d.py) all take. numpy only.

A triangle faces a light when the light lies on its outer side by more than IN_PLANE of the distance to it (the
sine of the light's elevation over the plane, seen from the triangle's third corner, the corner GL hands a flat
attribute from); a directional light faces it when the light's direction makes more than that sine with the
plane. A light in the plane (on a vertex, on an edge, level with a face) thus counts as behind the face: no face
is lit by noise in a dot product that should be 0, and the volumes and the light pass decide alike. IN_PLANE is
far above float32's rounding of that sine (about 1e-7) and far below any light a picture shows (the face gets
sin * its light: 1e-5 of it)."""
from __future__ import annotations

import numpy as np

from app.model.lights3d.scene import Light3D

IN_PLANE = 1e-5


def homogeneous(light: Light3D) -> np.ndarray:
    """The light as a vec4: (position, 1), or (towards the light, 0) for a directional one."""
    if light.kind == "directional":
        return np.array([*(-np.asarray(light.direction)), 0.0])
    return np.array([*light.position, 1.0])


def light_side(normals: np.ndarray, corners: np.ndarray, light: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(side, reach) per triangle: the light's height over each plane (unit `normals` (T, 3), a corner of each
    (T, 3)) and the length of the way to it; for a homogeneous `light` (4,) with w = 0, the direction towards it."""
    to_light = light[:3] - light[3] * corners
    return np.einsum("ij,ij->i", normals, to_light), np.linalg.norm(to_light, axis=1)


def faces_light(normals: np.ndarray, corners: np.ndarray, light: np.ndarray) -> np.ndarray:
    """(T,) bool: the light is on each triangle's outer side, beyond the in-plane margin."""
    side, reach = light_side(normals, corners, light)
    return side > IN_PLANE * reach


def in_plane(normals: np.ndarray, corners: np.ndarray, light: np.ndarray) -> np.ndarray:
    """(T,) bool: the light lies in each triangle's plane, within the margin (neither side faces it)."""
    side, reach = light_side(normals, corners, light)
    return np.abs(side) <= IN_PLANE * reach
