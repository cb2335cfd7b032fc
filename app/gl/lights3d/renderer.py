"""The 3D lights renderer (seeds 004 and 002): per-pixel point, spot and directional lights, each shadowed its
own way (Light3D.shadow, one of app/gl/lights3d/shadow_methods.py): stencil volumes (onepass, zpass, zfail...:
app/gl/lights3d/shadow_volume_pass.py), a shadow map with PCF (app/gl/lights3d/shadow_map.py) or none.

A frame is drawn into its own target, float colour and DEPTH24_STENCIL8 at the output's size (whatever stencil
the host's framebuffer has), then copied into the host's framebuffer:
1. depth pre-pass, coloured by the ambient light (depth LESS);
2. per light whose reach the view may see, scissored to its reach's box on screen: its shadow (the stencil
   cleared and every caster's volume marked in it, within the reach's window depths where GL has the depth
   bounds test, or its map drawn unless the last one still holds), then its
   light added (blend ONE, ONE) on the pixels the pre-pass left (depth EQUAL: the same vertex shader,
   invariant), restricted by the stencil or the map;
3. the editor's marks on top (app/gl/lights3d/overlay.py), then the copy, clamped to 0..1.
Every pass goes through stencil_state and blending, which put back whatever GL state they set.

The light formulas are app.model.lights3d.scene's, in resources/shaders/lights3d.shl. A shadowed light (any method
but none) reaches only faces that face it (app/model/lights3d/facing.py), as the reference's; only closed meshes
cast.
Work follows the scene and the view: meshes upload when their object changes (lights3d_meshes.py), volumes are
built and uploaded when their caster or light changes and drawn from their own buffers while they stay
(lights3d_volumes.py), a light whose reach lies outside the view is skipped, each light's passes are scissored
to its reach, and only casters within a light's reach shadow it (app/gl/lights3d/light_reach.py). `frame` counts it all.
"""
from __future__ import annotations

import logging
import time
from dataclasses import dataclass, replace

import moderngl
import numpy as np

from app.gl.core.blending import blending
from app.gl.core.depth_bounds import available as has_depth_bounds
from app.gl.lights3d.light_reach import (depth_range, frustum_planes, light_in_view, reach_box, reaches, screen_rect,
                                         span, sphere_in_view, union)
from app.gl.lights3d.meshes import ObjectBuffer, ObjectBuffers
from app.gl.lights3d.overlay import Overlay
from app.gl.lights3d.caster_volumes import VolumeCache, build
from app.gl.lights3d.map_fitting import fit_views
from app.gl.lights3d.shadow_map import ShadowMap
from app.gl.lights3d.shadow_methods import MAP, METHODS
from app.gl.lights3d.shadow_volume_pass import ShadowVolumePass, shadowed
from app.gl.core.stencil import GL, StencilState, StencilTarget, clear_stencil, stencil_state
from app.gl.core.texture_units import TextureUnits
from app.gl.core.uniforms import set_uniforms
from app.gl.core.vertex_arrays import VertexArrays
from app.model.camera3d import OrbitCamera
from app.model.lights3d.facing import IN_PLANE
from app.model.lights3d.scene import BACKGROUND, Light3D, Scene3D
from app.model.lights3d.render_settings import Lights3DRenderSettings
from app.model.transforms import gl_matrix

log = logging.getLogger(__name__)
# Scene depth and ambient colour: depth LESS and written, stencil untouched.
SCENE_PASS = StencilState(write_mask=0, depth_write=True, colour_write=True)
COPY_PASS = StencilState(write_mask=0, depth_func=GL.GL_ALWAYS, colour_write=True)
LIGHT_KIND = {"point": 0, "spot": 1, "directional": 2}
HOW_BRIGHT = ("u_range", "u_falloff", "u_cos_angle")  # lights3d_mask reads where a light falls, not how bright


def drop_stale_errors() -> None:
    """Take the GL errors left queued before the frame (moderngl never asks for them: a framebuffer deleted while
    bound leaves one at the next one made), logged, so that glGetError after the frame tells of its own alone."""
    while (error := GL.glGetError()) != GL.GL_NO_ERROR:
        log.warning("a GL error left before the 3D lights' frame: 0x%x", error)


