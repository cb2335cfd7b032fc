"""vispy's Volume visual on the same volume and camera, for the volume bench (an optional extra).

Run in its own process (`python -m app.bench.vispy_peer IN.npz OUT.npz`) with EGL_PLATFORM=surfaceless:
vispy makes its own EGL context, which should not share a thread with ours. vispy takes scalar volumes,
so the bench gives it the grey volume whose RGBA twin our modes draw. Its times include reading the
image back (`canvas.render()` returns it); ours do not.
"""
from __future__ import annotations

import statistics
import sys
import time

import numpy as np


def render(job: dict) -> dict:
    import vispy

    vispy.use(app="egl")
    from vispy import scene
    from vispy.visuals.transforms import STTransform

    volume = job["volume"]  # (d, h, w) float32, 0..1
    d, h, w = volume.shape
    longest = max(volume.shape)
    size = tuple(int(v) for v in job["size"])
    canvas = scene.SceneCanvas(size=size, show=False, bgcolor=(0, 0, 0, 1))
    view = canvas.central_widget.add_view()
    visual = scene.visuals.Volume(volume, parent=view.scene, method=str(job["method"]), clim=(0, 1), cmap="grays",
                                  threshold=float(job["threshold"]), relative_step_size=float(job["step"]))
    # Voxel indices (x right, y down, z away) onto our world box: the longest side spans [-1, 1].
    visual.transform = STTransform(scale=(2 / longest, -2 / longest, -2 / longest),
                                   translate=(-w / longest, h / longest, d / longest))
    # Measured to match app/model/camera3d.py: vispy's azimuth is our yaw + 90 with +y up.
    view.camera = scene.TurntableCamera(fov=40, azimuth=float(job["yaw"]) + 90, elevation=float(job["pitch"]),
                                        distance=float(job["distance"]), center=(0, 0, 0), up="+y")
    image = canvas.render()
    times = []
    for _ in range(int(job["runs"])):
        start = time.perf_counter()
        canvas.render()
        times.append((time.perf_counter() - start) * 1e3)
    return {"image": image[..., :3], "ms": statistics.median(times)}


def main(argv: list[str]) -> int:
    job = dict(np.load(argv[0], allow_pickle=False))
    np.savez(argv[1], **render(job))
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
