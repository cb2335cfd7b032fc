"""Koch snowflake renderer: points in, line strips out of a GLSL 330 geometry shader."""
from __future__ import annotations


import moderngl

import numpy as np

from app.gl.core.uniforms import set_uniforms
from app.gl.core.vertex_arrays import VertexArrays
from app.model.camera2d import Camera2D
from app.model.snowflake import SnowflakeScene, split_level

CHUNK_DEPTH = 3  # 4**3 segments = 65 vertices per emission, must match #GS_count in snowflake_GS.glsl
BACKGROUND = (0.05, 0.07, 0.12, 1.0)
LINE_COLOR = (0.72, 0.88, 1.0, 1.0)


def chunk_layout(level: float) -> tuple[int, float, int, int]:
    """(m, t, chunk depth, chunks per flake) for a level: 3 * 4**(m - depth) chunks."""
    m, t = split_level(level)
    depth = min(m, CHUNK_DEPTH)
    return m, t, depth, 3 * 4 ** (m - depth)


class SnowflakeRenderer:
    """Draws a SnowflakeScene; re-uploads the flake buffer only when the scene changed."""

    def __init__(self, ctx: moderngl.Context, shaders) -> None:
        self.ctx = ctx
        self.shaders = shaders
        self._flakes = ctx.buffer(reserve=12)
        self._count = 0
        self._uploaded: tuple | None = None  # the flakes in the buffer: scenes share the tuple until one changes
        self._capture_fbo: moderngl.Framebuffer | None = None
        self._vaos = VertexArrays(lambda program: ctx.vertex_array(program, [(self._flakes, "3f/i", "in_flake")]))

    def render(self, fbo: moderngl.Framebuffer, scene: SnowflakeScene, camera: Camera2D,
               color=LINE_COLOR, background=BACKGROUND) -> None:
        fbo.use()
        fbo.clear(*background)
        vao, chunks = self._prepare(self.shaders.program("snowflake"), scene, camera, *fbo.size)
        if vao is not None:
            vao.program["u_color"].value = tuple(color)
            vao.render(moderngl.POINTS, vertices=chunks, instances=self._count)

    def capture(self, scene: SnowflakeScene, camera: Camera2D) -> np.ndarray:
        """The shader's world-space segments via transform feedback, as (n, 2, 2) float32."""
        program = self.shaders.program("snowflake", varyings=("v_world",))
        vao, chunks = self._prepare(program, scene, camera, 1, 1)
        if vao is None:
            return np.zeros((0, 2, 2), "f4")
        segments = self._count * chunks * 4 ** min(split_level(scene.level)[0], CHUNK_DEPTH)
        out = self.ctx.buffer(reserve=segments * 2 * 2 * 4)
        if self._capture_fbo is None:
            self._capture_fbo = self.ctx.simple_framebuffer((1, 1))
        # Draw calls need a complete framebuffer even with rasterizing off; a surfaceless (EGL) context has
        # none bound once the last target was released.
        self._capture_fbo.use()
        try:
            vao.transform(out, mode=moderngl.POINTS, vertices=chunks, instances=self._count)
            return np.frombuffer(out.read(), "f4").reshape(-1, 2, 2).copy()
        finally:
            out.release()

    def _prepare(self, program: moderngl.Program, scene: SnowflakeScene, camera: Camera2D, width: int, height: int):
        if self._uploaded is not scene.flakes:
            data = scene.instances()
            if data.nbytes > self._flakes.size:
                self._flakes.orphan(data.nbytes)
            if data.size:
                self._flakes.write(data)
            self._count, self._uploaded = len(data), scene.flakes
        if self._count == 0:
            return None, 0
        m, t, depth, chunks = chunk_layout(scene.level)
        scale, offset = camera.scale_offset(width, height)
        set_uniforms(program, u_levels=m, u_chunk_depth=depth, u_last_t=t, u_scale=tuple(scale),
                     u_offset=tuple(offset))
        return self._vaos.get(program), chunks