@dataclass
class FrameStats:
    """The work of the last frame."""
    uploads: int = 0           # object meshes uploaded (new or changed objects)
    objects_drawn: int = 0     # objects in the view
    lights_drawn: int = 0
    lights_skipped: int = 0    # their reach outside the view, or nothing of what they reach in it
    scissor_pixels: int = 0    # the pixels of the lights drawn: their reach's box on screen, summed
    depth_bounded: int = 0     # stencil passes clamped to their light's reach in depth (where GL has depth bounds)
    volumes_built: int = 0     # caster volumes built and uploaded (the others kept from earlier frames, on the GPU)
    volume_bytes: int = 0      # volume vertices sent to the GPU: the built ones' alone
    volumes_drawn: int = 0     # caster volumes marked in the stencil, over every light
    volume_triangles: int = 0  # their triangles: the stencil's fill cost
    maps_rendered: int = 0     # shadow maps drawn (the others still held)
    overlay_triangles: int = 0


@dataclass(frozen=True)
class MaskStats:
    """What one light's shadow cost in shadow_mask."""
    casters: int               # closed meshes within the light's reach
    volume_triangles: int
    extruded_edges: int        # edges pushed to infinity: 3 per caster triangle (onepass), the silhouettes' else
    build_ms: float            # the volumes built on the CPU, or the map's views fitted (numpy)
    draw_ms: float             # the stencil marked, or the map drawn and read over the view (GPU, finished)
    visibility: np.ndarray | None = None  # map: the share of PCF taps that see the light, (H, W) top row first
    fill_px: int = 0           # volumes: the fragments the stencil pass rasterised (ShadowVolumePass.fill)


