"""`shadelab bench frames`: each workspace's default scene at the editor's default view size, drawn as the
viewport draws it while the user moves the view (interactive frames within r_frameBudget, the host's ladder
learning from the times it measures) and once still. A row per workspace: the interactive frame time (median and
10th..90th percentile), the level the ladder settled on, the still frame's time, and what the interactive picture
gives up: its error against the still frame of the same view; then the processor time of both (all the GL
driver's threads: on a software renderer, what the frames cost whatever else the machine runs), and the first full
frame after the drag (what the viewport draws once the view has been still a moment): its time and its error
against the settled picture."""
from __future__ import annotations

import csv
import io
import statistics
import time
from pathlib import Path
from typing import Callable, Sequence

import numpy as np

from app.editor import Editor
from app.gl.core.headless import OffscreenTarget
from app.gl.core.workspace_renderer import RENDERERS, WorkspaceRenderer
from app.io.atomic import write_text
from app.model.workspace import WorkspaceMapping

# The viewport of the editor's default 1400x860 window with its docks (measured under Xvfb; the volume's wider
# dock leaves it 448 wide): the size a new user's frames have.
DEFAULT_VIEW = (588, 614)
CSV_COLUMNS = ("workspace", "width", "height", "budget_ms", "level", "scale", "cheap", "interactive_ms_median",
               "interactive_ms_p10", "interactive_ms_p90", "still_ms_median", "still_ms_p10", "still_ms_p90",
               "interactive_rmse", "interactive_max_abs_error", "frames", "interactive_cpu_ms_median",
               "still_cpu_ms_median", "first_still_ms", "first_still_rmse")
SETTLE_FRAMES = 64  # a temporal history (the clouds' TAA) fills within this


def _pan(view_command: str) -> Callable[[object], str]:
    """A 2D view moved right by 1 % of its height a frame."""
    return lambda state: (f"{view_command} {state.camera.cx + 0.01 * state.camera.height!r} {state.camera.cy!r} "
                          f"{state.camera.height!r}")


# The bench layer's mapping from a workspace to the command that moves its view one frame's worth of a drag.
MOVES: dict[str, Callable[[object], str]] = WorkspaceMapping("MOVES (app/bench/frame_budget.py)", {
    "snowflake": _pan("snow.view"),
    "lighting2d": _pan("lighting.view"),
    "volume": lambda state: "orbit.step 2 0",
    "clouds": lambda state: f"camera.look {state.view.yaw + 1.0!r} {state.view.pitch!r}",
    "lights3d": lambda state: f"view.orbit {state.camera.yaw + 2.0!r} {state.camera.pitch!r}",
})


def _percentiles(values: list[float]) -> tuple[float, float, float]:
    ordered = sorted(values)
    pick = lambda q: ordered[min(len(ordered) - 1, round(q * (len(ordered) - 1)))]  # noqa: E731
    return statistics.median(ordered), pick(0.1), pick(0.9)


class _Workspace:
    """One workspace's frames through the host the viewport uses, timed as the viewport times them."""

    def __init__(self, ctx, editor: Editor, name: str, size: tuple[int, int], budget_ms: float,
                 setup: Sequence[str] = ()) -> None:
        self.ctx, self.editor, self.name, self.budget_ms = ctx, editor, name, budget_ms
        assert editor.execute(f"workspace {name}")
        for line in setup:
            assert editor.execute(line), f"{name}: {line} failed"
        RENDERERS[name].prepare()
        self.host = WorkspaceRenderer(ctx)
        self.target = OffscreenTarget(ctx, size)
        self.cpu_ms = 0.0  # the processor time of the last frame

    def frame(self, interactive: bool) -> float:
        start, cpu = time.perf_counter(), time.process_time()
        self.host.render(self.target.fbo, self.editor.current, self.editor.render_settings(), interactive,
                         self.budget_ms)
        self.ctx.finish()
        ms = (time.perf_counter() - start) * 1e3
        self.cpu_ms = (time.process_time() - cpu) * 1e3
        self.host.frame_took(ms)
        return ms

    def move(self) -> None:
        assert self.editor.execute(MOVES[self.name](self.editor.current)), f"{self.name}: the move failed"

    def settled_image(self) -> np.ndarray:
        for _ in range(SETTLE_FRAMES):
            self.frame(False)
            if not self.host.settling():
                break
        return self.target.read()

    def release(self) -> None:
        self.host.release()
        self.target.release()


