"""Shadow volumes of the 3D scene's casters, kept between frames: a volume depends on its caster, the light's
position (or direction) and the method, never on the camera, so an orbiting view builds none."""
from __future__ import annotations

import numpy as np

from app.gl.shadow_volume_pass import volume
from app.gl.shadow_volumes import VolumeGeometry
from app.model.lights3d import Light3D, Object3D


def light_vector(light: Light3D) -> np.ndarray:
    """The light as shadow_volumes.py takes it: (position, 1), or (towards the light, 0) for a directional one."""
    if light.kind == "directional":
        return np.array([*(-np.asarray(light.direction)), 0.0])
    return np.array([*light.position, 1.0])


def build(method: str, obj: Object3D, light: Light3D) -> VolumeGeometry:
    mesh = obj.mesh()  # a caster: closed, so its adjacency (kept across moves) is there to take
    return volume(method, mesh.positions, mesh.triangles, light_vector(light), mesh.adjacency())


class VolumeCache:
    """Volumes by (method, caster, light vector); a frame keeps the ones it used and drops the rest."""

    def __init__(self) -> None:
        self._volumes: dict[tuple, VolumeGeometry] = {}
        self._used: dict[tuple, VolumeGeometry] = {}
        self.built = 0  # volumes built since made

    def get(self, method: str, obj: Object3D, light: Light3D) -> VolumeGeometry:
        key = (method, obj, tuple(light_vector(light)))
        geometry = self._used.get(key) or self._volumes.get(key)
        if geometry is None:
            geometry = build(method, obj, light)
            self.built += 1
        self._used[key] = geometry
        return geometry

    def end_frame(self) -> None:
        self._volumes, self._used = self._used, {}

    def clear(self) -> None:
        self._volumes.clear()
        self._used.clear()
