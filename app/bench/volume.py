"""Volume ray tracer bench (seed 003's Table 1 re-measured, and more).

One method per mode; the knob is cl_steps (the shadow modes also scale cl_shadowSteps with it, as a
user raising quality would). Each mode's reference is the CPU renderer (app/reference/volume.py) at
2048 steps per unit. Every row also reports the texture samples per pixel (`samples_per_px`, counted
by the shader itself), so the distance texture's effect shows without timing noise. Two cameras:
the Cornell box seen through its open front (where empty-space skipping pays) and coords3d from a
corner. Table 1 is the rows at cl_steps 128: frames/s = 1000 / ms_median. A scalar volume's modes follow, rows
`scalar <mode>` on a CT phantom (app/bench/volume_scalar.py), then vispy's where it is installed.
"""
from __future__ import annotations

from functools import lru_cache

import numpy as np

from app.bench.harness import Method, Technique
from app.bench.volume_scalar import scalar_rows
from app.gl.volume.raytracer import RayTracer, TraceSettings
from app.gl.core.shaders import ShaderLibrary
from app.model.camera3d import OrbitCamera
from app.model.volume.render_modes import MODES
from app.model.volume.voxels import Voxels
from app.model.volume.samples import coords3d, cornell_box
from app.model.volume.view import VolumeView
from app.reference.volume import render as reference_render
from app.resources import SHADERS

STEPS = (16, 32, 64, 128, 256)
QUICK_STEPS = (32, 128)
QUICK_MODES = (2, 4, 5, 7)
REFERENCE_STEPS = 2048  # at 64 voxels a side; a smaller volume as many a voxel (reference_steps)


def _scene(name: str, side: int):
    if name == "cornell grey":
        return grey_scene(side)[:3]
    data = {"cornell": cornell_box, "coords3d": coords3d}[name](side)
    camera = OrbitCamera(yaw=0, pitch=0, distance=3.4) if name == "cornell" else OrbitCamera(yaw=35, pitch=25)
    return name, Voxels(data), VolumeView(camera=camera)