def measure(ctx, name: str, size: tuple[int, int] = DEFAULT_VIEW, budget_ms: float = 100.0, frames: int = 24,
            learn: int = 8, setup: Sequence[str] = ()) -> dict:
    """One workspace's row: `learn` interactive frames for the ladder to find its level, then `frames` timed; on its
    default scene, or on what the commands `setup` make of it."""
    editor = Editor(configs=False)
    bench = _Workspace(ctx, editor, name, size, budget_ms, setup)
    try:
        bench.settled_image()
        still, still_cpu = [], []
        for _ in range(max(3, frames // 4)):
            still.append(bench.frame(False))
            still_cpu.append(bench.cpu_ms)
        interactive, interactive_cpu = [], []
        for i in range(learn + frames):
            bench.move()
            ms = bench.frame(True)
            if i >= learn:
                interactive.append(ms)
                interactive_cpu.append(bench.cpu_ms)
        budget = bench.host.budgets[name]
        index = budget.level  # the level the drag settled on (the still frames below go back to 0)
        level = budget.levels[index]
        moving = bench.target.read().astype(np.float64) / 255.0
        first_ms = bench.frame(False)
        first = bench.target.read().astype(np.float64) / 255.0
        settled = bench.settled_image().astype(np.float64) / 255.0
        diff = (moving - settled)[..., :3]
        median, p10, p90 = _percentiles(interactive)
        s_median, s_p10, s_p90 = _percentiles(still)
        return {"workspace": name, "width": size[0], "height": size[1], "budget_ms": budget_ms,
                "level": index, "scale": level.scale, "cheap": level.cheap,
                "interactive_ms_median": median, "interactive_ms_p10": p10, "interactive_ms_p90": p90,
                "still_ms_median": s_median, "still_ms_p10": s_p10, "still_ms_p90": s_p90,
                "interactive_rmse": float(np.sqrt(np.mean(diff ** 2))),
                "interactive_max_abs_error": float(np.abs(diff).max()), "frames": len(interactive),
                "interactive_cpu_ms_median": statistics.median(interactive_cpu),
                "still_cpu_ms_median": statistics.median(still_cpu), "first_still_ms": first_ms,
                "first_still_rmse": float(np.sqrt(np.mean((first - settled)[..., :3] ** 2)))}
    finally:
        bench.release()


def run(ctx, names: list[str], size: tuple[int, int] = DEFAULT_VIEW, budget_ms: float = 100.0, frames: int = 24,
        progress: Callable[[str], None] = print) -> list[dict]:
    rows = []
    for name in names:
        row = measure(ctx, name, size, budget_ms, frames)
        progress(f"{name}: interactive {row['interactive_ms_median']:.1f} ms (level {row['level']}, "
                 f"{row['interactive_ms_p10']:.1f}..{row['interactive_ms_p90']:.1f}; processor "
                 f"{row['interactive_cpu_ms_median']:.0f} ms), still {row['still_ms_median']:.1f} ms (processor "
                 f"{row['still_cpu_ms_median']:.0f} ms); interactive rmse {row['interactive_rmse'] * 255:.2f}/255; "
                 f"first still frame {row['first_still_ms']:.0f} ms, rmse {row['first_still_rmse'] * 255:.2f}/255")
        rows.append(row)
    return rows


def write_csv(path: Path, rows: list[dict]) -> None:
    out = io.StringIO()
    writer = csv.DictWriter(out, fieldnames=CSV_COLUMNS, lineterminator="\n")
    writer.writeheader()
    for row in rows:
        writer.writerow({k: f"{v:.4g}" if isinstance(v, float) else v for k, v in row.items()})
    write_text(path, out.getvalue())
