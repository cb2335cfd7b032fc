"""2D lighting bench (seed 000): every shadow method on every sample scene against the exact reference,
plus pygame-light2d on its own benchmark set-ups and the cost of hulls far outside the view.

Each method's output is the lightmap as the screen shows it (diffuse white, 8-bit), compared with
app.reference.lighting2d on a 0..1 scale. Extra rows:
- `pygame-light2d` and our methods on lights/hulls 10/10, 200/1, 10/200, 200/200 (random, seeded), in
  pygame's y-down pixel coordinates (r_flipY) with hard point lights (its lights have no disc);
- `offscreen hulls`: the default method on scene j with 0 and 10,000 hulls outside the view, the lightmap
  alone and the editor's whole frame, their frames interleaved, with each frame's work.
Every row has its frames' min and max beside the median (ms_min, ms_max, gpu_ms_min, gpu_ms_max).
"""
from __future__ import annotations

import functools
import math
from dataclasses import replace

import numpy as np

from app.bench.harness import Method, Row, Technique, errors, frame_timings
from app.gl.core.headless import OffscreenTarget
from app.gl.lighting2d.renderer import Lighting2DRenderer, Shading2D
from app.gl.core.shaders import ShaderLibrary
from app.io import lighting2d_scene as scene2d
from app.model.camera2d import Camera2D
from app.model.lighting2d.scene import Hull, Light, Scene2D
from app.reference import lighting2d as reference
from app.resources import SCENES, SHADERS

DEFAULT = "exact"
QUICK_SCENES = (
    "a_penumbra_transition", "e_antumbra", "g_overlapping_hulls", "j_concave_three_lights", "l_hull_through_the_disc")
PEER_SETUPS = ((10, 10), (200, 1), (10, 200), (200, 200))
OFFVIEW_HULLS = 10_000
OFFVIEW_ROUNDS_PER_RUN = 80  # a few percent to tell apart on a busy machine: many short frames, interleaved
WORK = ("hulls_considered", "index_cells", "index_boxes", "vertices_uploaded")  # one frame's, as CSV columns


def sample_scenes() -> dict[str, tuple[Scene2D, Camera2D]]:
    out = {}
    for path in sorted(SCENES.glob("*.json")):
        scene = scene2d.load(path)
        out[path.stem] = (scene, Camera2D(*scene.view))
    return out


@functools.lru_cache(maxsize=None)
def _reference_cached(name: str, size: tuple[int, int], flip_y: bool = False) -> np.ndarray:
    scene = _SCENES_BY_NAME[name]
    return reference.render(scene, *size, flip_y=flip_y)


_SCENES_BY_NAME: dict[str, Scene2D] = {}


def _reference(sc, _value, size) -> np.ndarray:
    scene, _camera = sc
    key = next(k for k, v in _SCENES_BY_NAME.items() if v is scene)
    return _reference_cached(key, tuple(size))


def _output(state, target: OffscreenTarget, _value, _sc) -> np.ndarray:
    return target.read()[..., :3].astype(np.float64) / 255.0


def _method(name: str, knob: str, values, quick_values, settings_for) -> Method:
    def render(state: Lighting2DRenderer, target, value, sc):
        scene, camera = sc
        state.render(target.fbo, scene, camera, settings_for(value), lightmap_only=True)

    setup = lambda ctx: Lighting2DRenderer(ctx, ShaderLibrary(ctx, [SHADERS]))  # noqa: E731
    return Method(name, knob, values, setup, render, _output, quick_values)


METHODS = [
    _method("hard", "lightmap_scale", (1.0,), (1.0,), lambda v: Shading2D(method="hard", lightmap_scale=v)),
    _method("penumbra", "lightmap_scale", (1.0,), (1.0,), lambda v: Shading2D(method="penumbra", lightmap_scale=v)),
    _method("jitter", "samples", (1, 4, 16, 64), (4, 16), lambda v: Shading2D(method="jitter", samples=int(v))),
    _method("blur", "blur", (0.1, 0.25, 0.5), (0.25,), lambda v: Shading2D(method="blur", blur=v)),
    _method("exact", "lightmap_scale", (1.0, 0.5, 0.25), (1.0, 0.5),
            lambda v: Shading2D(method="exact", lightmap_scale=v)),
]


