"""The scalar render modes in `shadelab bench volume`: rows `scalar <mode>` (app/model/volume/scalar_modes.py) on
a CT-like phantom (int16 HU, app/model/volume/phantom.py), knob cl_steps, each against its CPU reference
(app/reference/volume_scalar.py) at the F-modes' reference steps. The window is a bone window (minip's sees air
against the scanner's outside, average's air and tissue), the iso value bone's edge; the camera sees the chest from
a corner."""
from __future__ import annotations

from functools import lru_cache

import numpy as np

from app.bench.harness import Row, errors, frame_timings
from app.gl.core.headless import OffscreenTarget
from app.gl.core.shaders import ShaderLibrary
from app.gl.volume.raytracer import RayTracer
from app.model.camera3d import OrbitCamera
from app.model.volume.phantom import ct_phantom
from app.model.volume.render_modes import TraceSettings
from app.model.volume.scalar_modes import SCALAR_MODES
from app.model.volume.scalars import TransferFunction
from app.model.volume.view import VolumeView
from app.model.volume.volume import Volume
from app.reference.volume_scalar import render as reference_render
from app.resources import SHADERS

SCENE = "ct phantom"
WINDOW = TransferFunction(-200.0, 1200.0, "bone")  # soft tissue faint, bone bright
WINDOWS = {"minip": TransferFunction(-3100.0, -900.0), "average": TransferFunction(-1100.0, 100.0)}
ISO = 300.0                                        # HU: bone's surface
VIEW = VolumeView(camera=OrbitCamera(yaw=30, pitch=20, distance=4.6), background=(0, 0, 0))


def window(mode: str) -> TransferFunction:
    return WINDOWS.get(mode, WINDOW)


def phantom_volume(side: int, transfer: TransferFunction = WINDOW) -> Volume:
    volume = Volume.new(1, 1, 1)
    volume.replace_scalars(ct_phantom(side), transfer, copy=False)
    return volume


def settings(mode: str, steps: float) -> TraceSettings:
    return TraceSettings(steps=steps, shadow_steps=max(4, int(steps) // 6), slice_planes=False, scalar_mode=mode,
                         iso=ISO)


@lru_cache(maxsize=None)
def reference(side: int, mode: str, size: tuple[int, int], steps: int) -> np.ndarray:
    return reference_render(ct_phantom(side), window(mode), VIEW.camera, size, mode, steps, iso=ISO,
                            shadow_steps=steps // 6, background=np.array(VIEW.background) / 255.0)


def scalar_rows(ctx, side: int, size: tuple[int, int], runs: int, steps: tuple[int, ...], reference_steps: int,
                progress) -> list[Row]:
    """Every scalar mode at every cl_steps, on the phantom: time per frame (the modes' frames in turn, as the
    harness interleaves) and the error against the reference."""
    shaders = ShaderLibrary(ctx, [SHADERS])
    target = OffscreenTarget(ctx, size)
    modes = SCALAR_MODES[1:]
    voxels = {mode: phantom_volume(side, window(mode)).voxels for mode in modes}
    tracers = {mode: RayTracer(ctx, shaders) for mode in modes}  # each keeps its volume's textures, as the editor's
    try:
        draws = {(mode, s): (lambda mode=mode, s=s: tracers[mode].render(target.fbo, voxels[mode], VIEW,
                                                                         settings(mode, s)))
                 for mode in modes for s in steps}
        rows = []
        for (mode, s), timing in frame_timings(ctx, draws, runs).items():
            draws[(mode, s)]()
            rmse, max_err = errors(target.read()[..., :3] / 255.0, reference(side, mode, size, reference_steps))
            ms, gpu_ms = timing.medians()
            progress(f"scalar {mode:>14} {SCENE} cl_steps={s}: {timing.summary()}  rmse {rmse:.2e}  "
                     f"max {max_err:.2e}")
            rows.append(Row("volume", f"scalar {mode}", "cl_steps", float(s), SCENE, size[0], size[1], ms, gpu_ms,
                            runs, rmse, max_err, timing.spread()))
        return rows
    finally:
        target.release()  # the tracer's textures go with the bench's context, as the harness's methods' do
