"""The clouds' last passes: the linear HDR frame to the output (docs/clouds.md, "Exposure and tone mapping").

With automatic exposure, the frame's mean log2 luminance is reduced on the GPU (a 64x64 target of per-block sums
and pixel counts, mipmapped to one texel: their ratio is the exact mean) and an adapted average follows it, ADAPT
of the way a frame (all of it at a restart), in a 1x1 target; the tone-map pass reads it there, so nothing is
read back to draw a frame. Then exposure, the curve and sRGB encoding (resources/shaders/tone_map.shl).

It runs after every pass of the clouds and binds all it reads before each of its own, so it hands out its own
texture units (the clouds' samplers keep theirs: the next frame binds the noise again before it reads it)."""
from __future__ import annotations

import math

import moderngl
import numpy as np

from app.gl.core.texture_units import TextureUnits
from app.gl.core.uniforms import set_uniforms
from app.gl.core.vertex_arrays import VertexArrays
from app.model.clouds.exposure import (ADAPT, AUTO_RANGE, KEY, MIN_LUMINANCE, SETTLED_EV, TONE_MAPS,
                                       ToneSettings)

CELLS = 64  # the reduction's blocks per axis (a power of 2: each mipmap level halves it exactly)


class ToneMap:
    def __init__(self, ctx: moderngl.Context, shaders) -> None:
        self.ctx, self.shaders = ctx, shaders
        self.units = TextureUnits()
        self._screen = VertexArrays(lambda program: ctx.vertex_array(program, []))
        self._sums = ctx.texture((CELLS, CELLS), 2, dtype="f4")
        self._sums_fbo = ctx.framebuffer([self._sums])
        self._averages = [ctx.texture((1, 1), 2, dtype="f4") for _ in range(2)]
        self._average_fbos = [ctx.framebuffer([t]) for t in self._averages]
        for t in self._averages:
            t.filter = (moderngl.NEAREST, moderngl.NEAREST)
        self._current = 0       # which of the two holds the last average
        self._adapting = False  # the last frame was exposed automatically (its average is there to follow)

    def _draw(self, name: str, fbo: moderngl.Framebuffer, **values) -> None:
        program = self.shaders.program(name)
        set_uniforms(program, values)
        fbo.use()
        self._screen.get(program).render(moderngl.TRIANGLES, vertices=3)

    def apply(self, hdr: moderngl.Texture, fbo: moderngl.Framebuffer, tone: ToneSettings, restart: bool) -> None:
        """Draw `hdr` (linear radiance, the output's size) into `fbo`; `restart`: the scene changed, so the
        exposure takes the frame's average at once rather than adapting to it."""
        if tone.auto:
            self._average(hdr, 1.0 if restart or not self._adapting else ADAPT)
        self._adapting = tone.auto
        self._draw("clouds_tone_map", fbo, **self.units.bind(u_hdr=hdr, u_average=self._averages[self._current]),
                   u_auto=int(tone.auto), u_ev=tone.ev, u_key=math.log2(KEY), u_auto_range=AUTO_RANGE,
                   u_curve=TONE_MAPS.index(tone.curve))

    def _average(self, hdr: moderngl.Texture, adapt: float) -> None:
        self._draw("clouds_luminance", self._sums_fbo, **self.units.bind(u_hdr=hdr), u_cells=(CELLS, CELLS),
                   u_min_luminance=MIN_LUMINANCE)
        self._sums.build_mipmaps()
        self._sums.filter = (moderngl.NEAREST_MIPMAP_NEAREST, moderngl.NEAREST)  # every level fetched as it is
        last, self._current = self._current, 1 - self._current
        self._draw("clouds_exposure", self._average_fbos[self._current],
                   **self.units.bind(u_sums=self._sums, u_average=self._averages[last]),
                   u_top=int(math.log2(CELLS)), u_adapt=adapt)

    def averages(self) -> tuple[float, float]:
        """(adapted, the last frame's) mean log2 luminance, read back: what automatic exposure used."""
        adapted, frame = np.frombuffer(self._averages[self._current].read(), dtype="f4")
        return float(adapted), float(frame)

    def settling(self) -> bool:
        """Whether the adapted exposure is still on its way to the last frame's (automatic exposure only)."""
        if not self._adapting:
            return False
        adapted, frame = self.averages()
        return abs(adapted - frame) > SETTLED_EV
