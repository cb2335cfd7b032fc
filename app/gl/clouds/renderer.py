"""The clouds on the GPU: the model's textures, the march into a reduced cloud buffer, the temporal passes
(Guerrilla's reprojection, TAA) and the composite over the cirrus, sky and ground at the output's size.

Passes per frame (docs/clouds.md, "Optimisations"):
1. trace: every pixel of the cloud buffer (1/d of the output on each axis); with reprojection that pixel is
   one output pixel of its d x d block, a different one each frame (d = 4: Guerrilla's 4x4 Bayer order);
2. resolve (reprojection only, at the output's size; half of it for a drag's cheapest level): the traced pixels,
   the others from the last frame where their clouds were then (through a turn and the wind's motion at the
   clouds' depth; clamped to what was traced around them while the clock runs), or this frame's buffer where the
   last frame has nothing; what a turn brought into view is traced at that size;
3. taa (without reprojection): the history, clamped to this frame's 3x3 neighbourhood, blended with it;
4. composite: the buffer under or over the cirrus, over the sky or the shadowed ground, into a float target: linear
   radiance, unclamped;
5. tone map (app/gl/clouds/tone_map.py): exposure, the tone curve and sRGB encoding into the output.
Every buffer is read between its texels only from those whose rays end where the pixel's does, the ground or
the sky (resources/shaders/clouds_upsample.shl): clouds never spread across the horizon.

A still view keeps drawing (`settling`) until a frame changes the clouds by less than CONVERGED."""
from __future__ import annotations

import math
from dataclasses import asdict, replace

import moderngl
import numpy as np

from app.gl.clouds.atmosphere import AtmosphereTables
from app.gl.clouds.reprojection import NEW_SHARE, buffer_change, cloud_motion, new_directions
from app.gl.clouds.tone_map import ToneMap
from app.gl.core.texture_units import TextureUnits
from app.gl.core.uniforms import set_uniforms
from app.gl.core.vertex_arrays import VertexArrays
from app.model.clouds.scene import ATMOSPHERE, CloudRenderSettings, Frame, furnace


def bayer_order(n: int) -> tuple[int, ...]:
    """The pixels (x + n y) of an n x n block, n a power of two, in the order of Bayer's matrix."""
    m = np.zeros((1, 1), dtype=int)
    while len(m) < n:
        m = np.block([[4 * m, 4 * m + 2], [4 * m + 3, 4 * m + 1]])
    return tuple(int(i) for i in np.argsort(m.ravel()))


# The order in which reprojection traces the pixels of a d x d block, one a frame (index = x + d y), each
# frame's pixel far from the last ones: Bayer's for 2, Guerrilla's 4x4, a dispersed one for 3, and Bayer's for 8
# (only the host's cheapest levels reduce the buffer that far: r_cloudDownsample stops at 4).
ORDERS = {2: (0, 3, 1, 2), 3: (0, 8, 2, 6, 4, 1, 7, 3, 5),
          4: (0, 8, 2, 10, 12, 4, 14, 6, 3, 11, 1, 9, 15, 7, 13, 5), 8: bayer_order(8)}
TAA_FRAMES = 16       # while the clock runs the history's weight settles at 1 - 1/16 (old clouds fade)
# A clock still for this many frames has stopped; fewer are gaps between an animation's ticks (the editor draws
# frames between them: counted as stops, each restarted the reprojection's count, so the view never settled).
STOP_FRAMES = 4
GOLDEN = 0.61803398875  # the blue noise's shift per frame: every offset visited evenly over time
# What the host's cheaper levels change (the workspace's `cheaper`, TAA off while interactive): a reprojected
# history outlives a change to a cheaper one (a drag goes on through the levels), each of its pixels traced again
# within d^2 frames, but not to a finer one (the first still frames would show a drag's coarse, noisy picture;
# this frame's buffer stretched is nearer the truth: 11.4 against 14.3/255 RMSE after a drag at a quarter
# buffer and half the steps, at the editor's view).
REFINED = ("steps", "downsample", "taa", "reproject_downsample")


def finer(quality: tuple, before: tuple | None) -> bool:
    """Whether REFINED settings `quality` trace more finely than `before`: more steps, a smaller buffer or picture
    reduction."""
    if before is None:
        return False
    (steps, down, _taa, picture), (steps0, down0, _taa0, picture0) = quality, before
    return steps > steps0 or down < down0 or picture < picture0


