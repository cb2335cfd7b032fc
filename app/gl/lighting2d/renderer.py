"""The 2D lighting renderer (seed 000, Penumbra): lightmap cleared to ambient with alpha 1; per light a
shadow mask in the alpha, the hull pass, the light added weighted by that alpha; then diffuse x lightmap.

Five shadow methods (`METHODS`) share the pipeline and differ only in how the mask is made. Geometry is
uploaded relative to each light's centre (subtracted in double on the CPU) so coordinates near 1e6 keep
their precision. Lights whose quad misses the view are skipped, each light is scissored to its quad, and
only hulls that can reach its quad are considered (a grid index), so hulls and lights far from the view
cost nothing."""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import moderngl
import numpy as np

from app.gl.lighting2d.geometry import LightGeometry, disc_samples
from app.gl.core.texture_units import TextureUnits
from app.gl.core.uniforms import set_uniforms
from app.gl.core.vertex_arrays import VertexArrays
from app.io.textures2d import image
from app.model.camera2d import Camera2D
from app.model.lighting2d.scene import SHADOW_METHODS, Light, Scene2D, Shading2D
from app.model.lighting2d.index import SceneIndex, SceneIndexes, light_bounds

METHODS = SHADOW_METHODS
KINDS = {"point": 0, "spot": 1, "textured": 2}
SHADOW_TYPES = {"solid": 0, "illuminated": 1, "occluded": 2}
ALPHA = (False, False, False, True)
ALL = (True, True, True, True)


@dataclass
class FrameStats:
    """What one frame did: the work that must not grow with hulls outside the view."""
    lights_drawn: int = 0
    lights_culled: int = 0
    hulls_considered: int = 0
    skipped_inside: list[int] = field(default_factory=list)
    index_cells: int = 0        # grid cells the scene index visited
    index_boxes: int = 0        # hull boxes the scene index tested
    hulls_built: int = 0        # hulls whose geometry was (re)built for a light
    vertices_uploaded: int = 0  # rows written to the edge, triangle and region buffers
    disc_ordered: int = 0       # lights whose disc hulls enter, apart, of few pieces (light2d_disc_order.shl)
    disc_fused: int = 0         # ... overlapping or of more pieces (light2d_disc.shl)


