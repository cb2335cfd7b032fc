"""The clouds bench (app/bench/clouds.py, clouds_frames.py, clouds_report.py) on tiny images, few steps and tiny
textures: the rows and their columns, the sample-count images and table, the report, and `shadelab bench clouds`.
No timing is checked, only that the work is done and measured."""
from __future__ import annotations

import math
import re

import numpy as np
import pytest

from app.bench import WORKSPACE_TECHNIQUE, TECHNIQUES, clouds, clouds_frames, clouds_report, harness, report
from app.io.clouds.textures import NoiseTextures
from app.io.png import read_png
from app.model.clouds import noise as cn
from app.model.clouds.weather import WeatherBlend

TINY = clouds.Plan(reference_size=(32, 18), reference_steps=64, gpu_steps=(16, 32), cpu_steps=(32,),
                   buffer_size=(32, 18), buffer_steps=(8, 16), settings_size=(32, 18), settings_steps=(16,),
                   stage_steps=16, converged_steps=48, interleaved_rounds=1)
SIZE = (32, 18)


def tiny_noise() -> NoiseTextures:
    rng = np.random.default_rng(0)
    return NoiseTextures(shape=cn.shape_noise(8, 0), detail=cn.detail_noise(4, 0), curl=cn.curl_noise(8, 0),
                         cirrus=rng.random((8, 8), dtype=np.float32), blue=rng.random((8, 8), dtype=np.float32))


@pytest.fixture
def tiny_textures(monkeypatch):
    """The bench and the clouds renderer's prepare() get tiny noise textures instead of the cached ones."""
    import app.gl.clouds.workspace
    import app.io.clouds.textures

    noise = tiny_noise()
    prepared = []

    def provide(progress=None, cache_dir=None, warn=None):
        prepared.append(progress)
        return noise

    monkeypatch.setattr(app.io.clouds.textures, "noise_textures", provide)
    monkeypatch.setattr(app.gl.clouds.workspace, "noise_textures", provide)
    return prepared


def tiny_bench() -> clouds.CloudsBench:
    bench = clouds.CloudsBench(TINY)
    weather = np.random.default_rng(1).random((8, 8, 3), dtype=np.float32)
    weather[..., 0] = 0.3 + 0.7 * weather[..., 0]  # patchy coverage: clouds and clear sky both
    bench.scene.weather = WeatherBlend(weather)
    return bench


@pytest.fixture(scope="module")
def measured(gl, qapp, tmp_path_factory):
    """One run of the tiny technique: (bench, rows, output folder with the CSV and the extra outputs)."""
    mp = pytest.MonkeyPatch()
    import app.io.clouds.textures

    noise = tiny_noise()
    mp.setattr(app.io.clouds.textures, "noise_textures", lambda progress=None, cache_dir=None, warn=None: noise)
    try:
        bench = tiny_bench()
        tech = clouds.make_technique(bench)
        rows = harness.run(gl, tech, quick=True, runs=1)
        out = tmp_path_factory.mktemp("clouds-bench")
        report.write_csv(out / "clouds.csv", rows)
        lines = []
        tech.extra_outputs(gl, out, True, rows, lines.append)
    finally:
        mp.undo()
    return bench, rows, out, lines


def test_registered_for_the_cli_and_the_workspace_dock():
    assert TECHNIQUES["clouds"] is clouds.technique
    assert WORKSPACE_TECHNIQUE["clouds"] == "clouds"
    quick = clouds.technique(quick=True)
    assert quick.name == "clouds" and quick.extra_outputs is not None
    assert quick.charts is clouds_report.chart_parts
    assert {m.name for m in quick.methods} >= {"energy", "seed", "buffer 1", "buffer 1/2", "buffer 1/3",
                                                "buffer 1/4", "none", "all"}


def test_stages_add_each_optimisation_in_figure_39s_order():
    labels = [label for label, _method, _s in clouds_frames.stages()]
    assert labels == ["none", "+ early exit", "+ big steps", "+ light skip", "+ detail skip", "+ buffer 1/4",
                      "+ jitter+TAA", "+ reprojection"]
    settings = [s for _l, _m, s in clouds_frames.stages()]
    assert settings[0] == clouds_frames.NONE and settings[-1] == clouds_frames.ALL
    assert [m for _l, m, _s in clouds_frames.stages()][:2] == ["none", "only early exit"]


