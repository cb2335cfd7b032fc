"""The clouds workspace's renderer: its model's frame through the cloud renderer; it keeps asking for
frames while its temporal histories fill (TAA, reprojection) and its automatic exposure adapts. Its cheaper
levels trace a smaller cloud buffer and fewer steps into the reprojected picture (the cheapest a half-size one)
under the full-size composite: none draws fewer pixels, so the ground and the horizon stay exact and a drag goes
on from the picture through the levels (the host's reduced target would stretch the horizon over the ground and
restart the history)."""
from __future__ import annotations

from dataclasses import replace

from app.gl.clouds.renderer import CloudRenderer
from app.gl.core.frame_budget import FULL, Level
from app.gl.core.renderer_base import WorkspaceRendererBase
from app.io.clouds.textures import noise_textures
from app.model.clouds.scene import CloudRenderSettings

# By the level's `cheap`: the cloud buffer's least reduction (of the reprojected picture), the share of the steps,
# and the reprojected picture's reduction.
SAVINGS = ((1, 1, 1), (2, 1, 1), (4, 1, 1), (4, 0.5, 1), (8, 0.5, 1), (8, 0.25, 1), (4, 0.25, 2))
MIN_STEPS = 8
CHEAPEST = len(SAVINGS) - 1


class CloudsWorkspaceRenderer(WorkspaceRendererBase):
    LEVELS = (FULL, *(Level(1.0, cheap) for cheap in range(1, CHEAPEST + 1)))

    def __init__(self, ctx, shaders) -> None:
        super().__init__(ctx, shaders)
        self.clouds = CloudRenderer(ctx, shaders)
        self._settling = False

    @staticmethod
    def prepare(progress=None, warn=None) -> None:
        noise_textures(progress, warn=warn)

    def cheaper(self, settings: CloudRenderSettings, cheap: int) -> CloudRenderSettings:
        down, steps, picture = SAVINGS[cheap]
        if not settings.reproject:  # no reprojected picture: the stretched buffer is reduced as far instead
            down, picture = down * picture, 1
        return replace(settings, downsample=max(settings.downsample, down),
                       steps=max(MIN_STEPS, round(settings.steps * steps)), reproject_downsample=picture)

    def render(self, fbo, state, settings: CloudRenderSettings, interactive: bool = False) -> bool:
        # Hosts call prepare() first, with a progress bar; one that did not waits for the textures here.
        noise = noise_textures()
        if interactive:  # while the view moves no TAA (its history would ghost); reprojection, if the settings
            # ask for it, follows the turn; the full frame after
            settings = replace(settings, taa=False)
        self.clouds.render(fbo, state.frame(), state.weather, settings, noise)
        self._settling = not interactive and self.clouds.settling(settings)
        return interactive

    def settling(self) -> bool:
        return self._settling