def _settings(mode: int, steps: float, **kw) -> TraceSettings:
    return TraceSettings(mode=mode, steps=steps, shadow_steps=max(4, int(steps) // 6), slice_planes=False, **kw)


class State:
    def __init__(self, ctx) -> None:
        self.ctx = ctx
        self.tracer = RayTracer(ctx, ShaderLibrary(ctx, [SHADERS]))
        self.count_fbo = None


def _method(mode: int) -> Method:
    def render(state: State, target, steps, scene) -> None:
        _name, voxels, view = scene
        state.tracer.render(target.fbo, voxels, view, _settings(mode, steps))

    def output(state: State, target, steps, scene) -> np.ndarray:
        render(state, target, steps, scene)
        return target.read()[..., :3] / 255.0

    def reference(scene, steps, size) -> np.ndarray:
        return _reference(scene[0], scene[1].size[0], mode, size, tuple(np.array(scene[2].background) / 255))

    def stats(state: State, target, steps, scene) -> dict:
        if state.count_fbo is None or state.count_fbo.size != target.size:
            state.count_fbo = state.ctx.framebuffer([state.ctx.renderbuffer(target.size, 4, dtype="f4")])
        _name, voxels, view = scene
        state.tracer.render(state.count_fbo, voxels, view, _settings(mode, steps, debug_samples=True))
        counts = np.frombuffer(state.count_fbo.read(components=4, dtype="f4"), "f4")[0::4]
        return {"samples_per_px": float(counts.mean())}

    m = MODES[mode]
    return Method(f"F{mode} {m.name}", "cl_steps", STEPS, State, render, output, QUICK_STEPS,
                  reference=reference, stats=stats)


@lru_cache(maxsize=None)
def _reference(name: str, side: int, mode: int, size, background) -> np.ndarray:
    _n, voxels, view = _scene(name, side)
    steps = reference_steps(side)
    return reference_render(voxels.data, view.camera, size, MODES[mode], steps=steps, shadow_steps=steps // 6,
                            background=background)


def reference_steps(side: int) -> int:
    """cl_steps counts steps across the whole box: the same steps a voxel at any size (--quick's 32^3 volume
    needs half of 64^3's)."""
    return REFERENCE_STEPS * side // 64


def technique(quick: bool = False) -> Technique:
    side = 32 if quick else 64
    scenes = {name: _scene(name, side) for name in ("cornell", "coords3d", "cornell grey")}
    return Technique(
        name="volume",
        methods=[_method(m) for m in (QUICK_MODES if quick else MODES)],
        scenes=scenes,
        reference=lambda *_: None,  # every method brings its own (one per mode)
        size=(128, 128),
        quick_size=(64, 64),
        quick_scenes=("cornell",) if not vispy_available() else ("cornell", "cornell grey"),
        gl_rows=lambda ctx, quick, size, runs, progress: scalar_rows(
            ctx, side, size, runs, QUICK_STEPS if quick else STEPS, reference_steps(side), progress),
        extra_rows=vispy_rows if vispy_available() else None,
    )


# --- vispy, an optional extra: the same volume and camera drawn by vispy's Volume visual -----------

VISPY_METHODS = {"average": 4, "iso": 2}  # vispy's method -> our closest mode (mean along the ray; first hit)


def vispy_available() -> bool:
    import importlib.util

    return all(importlib.util.find_spec(m) is not None for m in ("vispy", "OpenGL"))


def grey_scene(side: int):
    """The Cornell box as grey levels, on black: a scalar volume for vispy and its RGBA twin for us."""
    rgba = cornell_box(side)
    grey = (rgba[..., :3].astype(np.float32).mean(-1) / 255.0) * (rgba[..., 3] > 0)
    twin = np.zeros_like(rgba)
    twin[..., :3] = np.round(grey * 255)[..., None].astype(np.uint8)
    twin[..., 3] = np.where(grey > 0, 255, 0)
    return "cornell grey", Voxels(twin), VolumeView(camera=OrbitCamera(yaw=0, pitch=0, distance=3.4),
                                                    background=(0, 0, 0)), grey.astype(np.float32)


def vispy_rows(quick: bool, size: tuple[int, int], runs: int, progress) -> list:
    """Rows for vispy's methods, each against our reference of its closest mode (our modes also run on
    this scene, so the CSV compares like with like)."""
    import os
    import subprocess
    import sys
    import tempfile

    from app.bench.harness import Row, errors

    side = 32 if quick else 64
    name, voxels, view, grey = grey_scene(side)
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for method, mode in VISPY_METHODS.items():
            truth = _grey_reference(side, mode, size)
            for steps in QUICK_STEPS if quick else STEPS:
                job, out = os.path.join(tmp, "job.npz"), os.path.join(tmp, "out.npz")
                cam = view.camera
                np.savez(job, volume=grey, size=np.array(size), method=method, threshold=0.1,
                         step=side / steps, yaw=cam.yaw, pitch=cam.pitch, distance=cam.distance, runs=runs)
                env = {**os.environ, "EGL_PLATFORM": "surfaceless"}
                done = subprocess.run([sys.executable, "-m", "app.bench.vispy_peer", job, out], env=env,
                                      capture_output=True, text=True, timeout=300)
                if done.returncode != 0:
                    progress(f"vispy {method}: failed: {done.stderr.strip().splitlines()[-1:]}")
                    return rows
                result = np.load(out)
                rmse, max_err = errors(result["image"] / 255.0, truth)
                rows.append(Row("volume", f"vispy {method}", "cl_steps", float(steps), name, size[0], size[1],
                                float(result["ms"]), float("nan"), runs, rmse, max_err))
                progress(f"vispy {method:>8} {name} cl_steps={steps}: {float(result['ms']):8.2f} ms  "
                         f"rmse {rmse:.2e}  max {max_err:.2e}")
    return rows


@lru_cache(maxsize=None)
def _grey_reference(side: int, mode: int, size) -> np.ndarray:
    _n, voxels, view, _grey = grey_scene(side)
    return reference_render(voxels.data, view.camera, size, MODES[mode], steps=reference_steps(side),
                            background=(0.0, 0.0, 0.0))