CONVERGED = 0.1 / 255   # a still view has settled once a frame changes its clouds by less (mean per texel, RGB)
MAX_SETTLING = 256      # ... or after this many frames since its history restarted
STATE = 4               # the state texture's components: lookups, traced, ground, depth (clouds_upsample.shl)


class Target:
    """A framebuffer of float textures, nearest: the passes read between texels themselves
    (resources/shaders/clouds_upsample.shl)."""

    def __init__(self, ctx: moderngl.Context, size: tuple[int, int], components: tuple[int, ...]) -> None:
        self.size = size
        self.textures = [ctx.texture(size, c, dtype="f4") for c in components]
        for texture in self.textures:
            texture.filter = (moderngl.NEAREST, moderngl.NEAREST)
            texture.repeat_x = texture.repeat_y = False
        self.fbo = ctx.framebuffer(self.textures)


def buffer_size(size: tuple[int, int], downsample: int) -> tuple[int, int]:
    return max(1, math.ceil(size[0] / downsample)), max(1, math.ceil(size[1] / downsample))


class CloudTexturesGL:
    """The noise textures (uploaded once) and the two weather maps (uploaded when they change)."""

    def __init__(self, ctx: moderngl.Context, noise) -> None:
        self.ctx = ctx
        self.shape = self._volume(noise.shape)
        self.detail = self._volume(noise.detail)
        self.curl = self._image(noise.curl)
        self.cirrus = self._image(noise.cirrus)
        self.blue = self._image(noise.blue, linear=False)
        self.weather: list[moderngl.Texture] = []
        self._weather_key = None

    def _volume(self, a: np.ndarray) -> moderngl.Texture3D:
        t = self.ctx.texture3d(a.shape[::-1], 1, np.ascontiguousarray(a, dtype="f4").tobytes(), dtype="f4")
        t.filter = (moderngl.LINEAR, moderngl.LINEAR)
        t.repeat_x = t.repeat_y = t.repeat_z = True
        return t

    def _image(self, a: np.ndarray, linear: bool = True) -> moderngl.Texture:
        components = 1 if a.ndim == 2 else a.shape[2]
        t = self.ctx.texture((a.shape[1], a.shape[0]), components, np.ascontiguousarray(a, dtype="f4").tobytes(),
                             dtype="f4")
        f = moderngl.LINEAR if linear else moderngl.NEAREST
        t.filter = (f, f)
        t.repeat_x = t.repeat_y = True
        return t

    def sync_weather(self, blend) -> int:
        """Upload the blend's maps if they changed; returns the number of maps uploaded."""
        if blend.version == self._weather_key:
            return 0
        for t in self.weather:
            t.release()
        self.weather = [self._image(m) for m in blend.maps]
        self._weather_key = blend.version
        return len(self.weather)

    def use(self, units: TextureUnits) -> dict[str, int]:
        """Bound at their units of the renderer's `units`: the samplers' values."""
        return units.bind(u_shape=self.shape, u_detail=self.detail, u_curl=self.curl, u_cirrus=self.cirrus,
                          u_weather_old=self.weather[0], u_weather_new=self.weather[1], u_blue=self.blue)


def reprojects(settings: CloudRenderSettings) -> bool:
    """Reprojection fills in the blocks of a reduced buffer: a full one has none."""
    return settings.reproject and settings.downsample > 1


def uniforms(frame: Frame, settings: CloudRenderSettings, aspect: float, frame_index: int) -> dict:
    values = {f"u_{name}": value for name, value in asdict(furnace(frame) if settings.furnace else frame).items()}
    values.update(u_aspect=aspect, u_steps=settings.steps, u_seed_integration=int(settings.integration == "seed"),
                  u_early_exit=int(settings.early_exit), u_big_steps=int(settings.big_steps),
                  u_light_skip=int(settings.light_skip), u_detail_skip=int(settings.detail_skip),
                  u_jitter=int(settings.jitter), u_frame_offset=(frame_index * GOLDEN) % 1.0)
    return values


