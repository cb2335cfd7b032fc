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
