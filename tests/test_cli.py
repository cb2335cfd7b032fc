"""The headless host through the real command line: render and bench."""
import csv
import subprocess
import sys

import numpy as np
import pytest

from app.bench.harness import CSV_COLUMNS
from app.io.png import read_png


def shadelab(*args, **kw):
    return subprocess.run([sys.executable, "-m", "app", *args], capture_output=True, text=True, timeout=120, **kw)


def test_render_snowflake_png(tmp_path):
    out = tmp_path / "x.png"
    r = shadelab("render", "snowflake", "--size", "256x256", "--out", str(out))
    assert r.returncode == 0, r.stderr
    image = read_png(out)
    assert image.shape == (256, 256, 4)
    assert (image[..., 1] > 60).sum() > 500  # the default scene's outlines


def test_render_runs_commands_in_order_and_loads_scenes(tmp_path):
    scene = tmp_path / "one.json"
    scene.write_text('{"format": "shadelab.snowflake", "version": 1, "level": 1, '
                     '"flakes": [{"x": 0, "y": 0, "radius": 1}]}')
    a, b = tmp_path / "a.png", tmp_path / "b.png"
    assert shadelab("render", "snowflake", "--scene", str(scene), "--size", "96x96", "--out", str(a)).returncode == 0
    r = shadelab("render", "snowflake", "--scene", str(scene), "--cmd", "snow.level 5", "--cmd", "snow.view 0 0 3",
                 "--size", "96x96", "--out", str(b))
    assert r.returncode == 0, r.stderr
    assert "] snow.level 5" in r.stdout
    assert not np.array_equal(read_png(a), read_png(b))


def test_render_refuses_a_failing_command_and_writes_nothing(tmp_path):
    out = tmp_path / "x.png"
    r = shadelab("render", "snowflake", "--cmd", "snow.level 99", "--size", "64x64", "--out", str(out))
    assert r.returncode == 1
    assert "within 0..8" in r.stderr and "no image written" in r.stderr
    assert not out.exists()


@pytest.mark.parametrize("size", ["64", "0x10", "axb"])
def test_render_bad_size(tmp_path, size):
    r = shadelab("render", "snowflake", "--size", size, "--out", str(tmp_path / "x.png"))
    assert r.returncode == 2 and "size must" in r.stderr


def test_bench_quick_writes_csv_and_chart(tmp_path):
    r = shadelab("bench", "snowflake", "--quick", "--out", str(tmp_path))
    assert r.returncode == 0, r.stderr
    with open(tmp_path / "snowflake.csv") as f:
        rows = list(csv.DictReader(f))
    assert set(CSV_COLUMNS) <= set(rows[0])
    assert {r["method"] for r in rows} == {"gs", "cpu"}
    assert {float(r["knob"]) for r in rows} >= {0.0, 6.0}
    for row in rows:
        assert row["technique"] == "snowflake" and float(row["ms_median"]) > 0
        assert 0 <= float(row["rmse"]) <= float(row["max_abs_error"]) < 1e-5
    chart = read_png(tmp_path / "snowflake.png")
    assert chart.shape[1] == 1400 and chart.std() > 10  # a drawn chart, not a blank image