def technique(quick: bool = False) -> Technique:
    scenes = sample_scenes()
    _SCENES_BY_NAME.clear()
    _SCENES_BY_NAME.update({k: v[0] for k, v in scenes.items()})
    return Technique(
        name="lighting2d",
        methods=METHODS,
        scenes=scenes,
        reference=_reference,
        size=(512, 320),
        quick_size=(256, 160),
        quick_scenes=QUICK_SCENES,
        extra_rows=extra_rows,
        interleave=True,  # the table compares the methods' times (exact against penumbra): they take turns
    )


# --- pygame-light2d's set-ups and the offscreen-hull test -------------------------------------------------


def peer_scene(lights: int, hulls: int, size=(1280, 720), seed: int = 7):
    """Random lights and square hulls in pixel coordinates (y down), as pygame-light2d's examples use."""
    rng = np.random.default_rng(seed + lights * 1000 + hulls)
    w, h = size
    reach = 200.0 * w / 1280
    colour = 1.0 if lights <= 10 else 0.15  # 200 overlapping lights would saturate everything
    light_pos = rng.uniform((0, 0), (w, h), (lights, 2))
    side = 20.0 * w / 1280
    hull_pos = rng.uniform((0, 0), (w, h), (hulls, 2))
    hulls = [Hull([(0, 0), (side, 0), (side, side), (0, side)], position=(x, y)) for x, y in hull_pos]
    lights = []
    # a light whose centre is in a hull is not drawn by us; nudge it out so both engines draw it
    for x, y in light_pos:
        while any(hl.contains(x, y) for hl in hulls):
            x += side
        lights.append(Light(position=(x, y), scale=(2 * reach, 2 * reach), radius=0.0, color=(colour, colour, colour)))
    scene = Scene2D(ambient=(0.1, 0.1, 0.1), lights=lights, hulls=hulls, view=(w / 2, h / 2, float(h)),
                    background="builtin:white")
    peer = {"ambient": scene.ambient,
            "lights": [{"position": light.position, "radius": reach, "color": light.color, "power": 1.0,
                        "casts_shadows": True} for light in scene.lights],
            "hulls": [hl.world() for hl in scene.hulls]}
    return scene, peer


def extra_rows(quick: bool, size, runs: int, progress) -> list[Row]:
    from app.bench import pygame_light2d_peer as peer
    from app.gl.core.headless import create_context

    rows = []
    ctx = create_context()
    renderer = Lighting2DRenderer(ctx, ShaderLibrary(ctx, [SHADERS]))
    peer_size = (128, 72) if quick else (1280, 720)
    why = peer.available()
    if why:
        progress(f"pygame-light2d skipped: {why}")
    for n_lights, n_hulls in PEER_SETUPS:
        name = f"peer {n_lights}/{n_hulls}"
        scene, data = peer_scene(n_lights, n_hulls, peer_size)
        ref = reference.render(scene, *peer_size, flip_y=True)
        camera = Camera2D(*scene.view)
        target = OffscreenTarget(ctx, peer_size)
        try:
            # one renderer for both: the scene's geometry serves every method, so their frames can take turns
            draws = {method: functools.partial(renderer.render, target.fbo, scene, camera,
                                               Shading2D(method=method, flip_y=True), lightmap_only=True)
                     for method in ("exact", "penumbra")}
            for method, timing in frame_timings(ctx, draws, runs).items():
                draws[method]()
                rmse, worst = errors(target.read()[..., :3] / 255.0, ref)
                rows.append(Row("lighting2d", method, "lights/hulls", float(n_lights), name, *peer_size,
                                *timing.medians(), runs, rmse, worst, {**timing.spread(), "hulls": n_hulls}))
                progress(f"{method:>14} {name}: {timing.summary()}  rmse {rmse:.2e}  max {worst:.2e}")
        finally:
            target.release()
        if why:
            continue
        try:
            # its frames take seconds on the biggest set-up here: fewer of them, a median all the same
            frames = runs if n_lights * n_hulls <= 2000 else 1
            result = peer.render(peer_size, data["ambient"], data["lights"], data["hulls"], frames=frames)
        except ValueError as exc:  # past the library's fixed shader arrays
            progress(f"pygame-light2d {name}: {exc}")
            continue
        rmse, worst = errors(result.image, ref)
        rows.append(Row("lighting2d", "pygame-light2d", "lights/hulls", float(n_lights), name, *peer_size,
                        result.ms_per_frame, math.nan, frames, rmse, worst, {"hulls": n_hulls}))
        progress(f"{'pygame-light2d':>14} {name}: {result.ms_per_frame:8.2f} ms  rmse {rmse:.2e}  max {worst:.2e}")
    rows += offscreen_rows(ctx, size, OFFVIEW_ROUNDS_PER_RUN * runs, progress)
    return rows


