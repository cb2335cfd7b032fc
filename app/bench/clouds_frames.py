"""What the clouds bench draws (app/bench/clouds.py measures it, app/bench/clouds_report.py times some of it again
and reports): the scene, the renderer settings compared (every optimisation off, each added in turn in Figure 39's
order, all of them) and a cloud renderer drawing steady frames into float targets."""
from __future__ import annotations

from dataclasses import dataclass, field, replace
from functools import cached_property

import numpy as np

from app.model.clouds.scene import CloudParams, CloudRenderSettings, CloudTextures, CloudView, frame

MAX_SETTLE = 32  # frames drawn at most before timing, until the temporal histories are full

# Every optimisation off: the image the others are measured against.
NONE = CloudRenderSettings(downsample=1, jitter=False, taa=False, early_exit=False, big_steps=False,
                           light_skip=False, detail_skip=False, reproject=False)
# Figure 39's order: (label, the settings it switches on)
OPTIMISATIONS: tuple[tuple[str, dict], ...] = (
    ("early exit", {"early_exit": True}),
    ("big steps", {"big_steps": True}),
    ("light skip", {"light_skip": True}),
    ("detail skip", {"detail_skip": True}),
    ("buffer 1/4", {"downsample": 4}),  # Guerrilla's: reprojection below fills it in over 16 frames
    ("jitter+TAA", {"jitter": True, "taa": True}),
    ("reprojection", {"reproject": True}),
)
ALL = replace(NONE, **{k: v for _label, changes in OPTIMISATIONS for k, v in changes.items()})
# Optimisations that can only take texture lookups away (the others move or re-take samples).
SAVING = ("early exit", "light skip", "detail skip", "buffer 1/4")
BUFFERS = {1: "buffer 1", 2: "buffer 1/2", 3: "buffer 1/3", 4: "buffer 1/4"}
# All the optimisations but the ones that cost the most accuracy: where the error of `all` comes from.
ALL_BUT = {"all but reprojection": {"reproject": False},
           "all but big steps": {"big_steps": False}}


def stages() -> list[tuple[str, str, CloudRenderSettings]]:
    """Figure 39: (step label, CSV method, settings), none first, then each optimisation added in turn; the
    first step is the `only early exit` row and the last the `all` row (one measurement each)."""
    out = [("none", "none", NONE)]
    settings = NONE
    for i, (label, changes) in enumerate(OPTIMISATIONS):
        settings = replace(settings, **changes)
        method = "only " + label if i == 0 else "all" if i == len(OPTIMISATIONS) - 1 else "+ " + label
        out.append(("+ " + label, method, settings))
    return out


@dataclass(eq=False)  # hashed by identity: the CPU reference's cache keys on it
class CloudScene:
    """What a frame shows: the model, the view, the weather (a WeatherBlend), the clock's wind and blend."""
    name: str
    params: CloudParams = field(default_factory=CloudParams)
    view: CloudView = field(default_factory=CloudView)
    wind_time: float = 0.0

    @cached_property
    def weather(self):
        from app.model.clouds.workspace import CloudsWorkspace

        return CloudsWorkspace().weather  # the workspace's first map, made on first use

    def frame(self):
        return frame(self.params, self.view, self.wind_time, 1.0)

    def textures(self) -> CloudTextures:
        from app.io.clouds.textures import noise_textures

        noise = noise_textures()
        return CloudTextures(noise.shape, noise.detail, noise.curl, noise.cirrus, *self.weather.maps)


class FloatTarget:
    """An RGBA float32 colour target, read back top row first."""

    def __init__(self, ctx, size: tuple[int, int]) -> None:
        self.size = size
        self.texture = ctx.texture(size, 4, dtype="f4")
        self.fbo = ctx.framebuffer([self.texture])

    def read(self) -> np.ndarray:
        w, h = self.size
        return np.frombuffer(self.texture.read(), dtype="f4").reshape(h, w, 4)[::-1].copy()

    def release(self) -> None:
        self.fbo.release()
        self.texture.release()


class Shared:
    """One shader library per GL context for all the methods of a run (the clouds' programs compile once)."""

    def __init__(self) -> None:
        self.ctx = None
        self.library = None

    def shaders(self, ctx):
        if self.ctx is not ctx:
            from app.gl.core.shaders import ShaderLibrary
            from app.resources import SHADERS

            self.ctx, self.library = ctx, ShaderLibrary(ctx, [SHADERS])
        return self.library


class CloudState:
    """One cloud renderer (its own histories) drawing into its own float targets."""

    def __init__(self, ctx, shared: Shared) -> None:
        from app.gl.clouds.renderer import CloudRenderer

        self.ctx = ctx
        self.renderer = CloudRenderer(ctx, shared.shaders(ctx))
        self.targets: dict[tuple, FloatTarget] = {}
        self.settled = None      # (settings, size) the histories are full for
        self.output = None       # the last image read (H, W, 3)

    def target(self, size: tuple[int, int], name: str = "colour") -> FloatTarget:
        t = self.targets.get((name, size))
        if t is None:
            t = self.targets[(name, size)] = FloatTarget(self.ctx, size)
        return t

    def draw(self, scene: CloudScene, settings: CloudRenderSettings, size: tuple[int, int],
             name: str = "colour") -> FloatTarget:
        from app.io.clouds.textures import noise_textures

        target = self.target(size, name)
        self.renderer.render(target.fbo, scene.frame(), scene.weather, settings, noise_textures())
        return target

    def steady(self, scene: CloudScene, settings: CloudRenderSettings, size: tuple[int, int]) -> None:
        """One frame, after enough frames that a still camera's histories are full (first call per setting)."""
        if self.settled != (settings, size):
            for _ in range(MAX_SETTLE):
                self.draw(scene, settings, size)
                if not self.renderer.settling(settings):
                    break
            self.settled = (settings, size)
        self.draw(scene, settings, size)

    def image(self, size: tuple[int, int]) -> np.ndarray:
        """The last frame's linear radiance (before its tone map), top row first: what the CPU reference renders."""
        hdr = self.renderer.last_hdr
        assert hdr.size == tuple(size), "image() reads the frame last drawn, at its size"
        self.output = np.frombuffer(hdr.read(), dtype="f4").reshape(size[1], size[0], 4)[::-1, :, :3].astype(np.float64)
        return self.output

    def samples(self, scene: CloudScene, settings: CloudRenderSettings, size: tuple[int, int]
                ) -> tuple[float, np.ndarray]:
        """(lookups per output pixel, the r_cloudDebugSamples view as grey uint8) of one more steady frame."""
        debug = self.draw(scene, replace(settings, debug_samples=True), size, "debug")
        grey = np.round(np.clip(debug.read()[..., 0], 0.0, 1.0) * 255).astype(np.uint8)
        return self.renderer.lookups(size, scene.frame(), settings), grey
