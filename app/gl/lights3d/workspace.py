"""The 3D lights workspace's renderer: its scene, camera and selection through the lights renderer, with the
render settings its commands build (shadow map size, PCF kernel, bias)."""
from __future__ import annotations

from dataclasses import replace

from app.gl.lights3d.renderer import Lights3DRenderer
from app.gl.core.renderer_base import WorkspaceRendererBase
from app.model.lights3d.render_settings import Lights3DRenderSettings


class Lights3DWorkspaceRenderer(WorkspaceRendererBase):
    def __init__(self, ctx, shaders) -> None:
        super().__init__(ctx, shaders)
        self.lights = Lights3DRenderer(ctx, shaders)

    def render(self, fbo, state, settings, interactive: bool = False) -> bool:
        self.lights.render(fbo, state.scene, state.camera, settings, state.selection,
                           marks=settings is None or settings.overlays)
        return False  # every frame is whole: volumes and maps are kept, not reduced, while the view moves

    def without_overlays(self, settings: Lights3DRenderSettings | None) -> Lights3DRenderSettings:
        return replace(settings or Lights3DRenderSettings(), overlays=False)

