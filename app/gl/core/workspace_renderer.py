"""Draws whichever workspace is current; shared by the Qt viewport and the headless host. The gl layer's
mapping from a workspace's name to its renderer is RENDERERS."""
from __future__ import annotations

import math

import moderngl

from app.gl.clouds.workspace import CloudsWorkspaceRenderer
from app.gl.core.frame_budget import FrameBudget
from app.gl.core.gl_state import GLStateError, apply_baseline, bound_framebuffer, debug_enabled, problems
from app.gl.lighting2d.workspace import Lighting2DWorkspaceRenderer
from app.gl.lights3d.workspace import Lights3DWorkspaceRenderer
from app.gl.core.renderer_base import WorkspaceRendererBase
from app.gl.core.shaders import ShaderLibrary
from app.gl.snowflake.workspace import SnowflakeWorkspaceRenderer
from app.gl.volume.workspace import VolumeWorkspaceRenderer
from app.model.workspace import WorkspaceMapping
from app.resources import SHADERS

RENDERERS: dict[str, type[WorkspaceRendererBase]] = WorkspaceMapping("RENDERERS (app/gl/core/workspace_renderer.py)", {
    "lighting2d": Lighting2DWorkspaceRenderer,
    "volume": VolumeWorkspaceRenderer,
    "clouds": CloudsWorkspaceRenderer,
    "lights3d": Lights3DWorkspaceRenderer,
    "snowflake": SnowflakeWorkspaceRenderer,
})
EMPTY_BACKGROUND = (0.16, 0.16, 0.18, 1.0)  # while a renderer prepares


class WorkspaceRenderer:
    """One per GL context; each workspace's renderer is made the first time it is shown."""

    def __init__(self, ctx: moderngl.Context, on_shader_error=None, cache_dir=None, debug: bool | None = None) -> None:
        self.ctx = ctx
        self.debug = debug_enabled() if debug is None else debug  # read the state back after every frame
        self.shaders = ShaderLibrary(ctx, [SHADERS], cache_dir=cache_dir, on_error=on_shader_error)
        self.renderers: dict[str, WorkspaceRendererBase] = {}
        self.budgets: dict[str, FrameBudget] = {}
        self._last: WorkspaceRendererBase | None = None  # the one that drew the last frame
        self._last_budget: FrameBudget | None = None

    def render(self, fbo: moderngl.Framebuffer, state, settings, interactive: bool = False,
               budget_ms: float = math.inf, overlays: bool = True) -> bool:
        """Draw `state` (a workspace, app/model/workspace.py) with its `settings`; while `interactive`, at the most
        accurate of its levels that fits `budget_ms` (app/gl/core/frame_budget.py); with the editor's `overlays`
        (its marks over the scene) or the scene alone. True when the frame was reduced or work was put off, so the
        host should ask for a full frame once idle."""
        before = self._check(fbo, f"what ran before the {state.name} frame", state=False)  # the baseline is set next
        previous = self.ctx.fbo  # None in a standalone context that bound none yet
        previous = previous if previous is not None and previous.glo == bound_framebuffer() else None
        apply_baseline(self.ctx, fbo)
        try:
            reduced = self._draw(fbo, state, settings, interactive, budget_ms, overlays)
            problem = self._check(fbo, f"the {state.name} frame")
        finally:
            apply_baseline(self.ctx, fbo)
            if previous is not None and previous.glo != fbo.glo:
                # the host's framebuffer bound again: one it releases later is then never moderngl's bound one,
                # which moderngl binds again after making a framebuffer (a GL error once it is deleted)
                previous.use()
        if before or problem:
            raise GLStateError("; ".join(p for p in (before, problem) if p))
        return reduced

    def _draw(self, fbo: moderngl.Framebuffer, state, settings, interactive: bool, budget_ms: float,
              overlays: bool) -> bool:
        kind = RENDERERS[state.name]
        if state.name not in self.renderers:
            self.renderers[state.name] = kind(self.ctx, self.shaders)
            self.budgets[state.name] = FrameBudget(self.ctx, self.shaders, kind.LEVELS)
        renderer, budget = self._last, self._last_budget = self.renderers[state.name], self.budgets[state.name]
        if not overlays:
            settings = renderer.without_overlays(settings)
        level = budget.choose(interactive, budget_ms)
        if level.cheap:
            settings = renderer.cheaper(settings, level.cheap)
        target = budget.target(fbo)
        put_off = renderer.render(target, state, settings, interactive)
        budget.present(fbo, target)
        return put_off or budget.level > 0

    def _check(self, fbo: moderngl.Framebuffer, what: str, state: bool = True) -> str | None:
        """In debug mode, what `what` left: GL errors queued and, with `state`, state other than the baseline."""
        found = problems(fbo, state) if self.debug else []
        return f"{what} left " + "; ".join(found) if found else None

    def frame_took(self, ms: float) -> None:
        """The host's measure of the frame just drawn, for the frame budget of the renderer that drew it."""
        if self._last_budget is not None:
            self._last_budget.frame_took(ms)

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
        count += sum(b.release() for b in self.budgets.values())
        self.renderers.clear()
        self.budgets.clear()
        self._last = self._last_budget = None
        return count
