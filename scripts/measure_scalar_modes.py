"""Measure the scalar modes on a 256^3 scan (the CT phantom, int16 HU), as docs/volume.md reports them:

1. mip and translucent at one voxel a step (cl_steps 256, vispy's relative_step_size 1) and at two, a 256x256
   picture from a corner: time per frame (median of 15, after one) and the error against the CPU reference at a
   quarter voxel a step. vispy's Volume visual on the same job where vispy is installed (app/bench/vispy_peer.py,
   an optional peer); where it is not, the script says so and measures ours alone.
2. Orbiting the scan in mip through the editor's host within r_frameBudget (100 ms), at the editor's view size,
   as `shadelab bench frames` measures each workspace's default scene.

    PYTHONPATH=. .venv/bin/python scripts/measure_scalar_modes.py [side]
"""
import importlib.util
import statistics
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from app.bench import frame_budget
from app.bench.harness import errors
from app.gl.core.headless import OffscreenTarget, create_context, release_context
from app.gl.core.shaders import ShaderLibrary
from app.gl.volume.raytracer import RayTracer
from app.model.camera3d import OrbitCamera
from app.model.volume.phantom import ct_phantom
from app.model.volume.render_modes import TraceSettings
from app.model.volume.scalars import TransferFunction
from app.model.volume.view import VolumeView
from app.model.volume.volume import Volume
from app.reference.volume_scalar import render as reference
from app.resources import SHADERS

SIZE = (256, 256)
WINDOW = TransferFunction(-200.0, 1200.0, "grey")
VIEW = VolumeView(camera=OrbitCamera(yaw=30, pitch=20, distance=4.6), background=(0, 0, 0))
RUNS = 15


def ours(ctx, volume: Volume, mode: str, steps: int) -> tuple[float, np.ndarray]:
    tracer = RayTracer(ctx, ShaderLibrary(ctx, [SHADERS]))
    target = OffscreenTarget(ctx, SIZE, samples=0)
    settings = TraceSettings(steps=steps, slice_planes=False, scalar_mode=mode)
    tracer.render(target.fbo, volume.voxels, VIEW, settings)
    ctx.finish()
    times = []
    for _ in range(RUNS):
        start = time.perf_counter()
        tracer.render(target.fbo, volume.voxels, VIEW, settings)
        ctx.finish()
        times.append((time.perf_counter() - start) * 1e3)
    image = target.read()[..., :3] / 255.0
    target.release()
    return statistics.median(times), image


def main() -> None:
    side = int(sys.argv[1]) if len(sys.argv) > 1 else 256
    values = ct_phantom(side)
    volume = Volume.new(1, 1, 1)
    volume.replace_scalars(values, WINDOW, copy=False)
    vispy = all(importlib.util.find_spec(m) is not None for m in ("vispy", "OpenGL"))
    if not vispy:
        print("vispy is not installed (an optional peer): ours alone")
    ctx = create_context()
    try:
        print(f"{side}^3 int16 CT phantom, {SIZE[0]}x{SIZE[1]}, window {WINDOW.low:g}..{WINDOW.high:g}, "
              f"{ctx.info['GL_RENDERER']}")
        for mode in ("mip", "translucent"):
            start = time.perf_counter()
            truth = reference(values, WINDOW, VIEW.camera, SIZE, mode, 4 * side, background=(0.0, 0.0, 0.0))
            print(f"{mode}: CPU reference at a quarter voxel a step in {time.perf_counter() - start:.0f} s")
            for voxels_a_step in (1, 2):
                ms, image = ours(ctx, volume, mode, side // voxels_a_step)
                rmse, worst = errors(image, truth)
                print(f"  ours  {mode:<11} {voxels_a_step} voxel(s) a step: {ms:7.1f} ms  rmse {rmse:.2e}  "
                      f"max {worst:.2e}")
        rows = [frame_budget.measure(ctx, "volume", setup=setup) for setup in _orbit_setups(values)]
        for what, row in zip(("mip", "F5 on the same scan"), rows):
            print(f"orbit {what}: interactive {row['interactive_ms_median']:.1f} ms "
                  f"({row['interactive_ms_p10']:.1f}..{row['interactive_ms_p90']:.1f}) at level {row['level']} "
                  f"(scale {row['scale']:g}, cheap {row['cheap']}), still {row['still_ms_median']:.1f} ms, "
                  f"interactive rmse {row['interactive_rmse'] * 255:.2f}/255, budget {row['budget_ms']:g} ms, "
                  f"{row['width']}x{row['height']}")
    finally:
        release_context(ctx)


def _orbit_setups(values: np.ndarray) -> list[list[str]]:
    folder = Path(tempfile.mkdtemp())
    np.save(folder / "scan.npy", values)
    load = [f"load {folder / 'scan.npy'}", f"vol.window {WINDOW.low:g} {WINDOW.high:g}"]
    return [load, [*load, "r_scalarMode colour", "mode 5"]]


if __name__ == "__main__":
    main()
