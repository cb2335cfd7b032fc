"""vispy's Volume visual on the same volume and camera, for the volume bench (an optional extra).

Run in its own process (`python -m app.bench.vispy_peer IN.npz OUT.npz`) with EGL_PLATFORM=surfaceless:
vispy makes its own EGL context, which should not share a thread with ours. The job (an .npz) holds the scalar
volume (d, h, w) in data units, the window `clim` (default 0..1), the colour map as evenly spaced RGBA colours
`cmap` (default vispy's "grays"), the `texture_format` (default vispy's: 8 bits), the method, vispy's
relative_step_size `step` (voxels a step), the threshold, the camera (our yaw, pitch, distance), the picture's size
and the timed runs. Each frame draws into one framebuffer kept for all: `ms` is the median of the draws up to
glFinish, as our rows time theirs; `frame_ms` adds reading the picture back (what `canvas.render()` does, less
its new framebuffer each call); `renderer` names the GL it ran on. `available` and `run` are the bench's side:
whether vispy is installed, and one job in its child process.
"""
from __future__ import annotations

import importlib.util
import os
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np


def available() -> bool:
    return all(importlib.util.find_spec(m) is not None for m in ("vispy", "OpenGL"))


def run(job: dict, timeout: float = 600) -> dict:
    """`render`'s result for `job` (arrays and numbers, as np.savez takes them), drawn in a child process;
    RuntimeError with vispy's last line of error if it fails."""
    with tempfile.TemporaryDirectory() as tmp:
        job_path, out_path = os.path.join(tmp, "job.npz"), os.path.join(tmp, "out.npz")
        np.savez(job_path, **job)
        done = subprocess.run([sys.executable, "-m", "app.bench.vispy_peer", job_path, out_path],
                              env={**os.environ, "EGL_PLATFORM": "surfaceless"}, capture_output=True, text=True,
                              timeout=timeout)
        if done.returncode != 0:
            raise RuntimeError(f"vispy failed: {(done.stderr.strip().splitlines() or ['no message'])[-1]}")
        with np.load(out_path) as out:
            return {name: out[name] for name in out.files}


def render(job: dict) -> dict:
    import vispy

    vispy.use(app="egl")
    from vispy import gloo, scene
    from vispy.color import Colormap
    from vispy.visuals.transforms import STTransform

    volume = job["volume"]
    d, h, w = volume.shape
    longest = max(volume.shape)
    size = tuple(int(v) for v in job["size"])
    clim = tuple(float(v) for v in job.get("clim", (0.0, 1.0)))
    cmap = Colormap(np.asarray(job["cmap"], dtype=np.float32)) if "cmap" in job else "grays"
    canvas = scene.SceneCanvas(size=size, show=False, bgcolor=(0, 0, 0, 1))
    view = canvas.central_widget.add_view()
    visual = scene.visuals.Volume(volume, parent=view.scene, method=str(job["method"]), clim=clim, cmap=cmap,
                                  threshold=float(job["threshold"]), relative_step_size=float(job["step"]),
                                  texture_format=str(job["texture_format"]) if "texture_format" in job else None)
    # Voxel indices (x right, y down, z away) onto our world box, the longest side spanning [-1, 1]: vispy's box
    # runs from index -0.5 to n - 0.5 (texel centres at whole indices), ours has texel centres at (i + 0.5) / n.
    visual.transform = STTransform(scale=(2 / longest, -2 / longest, -2 / longest),
                                   translate=((1 - w) / longest, (h - 1) / longest, (d - 1) / longest))
    # Measured to match app/model/camera3d.py: vispy's azimuth is our yaw + 90 with +y up.
    view.camera = scene.TurntableCamera(fov=40, azimuth=float(job["yaw"]) + 90, elevation=float(job["pitch"]),
                                        distance=float(job["distance"]), center=(0, 0, 0), up="+y")
    fbo = gloo.FrameBuffer(color=gloo.RenderBuffer(size[::-1]), depth=gloo.RenderBuffer(size[::-1]))
    canvas.push_fbo(fbo, (0, 0), size)
    try:
        def draw() -> None:
            canvas.context.clear(color=canvas.bgcolor, depth=True)
            canvas.draw_visual(canvas.scene)
            canvas.context.finish()

        draw()  # the first frame compiles the shaders and uploads the volume
        image = fbo.read()
        draws, frames = [], []
        for _ in range(int(job["runs"])):
            start = time.perf_counter()
            draw()
            drawn = time.perf_counter()
            fbo.read()
            draws.append((drawn - start) * 1e3)
            frames.append((time.perf_counter() - start) * 1e3)
    finally:
        canvas.pop_fbo()
    renderer = gloo.gl.glGetParameter(gloo.gl.GL_RENDERER)  # which GL vispy's EGL found (a GPU, or llvmpipe)
    return {"image": image[..., :3], "ms": statistics.median(draws), "frame_ms": statistics.median(frames),
            "renderer": str(renderer)}


def main(argv: list[str]) -> int:
    job = dict(np.load(argv[0], allow_pickle=False))
    np.savez(argv[1], **render(job))
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
