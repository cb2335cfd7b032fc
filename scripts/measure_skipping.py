"""Measure what empty-space skipping does to the picture (docs/raytracer.md): F5 against F7 and F8 against itself
with skipping off (cl_distanceScale 0) over 24 seeded random sparse volumes x 16 random cameras at 128x128
(tests/sparse_volumes.py), every 8th pair also against the CPU reference at the same cl_steps; then F5 and F6 on
the bench's Cornell box against the CPU reference at the same cl_steps 128.

    PYTHONPATH=$PWD .venv/bin/python scripts/measure_skipping.py
"""
import numpy as np

from app.gl.core.headless import OffscreenTarget, create_context
from app.gl.volume.raytracer import RayTracer, TraceSettings
from app.gl.core.shaders import ShaderLibrary
from app.model.camera3d import OrbitCamera
from app.model.volume.render_modes import MODES
from app.model.volume.voxels import Voxels
from app.model.volume.samples import cornell_box
from app.model.volume.view import VolumeView
from app.reference.volume import render as reference
from app.resources import SHADERS
from tests.sparse_volumes import KINDS, random_camera, random_steps, sparse_volume

SIZE = (128, 128)
ctx = create_context()
ctx.simple_framebuffer((8, 8)).use()
tracer = RayTracer(ctx, ShaderLibrary(ctx, [SHADERS]))
target = OffscreenTarget(ctx, SIZE, samples=0)


def gpu(voxels, view, **settings) -> np.ndarray:
    tracer.render(target.fbo, voxels, view, TraceSettings(slice_planes=False, **settings))
    return target.read()[..., :3].astype(float)


def cpu(data, view, mode, steps) -> np.ndarray:
    return reference(data, view.camera, SIZE, MODES[mode], steps=steps["steps"], shadow_steps=steps["shadow_steps"],
                     background=np.array(view.background) / 255.0) * 255


def errors(image, truth) -> tuple[float, int]:
    """RMSE in 1/255 and the pixels off by more than 8/255 (a surface decided the other way)."""
    e = np.abs(image - truth)
    return float(np.sqrt((e ** 2).mean())), int((e.max(-1) > 8).sum())


rng = np.random.default_rng(13)
pairs, over, worst, worst_f8, against_cpu = 0, 0, 0.0, 0.0, []
for v in range(24):
    data = sparse_volume(rng, KINDS[v % len(KINDS)], tuple(int(s) for s in rng.integers(8, 97, 3)))
    voxels = Voxels(data)
    for c in range(16):
        view, steps = VolumeView(camera=random_camera(rng)), random_steps(rng)
        f5, f7 = gpu(voxels, view, mode=5, **steps), gpu(voxels, view, mode=7, **steps)
        difference = float(np.abs(f5 - f7).max())
        worst, over = max(worst, difference), over + (difference > 1)
        if c % 4 == 0:
            f8 = gpu(voxels, view, mode=8, **steps) - gpu(voxels, view, mode=8, distance_scale=0.0, **steps)
            worst_f8 = max(worst_f8, float(np.abs(f8).max()))
        if pairs % 8 == 0:
            truth = cpu(data, view, 5, steps)
            against_cpu.append((errors(f5, truth), errors(f7, truth)))
        pairs += 1
print(f"{pairs} pairs F5/F7: max |F5 - F7| {worst:.0f}/255, {over} pairs over 1/255; "
      f"{pairs // 4} pairs F8: max |F8 - F8 unskipped| {worst_f8:.0f}/255")
a = np.array(against_cpu)  # (images, F5 / F7, (rmse, pixels))
for i, mode in enumerate((5, 7)):
    print(f"F{mode} against the CPU at the same steps, {len(a)} images: mean RMSE {a[:, i, 0].mean():.3f}/255, "
          f"{int(a[:, i, 1].sum())} pixels off by more than 8/255")

data = cornell_box(64)
view = VolumeView(camera=OrbitCamera(yaw=0, pitch=0, distance=3.4))  # the bench's Cornell camera
steps = {"steps": 128, "shadow_steps": 21}
for mode in (5, 6):
    rmse = np.sqrt(((gpu(Voxels(data), view, mode=mode, **steps) - cpu(data, view, mode, steps)) ** 2).mean()) / 255
    print(f"Cornell box F{mode} against the CPU at cl_steps 128: RMSE {rmse:.4f}")
