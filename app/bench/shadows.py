"""Shadows bench (seeds 002 and 004): each shadow method of the 3D lights against the CPU reference's shadows,
and what it costs.

The scene is the 3D lights' default one (seed 004's point and spot light over a ground with five objects) seen
from 250 units; its sphere and torus are tessellated finer for the `triangles` knob (half the requested
triangles each). Per method and setting:
- `ms_median`: a whole frame (app/gl/lights3d/renderer.py) with both lights shadowed that way, their volumes and maps
  made anew each frame, as when a light or an object moves; `still_ms`: the frame with them kept (the view moves);
- `mismatch_pct`: the pixels whose shadow differs from the reference's (`facing & ~visible`), over the pixels a
  light faces and reaches, both lights together (Lights3DRenderer.shadow_mask: the stencil, or under half the
  map's PCF taps seeing the light); `mismatch_off_edge_pct`: those not within 1 px of a shadow edge of the
  reference (a pixel of its mask beside one not in it, dilated by a pixel); rmse is the square root of the
  mismatched share of all pixels (lights together), so that the harness's chart plots it against time;
- `volume_triangles`: the volume triangles drawn for both lights (onepass: 8 per caster triangle, seed 002's 7
  and a far cap; onepass-seed: the 7; zpass: the silhouettes' quads; zfail: those and both caps), beside
  `caster_triangles` (within the lights' reach) and `extruded_edges`; `fill_px`: the stencil's fill cost, the
  fragments the volume draws rasterise for both lights within each light's scissor rectangle and depth bounds,
  whether their depth test passes or fails (ShadowVolumePass.fill: an occlusion query over the same draw with
  every test passing; 0 for the map); `depth_bounds`: 1 where the context has the depth bounds test, so the
  passes were clamped to the lights' depths too (llvmpipe: 0, the scissor alone);
- `shadow_ms`: one light after another, the volumes built (`build_ms`, numpy) and marked in the stencil
  (`draw_ms`, finished), or the map drawn and read (shadow_mask's cost).

Methods: every one that shadows (app/gl/lights3d/shadow_methods.py: onepass, onepass-seed, zpass, zfail and map,
the renderer's default map: 1024 texels, PCF 3, bias 0.0002, 3 cascades) against the triangles; the map's size as
its own series at PCF 1, 3 and 5 (the default bias); the bias as a series at 1024 texels, PCF 3; a directional
light's cascades as a series (`map cascades`, 1 to 4) on the scene with app/bench/map_texels.py's sun besides its
two lights, all three judged. The map's rows say `texels_px` too: the texels a screen pixel's footprint covers in
the map, median over the pixels the lights face and reach (app/bench/map_texels.py), and `cascades`.
"""
from __future__ import annotations

from dataclasses import dataclass, replace
from functools import lru_cache

import numpy as np
from scipy import ndimage

from app.bench.harness import Method, Technique, time_frames
from app.bench.map_texels import SUN, footprints
from app.gl.lights3d.light_reach import reaches
from app.gl.lights3d.shadow_methods import MAP, METHODS
from app.model.lights3d import mesh as mesh3d
from app.model.lights3d.scene import Lights3DCamera, Scene3D, default_scene
from app.model.lights3d.render_settings import Lights3DRenderSettings

SCENE = "default"
CAMERA = Lights3DCamera(distance=250.0)
SPHERE, TORUS = 2, 3  # the default scene's objects the triangles knob tessellates


@dataclass(frozen=True)
class Plan:
    size: tuple[int, int] = (480, 360)
    triangles: tuple[int, ...] = (2530, 10_000, 30_000, 100_000)  # 2530: the default scene as it is
    map_sizes: tuple[int, ...] = (256, 512, 1024, 2048, 4096)
    biases: tuple[float, ...] = (0.0, 0.0002, 0.001, 0.005, 0.02)
    cascades: tuple[int, ...] = (1, 2, 3, 4)
    runs: int = 5


FULL = Plan()
QUICK = Plan(size=(160, 120), triangles=(2530, 20_000), map_sizes=(256, 1024), biases=(0.0, 0.005), cascades=(1, 3),
             runs=2)


