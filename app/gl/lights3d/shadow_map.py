"""Shadow maps for the 3D lights: a depth texture the casters are drawn into from the light's views (moderngl),
sampled through a sampler2DShadow with PCF (resources/shaders/shadow_map.shl). The views are fitted to what the
camera sees (app/gl/lights3d/map_fitting.py): a directional light's cascades, a spot's one view (or, for a wide
cone seen whole, a point light's faces), a point light's six cube faces; each is a tile of one depth texture,
side by side in an atlas (cascades 2 x 2 from three on, cube faces 3 x 2).

- Each tile is `map_size` texels a side and a little wider than its own window (PAD texels each side for the PCF
  kernel and the bilinear tap), so a kernel at a tile's edge still reads depths of that tile.
- Depth is linear: a spot's or point light's distance, from `near` (the nearest caster) to `far` (the farthest
  receiver), or the orthographic view's own depth, so the bias is one share of the map's depth span anywhere in
  it: max(10 bias (1 - N.L), bias) with N the geometric normal.
- Only the casters' back faces (seen from the light) are drawn: casters are closed, so a lit face meets the
  depth of its object's far side, not its own (no acne there); the ground casts nothing and needs no bias.
"""
from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace

import moderngl
import numpy as np

from app.gl.core.stencil import GL, StencilState, stencil_state
from app.gl.core.texture_units import TextureUnits
from app.gl.core.uniforms import set_uniforms
from app.model.lights3d.scene import Light3D
from app.model.transforms import gl_matrix

PROGRAM = "shadow_map"
NEAR_SHARE = 1e-3  # a perspective view's near plane, as a share of its far one
# Depth only, from the light: LESS, the casters' back faces (culled front faces). An orthographic view's depth
# clamped, not clipped: a caster nearer the light than the receivers its box holds lies at depth 0, shadowing them
# all, however far it is (the box's depth spans the receivers alone: the bias a share of that).
DEPTH_STATE = StencilState(write_mask=0, depth_write=True, cull=GL.GL_FRONT)
ORTHOGRAPHIC_DEPTH_STATE = replace(DEPTH_STATE, depth_clamp=True)
CUBE_FACES = ((1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1))  # +x -x +y -y +z -z
# u_map_mode: which tile the light pass reads: the one view, the cube face the direction from the light leaves
# through, or the cascade whose view depths hold the pixel's.
ONE, CUBE, CASCADES = 1, 2, 3
MAX_TILES = 6  # u_map_view_proj's length
MAX_SPLITS = 3  # u_map_splits's: four cascades at most
NO_SPLIT = 1e30  # an unused split: no view depth passes it


