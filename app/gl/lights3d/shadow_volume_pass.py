"""Shadow volumes into the stencil of a framebuffer whose depth already holds the scene, for one light, and the
in-shadow mask read back. The methods (onepass, zpass, zfail) and their stencil states are the volume methods of
app/gl/lights3d/shadow_methods.py; the pass takes them by name.

onepass: within one caster triangle's 7 any order gives the same stencil, as the seed claims; the volumes of a
mesh's triangles overlap, though, and interleaving their triangles can lock a pixel early (measured in
tests/test_shadow_volumes_gl.py), so they are drawn as built, each triangle's 7 together. A pixel the scene left
at depth 1 (no surface) is never in shadow.

Depth LESS must fail where a cap or caster triangle lies on the scene's own surface: draw the scene's depth
with `draw_depth` (the same vertex shader) or a shader declaring `invariant gl_Position` with the same
`u_view_proj * position`."""
from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass, replace

import moderngl
import numpy as np

from app.gl.lights3d import shadow_methods
from app.gl.lights3d.shadow_methods import StencilVolumes
from app.gl.lights3d.shadow_volumes import VolumeGeometry
from app.gl.core.depth_bounds import depth_bounds
from app.gl.core.stencil import GL, KEEP, StencilState, StencilTarget, clear_stencil, stencil_state
from app.gl.lights3d.shadow_volume_buffers import VolumeBuffer
from app.model.lights3d.mesh import Adjacency
from app.model.transforms import gl_matrix

PROGRAM = "shadow_volume"
METHODS = tuple(name for name, m in shadow_methods.METHODS.items() if m.volumes)  # the volume methods' names
# The scene's depth: stencil untouched (ALWAYS, KEEP, write mask 0), depth written, both faces drawn.
DEPTH_ONLY = StencilState(write_mask=0, depth_write=True)


def _volumes(method: str) -> StencilVolumes:
    if method not in METHODS:
        raise ValueError(f"unknown shadow volume method {method!r}; one of {', '.join(METHODS)}")
    return shadow_methods.METHODS[method].volumes


def volume(method: str, positions, triangles, light, adjacency: Adjacency | None = None) -> VolumeGeometry:
    """The volume `method` draws for one caster mesh and one light; `adjacency` the mesh's, where it keeps one
    (the silhouette methods pair the edges otherwise)."""
    return _volumes(method).build(positions, triangles, light, adjacency)


def joined(geometries: Sequence[VolumeGeometry]) -> VolumeGeometry:
    """Several casters' volumes as one, in their order."""
    if len(geometries) == 1:
        return geometries[0]
    return VolumeGeometry(np.concatenate([g.vertices for g in geometries] or [np.empty((0, 4), np.float32)]),
                          sum(g.extruded_edges for g in geometries))


def shadowed(method: str, stencil: np.ndarray) -> np.ndarray:
    """Which stencil values `method` leaves in shadow."""
    return _volumes(method).shadowed(stencil)


Bounds = tuple[float, float] | None  # the depth bounds of a light's reach (app/gl/core/depth_bounds.py), or none


def counting(state: StencilState) -> StencilState:
    """`state` with every fragment passing the depth and stencil tests and nothing written: what fill counts."""
    return replace(state, func=GL.GL_ALWAYS, write_mask=0, front=KEEP, back=KEEP, depth_func=GL.GL_ALWAYS)


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
        self._samples: moderngl.Query | None = None  # fill's occlusion query, made at its first count

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
             view_proj: np.ndarray, bounds: Bounds = None) -> int:
        """Draw the geometries into the stencil of `fbo` (bound and used by this call, within its scissor), one
        after another in the order their triangles come: one upload, one draw and one stencil state for all the
        casters of a light; within depth `bounds` where the context has the test. Returns the triangles drawn.
        The caller cleared the stencil."""
        state = _volumes(method).marks
        self._stream.write(joined(geometries).vertices)
        return self._draw(fbo, [self._stream], view_proj, state, bounds)

    def mark_uploaded(self, fbo: moderngl.Framebuffer, method: str, volumes: Sequence[VolumeBuffer],
                      view_proj: np.ndarray, bounds: Bounds = None) -> int:
        """As mark, for volumes `upload` made: nothing is sent but the matrix. Drawn in their order, one draw each
        (GL keeps the order of primitives across draws: the stencil is mark's of the geometries joined)."""
        return self._draw(fbo, volumes, view_proj, _volumes(method).marks, bounds)

    def fill(self, fbo: moderngl.Framebuffer, method: str, geometries: Sequence[VolumeGeometry],
             view_proj: np.ndarray, bounds: Bounds = None) -> int:
        """The fill of mark's draw of the same volumes: the fragments it rasterises within the scissor (and the
        depth bounds, where the context has them), whether their depth test passes or fails (either may write
        the stencil, and each costs a stencil test). Counted by an occlusion query (GL_SAMPLES_PASSED) over the
        same draw with both tests passing everything and nothing written; `fbo` single-sampled: one a pixel."""
        self._samples = self._samples or self.ctx.query(samples=True)
        self._stream.write(joined(geometries).vertices)
        with self._samples:
            self._draw(fbo, [self._stream], view_proj, counting(_volumes(method).marks), bounds)
        return self._samples.samples

    def shadow_mask(self, target: StencilTarget, method: str, casters: Iterable[tuple[np.ndarray, np.ndarray]],
                    light, view_proj: np.ndarray, bounds: Bounds = None) -> ShadowMask:
        """The casters' (positions, triangles) volumes for `light`, marked in `target`'s stencil (cleared first)
        over the scene depth already in it, read back."""
        volumes = [volume(method, positions, triangles, light) for positions, triangles in casters]
        clear_stencil(target.fbo)
        drawn = self.mark(target.fbo, method, volumes, view_proj, bounds)
        mask = shadowed(method, target.read_stencil()) & (target.read_depth() < 1.0)
        return ShadowMask(mask, drawn, sum(v.extruded_edges for v in volumes))

    def _draw(self, fbo: moderngl.Framebuffer, buffers: Sequence[VolumeBuffer], view_proj: np.ndarray,
              state: StencilState, bounds: Bounds = None) -> int:
        """Returns the triangles drawn."""
        triangles = sum(b.triangles for b in buffers)
        if not triangles:
            return 0
        program = self.shaders.program(PROGRAM)
        program["u_view_proj"].value = gl_matrix(view_proj)
        fbo.use()  # before the state: use() re-applies the framebuffer's colour, depth masks and scissor
        with stencil_state(state), depth_bounds(self.ctx, bounds):
            for b in buffers:
                b.render(program)
        return triangles

    def release(self) -> None:
        self._stream.release()
