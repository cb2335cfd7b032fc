"""Draws whichever workspace is current; shared by the Qt viewport and the headless host."""
from __future__ import annotations

import moderngl

from app.gl.shaders import ShaderLibrary
from app.gl.snowflake import SnowflakeRenderer
from app.gl.raytracer import RayTracer, TraceSettings
from app.model.render_modes import LIGHTS
from app.resources import SHADERS

EMPTY_BACKGROUND = (0.16, 0.16, 0.18, 1.0)


def trace_settings(editor) -> TraceSettings:
    """The ray tracer's settings from the editor's cvars and view."""
    cvars = editor.console.registry.cvars
    view = editor.volume_view
    return TraceSettings(mode=view.mode, steps=cvars["cl_steps"].value, shadow_steps=cvars["cl_shadowSteps"].value,
                         sample_range=cvars["cl_sampleRange"].value, distance_scale=cvars["cl_distanceScale"].value,
                         shadows=view.shadows, lights=(view.light, *LIGHTS[1:]))


class WorkspaceRenderer:
    """One per GL context; each technique's renderer is created the first time it is shown."""

    def __init__(self, ctx: moderngl.Context, on_shader_error=None, cache_dir=None) -> None:
        self.ctx = ctx
        self.shaders = ShaderLibrary(ctx, [SHADERS], cache_dir=cache_dir, on_error=on_shader_error)
        self._snowflake: SnowflakeRenderer | None = None
        self._volume: RayTracer | None = None

    def render(self, editor, fbo: moderngl.Framebuffer) -> None:
        """`editor` holds the models (app.editor.Editor); only attributes are read here."""
        if editor.workspace == "snowflake":
            if self._snowflake is None:
                self._snowflake = SnowflakeRenderer(self.ctx, self.shaders)
            self._snowflake.render(fbo, editor.snowflake, editor.snowflake_camera)
        elif editor.workspace == "volume":
            if self._volume is None:
                self._volume = RayTracer(self.ctx, self.shaders)
            self._volume.render(fbo, editor.volume, editor.volume_view, trace_settings(editor))
        else:
            fbo.use()
            fbo.clear(*EMPTY_BACKGROUND)
