"""The volume ray tracer: every Tex3Dtrace mode (app/model/volume/render_modes.py), one pass or two, and a scalar
volume's modes (app/model/volume/scalar_modes.py), one pass. An RGBA volume is drawn from its RGBA texture; a scan,
in every mode, from its values' texture (the F-modes look the colours up in the shader: no RGBA copy of a scan is
held on the GPU, nor its distance field: its bricks skip the clear space)."""
from __future__ import annotations

from dataclasses import replace

import moderngl
import numpy as np
from scipy.ndimage import distance_transform_edt

from app.gl.core.texture_units import TextureUnits
from app.gl.core.uniforms import set_uniforms
from app.gl.core.vertex_arrays import VertexArrays
from app.gl.volume.clip_box import ClipBox
from app.gl.volume.label_texture import LabelTexture
from app.gl.volume.scalar_texture import ScalarTexture
from app.gl.volume.texture import VolumeTexture, texture3d_bytes
from app.model.volume.voxels import VolumeWatch, Voxels
from app.model.volume import render_modes as rm
from app.model.volume.render_modes import TraceSettings
from app.model.volume.scalar_modes import ISO_MODE, mode_number
from app.model.volume.view import AXIS_INDEX, VolumeView, box_extents, voxel_extent
from app.model.transforms import gl_matrix

EDITED_SLICE = (0.35, 0.85, 1.0, 0.10)   # faint: where the painter works
PICKED_SLICE = (1.0, 0.85, 0.2, 0.35)    # the slice picker's hovered slice
KIND = {"translucent": 0, "pure": 1, "phong": 2}
SHADOWS = {"none": 0, "constant": 1, "correct": 2}
# Box corners, the 12 triangles of its faces (counter-clockwise seen from outside) and its 12 edges.
CORNERS = np.array([[x, y, z] for z in (-1, 1) for y in (-1, 1) for x in (-1, 1)], dtype="f4")
FACES = np.array([0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4, 2, 6, 3, 3, 6, 7,
                  0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5], dtype="i4")
EDGES = np.array([0, 1, 2, 3, 4, 5, 6, 7, 0, 2, 1, 3, 4, 6, 5, 7, 0, 4, 1, 5, 2, 6, 3, 7], dtype="i4")
WIREFRAME = (0.85, 0.87, 0.92, 1.0)
LEFT_EYE, RIGHT_EYE, ALL = (True, False, False, True), (False, True, True, True), (True, True, True, True)
SCALAR_MODES_ONLY = ("u_opacity", "u_opacity_span", "u_opacity_entries", "u_clear_below")  # not in the F-modes'


class DistanceTexture:
    """Distance (voxels) from every voxel to the nearest non-empty one, for empty-space skipping.

    An edit does not rebuild it: distances are clamped at once to the distance from the edited box (an
    edit can only bring a non-empty voxel there, so this never overstates a distance; an erased voxel
    just keeps a smaller, safe value), and only the voxels that changed are uploaded. `refine()`, run when
    the editor is idle, rebuilds the exact field."""

    def __init__(self, ctx: moderngl.Context) -> None:
        self.ctx = ctx
        self.texture: moderngl.Texture3D | None = None
        self.field: np.ndarray | None = None
        self.watch = VolumeWatch()
        self.stale = False  # clamped since the last exact build

    def sync(self, voxels: Voxels) -> moderngl.Texture3D:
        box = self.watch.changes(voxels)
        if self.texture is None or self.texture.size != voxels.size or (box is not None and box.shape == voxels.size):
            self._rebuild(voxels)
        elif box is not None:
            self._clamp(box)
        return self.texture

    def release(self) -> None:
        """Hold no field (a scan is shown: its bricks skip instead); the next sync builds it again."""
        if self.texture is not None:
            self.texture.release()
        self.texture, self.field, self.watch, self.stale = None, None, VolumeWatch(), False

    def refine(self) -> bool:
        """The exact field again after clamped edits; True if anything was done."""
        if not self.stale or self.watch.source is None:
            return False
        self._rebuild(self.watch.source)
        return True

    def _rebuild(self, voxels: Voxels) -> None:
        self.field = distance_field(voxels.data)
        if self.texture is None or self.texture.size != voxels.size:
            if self.texture is not None:
                self.texture.release()
            self.texture = self.ctx.texture3d(voxels.size, 1, self.field, dtype="f4")
            self.texture.repeat_x = self.texture.repeat_y = self.texture.repeat_z = False
        else:
            self.texture.write(self.field)
        self.stale = False

    def _clamp(self, box) -> None:
        d, h, w = self.field.shape
        gaps = [np.maximum(np.maximum(lo - np.arange(n), np.arange(n) - (hi - 1)), 0).astype("f4")
                for lo, hi, n in ((box.z0, box.z1, d), (box.y0, box.y1, h), (box.x0, box.x1, w))]
        to_box = np.sqrt(gaps[0][:, None, None] ** 2 + gaps[1][None, :, None] ** 2 + gaps[2][None, None, :] ** 2)
        closer = to_box < self.field
        if not closer.any():
            return
        np.minimum(self.field, to_box, out=self.field)
        (z0, z1), (y0, y1), (x0, x1) = [_span(closer.any(axis=axes)) for axes in ((1, 2), (0, 2), (0, 1))]
        part = np.ascontiguousarray(self.field[z0:z1, y0:y1, x0:x1])
        self.texture.write(part, viewport=(x0, y0, z0, x1 - x0, y1 - y0, z1 - z0))
        self.stale = True


