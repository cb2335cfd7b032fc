"""World-space 2D line segments drawn as GL_LINES: CPU-built geometry and editor overlays."""
from __future__ import annotations

import moderngl
import numpy as np

from app.gl.core.blending import ALPHA, blended
from app.gl.core.vertex_arrays import VertexArrays
from app.model.camera2d import Camera2D


class Lines2D:
    def __init__(self, ctx: moderngl.Context, shaders) -> None:
        self.ctx = ctx
        self.shaders = shaders
        self.buffer = ctx.buffer(reserve=16, dynamic=True)
        self._count = 0
        self._vaos = VertexArrays(lambda program: ctx.vertex_array(program, [(self.buffer, "2f", "in_world")]))

    def upload(self, segments: np.ndarray) -> None:
        """(n, 2, 2) world-space segment end points."""
        data = np.ascontiguousarray(segments, dtype="f4")
        if data.nbytes > self.buffer.size:
            self.buffer.orphan(data.nbytes)
        if data.size:
            self.buffer.write(data)
        self._count = len(data)

    def uploaded(self) -> np.ndarray:
        return np.frombuffer(self.buffer.read(size=self._count * 16), "f4").reshape(-1, 2, 2).copy()

    def draw(self, fbo: moderngl.Framebuffer, camera: Camera2D, color, first: int = 0,
             count: int | None = None) -> None:
        """The segments uploaded (or `count` of them from `first`) in one colour."""
        count = self._count - first if count is None else count
        if count <= 0:
            return
        program = self.shaders.program("lines2d")
        scale, offset = camera.scale_offset(*fbo.size)
        program["u_scale"].value, program["u_offset"].value = tuple(scale), tuple(offset)
        program["u_color"].value = tuple(color)
        fbo.use()
        with blended(ALPHA):  # a colour's alpha is its opacity over the picture
            self._vaos.get(program).render(moderngl.LINES, vertices=2 * count, first=2 * first)
