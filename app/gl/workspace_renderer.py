"""Draws whichever workspace is current; shared by the Qt viewport and the headless host. The gl layer's
mapping from a workspace's name to its renderer is RENDERERS."""
from __future__ import annotations

import moderngl

from app.gl.clouds_workspace import CloudsWorkspaceRenderer
from app.gl.lighting2d_workspace import Lighting2DWorkspaceRenderer
from app.gl.lights3d_workspace import Lights3DWorkspaceRenderer
from app.gl.renderer_base import WorkspaceRendererBase
from app.gl.shaders import ShaderLibrary
from app.gl.snowflake_workspace import SnowflakeWorkspaceRenderer
from app.gl.volume_workspace import VolumeWorkspaceRenderer
from app.resources import SHADERS

RENDERERS: dict[str, type[WorkspaceRendererBase]] = {
    "lighting2d": Lighting2DWorkspaceRenderer,
    "volume": VolumeWorkspaceRenderer,
    "clouds": CloudsWorkspaceRenderer,
    "lights3d": Lights3DWorkspaceRenderer,
    "snowflake": SnowflakeWorkspaceRenderer,
}
EMPTY_BACKGROUND = (0.16, 0.16, 0.18, 1.0)


class WorkspaceRenderer:
    """One per GL context; each workspace's renderer is made the first time it is shown."""

    def __init__(self, ctx: moderngl.Context, on_shader_error=None, cache_dir=None) -> None:
        self.ctx = ctx
        self.shaders = ShaderLibrary(ctx, [SHADERS], cache_dir=cache_dir, on_error=on_shader_error)
        self.renderers: dict[str, WorkspaceRendererBase] = {}
        self._last: WorkspaceRendererBase | None = None  # the one that drew the last frame

    def render(self, fbo: moderngl.Framebuffer, state, settings, interactive: bool = False) -> bool:
        """Draw `state` (a workspace, app/model/workspace.py) with its `settings`. True when the frame was
        reduced or work was put off, so the host should ask for a full frame once idle."""
        kind = RENDERERS.get(state.name)
        if kind is None:
            fbo.use()
            fbo.clear(*EMPTY_BACKGROUND)
            self._last = None
            return False
        if state.name not in self.renderers:
            self.renderers[state.name] = kind(self.ctx, self.shaders)
        self._last = self.renderers[state.name]
        return self._last.render(fbo, state, settings, interactive)

    def frame_took(self, ms: float, interactive: bool) -> None:
        """The host's measure of the frame just drawn, for the renderer that drew it."""
        if self._last is not None:
            self._last.frame_took(ms, interactive)

    def value_at(self, x: float, y: float, size: tuple[int, int]):
        """What the last frame shows at a pixel (WorkspaceRendererBase.value_at), or None."""
        return None if self._last is None else self._last.value_at(x, y, size)

    def settling(self) -> bool:
        """The last frame's renderer would still improve an unchanged scene with another frame."""
        return self._last is not None and self._last.settling()

    def idle(self) -> bool:
        """Work any renderer put off while the user interacted; True if a redraw is due."""
        return any([r.idle() for r in self.renderers.values()])

    def release(self) -> int:
        """Release every renderer's GL objects (the context current); returns how many."""
        count = sum(r.release() for r in self.renderers.values())
        self.renderers.clear()
        self._last = None
        return count