def offview_scene(hulls: int, seed: int = 3) -> Scene2D:
    """Scene j with `hulls` small squares 5,000..15,000 units to its right, far outside its view."""
    scene = scene2d.load(SCENES / "j_concave_three_lights.json")
    square = [(0, 0), (12, 0), (12, 12), (0, 12)]
    far = np.random.default_rng(seed).uniform((5_000, -5_000), (15_000, 5_000), (hulls, 2))
    return replace(scene, hulls=scene.hulls + tuple(Hull(square, position=(x, y)) for x, y in far))


def offscreen_rows(ctx, size, rounds: int, progress) -> list[Row]:
    """The default method on scene j alone and with 10,000 hulls far outside the view: the lightmap alone
    (`exact`) and the editor's whole frame, its overlay included (`exact+overlay`). Each of the four has its
    own renderer (one renderer would rebuild its index at every change of scene) and their frames take
    turns, so that a busy machine slows them alike; the rows carry each frame's work beside its times."""
    from app.gl.lighting2d.workspace import Lighting2DWorkspaceRenderer
    from app.model.lighting2d.workspace import Lighting2DWorkspace

    settings = Shading2D(method=DEFAULT)
    target = OffscreenTarget(ctx, size)
    variants, draws = {}, {}
    for hulls in (0, OFFVIEW_HULLS):
        state = Lighting2DWorkspace(offview_scene(hulls))
        lit = Lighting2DRenderer(ctx, ShaderLibrary(ctx, [SHADERS]))
        editor = Lighting2DWorkspaceRenderer(ctx, ShaderLibrary(ctx, [SHADERS]))
        variants[(DEFAULT, hulls)] = (state, lit, None)
        variants[(f"{DEFAULT}+overlay", hulls)] = (state, editor.lighting, editor.overlay)
        draws[(DEFAULT, hulls)] = functools.partial(lit.render, target.fbo, state.scene, state.camera, settings,
                                                    lightmap_only=True)
        draws[(f"{DEFAULT}+overlay", hulls)] = functools.partial(editor.render, target.fbo, state, settings)
    rows = []
    try:
        ref = reference.render(variants[(DEFAULT, 0)][0].scene, *size)
        for (method, hulls), timing in frame_timings(ctx, draws, rounds).items():
            state, lit, overlay = variants[(method, hulls)]
            draws[(method, hulls)]()
            work = {name: getattr(lit.stats, name) for name in WORK}
            if overlay is not None:
                work["overlay_hulls"] = overlay.hulls_seen
            # the lightmap is what the reference defines; the editor's frame has the background and overlay too
            rmse, worst = errors(target.read()[..., :3] / 255.0, ref) if method == DEFAULT else (math.nan, math.nan)
            label = f"offscreen hulls {hulls}"
            rows.append(Row("lighting2d", method, "offscreen_hulls", float(hulls), label, *size, *timing.medians(),
                            rounds, rmse, worst, {**timing.spread(), "hulls": len(state.scene.hulls), **work}))
            progress(f"{method:>14} {label}: {timing.summary()}  rmse {rmse:.2e}  max {worst:.2e}  "
                     + " ".join(f"{k} {v}" for k, v in work.items()))
    finally:
        target.release()
    return rows
