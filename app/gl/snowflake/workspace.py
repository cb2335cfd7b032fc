"""The snowflake workspace's renderer: the Koch flakes of its scene through its 2D camera."""
from __future__ import annotations

from app.gl.core.renderer_base import WorkspaceRendererBase
from app.gl.snowflake.renderer import SnowflakeRenderer


class SnowflakeWorkspaceRenderer(WorkspaceRendererBase):
    def __init__(self, ctx, shaders) -> None:
        super().__init__(ctx, shaders)
        self.flakes = SnowflakeRenderer(ctx, shaders)

    def render(self, fbo, state, settings=None, interactive: bool = False) -> bool:
        self.flakes.render(fbo, state.scene, state.camera)
        return False
