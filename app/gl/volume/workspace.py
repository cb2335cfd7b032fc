"""The volume workspace's renderer: the ray tracer, with fewer steps as the cheaper levels the host's frame
budget may choose while the user interacts, and at full quality once idle (with the exact distance field)."""
from __future__ import annotations

from dataclasses import replace

from app.gl.core.frame_budget import FULL, Level
from app.gl.volume.raytracer import RayTracer
from app.gl.core.renderer_base import WorkspaceRendererBase
from app.model.volume.render_modes import TraceSettings

STEP_FACTORS = (1.0, 0.5, 0.25)  # by the level's `cheap`
MIN_STEPS = 4.0


class VolumeWorkspaceRenderer(WorkspaceRendererBase):
    # fewer pixels cost less accuracy than fewer steps: halve those first
    LEVELS = (FULL, Level(0.5), Level(0.5, 1), Level(0.25, 1), Level(0.25, 2), Level(0.125, 2))

    def __init__(self, ctx, shaders) -> None:
        super().__init__(ctx, shaders)
        self.tracer = RayTracer(ctx, shaders)

    def cheaper(self, settings: TraceSettings, cheap: int) -> TraceSettings:
        return replace(settings, steps=max(MIN_STEPS, settings.steps * STEP_FACTORS[cheap]))

    def without_overlays(self, settings: TraceSettings) -> TraceSettings:
        return replace(settings, slice_planes=False)

    def render(self, fbo, state, settings: TraceSettings, interactive: bool = False) -> bool:
        self.tracer.render(fbo, state.volume.voxels, state.view, settings)
        return self.tracer.distance.stale

    def idle(self) -> bool:
        """The exact distance field, put off while the user edited."""
        return self.tracer.distance.refine()
