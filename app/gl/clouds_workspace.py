"""The clouds workspace's renderer: its model's frame through the cloud renderer; it keeps asking for
frames while its temporal histories fill (TAA, reprojection)."""
from __future__ import annotations

from dataclasses import replace

from app.gl.clouds import CloudRenderer
from app.gl.renderer_base import WorkspaceRendererBase
from app.io.cloud_textures import noise_textures
from app.model.clouds import CloudRenderSettings

INTERACTIVE_DOWNSAMPLE = 4


class CloudsWorkspaceRenderer(WorkspaceRendererBase):
    def __init__(self, ctx, shaders) -> None:
        super().__init__(ctx, shaders)
        self.clouds = CloudRenderer(ctx, shaders)
        self._settling = False

    @staticmethod
    def prepare(progress=None) -> None:
        noise_textures(progress)

    def render(self, fbo, state, settings: CloudRenderSettings, interactive: bool = False) -> bool:
        # Hosts call prepare() first, with a progress bar; one that did not waits for the textures here.
        noise = noise_textures()
        if interactive:  # while the view moves: a quarter-size buffer, reprojected through the turn if the
            # settings reproject, with no TAA; the full frame after
            settings = replace(settings, downsample=max(settings.downsample, INTERACTIVE_DOWNSAMPLE), taa=False)
        self.clouds.render(fbo, state.frame(), state.weather, settings, noise)
        self._settling = not interactive and self.clouds.settling(settings)
        return interactive

    def settling(self) -> bool:
        return self._settling