def _span(mask: np.ndarray) -> tuple[int, int]:
    where = np.flatnonzero(mask)
    return int(where[0]), int(where[-1]) + 1


def distance_field(data: np.ndarray) -> np.ndarray:
    empty = data[..., 3] == 0
    if empty.all():
        return np.full(empty.shape, float(sum(empty.shape)), dtype="f4")
    return distance_transform_edt(empty).astype("f4")


class RayTracer:
    def __init__(self, ctx: moderngl.Context, shaders) -> None:
        self.ctx = ctx
        self.shaders = shaders
        self.volume = VolumeTexture(ctx)
        self.distance = DistanceTexture(ctx)
        self.labels = LabelTexture(ctx)  # a scan's labels, over whatever the mode draws
        self.scalars = ScalarTexture(ctx)
        self.clip = ClipBox()  # the box of a scalar volume a mode's rays sample
        # Trilinear with a transparent border: the volume floats in empty space, so a voxel on the box's face is
        # a surface with an outward normal, as one inside is (clamped to its edge, its gradient pointed inwards
        # and the voxel shaded black). The reference samples the same way.
        self.linear = ctx.sampler(filter=(moderngl.LINEAR, moderngl.LINEAR), border_color=(0.0, 0.0, 0.0, 0.0))
        self.nearest = ctx.sampler(filter=(moderngl.NEAREST, moderngl.NEAREST), repeat_x=False, repeat_y=False,
                                   repeat_z=False)
        self.cube = ctx.buffer(CORNERS[FACES].tobytes())
        self.edges = ctx.buffer(CORNERS[EDGES].tobytes())
        self._edges = VertexArrays(lambda program: ctx.vertex_array(program, [(self.edges, "3f", "in_position")]))
        self._screen = VertexArrays(lambda program: ctx.vertex_array(program, []))
        self._box = VertexArrays(lambda program: ctx.vertex_array(program, [(self.cube, "3f", "in_position")]))
        self._entry: tuple | None = None  # (size, texture, framebuffer) of the two-pass setup
        self.units = TextureUnits()

    def render(self, fbo: moderngl.Framebuffer, voxels: Voxels, view: VolumeView, settings: TraceSettings) -> None:
        """Key x magnifies, t draws an anaglyph pair (red: left eye; green and blue: right), f the edges."""
        cam = replace(view.camera, fov=view.camera.fov / 2) if view.magnify else view.camera
        if view.stereo:
            for shift, mask in ((-settings.eye_distance / 2, LEFT_EYE), (settings.eye_distance / 2, RIGHT_EYE)):
                fbo.color_mask = mask
                self._render(fbo, voxels, view, replace(cam, shift=shift), settings)
            fbo.color_mask = ALL
        else:
            self._render(fbo, voxels, view, cam, settings)
        if view.wireframe:
            self._wireframe(fbo, voxels, cam)

    def _wireframe(self, fbo: moderngl.Framebuffer, voxels, cam) -> None:
        w, h = fbo.size
        program = self.shaders.program("box_edges")
        view_proj = cam.clip_from_world((w, h))
        set_uniforms(program, {"u_view_proj": gl_matrix(view_proj), "u_color": WIREFRAME,
                            "u_extent": box_extents(voxels.size, voxels.spacing)})
        fbo.use()
        self._edges.get(program).render(moderngl.LINES)

    def held_bytes(self) -> int:
        """What the volume's 3D textures hold on the GPU: the RGBA volume and its distance field, or a scan's values
        and bricks; and the labels."""
        textures = (self.volume.texture, self.distance.texture, self.scalars.values, self.scalars.bricks,
                    self.labels.texture)
        return sum(texture3d_bytes(t) for t in textures if t is not None)

    def _render(self, fbo: moderngl.Framebuffer, voxels, view: VolumeView, cam, settings: TraceSettings) -> None:
        scan = voxels.scalars is not None
        scalar = scan and settings.scalar_mode != "colour"  # else the F-mode's colours
        mode = rm.MODES[5 if scalar else settings.mode]  # iso is lit as F5
        w, h = fbo.size
        view_proj = cam.clip_from_world((w, h))
        extent = np.array(box_extents(voxels.size, voxels.spacing), dtype="f4")
        uniforms = self._uniforms(voxels, view, settings, mode, extent)
        uniforms["u_eye"] = tuple(cam.position())
        uniforms.update(self.labels.uniforms(voxels.labels, settings.label_opacity, self.units))
        uniforms.update(self._scan(voxels) if scan else self._colours(voxels, mode))
        if scalar:
            self._render_scalars(fbo, voxels, settings, uniforms, view_proj)
            return
        uniforms.update(u_field=0)
        background = tuple(c / 255 for c in view.background)
        if mode.two_pass:
            entry = self._entry_pass((w, h), view_proj, extent)
            program = self.shaders.program("raytrace2")
            uniforms.update(self.units.bind(u_entry=entry), u_view_proj=gl_matrix(view_proj))
            set_uniforms(program, uniforms, optional=SCALAR_MODES_ONLY)
            fbo.use()
            fbo.clear(*background, 1.0)  # within the colour mask: a stereo pair's first eye stays
            self.ctx.enable(moderngl.CULL_FACE)
            self.ctx.front_face = "cw"  # draw only the back faces: every ray's exit
            self._box.get(program).render(moderngl.TRIANGLES)
            self.ctx.front_face = "ccw"
            self.ctx.disable(moderngl.CULL_FACE)
        else:
            program = self.shaders.program("raytrace", defines={"SCALAR_MODE": 0})  # the F-modes' code alone
            uniforms.update(u_inv_view_proj=gl_matrix(np.linalg.inv(view_proj)))
            set_uniforms(program, uniforms, optional=SCALAR_MODES_ONLY)
            fbo.use()
            self._screen.get(program).render(moderngl.TRIANGLES, vertices=3)
        self.linear.clear(self.units["u_volume"])
        self.nearest.clear(self.units["u_nearest"])

    def _colours(self, voxels, mode: rm.Mode) -> dict:
        """An RGBA volume's textures at their units: one volume at two, read through two samplers (the linear one's
        border transparent), and its distance field where the mode skips; a scan's textures go."""
        self.scalars.release()
        values = self.units.bind(u_volume=self.volume.sync(voxels), u_nearest=self.volume.texture)
        self.units.bind(u_volume=self.linear, u_nearest=self.nearest)
        if mode.distance:
            self.units.bind(u_distance=self.distance.sync(voxels))
        values.update(self.units.uniforms("u_distance", "u_scalars", "u_colormap", "u_opacity", "u_bricks"), u_scan=0)
        return values  # the samplers whose textures are unread still get their own units

    def _scan(self, voxels) -> dict:
        """A scan's textures at their units, for every mode: its values (clamped to the edge; at u_nearest too,
        through the nearest sampler), the colour map, the opacity curve and the bricks; an RGBA volume's go."""
        self.volume.release()
        self.distance.release()
        scalars = voxels.scalars
        self.scalars.sync(scalars)
        values = self.scalars.uniforms(scalars.transfer)
        values.update(self.units.bind(u_scalars=self.scalars.values, u_nearest=self.scalars.values,
                                      u_colormap=self.scalars.colours, u_opacity=self.scalars.opacity,
                                      u_bricks=self.scalars.bricks), u_scan=1)
        self.units.bind(u_nearest=self.nearest)
        values.update(self.units.uniforms("u_volume", "u_distance"))  # unread: their own units
        return values

    def _render_scalars(self, fbo: moderngl.Framebuffer, voxels, settings: TraceSettings, uniforms: dict,
                        view_proj: np.ndarray) -> None:
        """The one-pass tracer on the values, in a scalar mode, each ray clipped to the box where the mode's picture
        can change. A program for the mode alone: llvmpipe runs every mode's code on every pixel of one for all
        (twice the time of a translucent frame at two voxels a step); it reads the uniforms of its mode alone."""
        uniforms.update(u_inv_view_proj=gl_matrix(np.linalg.inv(view_proj)), u_iso=float(settings.iso),
                        u_field=int(settings.scalar_mode == ISO_MODE),
                        u_mip_attenuation=float(settings.mip_attenuation))
        level = {"iso": uniforms["u_iso"], "translucent": uniforms["u_clear_below"]}.get(settings.scalar_mode,
                                                                                         voxels.scalars.transfer.low)
        uniforms.update(self.clip.uniforms(settings.scalar_mode, self.scalars.maxima, voxels.size, level,
                                           self.scalars.scale))
        program = self.shaders.program("raytrace", defines={"SCALAR_MODE": mode_number(settings.scalar_mode)})
        set_uniforms(program, uniforms, optional=uniforms.keys())
        fbo.use()
        self._screen.get(program).render(moderngl.TRIANGLES, vertices=3)
        self.nearest.clear(self.units["u_nearest"])

    def _entry_pass(self, size, view_proj: np.ndarray, extent: np.ndarray) -> moderngl.Texture:
        if self._entry is None or self._entry[0] != size:
            if self._entry is not None:
                self._entry[2].release()
                self._entry[1].release()
            texture = self.ctx.texture(size, 4, dtype="f4")
            texture.filter = (moderngl.NEAREST, moderngl.NEAREST)
            self._entry = (size, texture, self.ctx.framebuffer([texture]))
        _size, texture, framebuffer = self._entry
        program = self.shaders.program("box_faces")
        set_uniforms(program, {"u_view_proj": gl_matrix(view_proj), "u_extent": tuple(extent)})
        framebuffer.use()
        framebuffer.clear(0.0, 0.0, 0.0, 0.0)
        self.ctx.enable(moderngl.CULL_FACE)  # front faces only: where each ray enters
        self._box.get(program).render(moderngl.TRIANGLES)
        self.ctx.disable(moderngl.CULL_FACE)
        return texture

    def _uniforms(self, voxels, view: VolumeView, s: TraceSettings, mode: rm.Mode, extent) -> dict:
        planes = [(view.axis, view.index, EDITED_SLICE)]
        planes.append((*view.highlight, PICKED_SLICE) if view.highlight else ("", 0, PICKED_SLICE))
        if not s.slice_planes:
            planes = [("", 0, EDITED_SLICE), ("", 0, PICKED_SLICE)]
        lights = [tuple(map(float, p)) for p in s.lights[:2]] + [(0.0, 0.0, 0.0)] * (2 - len(s.lights[:2]))
        return {
            "u_shadow_offset": float(s.shadow_offset),
            "u_extent": tuple(extent),
            "u_voxels": tuple(float(v) for v in voxels.size),
            "u_voxel": voxel_extent(voxels.size, voxels.spacing),
            "u_steps": float(s.steps),
            "u_shadow_steps": int(s.shadow_steps),
            "u_sample_range": float(s.sample_range),
            "u_distance_scale": float(s.distance_scale),
            "u_background": tuple(c / 255 for c in view.background),
            "u_kind": KIND[mode.kind],
            "u_shadows": SHADOWS[mode.shadows] if s.shadows else 0,
            "u_translucency": int(mode.translucency),
            "u_lights": mode.lights,
            "u_light": lights,
            "u_dual": int(mode.dual),
            "u_reflections": int(mode.reflections),
            "u_skip": int(mode.distance),
            "u_debug_samples": int(s.debug_samples),
            "u_plane_axis": [AXIS_INDEX.get(a, -1) for a, _i, _c in planes],
            "u_plane_pos": [(i + 0.5) / voxels.size[AXIS_INDEX.get(a, 0)] for a, i, _c in planes],
            "u_plane_color": [c for _a, _i, c in planes],
        }
