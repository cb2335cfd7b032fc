"""Shadow maps for the 3D lights: the light's views (numpy) and a depth texture the casters are drawn into
(moderngl), sampled through a sampler2DShadow with PCF (resources/shaders/shadow_map.shl).

- spot: one perspective view over its cone; directional: one orthographic view fitted to the scene's bounds;
  point: six 90-degree views, one per cube face, side by side in a 3 x 2 atlas of one depth texture.
- Each face is `map_size` texels a side and a little wider than its cone or cube face (PAD texels each side for
  the PCF kernel and the bilinear tap), so a kernel at a face's edge still reads depths of that face.
- Depth is linear: the distance to the light over its far distance (a point light's range, the farthest
  corner of the scene's bounds for a spot), or the orthographic view's own depth, so the bias is one share
  of the map's depth range anywhere in it: max(10 bias (1 - N.L), bias) with N the geometric normal.
- Only the casters' back faces (seen from the light) are drawn: casters are closed, so a lit face meets the
  depth of its object's far side, not its own (no acne there); the ground casts nothing and needs no bias.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import moderngl
import numpy as np

from app.gl.lights3d.light_reach import box_corners
from app.gl.core.stencil import GL, StencilState, stencil_state
from app.gl.core.texture_units import TextureUnits
from app.gl.core.uniforms import set_uniforms
from app.model.lights3d.scene import Light3D
from app.model.transforms import gl_matrix, look_at, orthographic, perspective

PROGRAM = "shadow_map"
NEAR_SHARE = 1e-3  # a perspective view's near plane, as a share of its far one
# Depth only, from the light: LESS, the casters' back faces (culled front faces).
DEPTH_STATE = StencilState(write_mask=0, depth_write=True, cull=GL.GL_FRONT)
CUBE_FACES = ((1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1))  # +x -x +y -y +z -z


@dataclass(frozen=True)
class MapViews:
    view_proj: tuple      # (4, 4) row-major clip-from-world per face: 1, or 6 (+x -x +y -y +z -z)
    far: float            # distances over this are the stored depth; 0: the orthographic view's own depth
    grid: tuple[int, int]  # faces across and down the atlas

    def atlas(self, size: int) -> tuple[int, int]:
        return self.grid[0] * size, self.grid[1] * size

    def tile(self, face: int, size: int) -> tuple[int, int, int, int]:
        return (face % self.grid[0]) * size, (face // self.grid[0]) * size, size, size


def pad(pcf: int) -> int:
    """Texels kept around a face's own area: the PCF kernel's half width and the bilinear tap's half texel."""
    return pcf // 2 + 1


def widening(size: int, pcf: int) -> float:
    """How much wider than its own area a face is drawn, so that area spans all but pad() texels a side."""
    return size / (size - 2 * pad(pcf))


def map_views(light: Light3D, bounds: tuple, size: int, pcf: int) -> MapViews:
    """The views a light's map is drawn from; `bounds` (lo, hi) hold every object, casters and receivers."""
    corners = box_corners(*bounds)
    wider = widening(size, pcf)
    # look_at takes a unit forward: the direction is one, normalised again as the maps always were (the same bits)
    direction = np.asarray(light.direction, np.float64) / np.linalg.norm(light.direction)
    if light.kind == "point":
        far = light.range  # beyond it katt is 0: nothing there needs a shadow, nothing casts into the range
        faces = tuple(perspective(1.0 / wider, 1.0, NEAR_SHARE * far, far) @ look_at(light.position, d)
                      for d in CUBE_FACES)
        return MapViews(faces, far, (3, 2))
    if light.kind == "spot":
        far = max(float(np.linalg.norm(corners - light.position, axis=1).max()), 1e-6)
        tan_half = math.tan(math.radians(light.angle)) * wider
        view = perspective(1.0 / tan_half, 1.0, NEAR_SHARE * far, far) @ look_at(light.position, direction)
        return MapViews((view,), far, (1, 1))
    centre = (corners.min(0) + corners.max(0)) / 2
    view = look_at(centre, direction)
    local = corners @ view[:3, :3].T + view[:3, 3]
    half = np.maximum(np.abs(local[:, :2]).max(0), 1e-6) * wider
    depth = -local[:, 2]
    margin = 1e-3 * max(depth.max() - depth.min(), 1e-6)
    lo = (-half[0], -half[1], depth.min() - margin)
    hi = (half[0], half[1], depth.max() + margin)
    return MapViews((orthographic(lo, hi) @ view,), 0.0, (1, 1))


class ShadowMap:
    """One light's depth atlas. `render` draws it unless the light, the casters, the bounds and the map's
    settings are those it last drew (a camera that moves needs no new map). It is read at the unit that `units`,
    the renderer's (its programs read the map), gives u_shadow_map."""

    def __init__(self, ctx: moderngl.Context, shaders, units: TextureUnits) -> None:
        self.ctx, self.shaders, self.units = ctx, shaders, units
        self.texture: moderngl.Texture | None = None
        self.fbo: moderngl.Framebuffer | None = None
        self.views: MapViews | None = None
        self.size = 0
        self._drawn = None

    def render(self, light: Light3D, casters, bounds: tuple, size: int, pcf: int) -> bool:
        """Draw the casters (ObjectBuffers, closed meshes) from the light; False when the last map still holds."""
        key = (light.kind, light.position, light.direction, light.range, light.angle,
               tuple(c.obj for c in casters), tuple(map(tuple, bounds)), size, pcf)
        if key == self._drawn:
            return False
        views = map_views(light, bounds, size, pcf)
        self._target(views.atlas(size))
        self.fbo.use()  # first: moderngl's use() applies this framebuffer's scissor (none), which glClear obeys
        self.fbo.clear(depth=1.0)
        program = self.shaders.program(PROGRAM)
        program["u_light"].value = tuple(light.position)
        program["u_far"].value = views.far
        with stencil_state(DEPTH_STATE):
            for face, view_proj in enumerate(views.view_proj):
                self.fbo.viewport = views.tile(face, size)
                program["u_view_proj"].value = gl_matrix(view_proj)
                for caster in casters:
                    caster.render(program)
        self.views, self.size, self._drawn = views, size, key
        return True

    def reserve(self, light: Light3D, bounds: tuple, size: int, pcf: int) -> None:
        """Make the depth texture `render` will need, ahead of it."""
        self._target(map_views(light, bounds, size, pcf).atlas(size))

    def forget(self) -> None:
        """The next render draws the map whatever it last drew."""
        self._drawn = None

    def bind(self, program: moderngl.Program, bias: float, pcf: int) -> None:
        """The map and how to read it, for a program that includes shadow_map.shl."""
        faces = list(self.views.view_proj) + [np.identity(4)] * (6 - len(self.views.view_proj))
        values = {**self.units.bind(u_shadow_map=self.texture),
                  "u_map_mode": 2 if len(self.views.view_proj) == 6 else 1,
                  "u_map_view_proj": [gl_matrix(f) for f in faces], "u_map_far": self.views.far,
                  "u_map_size": float(self.size), "u_map_grid": tuple(map(float, self.views.grid)),
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