class CloudRenderer:
    def __init__(self, ctx: moderngl.Context, shaders) -> None:
        self.ctx, self.shaders = ctx, shaders
        self.textures: CloudTexturesGL | None = None
        self.atmosphere = AtmosphereTables(ctx, shaders)
        self.units = TextureUnits()  # every pass's samplers: the noise stays bound while each pass binds its own
        self._screen = VertexArrays(lambda program: ctx.vertex_array(program, []))
        self._targets: dict[str, Target] = {}
        self.tone_map = ToneMap(ctx, shaders)
        self.frame_index = 0
        self._key = None           # what the histories were made with: all but the clock, the turn, the quality
        self._quality = None       # the REFINED settings of the last frame
        self._basis = None         # the last frame's camera basis: a turn reprojects through it
        self._clock = None         # the last frame's wind offsets and blend
        self._clock_moved = False  # ... and whether they had moved
        self._clock_age = None     # frames since the clock last moved (None: not since the histories restarted)
        self._resolved = None      # the last resolved buffer (reprojection)
        self._taa = None           # the last TAA output
        self._compared = None      # (the last frame's buffer, this frame's) where this frame kept the history
        self._change = None        # the mean change between them, once asked for
        self.taa_frames = 0
        self._taa_samples = 0      # the samples the TAA history averages (a running clock caps them)
        self.reprojected_frames = 0
        self.last_lookups: Target | None = None  # the last frame's cloud buffer and its state (lookups...)
        self.last_clouds: moderngl.Texture | None = None  # the buffer the last composite read
        self.last_hdr: moderngl.Texture | None = None     # the last frame's linear radiance (the tone map's input)

    # ---- targets ------------------------------------------------------------------------------------

    def _target(self, name: str, size, components) -> Target:
        t = self._targets.get(name)
        if t is None or t.size != size:
            if t is not None:
                t.fbo.release()
                for texture in t.textures:
                    texture.release()
            t = self._targets[name] = Target(self.ctx, size, components)
        return t

    def _draw(self, program_name: str, target_fbo, scene: dict, **own) -> None:
        """One pass over its target: `scene` the frame's uniforms, shared by the passes, each reading some (every
        one read by some pass: tests/test_clouds_gl.py); `own` the pass's, all of them read."""
        program = self.shaders.program(program_name)
        set_uniforms(program, scene, optional=scene.keys())
        set_uniforms(program, own)
        target_fbo.use()
        self._screen.get(program).render(moderngl.TRIANGLES, vertices=3)

    # ---- a frame ------------------------------------------------------------------------------------

    def render(self, fbo: moderngl.Framebuffer, frame: Frame, weather, settings: CloudRenderSettings, noise) -> None:
        """Draw one frame of the clouds into `fbo` (`weather`: the WeatherBlend; `noise`: NoiseTextures)."""
        if self.textures is None:
            self.textures = CloudTexturesGL(self.ctx, noise)
        self.textures.sync_weather(weather)
        size = fbo.size
        bsize = buffer_size(size, settings.downsample)
        aspect = size[0] / max(size[1], 1)
        self.atmosphere.update(ATMOSPHERE, frame.camera[1], frame.sun_dir[1])  # first: its passes bind their own units
        values = self._scene_values(frame, settings, aspect)
        # The histories hold while only the clock moves (the winds, a weather blend); reprojection's also
        # through a turn of the camera (a direction's colour does not depend on where the camera looks) and a
        # change to a cheaper quality (REFINED); anything else restarts them (docs/clouds.md, "Optimisations").
        basis = (frame.forward, frame.right, frame.up)
        clock = (frame.wind_offset, frame.weather_offset, frame.high_offset, frame.blend)
        key = (replace(frame, forward=None, right=None, up=None, wind_offset=None, weather_offset=None,
                       high_offset=None, blend=None),
               replace(settings, debug_samples=False, tone=None, **{name: None for name in REFINED}), size,
               weather.version)
        quality = tuple(getattr(settings, name) for name in REFINED)
        history = 0 if key != self._key or finer(quality, self._quality) else 1 if basis == self._basis else 2
        requality = history != 0 and quality != self._quality
        self._clock_moved = history != 0 and clock != self._clock
        self._clock_age = (0 if self._clock_moved else None if history == 0 or self._clock_age is None
                           else self._clock_age + 1)
        clock_stopped = self._clock_age == STOP_FRAMES
        values.update(u_buffer=bsize)
        self._compared = self._change = None

        clouds = self._trace(size, bsize, settings, values, history, requality, clock_stopped, clock)
        if settings.taa and not reprojects(settings):  # reprojection averages its cycles itself
            clouds = self._temporal_aa(bsize, clouds, values, history == 1 and not requality)
        else:
            self.taa_frames = 0
        self.last_clouds = clouds
        hdr = None if settings.debug_samples else self._target("hdr", size, (4,))  # the lookups view: no light
        self._draw("clouds_composite", fbo if hdr is None else hdr.fbo, values,
                   **self.units.bind(u_clouds=clouds, u_lookups=self.last_lookups.textures[1]),
                   u_size=tuple(map(float, size)), u_debug=int(settings.debug_samples))
        if hdr is not None:
            self.last_hdr = hdr.textures[0]
            self.tone_map.apply(self.last_hdr, fbo, settings.tone, restart=history == 0)
        self._key, self._quality, self._basis, self._clock = key, quality, basis, clock
        self.frame_index += 1

    def _scene_values(self, frame: Frame, settings: CloudRenderSettings, aspect: float) -> dict:
        """The uniforms every pass shares, the textures bound: the frame's, the noise's and the atmosphere's."""
        values = uniforms(frame, settings, aspect, self.frame_index)
        values.update(self.textures.use(self.units), **self.atmosphere.uniforms(ATMOSPHERE),
                      **self.units.bind(u_atmosphere=self.atmosphere.atlas))
        return values

    def _trace(self, size, bsize, settings, values, history: int, requality: bool, clock_stopped: bool,
               clock: tuple) -> moderngl.Texture:
        if not reprojects(settings):
            target = self._target("trace", bsize, (4, STATE))
            self._draw("clouds_trace", target.fbo, values, u_stride=1, u_phase=(0, 0))
            self.last_lookups = target
            self._resolved, self.reprojected_frames = None, 0
            return target.textures[0]
        d = settings.downsample
        size = buffer_size(size, settings.reproject_downsample)  # the reprojected picture's
        bsize = buffer_size(size, d)
        last = self._resolved if history else None
        mode = history if last is not None else 0
        # the per-pixel sample counts restart with the history, on a turn and on a change of quality; when the
        # clock stops, the kept values stand for the TAA_FRAMES samples its fading average holds
        restart = mode != 1 or requality
        self.reprojected_frames = frames = 1 if restart or clock_stopped else self.reprojected_frames + 1
        prior = TAA_FRAMES if clock_stopped and not restart else 0
        # The order runs on through restarts (a turn restarts every frame: each pixel must still come round);
        # `rank` says how many frames after the restart each pixel of a block is first traced.
        order = ORDERS[d]
        n = len(order)
        phase = (order[self.frame_index % n] % d, order[self.frame_index % n] // d)
        start = self.frame_index - (frames - 1)
        rank = [0] * 64
        for k, index in enumerate(order):
            rank[index] = (k - start) % n
        fresh = self._target("fresh", bsize, (4, STATE))
        # A pixel keeps its sample for a cycle of d^2 frames: the blue noise moves once a cycle, so the pixels
        # of a block share one offset (different ones would show the block's pattern) and TAA averages cycles.
        offset = (self.frame_index // n * GOLDEN) % 1.0 if settings.jitter else 0.0
        self._draw("clouds_trace", fresh.fbo, values, u_buffer=size, u_stride=d, u_phase=phase,
                   u_frame_offset=offset)
        out = self._target("resolve_b" if last is self._targets.get("resolve_a") else "resolve_a", size,
                           (4, STATE))
        self.units.bind(u_fresh=fresh.textures[0], u_fresh_state=fresh.textures[1])
        if last is not None:
            self.units.bind(u_history=last.textures[0], u_history_state=last.textures[1])
        basis = self._basis or (values["u_forward"], values["u_right"], values["u_up"])
        moving = self._clock_moved and mode != 0
        self._draw("clouds_resolve", out.fbo, values,
                   **self.units.uniforms("u_fresh", "u_fresh_state", "u_history", "u_history_state"),
                   u_size=size, u_history_size=size if last is None else last.size, u_down=d, u_phase=phase,
                   u_history_mode=mode, u_prev_forward=basis[0], u_prev_right=basis[1], u_prev_up=basis[2],
                   u_motion=cloud_motion(self._clock, clock) if moving else (0.0, 0.0, 0.0), u_clock_moved=int(moving),
                   u_frames=frames, u_rank=rank, u_average=int(settings.taa and settings.jitter), u_prior=prior,
                   u_min_weight=1.0 / TAA_FRAMES if moving else 0.0)
        if mode == 2:
            self._trace_new(out, basis, (values["u_forward"], values["u_right"], values["u_up"]), values, offset)
        if last is not None and not restart:
            self._compared = (last.textures[0], out.textures[0])
        self._resolved = out
        self.last_lookups = out
        return out.textures[0]

    def _trace_new(self, out: Target, before, now, values, offset: float) -> None:
        """Trace every pixel of what a turn brought into view into the resolved picture (the last frame has nothing
        there), unless that is more than NEW_SHARE of it."""
        size = out.size
        rects = new_directions(before, now, values["u_tan_half_fov"], size)
        if not rects or sum(w * h for _x, _y, w, h in rects) > NEW_SHARE * size[0] * size[1]:
            return
        for rect in rects:  # the screen's triangle drawn into the strip alone: gl_FragCoord stays the pixel's
            out.fbo.viewport = rect
            self._draw("clouds_trace", out.fbo, values, u_buffer=size, u_stride=1, u_phase=(0, 0),
                       u_frame_offset=offset)
        out.fbo.viewport = (0, 0, *size)

    def _temporal_aa(self, bsize, current: moderngl.Texture, values, valid: bool) -> moderngl.Texture:
        history = self._taa if valid else None
        out = self._target("taa_b" if history is self._targets.get("taa_a") else "taa_a", bsize, (4,))
        self.taa_frames = self.taa_frames + 1 if history is not None else 1
        self.units.bind(u_current=current)
        if history is not None:
            self.units.bind(u_history=history.textures[0])
        # a running clock fades old frames out (at least 1/TAA_FRAMES each); a still one averages them all
        self._taa_samples = 1 if history is None else self._taa_samples + 1
        if self.clock_running:
            self._taa_samples = min(self._taa_samples, TAA_FRAMES)
        self._draw("clouds_taa", out.fbo, values, **self.units.uniforms("u_current", "u_history"),
                   u_history_valid=int(history is not None), u_weight=1.0 / self._taa_samples)
        if history is not None:
            self._compared = (history.textures[0], out.textures[0])
        self._taa = out
        return out.textures[0]

    @property
    def clock_running(self) -> bool:
        """Whether the clock moved within the last STOP_FRAMES frames (an animation, between its ticks too)."""
        return self._clock_age is not None and self._clock_age < STOP_FRAMES

    def change(self) -> float | None:
        """How much the last frame changed the clouds its history held (CONVERGED's measure), or None where it
        kept no history."""
        if self._change is None and self._compared is not None:
            self._change = buffer_change(*self._compared)
        return self._change

    def settling(self, settings: CloudRenderSettings) -> bool:
        """Whether more frames of an unchanged scene still change the image: an automatic exposure adapts to the
        frame's light; reprojection fills its blocks in d^2 frames; TAA, which has something to average only while
        the jitter moves, until a frame changes the clouds by less than CONVERGED (at most MAX_SETTLING frames).
        While the clock runs nothing converges: TAA fills its fading average in TAA_FRAMES frames (the animation
        asks for the frames after); once it has stood still for STOP_FRAMES frames it has stopped, and the still
        view converges from there."""
        if not settings.debug_samples and self.tone_map.settling():
            return True
        if self._clock_age is not None and 0 < self._clock_age < STOP_FRAMES:
            return True  # still since a move: a gap between ticks, or a stop that frames to come will see
        averaging = settings.taa and settings.jitter
        frames = self.reprojected_frames if reprojects(settings) else self.taa_frames
        if reprojects(settings) and frames < settings.downsample ** 2:
            return True
        if not averaging or frames >= (TAA_FRAMES if self.clock_running else MAX_SETTLING):
            return False
        change = self.change()
        return change is None or change >= CONVERGED

    def lookups(self, size: tuple[int, int], frame: Frame, settings: CloudRenderSettings) -> float:
        """Texture lookups per output pixel of the last frame: the cloud buffer's (shared by the pixels it
        covers) plus the composite's own (cirrus, ground shadows), read back from float targets."""
        counts = self.last_lookups.textures[1]
        march = float(np.frombuffer(counts.read(), dtype="f4").reshape(-1, counts.components)[:, 0].sum())
        target = self._target("lookups", size, (1,))
        values = self._scene_values(frame, settings, size[0] / max(size[1], 1))
        self._draw("clouds_composite", target.fbo, values,
                   **self.units.bind(u_clouds=self.last_clouds, u_lookups=counts), u_size=tuple(map(float, size)),
                   u_debug=2)
        composite = float(np.frombuffer(target.textures[0].read(), dtype="f4").sum())
        return (march + composite) / (size[0] * size[1])
