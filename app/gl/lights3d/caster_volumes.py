"""Shadow volumes of the 3D scene's casters, kept between frames on the GPU: a volume depends on its caster, the
light's position (or direction) and the method, never on the camera, so an orbiting view builds and uploads none."""
from __future__ import annotations

from collections.abc import Callable

from app.gl.lights3d.shadow_volume_pass import volume
from app.gl.lights3d.shadow_volumes import VolumeGeometry
from app.gl.lights3d.shadow_volume_buffers import VolumeBuffer
from app.model.lights3d.facing import homogeneous
from app.model.lights3d.scene import Light3D, Object3D


def build(method: str, obj: Object3D, light: Light3D) -> VolumeGeometry:
    mesh = obj.mesh()  # a caster: closed, so its adjacency (kept across moves) is there to take
    return volume(method, mesh.positions, mesh.triangles, homogeneous(light), mesh.adjacency())


class VolumeCache:
    """Volumes on the GPU by (method, caster's shape and place, light vector): built and uploaded when one of
    them changes, drawn from their own buffers while they stay (a recoloured object or light keeps its volumes).
    A frame keeps the ones it used and releases the rest."""

    def __init__(self, upload: Callable[[VolumeGeometry], VolumeBuffer]) -> None:
        self._upload = upload
        self._volumes: dict[tuple, VolumeBuffer] = {}
        self._used: dict[tuple, VolumeBuffer] = {}
        self.built = 0  # volumes built since made

    def get(self, method: str, obj: Object3D, light: Light3D) -> VolumeBuffer:
        key = (method, obj.kind, obj.size, obj.position, tuple(homogeneous(light)))
        kept = self._used.get(key) or self._volumes.pop(key, None)
        if kept is None:
            kept = self._upload(build(method, obj, light))
            self.built += 1
        self._used[key] = kept
        return kept

    def end_frame(self) -> None:
        for dropped in self._volumes.values():
            dropped.release()
        self._volumes, self._used = self._used, {}

    def clear(self) -> None:
        for kept in (*self._volumes.values(), *self._used.values()):
            kept.release()
        self._volumes.clear()
        self._used.clear()