@lru_cache(maxsize=16)
def scene_of(triangles: int, sun: bool = False) -> Scene3D:
    """The default scene with about `triangles` triangles: the sphere and the torus share what the others leave;
    with `sun`, a directional light besides its two."""
    scene = default_scene().add_light(SUN) if sun else default_scene()
    if triangles <= scene.triangles:
        return scene
    rest = triangles - sum(o.triangles for i, o in enumerate(scene.objects) if i not in (SPHERE, TORUS))
    sides = max(mesh3d.MIN_SEGMENTS, round(np.sqrt(rest / 2 / 6)))  # the torus 3 times as long around as across
    scene = scene.with_object(TORUS, size=(*scene.objects[TORUS].size[:2], 3 * sides, sides))
    return scene.with_object(SPHERE, size=(scene.objects[SPHERE].size[0], mesh3d.sphere_segments(rest // 2)))


def shadowed(scene: Scene3D, method: str) -> Scene3D:
    for i in range(len(scene.lights)):
        scene = scene.with_light(i, shadow=method)
    return scene


@dataclass(frozen=True)
class Truth:
    """The reference's shadow per light, and where it is judged."""
    region: np.ndarray   # (lights, H, W): the light faces and reaches the surface
    shadow: np.ndarray   # (lights, H, W): ... and something is in the way
    edge: np.ndarray     # (lights, H, W): within 1 px of where the shadow begins or ends
    position: np.ndarray  # (H, W, 3): the surface's world points
    object_id: np.ndarray  # (H, W): whose


@lru_cache(maxsize=16)
def truth(triangles: int, size: tuple[int, int], sun: bool = False) -> Truth:
    from app.reference.lights3d import render

    result = render(scene_of(triangles, sun), CAMERA, size)
    shadow = result.facing & ~result.visible
    return Truth(result.facing, shadow, np.stack([shadow_edge(s) for s in shadow]), result.position,
                 result.object_id)


def shadow_edge(shadow: np.ndarray) -> np.ndarray:
    """Within 1 px of where a shadow mask (H, W) begins or ends: its boundary, both sides (a shadowed pixel beside
    a lit one and that lit one), then a pixel around it."""
    return ndimage.binary_dilation((shadow ^ ndimage.binary_erosion(shadow, border_value=1)) |
                                   (ndimage.binary_dilation(shadow) ^ shadow), np.ones((3, 3), bool))


class Shared:
    """One renderer per GL context for every method of a run (its programs compile once)."""

    def __init__(self) -> None:
        self.ctx = self.renderer = None

    def renderer_for(self, ctx):
        if self.ctx is not ctx:
            from app.gl.lights3d.renderer import Lights3DRenderer
            from app.gl.core.shaders import ShaderLibrary
            from app.resources import SHADERS

            self.ctx, self.renderer = ctx, Lights3DRenderer(ctx, ShaderLibrary(ctx, [SHADERS]))
        return self.renderer


@dataclass
class Setting:
    """What one row draws: a method, the scene's triangles, the map's settings, the sun or not."""
    method: str
    triangles: int
    map: Lights3DRenderSettings
    sun: bool = False


class ShadowsBench:
    def __init__(self, plan: Plan) -> None:
        self.plan = plan
        self.shared = Shared()
        self.masks: dict = {}  # (method name, knob value) -> the masks and their stats, for stats()

    def method(self, name: str, knob: str, values, setting_for) -> Method:
        def setup(ctx):
            return self.shared.renderer_for(ctx)

        def frame(renderer, target, s: Setting, keep: bool) -> None:
            if not keep:
                renderer.forget_shadows()
            renderer.render(target.fbo, shadowed(scene_of(s.triangles, s.sun), s.method), CAMERA, s.map, marks=False)

        def render(renderer, target, value, _scene) -> None:
            frame(renderer, target, setting_for(value), keep=False)

        def output(renderer, target, value, _scene) -> np.ndarray:
            s = setting_for(value)
            scene, t = scene_of(s.triangles, s.sun), truth(s.triangles, target.size, s.sun)
            masks, texels = [], []
            for i, light in enumerate(scene.lights):
                masks.append(renderer.shadow_mask(scene, CAMERA, target.size, i, s.method, s.map))
                if s.method == MAP.name:
                    texels.append(footprints(renderer.mask_map.views, light.position, s.map.map_size, t.position,
                                             t.object_id, t.region[i]))
            self.masks[name, value] = masks, texels
            return np.stack([m for m, _ in masks]) & t.region

        def reference(_scene, value, size) -> np.ndarray:
            s = setting_for(value)
            t = truth(s.triangles, tuple(size), s.sun)
            return t.shadow & t.region

        def stats(renderer, target, value, _scene) -> dict:
            s = setting_for(value)
            t = truth(s.triangles, target.size, s.sun)
            masks, texels = self.masks.pop((name, value))
            wrong = (np.stack([m for m, _ in masks]) != t.shadow) & t.region
            costs = [c for _, c in masks]
            still, _ = time_frames(renderer.ctx, lambda: frame(renderer, target, s, keep=True), self.plan.runs)
            frame(renderer, target, s, keep=True)
            scene = scene_of(s.triangles, s.sun)
            maps = {"texels_px": float(np.median(np.concatenate(texels))), "cascades": s.map.cascades} if texels else {}
            return {"mismatch_pct": 100.0 * wrong.sum() / t.region.sum(),
                    "mismatch_off_edge_pct": 100.0 * (wrong & ~t.edge).sum() / t.region.sum(),
                    "still_ms": still, "shadow_ms": sum(c.build_ms + c.draw_ms for c in costs),
                    "build_ms": sum(c.build_ms for c in costs),
                    "volume_triangles": sum(c.volume_triangles for c in costs),
                    "extruded_edges": sum(c.extruded_edges for c in costs),
                    "caster_triangles": caster_triangles(scene),
                    "scene_triangles": scene.triangles, "map_size": s.map.map_size, "pcf": s.map.pcf,
                    "bias": s.map.bias,  # the columns since issue 29 after the older ones:
                    "draw_ms": sum(c.draw_ms for c in costs), "fill_px": sum(c.fill_px for c in costs),
                    "depth_bounds": int(renderer.depth_bounds), **maps}

        return Method(name, knob, tuple(values), setup, render, output, quick_values=tuple(values),
                      reference=reference, stats=stats)

    def methods(self) -> list[Method]:
        p = self.plan
        default_map = Lights3DRenderSettings()
        out = [self.method(m.name, "triangles", p.triangles, lambda v, m=m: Setting(m.name, int(v), default_map))
               for m in METHODS.values() if m.shadows]
        out += [self.method(f"{MAP.name} pcf{k}", "map_size", p.map_sizes, lambda v, k=k: Setting(
                    MAP.name, p.triangles[0], replace(default_map, map_size=int(v), pcf=k))) for k in (1, 3, 5)]
        out.append(self.method(f"{MAP.name} bias", "bias", p.biases,
                               lambda v: Setting(MAP.name, p.triangles[0], replace(default_map, bias=float(v)))))
        out.append(self.method(f"{MAP.name} cascades", "cascades", p.cascades, lambda v: Setting(
            MAP.name, p.triangles[0], replace(default_map, cascades=int(v)), sun=True)))
        return out


def caster_triangles(scene: Scene3D) -> int:
    """The closed meshes' triangles within each light's reach, summed over the lights (onepass draws 8 each)."""
    total = 0
    for obj in scene.objects:
        total += sum(obj.triangles for light in scene.lights
                     if obj.mesh().closed and reaches(light, obj.position, obj.radius))
    return total


def technique(quick: bool = False, plan: Plan | None = None) -> Technique:
    bench = ShadowsBench(plan or (QUICK if quick else FULL))
    return Technique(
        name="shadows",
        methods=bench.methods(),
        scenes={SCENE: None},
        reference=lambda _scene, _value, size: truth(bench.plan.triangles[0], tuple(size)).shadow,
        size=bench.plan.size,
        quick_size=bench.plan.size,
    )

