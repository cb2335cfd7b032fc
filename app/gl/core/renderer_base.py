"""What every workspace's renderer is: made once per GL context, asked for frames, released with it."""
from __future__ import annotations

from typing import Callable

import moderngl

from app.gl.core.frame_budget import FULL, Level
from app.gl.core.shaders import ShaderLibrary

# What a renderer may own; programs belong to the shared ShaderLibrary and are not released here.
GL_OBJECTS = (moderngl.Buffer, moderngl.VertexArray, moderngl.Texture, moderngl.Texture3D, moderngl.TextureArray,
              moderngl.TextureCube, moderngl.Framebuffer, moderngl.Renderbuffer, moderngl.Sampler, moderngl.Query)


class WorkspaceRendererBase:
    """`render` draws the workspace's state into `fbo` with `settings` (a dataclass its commands build from
    the cvars, or None); it returns True when it drew a reduced frame or put work off, so the host asks for
    a full frame once the user stops (then `idle` does the put-off work).

    LEVELS are the ways it may draw while the user interacts, most accurate first (app/gl/core/frame_budget.py): the
    host picks the first whose measured time fits its budget, draws at its pixel scale, and passes the settings
    through `cheaper` for the level's own saving."""

    LEVELS: tuple[Level, ...] = (FULL, Level(0.5), Level(0.25))

    def __init__(self, ctx: moderngl.Context, shaders: ShaderLibrary) -> None:
        self.ctx, self.shaders = ctx, shaders

    @staticmethod
    def prepare(progress: Callable[[str, float], None] | None = None,
                warn: Callable[[str], None] | None = None) -> None:
        """Make what the renderer needs before its first frame, outside any GL context (once per process;
        the first time on a machine it may take seconds): reports progress(what, fraction done), and says to
        `warn` (else logs) what it had to make again (a damaged cache)."""

    def render(self, fbo: moderngl.Framebuffer, state, settings, interactive: bool = False) -> bool:
        raise NotImplementedError

    def cheaper(self, settings, cheap: int):
        """`settings` with the renderer's own saving number `cheap` (1, 2...: each cheaper) applied."""
        return settings

    def without_overlays(self, settings):
        """`settings` that draw the scene alone, without the editor's marks over it (the volume's slice plane, the
        2D light icons, the 3D lights' markers and gizmo): what `shadelab render` draws unless --overlays. A host
        asks for it (WorkspaceRenderer.render's `overlays`); a workspace that draws no marks keeps its settings."""
        return settings

    def idle(self) -> bool:
        """Work put off while the user interacted; True if a redraw is due."""
        return False

    def settling(self) -> bool:
        """Whether another frame of the unchanged scene would still improve the image (a temporal history
        filling): the host then draws again at once."""
        return False

    def value_at(self, x: float, y: float, size: tuple[int, int]):
        """What the last frame, `size` pixels, shows at pixel (x, y) from its top left, for the status bar (the
        light reaching there, say), or None; with the context current."""
        return None

    def release(self) -> int:
        """Release every GL object this renderer holds (through its attributes and the app.gl objects in
        them), with its context current; returns how many."""
        seen: set[int] = set()

        def walk(value) -> int:
            if id(value) in seen or value is self.shaders:
                return 0
            seen.add(id(value))
            if isinstance(value, GL_OBJECTS):
                value.release()
                return 1
            if isinstance(value, (list, tuple, set)):
                return sum(walk(v) for v in value)
            if isinstance(value, dict):
                return sum(walk(v) for v in value.values())
            if type(value).__module__.startswith("app.gl.") and hasattr(value, "__dict__"):
                return sum(walk(v) for v in vars(value).values())
            return 0

        return walk(self)
