"""`shadelab bench volume`'s scalar rows: one per mode and cl_steps, in the bench's CSV columns, each with its time
and its error against the CPU reference, which shrinks as the steps grow."""
import math

from app.bench.harness import CSV_COLUMNS
from app.bench.volume_scalar import scalar_rows
from app.model.volume.scalar_modes import SCALAR_MODES


def test_a_row_per_mode_and_steps_with_its_time_and_error(gl):
    lines = []
    rows = scalar_rows(gl, side=16, size=(32, 32), runs=1, steps=(8, 128), reference_steps=512, progress=lines.append)
    assert [(r.method, r.knob) for r in rows] == [(f"scalar {m}", s) for m in SCALAR_MODES[1:] for s in (8.0, 128.0)]
    assert len(lines) == len(rows)
    for row in rows:
        assert set(CSV_COLUMNS) <= set(row.as_csv()) and row.scene == "ct phantom"
        assert row.ms_median > 0 and math.isfinite(row.rmse) and row.max_abs_error <= 1.0
    for coarse, fine in zip(rows[0::2], rows[1::2]):
        assert fine.rmse < 0.03 and fine.rmse <= coarse.rmse + 1e-3, fine.method


def test_vispy_is_given_our_colours_and_our_opacity_once_a_step():
    """vispy's mip shows the colour map's colour and alpha as ours does; its translucent composites the alpha once a
    step where our curve's is once a voxel of ray, so it gets the curve corrected for its step (two voxels a step:
    what passes one step is what passes two voxels)."""
    import numpy as np

    from app.bench.volume_scalar import vispy_colormap, vispy_job
    from app.model.camera3d import OrbitCamera
    from app.model.volume.scalars import TransferFunction

    transfer = TransferFunction(-100.0, 300.0, "bone", points=((-100.0, 0.0), (100.0, 0.05), (300.0, 0.4)))
    table = transfer.table() / 255.0
    assert np.array_equal(vispy_colormap(transfer, "mip", 2.0), table)
    one, two = vispy_colormap(transfer, "translucent", 1.0), vispy_colormap(transfer, "translucent", 2.0)
    assert np.array_equal(one[:, :3], table[:, :3]) and np.array_equal(two[:, :3], table[:, :3])
    levels = np.linspace(-100.0, 300.0, 256)
    assert np.allclose(one[:, 3], np.interp(levels, (-100.0, 100.0, 300.0), (0.0, 0.05, 0.4)))
    assert np.allclose(1.0 - two[:, 3], (1.0 - one[:, 3]) ** 2)
    job = vispy_job(np.zeros((4, 5, 6), np.int16), transfer, "translucent", OrbitCamera(yaw=10), (32, 24), 2.0, 3)
    assert job["step"] == 2.0 and tuple(job["clim"]) == (-100.0, 300.0) and job["volume"].dtype == np.float32
    assert job["yaw"] == 10 and tuple(job["size"]) == (32, 24) and job["texture_format"] == "auto"