def test_every_row_measured_with_the_contract_columns(measured):
    bench, rows, out, _lines = measured
    methods = {r.method for r in rows}
    cf = clouds_frames
    expected = {"energy", "seed", "cpu energy", *cf.BUFFERS.values(), "none", "all", *cf.ALL_BUT,
                *("only " + label for label, _c in cf.OPTIMISATIONS), *(m for _l, m, _s in cf.stages())}
    assert methods == expected
    for r in rows:
        assert (r.width, r.height) == SIZE and r.knob_name == "steps"
        assert r.extra["samples_per_px"] > 0, r.method
        assert math.isfinite(r.rmse) and math.isfinite(r.max_abs_error) and r.ms_median > 0
    gpu = [r for r in rows if r.method != "cpu energy"]
    assert {r.knob for r in gpu if r.method == "energy"} == set(TINY.gpu_steps)
    assert {r.knob for r in gpu if r.method == "buffer 1/3"} == set(TINY.buffer_steps)
    back = report.read_csv(out / "clouds.csv")
    assert "samples_per_px" in back[0] and "mean_abs_error" in back[0]
    assert len(back) == len(rows)


def test_exact_optimisations_match_none_and_none_matches_itself(measured):
    _bench, rows, _out, _lines = measured
    row = {r.method: r for r in rows if r.knob == TINY.stage_steps and r.width == SIZE[0]}
    assert row["none"].max_abs_error == 0
    for name in ("only light skip", "only detail skip", "only reprojection"):  # they skip only zeros
        assert row[name].extra["mean_abs_error"] < 1e-5, name
    # the energy integration on the GPU is the CPU reference's, step for step: linear radiance against linear
    # (the GPU's HDR frame before its tone map, app/bench/clouds_frames.py CloudState.image)
    for r in rows:
        if r.method == "energy":
            assert r.extra["same_steps_max_error"] < 2 / 255


def test_sample_count_images_and_table(measured):
    bench, rows, out, _lines = measured
    stages = clouds_frames.stages()
    for i, (label, _method, _s) in enumerate(stages):
        image = read_png(out / f"clouds-samples-{i}-{clouds_report.slug(label)}.png")
        assert image.shape == (SIZE[1], SIZE[0], 4)
    assert read_png(out / "clouds-samples-0-none.png")[..., 0].max() > 0  # lookups counted somewhere
    table = (out / "clouds-samples.md").read_text()
    counts = {}
    for label, method, _s in stages:
        line = next(x for x in table.splitlines() if f"`{method}`" in x)
        assert label in line
        counts[label] = float(line.split("|")[4])
    assert counts["none"] > 0
    labels = [label for label, _m, _s in stages]
    for before, after in zip(labels, labels[1:]):
        if after[2:] in clouds_frames.SAVING:
            assert counts[after] <= counts[before] * (1 + 1e-6), (before, after)
    assert counts["+ reprojection"] < counts["none"] / 10


def test_report_has_every_measure_and_a_verdict_for_each_goal(measured):
    _bench, rows, out, lines = measured
    # each part's chart (the cli draws them: test_cli_bench_prepares_the_textures_and_writes_everything)
    parts = clouds_report.chart_parts(report.read_csv(out / "clouds.csv"))
    assert list(parts) == ["clouds-integration.png", "clouds-buffers.png", "clouds-settings.png"]
    assert {r["method"] for r in parts["clouds-integration.png"]} == {"energy", "seed", "cpu energy"}
    assert sum(len(part) for part in parts.values()) <= len(rows)
    text = (out / "clouds-report.md").read_text()
    for heading in ("## 1.", "Figure 41", "Figure 39", "## 4.", "## 5."):
        assert heading in text
    assert re.search(r"(PASS|FAIL): GPU energy at \d+ steps against the CPU reference", text)
    assert re.search(r"(PASS|FAIL): all optimisations against none at 16 steps: [\d.]+x faster", text)
    assert re.search(r"(PASS|FAIL): interleaved, all against none", text)
    # measure 7: ground pixels of the stretched, turned and dragged buffer; the slow turn, the wind, the settling
    assert "## 7. Upsampling and reprojection" in text and re.search(r"\| stretched, d = 4 \| [\d.]+ % \|", text)
    assert re.search(r"at frames 4: [\d.]+, 16: [\d.]+, 40: [\d.]+", text) and "d = 2: " in text
    assert re.search(r"settles \(TAA converged\) after \d+ frames", text)
    assert any("clouds-report.md" in line for line in lines)


def test_cli_bench_prepares_the_textures_and_writes_everything(tiny_textures, tmp_path, monkeypatch, qapp):
    from app import cli

    monkeypatch.setitem(TECHNIQUES, "clouds", lambda quick=False: clouds.make_technique(tiny_bench()))
    assert cli.main(["bench", "clouds", "--quick", "--out", str(tmp_path)]) == 0
    assert tiny_textures and callable(tiny_textures[0])  # prepare() with the terminal's progress bar
    for name in ("clouds.csv", "clouds.png", "clouds-samples.md", "clouds-report.md", "clouds-buffers.png",
                 "clouds-samples-7-reprojection.png"):
        assert (tmp_path / name).is_file(), name
    for chart in ("clouds-integration.png", "clouds-buffers.png", "clouds-settings.png"):
        assert read_png(tmp_path / chart).shape[2] == 4
    assert "samples_per_px" in (tmp_path / "clouds.csv").read_text().splitlines()[0]
