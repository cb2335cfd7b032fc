"""Shadow volumes into the stencil of a framebuffer whose depth already holds the scene, for one light, and the
in-shadow mask read back. Three methods:

- onepass (seed 002): the 7-triangle volume of every caster triangle, both faces alike, in one pass: stencil
  NOTEQUAL ref 0xFC, read and write masks 0xFD, sfail KEEP, zfail INVERT, zpass INCR, depth LESS. Bit 1 is never
  written, so from 0 a depth pass gives 1 and a second pass 2 & 0xFD = 0 (INCR toggles bit 0); a depth fail
  gives ~0 & 0xFD = 0xFD and a second one 0 (INVERT toggles 0 <-> 0xFD). One of each, in either order, gives
  0xFC (1 then INVERT: 0xFE & 0xFD; 0xFD then INCR: 0xFE & 0xFD), which equals the reference under the read
  mask, so the test fails from then on and nothing un-shadows it. Shadowed: stencil == 0xFC (SHADOW_VALUE).
  Within one caster triangle's 7 any order gives the same stencil, as the seed claims; the volumes of a mesh's
  triangles overlap, though, and interleaving their triangles can lock a pixel early (measured in
  tests/test_shadow_volumes_gl.py), so they are drawn as built, each triangle's 7 together. Like zpass it
  has no face in front of an eye inside a volume.
- zpass: the silhouette volume without caps, two-sided: front faces INCR_WRAP, back faces DECR_WRAP where the
  depth test passes. Wrong where the eye is inside a volume or the near plane cuts one (Everitt & Kilgard), so
  it is drawn as they describe it, near and far planes clipping.
- zfail (Carmack's reverse): the capped silhouette volume, back faces INCR_WRAP, front faces DECR_WRAP where the
  depth test fails; depth clamping stands in for an infinite far plane.
Shadowed for zpass and zfail: stencil != 0. A pixel the scene left at depth 1 (no surface) is never in shadow.

Depth LESS must fail where a cap or caster triangle lies on the scene's own surface: draw the scene's depth
with `draw_depth` (the same vertex shader) or a shader declaring `invariant gl_Position` with the same
`u_view_proj * position`."""
from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass

import moderngl
import numpy as np

from app.gl.lights3d.shadow_volumes import VolumeGeometry, onepass_volume, silhouette_volume
from app.gl.core.stencil import GL, StencilOps, StencilState, StencilTarget, clear_stencil, stencil_state
from app.gl.lights3d.shadow_volume_buffers import VolumeBuffer
from app.model.lights3d.mesh import Adjacency
from app.model.transforms import gl_matrix

PROGRAM = "shadow_volume"
SHADOW_VALUE = 0xFC  # onepass: a depth pass and a depth fail met here (see above)

STATES = {
    "onepass": StencilState(func=GL.GL_NOTEQUAL, ref=SHADOW_VALUE, read_mask=0xFD, write_mask=0xFD,
                            front=StencilOps(GL.GL_KEEP, GL.GL_INVERT, GL.GL_INCR),
                            back=StencilOps(GL.GL_KEEP, GL.GL_INVERT, GL.GL_INCR),
                            depth_clamp=True),  # w = 0 vertices: their depth fails must count, not be clipped
    "zpass": StencilState(front=StencilOps(GL.GL_KEEP, GL.GL_KEEP, GL.GL_INCR_WRAP),
                          back=StencilOps(GL.GL_KEEP, GL.GL_KEEP, GL.GL_DECR_WRAP)),
    "zfail": StencilState(front=StencilOps(GL.GL_KEEP, GL.GL_DECR_WRAP, GL.GL_KEEP),
                          back=StencilOps(GL.GL_KEEP, GL.GL_INCR_WRAP, GL.GL_KEEP), depth_clamp=True),
}
METHODS = tuple(STATES)
# The scene's depth: stencil untouched (ALWAYS, KEEP, write mask 0), depth written, both faces drawn.
DEPTH_ONLY = StencilState(write_mask=0, depth_write=True)


def _state(method: str) -> StencilState:
    try:
        return STATES[method]
    except KeyError:
        raise ValueError(f"unknown shadow volume method {method!r}; one of {', '.join(METHODS)}") from None


def volume(method: str, positions, triangles, light, adjacency: Adjacency | None = None) -> VolumeGeometry:
    """The volume `method` draws for one caster mesh and one light; `adjacency` the mesh's, where it keeps one
    (the silhouette methods pair the edges otherwise)."""
    _state(method)
    if method == "onepass":
        return onepass_volume(positions, triangles, light)
    return silhouette_volume(positions, triangles, light, caps=method == "zfail", adjacency=adjacency)