class Lights3DRenderer:
    def __init__(self, ctx: moderngl.Context, shaders) -> None:
        self.ctx, self.shaders = ctx, shaders
        self.objects = ObjectBuffers(ctx)
        self.volume_pass = ShadowVolumePass(ctx, shaders)
        self.volumes = VolumeCache(self.volume_pass.upload)
        self.maps: dict[int, ShadowMap] = {}  # by light index, for the lights that use one
        self.mask_map: ShadowMap | None = None  # shadow_mask's, drawn anew each time
        self.overlay = Overlay(ctx, shaders)
        self.units = TextureUnits()  # its passes' samplers and its shadow maps'
        self.target: StencilTarget | None = None
        self.frame = FrameStats()
        self.depth_bounds = has_depth_bounds(ctx)  # the stencil passes clamped in depth too (llvmpipe: no)
        self._fullscreen = VertexArrays(lambda program: ctx.vertex_array(program, []))

    # ---- a frame ------------------------------------------------------------------------------------

    def render(self, fbo: moderngl.Framebuffer, scene: Scene3D, camera: OrbitCamera,
               settings: Lights3DRenderSettings | None = None, selection=None, marks: bool = True) -> FrameStats:
        """Draw the scene into `fbo` with `settings` (the map's size, PCF and bias, and the debug view; None: the
        defaults); `selection` is None, ("object", i) or ("light", i); without `marks`, the lit scene alone (as
        the reference draws it). The debug views draw on black: `stencil` the first stencil-shadowed light's
        stencil after its volumes, value / 255 as grey; `mask` white where the first light lights a pixel."""
        settings = settings or Lights3DRenderSettings()
        fbo.use()  # first: moderngl binds its last framebuffer again after making one (the target), maybe a deleted one
        drop_stale_errors()
        stats = FrameStats()
        target = self._target(fbo.size)
        uploads, built, sent = self.objects.uploads, self.volumes.built, self.volume_pass.uploaded_bytes
        buffers = self.objects.update(scene.objects)
        view_proj = camera.clip_from_world(fbo.size)
        planes = frustum_planes(view_proj)
        in_view = [b for b in buffers if sphere_in_view(planes, b.centre, b.radius)]
        debug = settings.debug
        target.fbo.use()  # its own scissor (none) applied before the clear, whatever the host's was
        target.clear(colour=(*(BACKGROUND if debug == "none" else (0.0, 0.0, 0.0)), 1.0))
        self._scene_pass(target.fbo, in_view, scene.ambient if debug == "none" else (0.0, 0.0, 0.0), view_proj)
        lights = list(enumerate(scene.lights))
        if debug == "mask":
            lights = lights[:1]
        elif debug == "stencil":
            lights = [(i, light) for i, light in lights if METHODS[light.shadow].volumes][:1]
        visible = set(in_view)  # ObjectBuffers hash by identity
        for index, light in lights:
            reached = [b for b in buffers if reaches(light, b.centre, b.radius)]
            shown = [b for b in reached if b in visible]
            reach = self._reach(light, shown, view_proj, planes, camera.NEAR, fbo.size)
            if reach is None:
                stats.lights_skipped += 1
                continue
            rect, bounds = reach
            target.fbo.scissor = rect  # applied by each pass's use() of the target, the stencil's too
            self._shadow(target, index, light, reached, shown, view_proj, settings, stats, bounds)
            if debug == "stencil":
                self._stencil_view(target.fbo)
            else:
                self._light_pass(target.fbo, scene, camera, index, light, shown, view_proj, settings)
            target.fbo.scissor = None
            stats.lights_drawn += 1
            stats.scissor_pixels += rect[2] * rect[3]
        self.volumes.end_frame()
        for index in [i for i in self.maps if i >= len(scene.lights) or not METHODS[scene.lights[i].shadow].shadow_map]:
            self.maps.pop(index).release()
        if marks:
            stats.overlay_triangles = self.overlay.draw(target.fbo, scene, camera, selection)
        self._copy(target, fbo)
        stats.uploads, stats.volumes_built = self.objects.uploads - uploads, self.volumes.built - built
        stats.volume_bytes = self.volume_pass.uploaded_bytes - sent
        stats.objects_drawn = len(in_view)
        self.frame = stats
        return stats

    def forget_shadows(self) -> None:
        """Drop the kept volumes and maps: the next frame builds them all, as if every light had moved."""
        self.volumes.clear()
        for shadow_map in self.maps.values():
            shadow_map.forget()

    def _target(self, size: tuple[int, int]) -> StencilTarget:
        if self.target is None or self.target.size != tuple(size):
            if self.target is not None:
                self.target.release()
            self.target = StencilTarget(self.ctx, tuple(size), dtype="f2")  # sums of lights beyond 1, unrounded
            self.target.colour.filter = (moderngl.NEAREST, moderngl.NEAREST)
        return self.target

    def _scene_pass(self, fbo, buffers: list[ObjectBuffer], ambient, view_proj: np.ndarray) -> None:
        program = self.shaders.program("lights3d_ambient")
        program["u_view_proj"].value = gl_matrix(view_proj)
        program["u_ambient"].value = tuple(ambient)
        fbo.use()
        with stencil_state(SCENE_PASS), blending(False):
            for b in buffers:
                program["u_albedo"].value = tuple(b.obj.colour)
                b.render(program)

    @staticmethod
    def _reach(light: Light3D, shown, view_proj, planes, near: float, size) -> tuple[tuple, tuple | None] | None:
        """Where the light can light in view: its reach within the objects it reaches there (`shown`), as a
        scissor rectangle and a span of window depths (its stencil pass's depth bounds); None where that is
        nothing."""
        if not light_in_view(light, planes):
            return None
        boxes = [reach_box(light, b.lo, b.hi) for b in shown]
        rect = union(screen_rect(view_proj, near, lo, hi, size) for lo, hi in boxes)
        if rect is None:
            return None
        return rect, span(depth_range(view_proj, near, lo, hi) for lo, hi in boxes)

    def _shadow(self, target: StencilTarget, index: int, light: Light3D, reached, shown, view_proj,
                settings, stats: FrameStats, bounds) -> None:
        casters = [b for b in reached if b.casts]
        method = METHODS[light.shadow]
        if method.volumes:
            clear_stencil(target.fbo)
            volumes = [self.volumes.get(light.shadow, caster.obj, light) for caster in casters]
            stats.volume_triangles += self.volume_pass.mark_uploaded(target.fbo, light.shadow, volumes, view_proj,
                                                                     bounds)
            stats.volumes_drawn += len(casters)
            stats.depth_bounded += self.depth_bounds and bounds is not None
        elif method.shadow_map:
            if index not in self.maps:
                self.maps[index] = ShadowMap(self.ctx, self.shaders, self.units)
            shadow_map = self.maps[index]
            key = (light, tuple(b.obj for b in shown), tuple(c.obj for c in casters), view_proj.tobytes(), settings)
            views = shadow_map.fitted(key, lambda: fit_views(light, shown, casters, view_proj, settings.map_size,
                                                             settings.pcf, settings.cascades))
            stats.maps_rendered += shadow_map.render(light, casters, views, settings.map_size, settings.pcf)

    def _light_pass(self, fbo, scene: Scene3D, camera: OrbitCamera, index: int, light: Light3D, buffers,
                    view_proj, settings) -> None:
        method = METHODS[light.shadow]
        program = self.shaders.program("lights3d_light")
        self._light_uniforms(program, light, view_proj)
        values = {"u_light_colour": tuple(light.colour), "u_eye": tuple(camera.position()),
                  "u_shininess": scene.shininess, "u_specular": scene.specular,
                  "u_facing_test": method.shadows, "u_in_plane": IN_PLANE, "u_reach_mask": settings.debug == "mask"}
        set_uniforms(program, values)
        if method.shadow_map:
            self.maps[index].bind(program, settings.bias, settings.pcf)
        else:
            program["u_map_mode"].value = 0
        fbo.use()
        with stencil_state(method.light_pass), blending(True):
            for b in buffers:
                program["u_albedo"].value = tuple(b.obj.colour)
                b.render(program)

    @staticmethod
    def _light_uniforms(program: moderngl.Program, light: Light3D, view_proj, optional=()) -> None:
        values = {"u_view_proj": gl_matrix(view_proj), "u_light_kind": LIGHT_KIND[light.kind],
                  "u_light_pos": tuple(light.position), "u_light_dir": tuple(light.direction),
                  "u_range": light.range, "u_falloff": light.falloff,
                  "u_cos_angle": float(np.cos(np.radians(light.angle)))}
        set_uniforms(program, values, optional=optional)

    def _stencil_view(self, fbo) -> None:
        """The stencil as grey, value / 255: each bit's share added where that bit is set (8 passes)."""
        program = self.shaders.program("fullscreen_colour")
        fbo.use()
        with blending(True):
            for bit in range(8):
                program["u_color"].value = (*[(1 << bit) / 255] * 3, 0.0)
                state = StencilState(func=GL.GL_EQUAL, ref=1 << bit, read_mask=1 << bit, write_mask=0,
                                     depth_func=GL.GL_ALWAYS, colour_write=True)
                with stencil_state(state):
                    self._fullscreen.get(program).render(vertices=3)

    def _copy(self, target: StencilTarget, fbo) -> None:
        program = self.shaders.program("lights3d_present")
        set_uniforms(program, self.units.bind(u_image=target.colour))
        fbo.use()
        with stencil_state(COPY_PASS), blending(False):
            self._fullscreen.get(program).render(vertices=3)

    # ---- one light's shadow, measured ---------------------------------------------------------------

    def shadow_mask(self, scene: Scene3D, camera: OrbitCamera, size: tuple[int, int], light_index: int,
                    method: str, settings: Lights3DRenderSettings | None = None) -> tuple[np.ndarray, MaskStats]:
        """Light `light_index` shadowed by `method` ("map" or a stencil method) over the scene seen by `camera`:
        (bool (H, W) top row first, True where a surface is in its shadow, the reference's pixels; the cost).
        Volumes and maps are made anew, never kept ones, so the cost is a light's that moved; the stencil is
        marked as a frame marks it (scissored to the light's reach, clamped to its depths where GL can), and its
        fill counted after. The pixels meant
        are those of the stencil (zpass, zfail: a count; onepass: the shadow value; back faces of casters
        included) or of the map (under half its PCF taps see the light); the caller restricts them to the
        pixels the light reaches and faces, as the reference's `facing & ~visible` means. The target stays bound
        (release() unbinds it before deleting it)."""
        settings = settings or Lights3DRenderSettings()
        drop_stale_errors()
        light = replace(scene.lights[light_index], shadow=method)
        shadow = METHODS[method]
        target = self._target(size)
        buffers = self.objects.update(scene.objects)
        view_proj = camera.clip_from_world(size)
        target.fbo.use()
        target.clear(colour=(*BACKGROUND, 1.0))
        self._scene_pass(target.fbo, buffers, scene.ambient, view_proj)
        reached = [b for b in buffers if reaches(light, b.centre, b.radius)]
        casters = [b for b in reached if b.casts]
        planes = frustum_planes(view_proj)
        shown = [b for b in reached if sphere_in_view(planes, b.centre, b.radius)]
        rect, bounds = self._reach(light, shown, view_proj, planes, camera.NEAR, size) or (None, None)
        fit_ms = 0.0
        if shadow.shadow_map:  # its texture made before the clock starts: drawing a map is timed, not allocating it
            fitting = time.perf_counter()
            views = fit_views(light, shown, casters, view_proj, settings.map_size, settings.pcf, settings.cascades)
            fit_ms = (time.perf_counter() - fitting) * 1e3
            self.mask_map = self.mask_map or ShadowMap(self.ctx, self.shaders, self.units)
            self.mask_map.reserve(views, settings.map_size)
        self.ctx.finish()
        start = time.perf_counter()
        if shadow.volumes:
            geometries = [build(method, c.obj, light) for c in casters] if rect else []  # else it lights nothing
            built = time.perf_counter()
            clear_stencil(target.fbo)
            target.fbo.scissor = rect
            triangles = self.volume_pass.mark(target.fbo, method, geometries, view_proj, bounds)
            self.ctx.finish()
            done = time.perf_counter()
            mask, visibility = shadowed(method, target.read_stencil()), None
            edges = sum(g.extruded_edges for g in geometries)
            fill = self.volume_pass.fill(target.fbo, method, geometries, view_proj, bounds)
            target.fbo.scissor = None
        elif shadow.shadow_map:
            built = start
            visibility = self._map_visibility(target, light, casters, views, buffers, view_proj, settings)
            done = time.perf_counter()
            mask, triangles, edges, fill = visibility < 0.5, 0, 0, 0
        else:
            raise ValueError(f"shadow_mask measures the stencil methods and map, not {method!r}")
        mask &= target.read_depth() < 1.0
        return mask, MaskStats(len(casters), triangles, edges, fit_ms + (built - start) * 1e3, (done - built) * 1e3,
                               visibility, fill)

    def _map_visibility(self, target: StencilTarget, light: Light3D, casters, views, buffers, view_proj,
                        settings) -> np.ndarray:
        """The map drawn afresh and read over the pre-pass's pixels; (H, W) float top row first, finished."""
        self.mask_map.forget()
        self.mask_map.render(light, casters, views, settings.map_size, settings.pcf)
        program = self.shaders.program("lights3d_mask")
        self._light_uniforms(program, light, view_proj, optional=HOW_BRIGHT)
        self.mask_map.bind(program, settings.bias, settings.pcf)
        target.fbo.use()
        with stencil_state(MAP.light_pass), blending(False):
            for b in buffers:
                b.render(program)
        self.ctx.finish()
        w, h = target.size
        return np.frombuffer(target.fbo.read(components=1, dtype="f4"), np.float32).reshape(h, w)[::-1].copy()

    def release(self) -> None:
        if self.target is not None:
            self.target.release()  # first: it leaves no deleted framebuffer bound
            self.target = None
        for owner in (self.objects, self.volume_pass, *self.maps.values(), self.mask_map, self.overlay,
                      self._fullscreen):
            if owner is not None:
                owner.release()
        self.maps.clear()
        self.volumes.clear()
