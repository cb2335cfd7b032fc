"""The volume workspace's renderer: the ray tracer, drawn while the user interacts at the most accurate
level that fits the frame budget, and at full quality once idle (with the exact distance field)."""
from __future__ import annotations

from dataclasses import replace

from app.gl.quality import LEVELS, QualityLadder, ReducedTarget
from app.gl.raytracer import RayTracer
from app.gl.renderer_base import WorkspaceRendererBase
from app.model.render_modes import TraceSettings


class VolumeWorkspaceRenderer(WorkspaceRendererBase):
    def __init__(self, ctx, shaders) -> None:
        super().__init__(ctx, shaders)
        self.tracer = RayTracer(ctx, shaders)
        self.ladder = QualityLadder()
        self.level = 0  # the quality level of the last frame drawn
        self.reduced: ReducedTarget | None = None

    def render(self, fbo, state, settings: TraceSettings, interactive: bool = False) -> bool:
        self.level = self.ladder.choose(settings.frame_budget_ms) if interactive else 0
        scale, step_factor = LEVELS[self.level]
        if scale == 1.0:
            self.tracer.render(fbo, state.volume, state.view, settings)
        else:
            if self.reduced is None:
                self.reduced = ReducedTarget(self.ctx, self.shaders)
            cheap = replace(settings, steps=max(4.0, settings.steps * step_factor))
            self.tracer.render(self.reduced.framebuffer(fbo.size, scale), state.volume, state.view, cheap)
            self.reduced.present(fbo)
        return self.level > 0 or self.tracer.distance.stale

    def frame_took(self, ms: float, interactive: bool) -> None:
        """Teaches the ladder what each level costs."""
        if interactive:
            self.ladder.record(self.level, ms)

    def idle(self) -> bool:
        """The exact distance field, put off while the user edited."""
        return self.tracer.distance.refine()
