"""Cheaper frames while the user interacts: the most accurate measured setting within a frame budget."""
from __future__ import annotations

import math

import moderngl

from app.gl.vertex_arrays import VertexArrays

# (pixel scale, step factor), most accurate first: fewer pixels cost less accuracy than fewer steps.
LEVELS = ((1.0, 1.0), (0.5, 1.0), (0.5, 0.5), (0.25, 0.5), (0.25, 0.25), (0.125, 0.25))
SMOOTHING = 0.5  # weight of the newest frame time in each level's running estimate


class QualityLadder:
    """Remembers how long each level took here and picks the first that fits the budget."""

    def __init__(self) -> None:
        self.ms: list[float | None] = [None] * len(LEVELS)

    def choose(self, budget_ms: float) -> int:
        for i, ms in enumerate(self.ms):
            if ms is None or ms <= budget_ms:  # an unmeasured level is tried once its better one was too slow
                return i
        return len(LEVELS) - 1

    def record(self, level: int, ms: float) -> None:
        old = self.ms[level]
        self.ms[level] = ms if old is None else SMOOTHING * ms + (1 - SMOOTHING) * old


class ReducedTarget:
    """An offscreen colour texture at a fraction of the screen, stretched back over it."""

    def __init__(self, ctx: moderngl.Context, shaders) -> None:
        self.ctx, self.shaders = ctx, shaders
        self.size = None
        self.texture = self.fbo = None
        self._vaos = VertexArrays(lambda program: ctx.vertex_array(program, []))

    def framebuffer(self, screen: tuple[int, int], scale: float) -> moderngl.Framebuffer:
        size = (max(1, math.ceil(screen[0] * scale)), max(1, math.ceil(screen[1] * scale)))
        if size != self.size:
            if self.fbo is not None:
                self.fbo.release()
                self.texture.release()
            self.texture = self.ctx.texture(size, 4)
            self.texture.filter = (moderngl.LINEAR, moderngl.LINEAR)
            self.fbo = self.ctx.framebuffer([self.texture])
            self.size = size
        return self.fbo

    def present(self, screen: moderngl.Framebuffer) -> None:
        program = self.shaders.program("upscale")
        self.texture.use(0)
        if "u_image" in program:
            program["u_image"].value = 0
        screen.use()
        self._vaos.get(program).render(moderngl.TRIANGLES, vertices=3)
