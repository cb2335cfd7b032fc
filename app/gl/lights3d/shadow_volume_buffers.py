"""Shadow volume vertices on the GPU: a kept caster volume's, written once and drawn every frame it stays, or
the volume pass's stream, written again for each draw (grown by doubling, so it is seldom re-allocated)."""
from __future__ import annotations

import moderngl
import numpy as np

from app.gl.core.vertex_arrays import VertexArrays


class VolumeBuffer:
    def __init__(self, ctx: moderngl.Context) -> None:
        self.ctx = ctx
        self.buffer: moderngl.Buffer | None = None
        self.count = 0          # vertices written last
        self.written_bytes = 0  # all writes since made: what went to the GPU
        self._vaos = VertexArrays(lambda program: ctx.vertex_array(program, [(self.buffer, "4f", "in_position")]))

    @property
    def triangles(self) -> int:
        return self.count // 3

    def write(self, vertices: np.ndarray) -> None:
        """Vertices float32 (3 n, 4) in place of what the buffer held."""
        vertices = np.ascontiguousarray(vertices, np.float32)
        if len(vertices):  # GL has no empty buffer: none is made, nothing is drawn
            if self.buffer is None or self.buffer.size < vertices.nbytes:
                size = max(vertices.nbytes, 2 * self.buffer.size if self.buffer else 0)
                self.release()
                self.buffer = self.ctx.buffer(reserve=size)
            self.buffer.write(vertices)
            self.written_bytes += vertices.nbytes
        self.count = len(vertices)

    def render(self, program: moderngl.Program) -> None:
        if self.count:
            self._vaos.get(program).render(moderngl.TRIANGLES, vertices=self.count)

    def release(self) -> None:
        self._vaos.release()
        self.count = 0
        if self.buffer is not None:
            self.buffer.release()
            self.buffer = None
