"""The 3D scene's objects on the GPU: one vertex buffer per object, uploaded when the object first appears or
changes (an Object3D is a frozen value: a moved one is a new value), kept while it stays the same.

Vertices are world-space triangle corners as float32 vec4s with w = 1, the same numbers the shadow volumes are
built from (app/gl/lights3d/shadow_volumes.py casts the same float64 corners), so a caster's own triangle gets the
depth the scene pass wrote, bit for bit; then the corner's shading normal and the triangle's geometric one."""
from __future__ import annotations

from dataclasses import dataclass, field

import moderngl
import numpy as np

from app.gl.core.vertex_arrays import VertexArrays
from app.model.lights3d.scene import Object3D
from app.model.lights3d.mesh import Mesh

LAYOUT = ("4f 3f 3f", "in_position", "in_normal", "in_face")


def vertices(mesh: Mesh) -> np.ndarray:
    """(3 T, 10) float32: position (w = 1), shading normal, geometric normal per corner."""
    corners = mesh.corners().reshape(-1, 3)
    faces = np.repeat(mesh.face_normals(), 3, axis=0)
    return np.hstack([corners, np.ones((len(corners), 1)), mesh.normals.reshape(-1, 3), faces]).astype(np.float32)


@dataclass(eq=False)
class ObjectBuffer:
    obj: Object3D
    buffer: moderngl.Buffer
    count: int               # vertices
    vaos: VertexArrays = field(repr=False)

    @property
    def mesh(self) -> Mesh:
        return self.obj.mesh()

    @property
    def centre(self) -> np.ndarray:
        """The bounding sphere's (the mesh is centred on the object's position)."""
        return np.asarray(self.obj.position, np.float64)

    @property
    def radius(self) -> float:
        return self.obj.radius

    @property
    def lo(self) -> np.ndarray:
        """The bounding box's lowest corner."""
        return self.obj.bounds[0]

    @property
    def hi(self) -> np.ndarray:
        return self.obj.bounds[1]

    @property
    def casts(self) -> bool:
        return self.mesh.closed

    def render(self, program: moderngl.Program) -> None:
        self.vaos.get(program).render(moderngl.TRIANGLES, vertices=self.count)

    def release(self) -> None:
        self.vaos.release()
        self.buffer.release()


class ObjectBuffers:
    def __init__(self, ctx: moderngl.Context) -> None:
        self.ctx = ctx
        self._by_object: dict[Object3D, ObjectBuffer] = {}
        self.uploads = 0  # meshes uploaded since made

    def update(self, objects) -> list[ObjectBuffer]:
        """The buffers of `objects`, in order: new or changed ones uploaded, the ones no longer there released."""
        kept: dict[Object3D, ObjectBuffer] = {}
        for obj in objects:
            if obj not in kept:
                kept[obj] = self._by_object.pop(obj, None) or self._upload(obj)
        for gone in self._by_object.values():
            gone.release()
        self._by_object = kept
        return [kept[obj] for obj in objects]

    def _upload(self, obj: Object3D) -> ObjectBuffer:
        data = vertices(obj.mesh())
        buffer = self.ctx.buffer(data)
        self.uploads += 1
        # skip_errors: a program may leave attributes out (the depth-only ones read positions alone)
        vaos = VertexArrays(lambda program: self.ctx.vertex_array(program, [(buffer, *LAYOUT)], skip_errors=True))
        return ObjectBuffer(obj, buffer, len(data), vaos)

    def release(self) -> None:
        for entry in self._by_object.values():
            entry.release()
        self._by_object.clear()
