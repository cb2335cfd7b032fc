"""Draws whichever workspace is current; shared by the Qt viewport and the headless host."""
from __future__ import annotations

import moderngl

from dataclasses import replace

from app.gl.lighting2d import Lighting2DRenderer, Shading2D
from app.gl.lighting2d_overlay import Lighting2DOverlay
from app.gl.shaders import ShaderLibrary
from app.gl.snowflake import SnowflakeRenderer

from app.gl.quality import LEVELS, QualityLadder, ReducedTarget
from app.gl.raytracer import RayTracer, TraceSettings
from app.model.render_modes import LIGHTS
from app.resources import SHADERS

EMPTY_BACKGROUND = (0.16, 0.16, 0.18, 1.0)


def shading_settings(editor) -> Shading2D:
    """The 2D renderer's settings from the editor's cvars."""
    cvars = editor.console.registry.cvars
    return Shading2D(method=cvars["r_shadowMethod"].value, samples=cvars["r_shadowSamples"].value,
                     blur=cvars["r_shadowBlur"].value, lightmap_scale=cvars["r_lightmapScale"].value,
                     flip_y=cvars["r_flipY"].value, normal_maps=cvars["r_normalMaps"].value)


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
        self._lighting: Lighting2DRenderer | None = None
        self._overlay: Lighting2DOverlay | None = None
        self.ladder = QualityLadder()
        self.level = 0  # the quality level of the last frame drawn
        self._reduced: ReducedTarget | None = None

    def render(self, editor, fbo: moderngl.Framebuffer, interactive: bool = False) -> bool:
        """`editor` holds the models (app.editor.Editor); only attributes are read here. While the user
        interacts, the volume is drawn at the most accurate level that fits `r_frameBudgetMs`. True when the
        frame was reduced or work was put off, so the host should ask for a full frame once idle."""
        self.level = 0
        if editor.workspace == "snowflake":
            if self._snowflake is None:
                self._snowflake = SnowflakeRenderer(self.ctx, self.shaders)
            self._snowflake.render(fbo, editor.snowflake, editor.snowflake_camera)
        elif editor.workspace == "lighting2d":
            if self._lighting is None:
                self._lighting = Lighting2DRenderer(self.ctx, self.shaders)
                self._overlay = Lighting2DOverlay(self.ctx, self.shaders)
            settings = shading_settings(editor)
            self._lighting.render(fbo, editor.lighting, editor.lighting_camera, settings)
            debug = editor.console.registry.cvars["r_debug2d"].value
            self._overlay.draw(fbo, editor.lighting, editor.lighting_camera, settings.flip_y, debug,
                               editor.lighting_selection, editor.lighting_pending)
        elif editor.workspace == "volume":
            if self._volume is None:
                self._volume = RayTracer(self.ctx, self.shaders)
            settings = trace_settings(editor)
            budget = editor.console.registry.cvars["r_frameBudgetMs"].value
            self.level = self.ladder.choose(budget) if interactive else 0
            scale, step_factor = LEVELS[self.level]
            if scale == 1.0:
                self._volume.render(fbo, editor.volume, editor.volume_view, settings)
            else:
                if self._reduced is None:
                    self._reduced = ReducedTarget(self.ctx, self.shaders)
                cheap = replace(settings, steps=max(4.0, settings.steps * step_factor))
                self._volume.render(self._reduced.framebuffer(fbo.size, scale), editor.volume, editor.volume_view,
                                    cheap)
                self._reduced.present(fbo)
            return self.level > 0 or self._volume.distance.stale
        else:
            fbo.use()
            fbo.clear(*EMPTY_BACKGROUND)
        return False

    def frame_took(self, ms: float, interactive: bool) -> None:
        """The host's measure of the frame just drawn: teaches the ladder what each level costs."""
        if interactive:
            self.ladder.record(self.level, ms)

    def idle(self) -> bool:
        """Work put off while the user interacted (the exact distance field); True if a redraw is due."""
        return self._volume is not None and self._volume.distance.refine()
