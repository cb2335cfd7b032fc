"""The host's frame budget (docs/architecture.md rule 9): while the user drags, orbits or plays, each workspace draws at
the most accurate of its declared levels whose measured time fits the budget, and refines once still.

A level is a share of the screen's pixels (drawn into a reduced target and stretched back) and a saving of the
renderer's own, which it applies to its settings (`WorkspaceRendererBase.cheaper`: fewer steps, a cheaper
shadow formula, a smaller cloud buffer)."""
from __future__ import annotations

import math
from dataclasses import dataclass

import moderngl

from app.gl.core.texture_units import TextureUnits
from app.gl.core.uniforms import set_uniforms
from app.gl.core.vertex_arrays import VertexArrays

SMOOTHING = 0.5  # weight of the newest frame time in each level's running estimate


@dataclass(frozen=True)
class Level:
    scale: float = 1.0  # pixels drawn per screen pixel, along each axis
    cheap: int = 0      # the renderer's own saving: 0 none, each step cheaper (its `cheaper` says how)


FULL = Level()


class QualityLadder:
    """Remembers how long each level took here and picks the first that fits the budget."""

    def __init__(self, levels: int) -> None:
        self.ms: list[float | None] = [None] * levels

    def choose(self, budget_ms: float) -> int:
        for i, ms in enumerate(self.ms):
            if ms is None or ms <= budget_ms:  # an unmeasured level is tried once its better one was too slow
                return i
        return len(self.ms) - 1

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
        self.units = TextureUnits()

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
        set_uniforms(program, self.units.bind(u_image=self.texture))
        screen.use()
        self._vaos.get(program).render(moderngl.TRIANGLES, vertices=3)

    def release(self) -> int:
        self._vaos.release()
        held = [o for o in (self.fbo, self.texture) if o is not None]
        for obj in held:
            obj.release()
        self.fbo = self.texture = self.size = None
        return len(held)


class FrameBudget:
    """One workspace renderer's ladder over its levels, and the reduced target its cheaper frames go into."""

    def __init__(self, ctx: moderngl.Context, shaders, levels: tuple[Level, ...]) -> None:
        self.levels = levels
        self.ladder = QualityLadder(len(levels))
        self.reduced = ReducedTarget(ctx, shaders)
        self.level = 0  # the level of the last frame drawn

    def choose(self, interactive: bool, budget_ms: float) -> Level:
        self.level = self.ladder.choose(budget_ms) if interactive else 0
        return self.levels[self.level]

    def target(self, screen: moderngl.Framebuffer) -> moderngl.Framebuffer:
        """Where the chosen level draws: the screen, or the reduced target (present() then stretches it)."""
        scale = self.levels[self.level].scale
        return screen if scale == 1.0 else self.reduced.framebuffer(screen.size, scale)

    def present(self, screen: moderngl.Framebuffer, drawn: moderngl.Framebuffer) -> None:
        if drawn is not screen:
            self.reduced.present(screen)

    def release(self) -> int:
        return self.reduced.release()

    def frame_took(self, ms: float) -> None:
        """Every frame teaches the ladder (a still frame is level 0's measure, so a drag starts where it fits)."""
        self.ladder.record(self.level, ms)
