"""vispy's Volume visual sees the same volume from the same camera as our ray tracer (bench extra;
skipped where the optional 'peers' packages are not installed)."""
import os
import subprocess
import sys

import numpy as np
import pytest

pytest.importorskip("vispy")
pytest.importorskip("OpenGL")


def test_vispy_average_matches_our_translucent_mean_in_place(tmp_path):
    from app.bench.volume import grey_scene

    from app.model.camera3d import OrbitCamera

    name, volume, view, grey = grey_scene(32)
    job, out = tmp_path / "job.npz", tmp_path / "out.npz"
    cam = OrbitCamera(yaw=20, pitch=15, distance=5.2)  # the whole box in view, seen from a corner
    np.savez(job, volume=grey, size=np.array((64, 64)), method="average", threshold=0.1, step=0.25,
             yaw=cam.yaw, pitch=cam.pitch, distance=cam.distance, runs=1)
    done = subprocess.run([sys.executable, "-m", "app.bench.vispy_peer", str(job), str(out)], timeout=120,
                          env={**os.environ, "EGL_PLATFORM": "surfaceless"}, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    image = np.load(out)["image"].astype(float)
    from app.model.volume.render_modes import MODES
    from app.reference.volume import render

    ours = render(volume.data, cam, (64, 64), MODES[4], steps=256) * 255
    covered_vispy, covered_ours = image.sum(-1) > 3, ours.sum(-1) > 3
    assert (covered_vispy != covered_ours).mean() < 0.05  # the same box in the same place


def test_vispy_mip_and_translucent_rows_on_the_phantom_against_our_reference():
    """vispy's mip and translucent at one voxel a step, given our window, colours and opacity, come within a few
    levels of our CPU reference: the same picture in the same place (half a voxel off, its mip's RMSE was 0.08)."""
    import math

    from app.bench.volume_scalar import vispy_scalar_rows

    lines = []
    rows = vispy_scalar_rows(side=32, size=(64, 64), runs=1, steps=(32,), reference_steps=128, progress=lines.append)
    assert [(r.method, r.knob, r.scene) for r in rows] == [("vispy mip", 32.0, "ct phantom"),
                                                           ("vispy translucent", 32.0, "ct phantom")]
    assert len(lines) == 2
    for row in rows:
        assert row.ms_median > 0 and row.extra["frame_ms"] >= row.ms_median and math.isnan(row.gpu_ms_median)
        assert row.rmse < 0.02, row