class Lighting2DRenderer:
    def __init__(self, ctx: moderngl.Context, shaders) -> None:
        self.ctx = ctx
        self.shaders = shaders
        self._own = SceneIndexes()  # the scene's index where the host shares none
        self._index: SceneIndex | None = None  # the index the geometry below was built with
        self._geometry: dict[int, LightGeometry] = {}
        self._quad = ctx.buffer(np.array([0, 0, 1, 0, 0, 1, 1, 1], "f4"))
        self._edges = ctx.buffer(reserve=64, dynamic=True)
        self._tris = ctx.buffer(reserve=64, dynamic=True)
        self._regions = ctx.buffer(reserve=64, dynamic=True)
        self._pieces: moderngl.Texture | None = None
        self._batch_key = None
        self._spans: dict[int, _Span] = {}
        self._quad_vaos = VertexArrays(lambda p: ctx.vertex_array(p, [(self._quad, "2f", "in_uv")]))
        self._edge_vaos = VertexArrays(
            lambda p: ctx.vertex_array(p, [(self._edges, "2f 2f 2f", "in_a", "in_b", "in_s")]))
        self._tri_vaos = VertexArrays(lambda p: ctx.vertex_array(p, [(self._tris, "2f", "in_rel")]))
        self._region_vaos = VertexArrays(lambda p: ctx.vertex_array(p, [(self._regions, "2i", "in_piece")]))
        self._screen_vaos = VertexArrays(lambda p: ctx.vertex_array(p, []))
        self._targets: dict[str, tuple] = {}
        self._textures: dict[str, moderngl.Texture] = {}
        self.stats = FrameStats()
        self.units = TextureUnits()

    # ---- public -------------------------------------------------------------------------------------

    def render(self, fbo: moderngl.Framebuffer, scene: Scene2D, camera: Camera2D, settings: Shading2D,
               lightmap_only: bool = False, index: SceneIndex | None = None) -> FrameStats:
        """Draw the lit scene into `fbo` (its whole viewport); `index`: see index()."""
        lightmap = self.build_lightmap(scene, camera, fbo.size, settings, index)
        fbo.scissor = None
        _bind(fbo, ALL)
        self._blend_off()
        program = self.shaders.program("light2d_composite")
        diffuse = self._texture(scene.background, repeat=True)
        sx, sy, ox, oy = self._ndc_to_world(camera, *fbo.size, settings.flip_y, diffuse.size)
        set_uniforms(program, self.units.bind(u_diffuse=diffuse, u_lightmap=lightmap), u_world_scale=(sx, sy),
                     u_world_offset=(ox, oy), u_lightmap_only=lightmap_only)
        self._screen_vaos.get(program).render(moderngl.TRIANGLES, vertices=3)
        return self.stats

    def read_lightmap(self, scene: Scene2D, camera: Camera2D, size: tuple[int, int], settings: Shading2D) -> np.ndarray:
        """The lightmap as float32 (height, width, 3), clamped to 0..1, row 0 at the top (bench, tests)."""
        tex = self.build_lightmap(scene, camera, size, settings)
        data = np.frombuffer(tex.read(), "f2").reshape(tex.height, tex.width, 4)[::-1, :, :3].astype(np.float32)
        return np.clip(data, 0.0, 1.0)

    def lightmap_value(self, x: float, y: float, size: tuple[int, int]) -> np.ndarray | None:
        """The last lightmap built, for a view of `size` pixels, at the view's pixel (x, y) from its top left: the
        light reaching there (RGB, clamped to 0..1); None before any."""
        held = self._targets.get("lightmap")
        if held is None:
            return None
        tex, fbo = held[0], held[1]
        column = min(max(int(x * tex.width / size[0]), 0), tex.width - 1)
        row = min(max(int((size[1] - y) * tex.height / size[1]), 0), tex.height - 1)  # texture rows run up
        texel = np.frombuffer(fbo.read(viewport=(column, row, 1, 1), components=4, dtype="f2"), "f2")
        return np.clip(texel[:3].astype(np.float64), 0.0, 1.0)

    def build_lightmap(self, scene: Scene2D, camera: Camera2D, size: tuple[int, int], settings: Shading2D,
                       index: SceneIndex | None = None):
        if settings.method not in METHODS:
            raise ValueError(f"unknown shadow method {settings.method!r}; there are {', '.join(METHODS)}")
        index = self.index(scene, index)
        w, h = (max(1, round(v * settings.lightmap_scale)) for v in size)
        lightmap, fbo = self._target("lightmap", (w, h), 4, "f2", depth=True)
        fbo.scissor = None
        _bind(fbo, ALL)
        fbo.clear(*scene.ambient, 1.0)
        self.stats = FrameStats()
        cells, boxes = index.grid.cells_visited, index.grid.boxes_tested
        scale, offset = self._clip_transform(camera, w, h, settings.flip_y)
        view = camera.view_rect(w, h)
        drawn = []
        for i, light in enumerate(scene.lights):
            if not light.enabled:
                continue
            x0, y0, x1, y1 = light_bounds(light)
            if x1 < view[0] or x0 > view[2] or y1 < view[1] or y0 > view[3]:
                self.stats.lights_culled += 1
                continue
            if index.centre_blocked(light):
                self.stats.skipped_inside.append(i)
                continue
            drawn.append(i)
        self._upload_batch(scene, drawn)
        self.stats.index_cells = index.grid.cells_visited - cells
        self.stats.index_boxes = index.grid.boxes_tested - boxes
        for i in drawn:
            self._draw_light(fbo, scene.lights[i], self._spans[i], scale, offset, settings, scene)
            self.stats.lights_drawn += 1
        fbo.scissor = None
        _bind(fbo, ALL)
        self._blend_off()
        return lightmap

    def index(self, scene: Scene2D, shared: SceneIndex | None = None) -> SceneIndex:
        """The scene's index: `shared`, the one the host holds (the editor's workspace, whose tool's clicks ask
        it too), else the renderer's own, built again only for another scene (an edit makes one).
        The lights' geometry is built again with each new index."""
        index = shared if shared is not None else self._own.get(scene)
        if index is not self._index:
            self._index = index
            self._geometry.clear()
        return index

    def _upload_batch(self, scene: Scene2D, drawn: list[int]) -> None:
        """The geometry of every light drawn, in one buffer (and one texture) each, uploaded only when
        the scene or the set of lights in view changed; each light draws its own span."""
        key = (self._index, tuple(drawn))  # the index held: a new one is another object
        if key == self._batch_key:
            return
        for i in drawn:
            if i not in self._geometry:
                self._geometry[i] = LightGeometry.build(scene, self._index, scene.lights[i])
                self.stats.hulls_built += self._geometry[i].hull_count
        parts = [self._geometry[i] for i in drawn]
        starts = [np.cumsum([0] + [len(getattr(g, name)) for g in parts])
                  for name in ("edges", "triangles", "pieces", "heads")]
        self._spans = {i: _Span(g, *(int(column[k]) for column in starts))
                       for k, (i, g) in enumerate(zip(drawn, parts))}
        self._upload(self._edges, np.concatenate([g.edges for g in parts]) if parts else np.zeros((0, 6)))
        self._upload(self._tris, np.concatenate([g.triangles for g in parts]) if parts else np.zeros((0, 2)))
        # six corners per piece, each naming the piece's header texel in the batch's texture
        heads = np.concatenate([g.heads + starts[2][k] for k, g in enumerate(parts)]) if parts else np.zeros(0, "i4")
        corners = np.stack([np.repeat(heads, 6), np.tile(np.arange(6), len(heads))], axis=1)
        self._upload(self._regions, corners.astype("i4"), dtype="i4")
        texels = np.concatenate([g.pieces for g in parts]) if parts else np.zeros((0, 4))
        rows = max(1, -(-len(texels) // 1024))
        if self._pieces is None or self._pieces.height < rows:
            if self._pieces is not None:
                self._pieces.release()
            self._pieces = self.ctx.texture((1024, max(rows, 4)), 4, dtype="f4")
            self._pieces.filter = moderngl.NEAREST, moderngl.NEAREST
        padded = np.zeros((rows * 1024, 4), "f4")
        padded[:len(texels)] = texels
        self._pieces.write(padded.tobytes(), viewport=(0, 0, 1024, rows))
        self._batch_key = key

    # ---- one light ----------------------------------------------------------------------------------

    def _draw_light(self, fbo, light: Light, span: "_Span", scale, offset, settings: Shading2D, scene) -> None:
        geometry = span.geometry
        self.stats.hulls_considered += geometry.hull_count
        light_clip = tuple(np.asarray(light.position) * scale + offset)
        common = {"u_scale": tuple(scale), "u_light_clip": light_clip}
        box = self._scissor(light, scale, offset, *fbo.size)
        if box is None:
            return
        fbo.scissor = box
        shadows = light.casts_shadows and geometry.hull_count > 0
        method = settings.method
        self._fill(fbo, 0.0 if shadows and method == "jitter" else 1.0, ALPHA)
        if method == "penumbra" and light.radius == 0:
            method = "hard"  # the seed's wedges need a disc; a point casts hard shadows (no NaN)
        if shadows:
            if method == "exact":
                self._exact_mask(fbo, light, span, common)
            else:
                if method in ("hard", "penumbra"):
                    self._edge_mask(fbo, light, span, common, soft=method == "penumbra")
                elif method == "jitter":
                    self._jitter_mask(fbo, light, span, common, settings.samples, box)
                else:
                    self._blur_mask(fbo, light, span, common, settings.blur, box, scale)
                self._hull_pass(fbo, light, span, common)
        self._light_pass(fbo, scene, light, common, settings)

    def _edge_mask(self, fbo, light, span, common, soft: bool, emit=(0.0, 0.0), color_mask=ALPHA) -> None:
        program = self._program("light2d_edges", common, u_soft=soft,
                                u_radius=float(light.radius), u_emit=emit)
        _bind(fbo, color_mask)
        if soft:  # Penumbra: subtract each edge's occlusion, then clamp at 0 (overlaps would go negative)
            self.ctx.enable(moderngl.BLEND)
            self.ctx.blend_equation = moderngl.FUNC_REVERSE_SUBTRACT
            self.ctx.blend_func = moderngl.ONE, moderngl.ONE
        else:
            self._blend_off()
        span.draw_edges(self._edge_vaos.get(program))
        if soft:
            self._fill(fbo, 0.0, ALPHA, equation=moderngl.MAX)

    def _jitter_mask(self, fbo, light, span, common, samples: int, box) -> None:
        """N hard shadows from points spread over the disc, four per pass in a mask's channels."""
        points = disc_samples(light.radius, samples)
        mask, mask_fbo = self._target("jitter", fbo.size, 4, "f1")
        mask_fbo.scissor = box
        for start in range(0, len(points), 4):
            group = points[start:start + 4]
            self._fill(mask_fbo, 1.0, ALL)
            for k, emit in enumerate(group):
                self._edge_mask(mask_fbo, light, span, common, soft=False, emit=tuple(map(float, emit)),
                                color_mask=tuple(c == k for c in range(4)))
            weights = tuple(1.0 / len(points) if k < len(group) else 0.0 for k in range(4))
            self._mask_into_alpha(fbo, mask, weights, blend=True)

    def _blur_mask(self, fbo, light, span, common, blur: float, box, scale) -> None:
        sigma = max(blur * light.radius * abs(float(scale[1])) * fbo.size[1] / 2.0, 1e-3)
        reach = int(math.ceil(3 * sigma)) + 1
        x, y, w, h = box
        grown = (max(x - reach, 0), max(y - reach, 0), w + 2 * reach, h + 2 * reach)
        mask, mask_fbo = self._target("blur_a", fbo.size, 1, "f2")
        other, other_fbo = self._target("blur_b", fbo.size, 1, "f2")
        mask_fbo.scissor = other_fbo.scissor = grown
        self._fill(mask_fbo, 1.0, ALL)
        self._edge_mask(mask_fbo, light, span, common, soft=False, color_mask=ALL)
        program = self._program("light2d_blur", {}, u_sigma=float(sigma), u_mask=self.units["u_mask"])
        for source, target, step in ((mask, other_fbo, (1.0, 0.0)), (other, mask_fbo, (0.0, 1.0))):
            _bind(target, ALL)
            self.units.bind(u_mask=source)
            program["u_step"].value = step
            self._screen_vaos.get(program).render(moderngl.TRIANGLES, vertices=3)
        self._mask_into_alpha(fbo, mask, (1.0, 0.0, 0.0, 0.0), blend=False)

    def _exact_mask(self, fbo, light, span, common) -> None:
        """Mark in the depth buffer where some piece hides some of the disc (the cover: every piece and
        its shadow), and nearer where one piece hides all of it (its umbra, mask 0, solid lights only);
        run the per-pixel coverage where only the cover is. Elsewhere a pixel sees all of the disc or
        none of it, and the mask is already right."""
        if span.geometry.touching:  # a hull overlaps the disc: shadows can fall anywhere, so no cover
            self._exact_pass(fbo, light, span, common, outside=False)
            return
        region = self._program("light2d_region", common, **self.units.bind(u_pieces=self._pieces),
                               u_radius=float(light.radius), u_color=(0.0, 0.0, 0.0, 0.0))
        solid = light.shadow_type == "solid"
        fbo.depth_mask = True
        _bind(fbo, (False, False, False, False))
        fbo.clear(depth=1.0, viewport=fbo.scissor)
        self.ctx.enable(moderngl.DEPTH_TEST)
        self.ctx.depth_func = "<="
        self._blend_off()
        hull = self._program("light2d_hull", common, u_color=(0.0, 0.0, 0.0, 0.0))
        for umbra, depth in [(False, 0.0)] + [(True, -0.5)] * solid:
            if umbra:
                _bind(fbo, ALPHA)
            region["u_umbra"].value = umbra
            hull["u_depth"].value = depth
            span.draw_regions(self._region_vaos.get(region))
            span.draw_triangles(self._tri_vaos.get(hull))
        fbo.depth_mask = False
        self.ctx.depth_func = "=="
        try:
            self._exact_pass(fbo, light, span, common, outside=solid)
        finally:
            self.ctx.disable(moderngl.DEPTH_TEST)
            self.ctx.depth_func = "<"
            fbo.depth_mask = True

    def _exact_pass(self, fbo, light, span, common, outside: bool) -> None:
        name, cover = "light2d_exact", {"u_outside": outside}
        if span.geometry.touching:  # no cover (see _exact_mask), so nothing outside it: the disc programs lack it
            ordered = span.geometry.ordered
            name, cover = "light2d_disc_order" if ordered else "light2d_disc", {}
            self.stats.disc_ordered += ordered
            self.stats.disc_fused += not ordered
        program = self._program(
            name, common, **self.units.bind(u_pieces=self._pieces),
            u_begin=span.piece_first, u_end=span.piece_first + len(span.geometry.pieces),
            u_radius=float(light.radius), u_shadow_type=SHADOW_TYPES[light.shadow_type], **cover,
            **self._quad_uniforms(light))
        _bind(fbo, ALPHA)
        self._blend_off()
        self._quad_vaos.get(program).render(moderngl.TRIANGLE_STRIP)

    def _hull_pass(self, fbo, light, span, common) -> None:
        count = len(span.geometry.triangles)
        if light.shadow_type == "occluded" or not count:
            return  # occluded hulls keep what the other hulls' shadows left
        value = 0.0 if light.shadow_type == "solid" else 1.0
        program = self._program("light2d_hull", common, u_color=(value, value, value, value), u_depth=0.0)
        _bind(fbo, ALPHA)
        self._blend_off()
        span.draw_triangles(self._tri_vaos.get(program))

    def _light_pass(self, fbo, scene, light: Light, common, settings: Shading2D) -> None:
        normals_on = bool(settings.normal_maps and scene.normal_map and light.height > 0)
        extra = self.units.uniforms("u_cookie", "u_normals")  # bound only where read
        if light.kind == "textured":
            self.units.bind(u_cookie=self._texture(light.texture, repeat=False))
        if normals_on:
            normals = self._texture(scene.normal_map, repeat=True)
            self.units.bind(u_normals=normals)
            w, h = normals.size
            extra["u_normal_at"] = ((light.position[0] / w) % 1.0, (light.position[1] / h) % 1.0)
        program = self._program(
            "light2d_light", common, u_kind=KINDS[light.kind], u_color=light.color, u_intensity=light.intensity,
            u_cone=light.cone_half_angle() if light.kind == "spot" else 1.0, u_decay=light.cone_decay,
            u_normals_on=normals_on, u_height=float(light.height), **self._quad_uniforms(light), **extra)
        _bind(fbo, ALL)
        self.ctx.enable(moderngl.BLEND)
        self.ctx.blend_equation = moderngl.FUNC_ADD
        self.ctx.blend_func = moderngl.DST_ALPHA, moderngl.ONE, moderngl.ONE, moderngl.ZERO
        self._quad_vaos.get(program).render(moderngl.TRIANGLE_STRIP)
        self._blend_off()

    # ---- helpers ------------------------------------------------------------------------------------

    def _blend_off(self) -> None:
        """Blending off, with the equation and function a new context has, as the host's baseline (gl_state.py)."""
        self.ctx.disable(moderngl.BLEND)
        self.ctx.blend_equation = moderngl.FUNC_ADD
        self.ctx.blend_func = moderngl.DEFAULT_BLENDING

    def _program(self, name: str, common: dict, **uniforms) -> moderngl.Program:
        program = self.shaders.program(name)
        set_uniforms(program, {**common, **uniforms})
        return program

    @staticmethod
    def _quad_uniforms(light: Light) -> dict:
        c, s = math.cos(light.rotation), math.sin(light.rotation)
        sx, sy = light.scale
        return {"u_quad": (c * sx, s * sx, -s * sy, c * sy), "u_origin": light.origin}

    def _fill(self, fbo, value: float, color_mask, equation=None) -> None:
        """Set the scissored region to `value` in the masked channels (a clear that keeps the other
        channels), or combine it with what is there by a blend `equation`."""
        program = self._program("light2d_fill", {}, u_color=(value, value, value, value))
        _bind(fbo, color_mask)
        if equation is None:
            self._blend_off()
        else:
            self.ctx.enable(moderngl.BLEND)
            self.ctx.blend_equation = equation
            self.ctx.blend_func = moderngl.ONE, moderngl.ONE
        self._screen_vaos.get(program).render(moderngl.TRIANGLES, vertices=3)
        self._blend_off()

    def _mask_into_alpha(self, fbo, mask, weights, blend: bool) -> None:
        program = self._program("light2d_mask", {}, **self.units.bind(u_mask=mask), u_weights=weights)
        _bind(fbo, ALPHA)
        if blend:
            self.ctx.enable(moderngl.BLEND)
            self.ctx.blend_equation = moderngl.FUNC_ADD
            self.ctx.blend_func = moderngl.ONE, moderngl.ONE
        else:
            self._blend_off()
        self._screen_vaos.get(program).render(moderngl.TRIANGLES, vertices=3)
        self._blend_off()

    def _upload(self, buffer: moderngl.Buffer, data: np.ndarray, dtype: str = "f4") -> None:
        data = np.ascontiguousarray(data, dtype)
        self.stats.vertices_uploaded += len(data)
        if data.nbytes > buffer.size:
            buffer.orphan(data.nbytes)
        if data.nbytes:
            buffer.write(data)

    def _target(self, name: str, size, components: int, dtype: str, depth: bool = False):
        held = self._targets.get(name)
        if held is None or held[0].size != tuple(size):
            if held is not None:
                for item in held[::-1]:
                    if item is not None:
                        item.release()
            tex = self.ctx.texture(tuple(size), components, dtype=dtype)
            tex.repeat_x = tex.repeat_y = False
            rb = self.ctx.depth_renderbuffer(tuple(size)) if depth else None
            held = self._targets[name] = (tex, self.ctx.framebuffer([tex], rb), rb)
        return held[:2]

    def _texture(self, name: str, repeat: bool) -> moderngl.Texture:
        key = f"{name}|{repeat}"
        data = image(name)
        held = self._textures.get(key)
        if held is None or held[1] is not data:
            if held is not None:
                held[0].release()
            tex = self.ctx.texture((data.shape[1], data.shape[0]), 4, np.ascontiguousarray(data[::-1]).tobytes())
            tex.repeat_x = tex.repeat_y = repeat
            tex.filter = moderngl.LINEAR, moderngl.LINEAR
            held = self._textures[key] = (tex, data)
        return held[0]

    @staticmethod
    def _clip_transform(camera: Camera2D, w: int, h: int, flip_y: bool):
        scale, offset = camera.scale_offset(w, h)
        if flip_y:
            scale[1], offset[1] = -scale[1], -offset[1]
        return scale, offset

    def _ndc_to_world(self, camera: Camera2D, w: int, h: int, flip_y: bool, tex_size):
        scale, offset = self._clip_transform(camera, w, h, flip_y)
        sx, sy = 1.0 / scale
        ox, oy = -offset / scale
        return sx, sy, ox % tex_size[0], oy % tex_size[1]

    @staticmethod
    def _scissor(light: Light, scale, offset, width: int, height: int):
        """The light's quad bounds in lightmap pixels, clipped; None when nothing is left."""
        x0, y0, x1, y1 = light_bounds(light)
        corners = np.array([[x0, y0], [x1, y1]]) * scale + offset
        px = (corners[:, 0] * 0.5 + 0.5) * width
        py = (corners[:, 1] * 0.5 + 0.5) * height
        left, right = max(0, math.floor(px.min())), min(width, math.ceil(px.max()))
        bottom, top = max(0, math.floor(py.min())), min(height, math.ceil(py.max()))
        if right <= left or top <= bottom:
            return None
        return left, bottom, right - left, top - bottom


@dataclass
class _Span:
    """Where one light's geometry sits in the batch."""
    geometry: LightGeometry
    edge_first: int
    tri_first: int
    piece_first: int
    head_first: int

    def draw_edges(self, vao: moderngl.VertexArray) -> None:
        vao.render(moderngl.TRIANGLES, vertices=len(self.geometry.edges), first=self.edge_first)

    def draw_triangles(self, vao: moderngl.VertexArray) -> None:
        vao.render(moderngl.TRIANGLES, vertices=len(self.geometry.triangles), first=self.tri_first)

    def draw_regions(self, vao: moderngl.VertexArray) -> None:
        vao.render(moderngl.TRIANGLES, vertices=6 * len(self.geometry.heads), first=6 * self.head_first)


def _bind(fbo: moderngl.Framebuffer, color_mask) -> None:
    """moderngl applies a framebuffer's colour mask (and scissor) when it is bound: set them first."""
    fbo.color_mask = color_mask
    fbo.use()
