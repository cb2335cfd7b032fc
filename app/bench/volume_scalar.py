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


# --- vispy's Volume visual on the same scan (an optional peer, app/bench/vispy_peer.py) ---------------------------
VISPY_MODES = ("mip", "translucent")  # vispy's methods of the same name compute what ours do


def vispy_colormap(transfer: TransferFunction, mode: str, voxels_a_step: float) -> np.ndarray:
    """vispy's colour map (256 RGBA colours, 0..1, evenly spaced over its clim, the window) that draws what our
    `mode` draws. mip: the colour map's colours and alphas, so the greatest value shows over the background with
    its alpha as ours does. translucent: the colour map's colours with the opacity curve's alpha; vispy composites
    that alpha once a step where our curve's is once a voxel of ray, so it is corrected for the step as our shader
    corrects it, 1 - (1 - a)^(voxels a step): both then approximate the same integral (at one voxel a step no
    correction). vispy's clim clamps values outside the window to its ends: a curve for both keeps to the window."""
    table = transfer.table() / 255.0
    if mode == "translucent":
        curve = transfer.opacity()
        values = transfer.low + np.linspace(0.0, 1.0, len(table)) * (transfer.high - transfer.low)
        alpha = np.interp(values, [p[0] for p in curve], [p[1] for p in curve])
        table = np.concatenate([table[:, :3], 1.0 - (1.0 - alpha[:, None]) ** voxels_a_step], -1)
    return table


def vispy_job(values: np.ndarray, transfer: TransferFunction, mode: str, camera: OrbitCamera, size: tuple[int, int],
              voxels_a_step: float, runs: int) -> dict:
    """The peer's job for our `mode` on `values` (d, h, w) at `voxels_a_step` (vispy's relative_step_size: its
    steps are that many voxels long, as ours are at cl_steps = the volume's side / voxels_a_step for a cube). The
    values go as float32 in a float texture (texture_format "auto"): vispy's default scales them to the window
    and stores 8 bits, which adds half or more to its error on a CT."""
    return dict(volume=values.astype(np.float32), texture_format="auto",
                clim=np.array((transfer.low, transfer.high)), cmap=vispy_colormap(transfer, mode, voxels_a_step),
                method=mode, threshold=0.0, step=voxels_a_step, yaw=camera.yaw, pitch=camera.pitch,
                distance=camera.distance, size=np.array(size), runs=runs)


def vispy_scalar_rows(side: int, size: tuple[int, int], runs: int, steps: tuple[int, ...], reference_steps: int,
                      progress) -> list[Row]:
    """Rows `vispy mip` and `vispy translucent` on the phantom, at the same step lengths (cl_steps), window,
    colours and opacity as the `scalar` rows, against the same references; their times the draws alone, as ours."""
    from app.bench import vispy_peer

    values = ct_phantom(side)
    rows = []
    for mode in VISPY_MODES:
        for s in steps:
            job = vispy_job(values, window(mode), mode, VIEW.camera, size, side / s, runs)
            try:
                result = vispy_peer.run(job, timeout=300)
            except RuntimeError as e:
                progress(f"vispy {mode}: {e}")
                return rows
            rmse, max_err = errors(result["image"] / 255.0, reference(side, mode, size, reference_steps))
            ms = float(result["ms"])
            progress(f"vispy {mode:>14} {SCENE} cl_steps={s}: {ms:8.2f} ms  rmse {rmse:.2e}  max {max_err:.2e}")
            rows.append(Row("volume", f"vispy {mode}", "cl_steps", float(s), SCENE, size[0], size[1], ms,
                            float("nan"), runs, rmse, max_err, {"frame_ms": float(result["frame_ms"])}))
    return rows
