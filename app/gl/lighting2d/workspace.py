"""The 2D lighting workspace's renderer: the lit scene, then the editor's overlay (selection, handles,
the hull being drawn, and the debug wireframe). While the user works and a frame would miss the host's budget,
the shadows take the penumbra formula (one pass of wedges a light), then fewer pixels."""
from __future__ import annotations

from dataclasses import replace

from app.gl.core.frame_budget import FULL, Level
from app.gl.lighting2d.renderer import Lighting2DRenderer
from app.gl.lighting2d.overlay import Lighting2DOverlay
from app.gl.core.renderer_base import WorkspaceRendererBase
from app.model.lighting2d.scene import Shading2D


class Lighting2DWorkspaceRenderer(WorkspaceRendererBase):
    LEVELS = (FULL, Level(1.0, 1), Level(0.5, 1), Level(0.25, 1))

    def __init__(self, ctx, shaders) -> None:
        super().__init__(ctx, shaders)
        self.lighting = Lighting2DRenderer(ctx, shaders)
        self.overlay = Lighting2DOverlay(ctx, shaders)

    def cheaper(self, settings: Shading2D, cheap: int) -> Shading2D:
        return settings if settings.method == "hard" else replace(settings, method="penumbra")

    def render(self, fbo, state, settings: Shading2D, interactive: bool = False) -> bool:
        index = state.index()  # the workspace's, which its tool's clicks share
        self.lighting.render(fbo, state.scene, state.camera, settings, index=index)
        self.overlay.draw(fbo, state.scene, index, state.camera, settings.flip_y, settings.debug, state.selection,
                          state.pending, state.pending_cursor, marks=settings.overlays)
        return False

    def without_overlays(self, settings: Shading2D) -> Shading2D:
        return replace(settings, overlays=False)

    def value_at(self, x: float, y: float, size: tuple[int, int]):
        return self.lighting.lightmap_value(x, y, size)