def joined(geometries: Sequence[VolumeGeometry]) -> VolumeGeometry:
    """Several casters' volumes as one, in their order."""
    if len(geometries) == 1:
        return geometries[0]
    return VolumeGeometry(np.concatenate([g.vertices for g in geometries] or [np.empty((0, 4), np.float32)]),
                          sum(g.extruded_edges for g in geometries))


def shadowed(method: str, stencil: np.ndarray) -> np.ndarray:
    """Which stencil values `method` leaves in shadow."""
    _state(method)
    return stencil == SHADOW_VALUE if method == "onepass" else stencil != 0


@dataclass(frozen=True)
class ShadowMask:
    mask: np.ndarray    # bool (height, width), top row first: a surface in shadow of the light
    triangles: int      # volume triangles drawn (the fill cost's measure)
    extruded_edges: int


class ShadowVolumePass:
    """Draws volumes kept on the GPU (`upload`: a caster's, drawn every frame it stays) or streamed (numpy
    geometries, written for the one draw); programs belong to the ShaderLibrary. `uploaded_bytes` counts every
    vertex byte sent to the GPU since made."""

    def __init__(self, ctx: moderngl.Context, shaders) -> None:
        self.ctx, self.shaders = ctx, shaders
        self._stream = VolumeBuffer(ctx)
        self._kept_bytes = 0  # written to the uploaded volumes' buffers

    @property
    def uploaded_bytes(self) -> int:
        return self._kept_bytes + self._stream.written_bytes

    def upload(self, geometry: VolumeGeometry) -> VolumeBuffer:
        """A buffer of its own holding `geometry` (the caller releases it)."""
        kept = VolumeBuffer(self.ctx)
        kept.write(geometry.vertices)
        self._kept_bytes += kept.written_bytes
        return kept

    def draw_depth(self, fbo: moderngl.Framebuffer, vertices: np.ndarray, view_proj: np.ndarray) -> None:
        """The scene's depth (triangles as float32 (3 n, 4) vertices, w = 1) into `fbo`, colour untouched."""
        self._stream.write(vertices)
        self._draw(fbo, [self._stream], view_proj, DEPTH_ONLY)

    def mark(self, fbo: moderngl.Framebuffer, method: str, geometries: Sequence[VolumeGeometry],
             view_proj: np.ndarray) -> int:
        """Draw the geometries into the stencil of `fbo` (bound and used by this call), one after another in the
        order their triangles come: one upload, one draw and one stencil state for all the casters of a light.
        Returns the triangles drawn. The caller cleared the stencil."""
        state = _state(method)
        self._stream.write(joined(geometries).vertices)
        return self._draw(fbo, [self._stream], view_proj, state)

    def mark_uploaded(self, fbo: moderngl.Framebuffer, method: str, volumes: Sequence[VolumeBuffer],
                      view_proj: np.ndarray) -> int:
        """As mark, for volumes `upload` made: nothing is sent but the matrix. Drawn in their order, one draw each
        (GL keeps the order of primitives across draws: the stencil is mark's of the geometries joined)."""
        return self._draw(fbo, volumes, view_proj, _state(method))

    def shadow_mask(self, target: StencilTarget, method: str, casters: Iterable[tuple[np.ndarray, np.ndarray]],
                    light, view_proj: np.ndarray) -> ShadowMask:
        """The casters' (positions, triangles) volumes for `light`, marked in `target`'s stencil (cleared first)
        over the scene depth already in it, read back."""
        volumes = [volume(method, positions, triangles, light) for positions, triangles in casters]
        clear_stencil(target.fbo)
        drawn = self.mark(target.fbo, method, volumes, view_proj)
        mask = shadowed(method, target.read_stencil()) & (target.read_depth() < 1.0)
        return ShadowMask(mask, drawn, sum(v.extruded_edges for v in volumes))

    def _draw(self, fbo: moderngl.Framebuffer, buffers: Sequence[VolumeBuffer], view_proj: np.ndarray,
              state: StencilState) -> int:
        """Returns the triangles drawn."""
        triangles = sum(b.triangles for b in buffers)
        if not triangles:
            return 0
        program = self.shaders.program(PROGRAM)
        program["u_view_proj"].value = gl_matrix(view_proj)
        fbo.use()  # before the state: use() re-applies the framebuffer's colour and depth masks
        with stencil_state(state):
            for b in buffers:
                b.render(program)
        return triangles

    def release(self) -> None:
        self._stream.release()
