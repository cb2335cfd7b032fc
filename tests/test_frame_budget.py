"""The host's frame budget (app/gl/core/frame_budget.py): while the user interacts every workspace draws at the most
accurate level of its own that fits r_frameBudget, as its measured frames teach the ladder, and the still frame
after is whole again. Frame times are fed to the ladder here, so what is asserted is the level chosen and the
work it saves (pixels drawn, the settings a level gives the renderer), never the clock."""
from __future__ import annotations

import math

import numpy as np
import pytest

from app.editor import Editor
from app.gl.core.frame_budget import FULL, Level, QualityLadder
from app.gl.core.headless import OffscreenTarget
from app.gl.core.workspace_renderer import RENDERERS, WorkspaceRenderer

SIZE = (96, 64)


@pytest.fixture(scope="module")
def editor():
    return Editor(configs=False)


def test_the_ladder_takes_the_most_accurate_level_that_fits():
    ladder = QualityLadder(4)
    assert ladder.choose(100) == 0  # nothing measured: try the best
    ladder.record(0, 400)
    assert ladder.choose(100) == 1  # too slow: the next one, unmeasured, is tried
    ladder.record(1, 150)
    ladder.record(2, 60)
    assert ladder.choose(100) == 2
    for _ in range(3):  # the scene got cheaper (still frames measure it): back to full quality, smoothed
        ladder.record(0, 20)
    assert ladder.choose(100) == 0
    assert QualityLadder(2).choose(1) == 0 and ladder.choose(0.001) == 3  # none fits: the cheapest


@pytest.mark.parametrize("name", sorted(RENDERERS))
def test_each_workspace_steps_down_its_levels_while_interactive_and_is_whole_when_still(gl, editor, name):
    """A frame `cost` times the budget at full size, scaling with the pixels drawn: the ladder walks down the
    levels until one fits, each drawn into a target of its scale, and a still frame is full size again."""
    assert editor.execute(f"workspace {name}")
    host = WorkspaceRenderer(gl)
    target = OffscreenTarget(gl, SIZE)
    try:
        levels = RENDERERS[name].LEVELS
        assert levels[0] == FULL and len(levels) >= 2
        budget_ms = 10.0

        def frame(interactive: bool) -> Level:
            reduced = host.render(target.fbo, editor.current, editor.render_settings(), interactive, budget_ms)
            level = host.budgets[name].levels[host.budgets[name].level]
            assert reduced == (level != FULL) or not interactive or reduced
            image = target.read()
            assert (image != image[0, 0]).any(axis=-1).mean() > 0.02, level  # the scene, not a blank frame
            if level.scale != 1.0:
                drawn = host.budgets[name].reduced.size
                assert drawn == (math.ceil(SIZE[0] * level.scale), math.ceil(SIZE[1] * level.scale))
            host.frame_took(budget_ms * 4 * level.scale ** 2 / 2 ** level.cheap)
            return level

        chosen = [frame(True) for _ in range(len(levels) + 1)]
        assert chosen[0] == FULL and chosen[1] != FULL
        cost = [4 * lv.scale ** 2 / 2 ** lv.cheap for lv in chosen]
        assert cost[-1] <= 1.0 or chosen[-1] == levels[-1]  # settled on a level that fits, or the cheapest
        assert frame(False) == FULL
    finally:
        host.release()
        gl.detect_framebuffer(0).use()
        target.release()


def test_the_cheaper_settings_save_what_each_workspace_declares(gl, editor):
    host = WorkspaceRenderer(gl)
    try:
        made = {name: kind(gl, host.shaders) for name, kind in RENDERERS.items()}
        for name in ("volume", "clouds", "lighting2d"):
            assert editor.execute(f"workspace {name}")
            settings = editor.render_settings()
            cheapest = made[name].cheaper(settings, max(level.cheap for level in RENDERERS[name].LEVELS))
            if name == "volume":
                assert cheapest.steps < settings.steps
            elif name == "clouds":
                assert cheapest.downsample >= 4 and cheapest.steps < settings.steps
            else:
                assert settings.method == "exact" and cheapest.method == "penumbra"
        for renderer in made.values():
            renderer.release()
    finally:
        host.release()


def test_the_budget_is_a_cvar_and_the_editor_reads_it(editor):
    assert editor.frame_budget_ms() == 100.0
    assert editor.execute("r_frameBudget 40")
    assert editor.frame_budget_ms() == 40.0
    assert not editor.execute("r_frameBudget -1")  # refused with a message, unchanged
    assert editor.frame_budget_ms() == 40.0
    assert editor.execute("r_frameBudget 100")


def test_a_reduced_frame_is_the_still_frame_at_fewer_pixels(gl, editor):
    """What a drag gives up on the snowflake (no saving of its own): the stretched half-size frame against the
    whole one, small (it is the same picture) but not nothing (it is fewer pixels)."""
    assert editor.execute("workspace snowflake")
    host = WorkspaceRenderer(gl)
    target = OffscreenTarget(gl, SIZE)
    try:
        host.render(target.fbo, editor.current, None, False, 10.0)
        whole = target.read().astype(float)
        host.frame_took(100.0)
        assert host.render(target.fbo, editor.current, None, True, 10.0)  # reduced: a full frame is owed
        half = target.read().astype(float)
        assert host.budgets["snowflake"].level == 1
        error = np.abs(half - whole)[..., :3].mean()
        assert 0.0 < error < 20.0
    finally:
        host.release()
        gl.detect_framebuffer(0).use()
        target.release()


def test_the_frames_bench_writes_a_row_per_workspace(gl, tmp_path):
    from app.bench import frame_budget

    rows = frame_budget.run(gl, ["snowflake", "lighting2d"], size=(64, 48), frames=3, progress=lambda _: None)
    assert [r["workspace"] for r in rows] == ["snowflake", "lighting2d"]
    for row in rows:
        assert row["frames"] == 3 and row["interactive_ms_median"] > 0 and row["still_ms_median"] > 0
        assert row["interactive_ms_p10"] <= row["interactive_ms_median"] <= row["interactive_ms_p90"]
        assert 0.0 <= row["interactive_rmse"] <= row["interactive_max_abs_error"] <= 1.0
        assert row["interactive_cpu_ms_median"] > 0 and row["first_still_ms"] > 0 and 0 <= row["first_still_rmse"] <= 1
    frame_budget.write_csv(tmp_path / "frames.csv", rows)
    lines = (tmp_path / "frames.csv").read_text().splitlines()
    assert lines[0].split(",") == list(frame_budget.CSV_COLUMNS) and len(lines) == 3
