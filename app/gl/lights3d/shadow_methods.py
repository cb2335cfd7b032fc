"""The 3D lights' shadow methods, one ShadowMethod each in METHODS: how its shadow is built (a volume per caster,
with or without caps, or a depth map from the light), how the volumes mark the stencil, and where the light pass
then lights. The renderer, the shadow volume pass and the shadows bench read them here alone; their names are the
model's SHADOW_METHODS (Light3D.shadow: commands, scene files and bench CSVs say them), in the same order.

- onepass (seed 002, closed): the volume of each caster triangle, both faces alike, in one pass: stencil
  NOTEQUAL ref 0xFC, read and write masks 0xFD, sfail KEEP, zfail INVERT, zpass INCR, depth LESS. Bit 1 is never
  written, so from 0 a depth pass gives 1 and a second pass 2 & 0xFD = 0 (INCR toggles bit 0); a depth fail
  gives ~0 & 0xFD = 0xFD and a second one 0 (INVERT toggles 0 <-> 0xFD). One of each, in either order, gives
  0xFC (1 then INVERT: 0xFE & 0xFD; 0xFD then INCR: 0xFE & 0xFD), which equals the reference under the read
  mask, so the test fails from then on and nothing un-shadows it. Shadowed: stencil == 0xFC (SHADOW_VALUE).
  Each triangle's prism is closed at infinity by its far cap (8 triangles), so a view ray that enters it leaves
  it: one pass and one fail where the surface lies inside, two of a kind where it does not. Only the triangles
  turned from the light give one (their prisms' union is a closed caster's shadow: half the fill).
  Like zpass it has no face in front of an eye inside a volume.
- onepass-seed: the seed's own 7 triangles of every caster triangle, open at infinity: where a view ray runs to
  infinity inside a prism (looking along a point light's rays) it counts the entry and never the exit.
- zpass: the silhouette volume without caps, two-sided: front faces INCR_WRAP, back faces DECR_WRAP where the
  depth test passes. Wrong where the eye is inside a volume or the near plane cuts one (Everitt & Kilgard), so
  it is drawn as they describe it, near and far planes clipping.
- zfail (Carmack's reverse): the capped silhouette volume, back faces INCR_WRAP, front faces DECR_WRAP where the
  depth test fails; depth clamping stands in for an infinite far plane.
  Shadowed for zpass and zfail: stencil != 0.
- map: the casters' depth from the light (app/gl/lights3d/shadow_map.py), read with PCF in the light pass.
- none: the light formulas alone; a light shadowed any other way reaches only faces that face it.
"""
from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from app.gl.core.stencil import GL, StencilOps, StencilState
from app.gl.lights3d.shadow_volumes import VolumeGeometry, onepass_volume, silhouette_volume

SHADOW_VALUE = 0xFC  # onepass: a depth pass and a depth fail met here (see above)
# The stencil tests a light pass may make, as GL makes them (ref OP stencil, every bit read), for the mask read back.
_PASSES = {GL.GL_EQUAL: np.equal, GL.GL_NOTEQUAL: np.not_equal}


@dataclass(frozen=True)
class StencilVolumes:
    """A shadow marked in the stencil (cleared to 0 first) by a volume per caster."""
    build: Callable[..., VolumeGeometry]  # (positions, triangles, light vec4, adjacency or None): a caster's volume
    marks: StencilState                   # how the volumes are drawn into the stencil
    lit: tuple[int, int]                  # the stencil test (func, ref) of the pixels the light still reaches

    def __post_init__(self) -> None:
        if self.lit[0] not in _PASSES:
            raise ValueError(f"a light pass's stencil test is EQUAL or NOTEQUAL, got 0x{self.lit[0]:x}")

    def shadowed(self, stencil: np.ndarray) -> np.ndarray:
        """Which of the stencil's values the light pass leaves dark."""
        func, ref = self.lit
        return ~_PASSES[func](stencil, ref)


@dataclass(frozen=True)
class ShadowMethod:
    name: str
    volumes: StencilVolumes | None = None  # a stencil method's volumes
    shadow_map: bool = False               # a depth map drawn from the light, read with PCF

    @property
    def shadows(self) -> bool:
        return self.volumes is not None or self.shadow_map

    @property
    def light_pass(self) -> StencilState:
        """The light pass's state: added where the pre-pass left the surface (depth EQUAL) and the stencil says lit."""
        func, ref = self.volumes.lit if self.volumes else (GL.GL_ALWAYS, 0)
        return StencilState(func=func, ref=ref, write_mask=0, depth_func=GL.GL_EQUAL, colour_write=True)


def _onepass(closed: bool) -> Callable[..., VolumeGeometry]:
    def build(positions, triangles, light, _adjacency) -> VolumeGeometry:
        return onepass_volume(positions, triangles, light, closed)  # one triangle at a time: no adjacency needed
    return build


def _silhouette(caps: bool) -> Callable[..., VolumeGeometry]:
    def build(positions, triangles, light, adjacency) -> VolumeGeometry:
        return silhouette_volume(positions, triangles, light, caps=caps, adjacency=adjacency)
    return build


ONEPASS_MARKS = StencilState(func=GL.GL_NOTEQUAL, ref=SHADOW_VALUE, read_mask=0xFD, write_mask=0xFD,
                             front=StencilOps(GL.GL_KEEP, GL.GL_INVERT, GL.GL_INCR),
                             back=StencilOps(GL.GL_KEEP, GL.GL_INVERT, GL.GL_INCR),
                             depth_clamp=True)  # w = 0 vertices: their depth fails must count, not be clipped
ONEPASS = ShadowMethod("onepass", StencilVolumes(_onepass(closed=True), ONEPASS_MARKS, (GL.GL_NOTEQUAL, SHADOW_VALUE)))
ONEPASS_SEED = ShadowMethod("onepass-seed", StencilVolumes(_onepass(closed=False), ONEPASS_MARKS,
                                                           (GL.GL_NOTEQUAL, SHADOW_VALUE)))
ZPASS = ShadowMethod("zpass", StencilVolumes(
    _silhouette(caps=False),
    StencilState(front=StencilOps(GL.GL_KEEP, GL.GL_KEEP, GL.GL_INCR_WRAP),
                 back=StencilOps(GL.GL_KEEP, GL.GL_KEEP, GL.GL_DECR_WRAP)),
    lit=(GL.GL_EQUAL, 0)))
ZFAIL = ShadowMethod("zfail", StencilVolumes(
    _silhouette(caps=True),
    StencilState(front=StencilOps(GL.GL_KEEP, GL.GL_DECR_WRAP, GL.GL_KEEP),
                 back=StencilOps(GL.GL_KEEP, GL.GL_INCR_WRAP, GL.GL_KEEP), depth_clamp=True),
    lit=(GL.GL_EQUAL, 0)))
MAP = ShadowMethod("map", shadow_map=True)
NONE = ShadowMethod("none")

METHODS = {m.name: m for m in (ONEPASS, ONEPASS_SEED, ZPASS, ZFAIL, MAP, NONE)}