@dataclass(frozen=True, eq=False)
class MapViews:
    mode: int              # ONE, CUBE or CASCADES
    view_proj: tuple       # (4, 4) row-major clip-from-world per tile
    drawn: tuple           # per tile: whether a receiver in view lies in it (the others stay empty: lit)
    grid: tuple[int, int]  # tiles across and down the atlas
    near: float = 0.0      # radial depth: (distance - near) / (far - near)
    far: float = 0.0       # 0: the orthographic view's own depth
    depth_row: tuple = (0.0, 0.0, 0.0, 0.0)  # cascades: a world point's view depth, row . (x, y, z, 1)
    splits: tuple = ()     # cascades: the view depths where the second, third... begin

    def atlas(self, size: int) -> tuple[int, int]:
        return self.grid[0] * size, self.grid[1] * size

    def tile(self, face: int, size: int) -> tuple[int, int, int, int]:
        return (face % self.grid[0]) * size, (face // self.grid[0]) * size, size, size

    def key(self) -> bytes:
        """Equal for views that draw the same map."""
        numbers = [np.ravel(self.view_proj), self.drawn, self.grid, (self.mode, self.near, self.far),
                   self.depth_row, self.splits]
        return b"".join(np.asarray(n, np.float64).tobytes() for n in numbers)

    def tiles_of(self, points: np.ndarray, light_position) -> np.ndarray:
        """The tile the light pass reads for each world point (n, 3), as shadow_map.shl picks it."""
        points = np.asarray(points, np.float64)
        if self.mode == CUBE:
            v = points - np.asarray(light_position, np.float64)
            axis = np.argmax(np.abs(v), axis=1)  # the first of equals: x before y before z, as the shader
            return 2 * axis + (np.take_along_axis(v, axis[:, None], 1)[:, 0] < 0)
        if self.mode == CASCADES:
            depth = points @ np.asarray(self.depth_row[:3]) + self.depth_row[3]
            return (depth[:, None] > np.asarray(self.splits)[None]).sum(axis=1)
        return np.zeros(len(points), int)

    def texels(self, points: np.ndarray, tiles: np.ndarray, size: int) -> np.ndarray:
        """Where world points (n, 3) fall in the tiles given, in texels of a tile (x, y from its corner)."""
        matrices = np.asarray(self.view_proj, np.float64)[tiles]
        clip = np.einsum("nij,nj->ni", matrices, np.c_[points, np.ones(len(points))])
        return (clip[:, :2] / clip[:, 3:] * 0.5 + 0.5) * size


def pad(pcf: int) -> int:
    """Texels kept around a face's own area: the PCF kernel's half width and the bilinear tap's half texel."""
    return pcf // 2 + 1


def widening(size: int, pcf: int) -> float:
    """How much wider than its own area a face is drawn, so that area spans all but pad() texels a side."""
    return size / (size - 2 * pad(pcf))


class ShadowMap:
    """One light's depth atlas. `render` draws it unless the light, the casters, the views and the map's settings
    are those it last drew (a camera that moves the views needs a new map, one that keeps them none). It is read at
    the unit that `units`, the renderer's (its programs read the map), gives u_shadow_map."""

    def __init__(self, ctx: moderngl.Context, shaders, units: TextureUnits) -> None:
        self.ctx, self.shaders, self.units = ctx, shaders, units
        self.texture: moderngl.Texture | None = None
        self.fbo: moderngl.Framebuffer | None = None
        self.views: MapViews | None = None
        self.size = 0
        self._drawn = None
        self._fit = None  # the last views fitted and what they were fitted to

    def render(self, light: Light3D, casters, views: MapViews, size: int, pcf: int) -> bool:
        """Draw the casters (ObjectBuffers, closed meshes) from the light into the tiles of `views` that hold a
        receiver (app/gl/lights3d/map_fitting.py); False when the last map still holds."""
        key = (light.position, views.key(), tuple(c.obj for c in casters), size, pcf)
        if key == self._drawn:
            return False
        self._target(views.atlas(size))
        self.fbo.use()  # first: moderngl's use() applies this framebuffer's scissor (none), which glClear obeys
        self.fbo.clear(depth=1.0)
        program = self.shaders.program(PROGRAM)
        set_uniforms(program, {"u_light": tuple(light.position), "u_near": views.near, "u_far": views.far})
        with stencil_state(DEPTH_STATE if views.far > 0 else ORTHOGRAPHIC_DEPTH_STATE):
            for face, view_proj in enumerate(views.view_proj):
                if not views.drawn[face]:
                    continue
                self.fbo.viewport = views.tile(face, size)
                program["u_view_proj"].value = gl_matrix(view_proj)
                for caster in casters:
                    caster.render(program)
        self.views, self.size, self._drawn = views, size, key
        return True

    def fitted(self, key, fit: Callable[[], MapViews]) -> MapViews:
        """The views `fit` gives, fitted anew only when `key` (all they depend on) changes: a still camera's
        frame fits none."""
        if self._fit is None or self._fit[0] != key:
            self._fit = (key, fit())
        return self._fit[1]

    def reserve(self, views: MapViews, size: int) -> None:
        """Make the depth texture `render` will need, ahead of it."""
        self._target(views.atlas(size))

    def forget(self) -> None:
        """The next render fits and draws the map whatever it last did."""
        self._drawn = self._fit = None

    def bind(self, program: moderngl.Program, bias: float, pcf: int) -> None:
        """The map and how to read it, for a program that includes shadow_map.shl."""
        views = self.views
        faces = list(views.view_proj) + [np.identity(4)] * (MAX_TILES - len(views.view_proj))
        splits = tuple(views.splits) + (NO_SPLIT,) * (MAX_SPLITS - len(views.splits))
        values = {**self.units.bind(u_shadow_map=self.texture), "u_map_mode": views.mode,
                  "u_map_view_proj": [gl_matrix(f) for f in faces], "u_map_near": views.near,
                  "u_map_far": views.far, "u_map_depth_row": tuple(map(float, views.depth_row)),
                  "u_map_splits": tuple(map(float, splits)),
                  "u_map_size": float(self.size), "u_map_grid": tuple(map(float, views.grid)),
                  "u_pcf": pcf, "u_bias": bias}
        set_uniforms(program, values)

    def _target(self, shape: tuple[int, int]) -> None:
        if self.texture is not None and self.texture.size == shape:
            return
        self.release()
        self.texture = self.ctx.depth_texture(shape)
        self.texture.compare_func = "<="  # sampler2DShadow: 1 where the receiver is no farther than the map
        self.texture.filter = (moderngl.LINEAR, moderngl.LINEAR)  # 2 x 2 PCF in each tap
        self.texture.repeat_x = self.texture.repeat_y = False
        self.fbo = self.ctx.framebuffer(depth_attachment=self.texture)
        self._drawn = None

    def release(self) -> None:
        for obj in (self.fbo, self.texture):
            if obj is not None:
                obj.release()
        self.fbo = self.texture = None
        self._drawn = None
