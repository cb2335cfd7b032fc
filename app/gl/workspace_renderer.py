"""Draws whichever workspace is current; shared by the Qt viewport and the headless host."""
from __future__ import annotations

import moderngl

from app.gl.shaders import ShaderLibrary
from app.gl.snowflake import SnowflakeRenderer
from app.gl.volume import VolumeRenderer
from app.resources import SHADERS

EMPTY_BACKGROUND = (0.16, 0.16, 0.18, 1.0)


class WorkspaceRenderer:
    """One per GL context; each technique's renderer is created the first time it is shown."""

    def __init__(self, ctx: moderngl.Context, on_shader_error=None, cache_dir=None) -> None:
        self.ctx = ctx
        self.shaders = ShaderLibrary(ctx, [SHADERS], cache_dir=cache_dir, on_error=on_shader_error)
        self._snowflake: SnowflakeRenderer | None = None
        self._volume: VolumeRenderer | None = None

    def render(self, editor, fbo: moderngl.Framebuffer) -> None:
        """`editor` holds the models (app.editor.Editor); only attributes are read here."""
        if editor.workspace == "snowflake":
            if self._snowflake is None:
                self._snowflake = SnowflakeRenderer(self.ctx, self.shaders)
            self._snowflake.render(fbo, editor.snowflake, editor.snowflake_camera)
        elif editor.workspace == "volume":
            if self._volume is None:
                self._volume = VolumeRenderer(self.ctx, self.shaders)
            steps = editor.console.registry.cvars["cl_steps"].value
            self._volume.render(fbo, editor.volume, editor.volume_view, steps)
        else:
            fbo.use()
            fbo.clear(*EMPTY_BACKGROUND)
