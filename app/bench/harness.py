"""Speed against accuracy: time each method at each quality setting and compare it with the CPU reference."""
from __future__ import annotations

import functools
import statistics
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Sequence

import moderngl
import numpy as np

from app.gl.core.headless import OffscreenTarget

CSV_COLUMNS = ("technique", "method", "knob_name", "knob", "scene", "width", "height",
               "ms_median", "gpu_ms_median", "runs", "rmse", "max_abs_error")


@dataclass
class Method:
    """One way to draw a technique. `output` returns what is compared with the reference, on a 0..1 scale."""

    name: str
    knob: str
    values: Sequence[float]
    setup: Callable[[moderngl.Context], Any]
    render: Callable[[Any, OffscreenTarget, float, Any], None]
    output: Callable[[Any, OffscreenTarget, float, Any], np.ndarray]
    quick_values: Sequence[float] | None = None
    reference: Callable[[Any, float, tuple[int, int]], np.ndarray] | None = None  # else the technique's
    stats: Callable[[Any, OffscreenTarget, float, Any], dict] | None = None  # extra CSV columns
    size: tuple[int, int] | None = None        # the output's size for this method, else the technique's
    quick_size: tuple[int, int] | None = None  # ... with --quick, else the technique's quick_size


@dataclass
class Technique:
    name: str
    methods: list[Method]
    scenes: dict[str, Any]  # scene name -> model
    reference: Callable[[Any, float, tuple[int, int]], np.ndarray]  # (scene, knob value, size)
    size: tuple[int, int] = (512, 512)
    quick_size: tuple[int, int] = (256, 256)
    quick_scenes: Sequence[str] | None = None
    extra_rows: Callable[[bool, tuple[int, int], int, Callable[[str], None]], list] | None = None  # peers' rows
    # more rows drawn in the bench's own context, before the peers': (ctx, quick, size, runs, progress)
    gl_rows: Callable[[moderngl.Context, bool, tuple[int, int], int, Callable[[str], None]], list] | None = None
    # more charts beside the technique's own: file name -> the rows (read_csv's) it charts, drawn by the cli
    charts: Callable[[list[dict]], dict[str, list[dict]]] | None = None
    # more files in the bench's output folder, after the CSV and charts: (ctx, folder, quick, rows, progress)
    extra_outputs: Callable[[moderngl.Context, Path, bool, list["Row"], Callable[[str], None]], None] | None = None
    # every method's frames of a scene in turn (all methods' states alive at once), so that a busy machine slows
    # the methods compared alike; else each setting is timed on its own, one after the other
    interleave: bool = False


@dataclass
class Row:
    technique: str
    method: str
    knob_name: str
    knob: float  # the quality setting's value
    scene: str
    width: int
    height: int
    ms_median: float      # wall time of one frame, ctx.finish() included
    gpu_ms_median: float  # GL_TIME_ELAPSED of the same frames
    runs: int
    rmse: float
    max_abs_error: float
    extra: dict = field(default_factory=dict)  # a technique's own measures (samples per pixel...)

    def as_csv(self) -> dict[str, str]:
        values = {**{k: v for k, v in self.__dict__.items() if k != "extra"}, **self.extra}
        return {k: (f"{v:.6g}" if isinstance(v, float) else str(v)) for k, v in values.items()}


def errors(output: np.ndarray, reference: np.ndarray) -> tuple[float, float]:
    """RMSE and max absolute error; a shape mismatch is itself a failure, never silently broadcast."""
    if output.shape != reference.shape:
        raise ValueError(f"output shape {output.shape} differs from the reference's {reference.shape}")
    diff = np.abs(output.astype(np.float64) - reference.astype(np.float64))
    if diff.size == 0:
        return 0.0, 0.0
    return float(np.sqrt(np.mean(diff * diff))), float(diff.max())


@dataclass
class Timing:
    """Wall and GPU milliseconds of every timed frame of one draw."""

    wall: list[float]
    gpu: list[float]

    def medians(self) -> tuple[float, float]:
        return statistics.median(self.wall), statistics.median(self.gpu)

    def summary(self) -> str:
        """The median wall time with the spread, for progress lines: 'median (min..max) ms' (the bench dock
        counts lines with 'ms' before 'rmse')."""
        return f"{statistics.median(self.wall):8.2f} ({min(self.wall):.2f}..{max(self.wall):.2f}) ms"

    def spread(self) -> dict[str, float]:
        """Min and max beside the median: CSV columns that show how far one frame can stray from it."""
        return {"ms_min": min(self.wall), "ms_max": max(self.wall),
                "gpu_ms_min": min(self.gpu), "gpu_ms_max": max(self.gpu)}


def frame_timings(ctx: moderngl.Context, draws: dict[str, Callable[[], None]], runs: int) -> dict[str, Timing]:
    """Every frame's times for several draws, after one warm-up round: one frame of each in turn per round, so
    that whatever slows the machine for a while slows them alike."""
    for draw in draws.values():
        draw()
    ctx.finish()
    timings = {name: Timing([], []) for name in draws}
    query = ctx.query(time=True)
    for _ in range(runs):
        for name, draw in draws.items():
            start = time.perf_counter()
            with query:
                draw()
            ctx.finish()
            timings[name].wall.append((time.perf_counter() - start) * 1e3)
            timings[name].gpu.append(query.elapsed / 1e6)
    return timings


def time_frames(ctx: moderngl.Context, draw: Callable[[], None], runs: int) -> tuple[float, float]:
    """Median wall and GPU milliseconds of `runs` frames after one warm-up frame."""
    return frame_timings(ctx, {"": draw}, runs)[""].medians()


def time_interleaved(ctx: moderngl.Context, draws: dict[str, Callable[[], None]], runs: int
                     ) -> dict[str, tuple[float, float]]:
    """frame_timings' medians: name -> (median wall ms, median GPU ms)."""
    return {name: timing.medians() for name, timing in frame_timings(ctx, draws, runs).items()}


@dataclass
class _Prepared:
    """One method ready to draw: its target, its output's size, its state and its quality settings."""
    target: OffscreenTarget
    size: tuple[int, int]
    state: Any
    values: Sequence[float]


def run(ctx: moderngl.Context, tech: Technique, quick: bool = False, runs: int | None = None,
        progress: Callable[[str], None] = lambda _: None) -> list[Row]:
    size = tech.quick_size if quick else tech.size
    runs = runs or (3 if quick else 7)
    scene_names = list(tech.quick_scenes if quick and tech.quick_scenes else tech.scenes)
    references: dict[tuple, np.ndarray] = {}
    rows: list[Row] = []
    targets: dict[tuple[int, int], OffscreenTarget] = {}

    def prepare(method: Method) -> _Prepared:
        own = method.quick_size if quick else method.size
        method_size = tuple(own) if own is not None else size
        if method_size not in targets:
            targets[method_size] = OffscreenTarget(ctx, method_size)
        values = method.quick_values if quick and method.quick_values is not None else method.values
        return _Prepared(targets[method_size], method_size, method.setup(ctx), values)

    def draw(method: Method, p: _Prepared, scene_name: str, value: float) -> Callable[[], None]:
        return functools.partial(method.render, p.state, p.target, value, tech.scenes[scene_name])

    def row(method: Method, p: _Prepared, scene_name: str, value: float, timing: Timing) -> Row:
        """The row of one timed setting, from what its target holds now."""
        scene = tech.scenes[scene_name]
        ms, gpu_ms = timing.medians()
        reference = method.reference or tech.reference
        key = (reference, scene_name, value, p.size)
        if key not in references:
            references[key] = reference(scene, value, p.size)
        rmse, max_err = errors(method.output(p.state, p.target, value, scene), references[key])
        extra = {**timing.spread(), **(method.stats(p.state, p.target, value, scene) if method.stats else {})}
        progress(f"{method.name:>10} {scene_name:>10} {method.knob}={value:g}: {timing.summary()}  "
                 f"rmse {rmse:.2e}  max {max_err:.2e}")
        return Row(tech.name, method.name, method.knob, float(value), scene_name, p.size[0], p.size[1], ms, gpu_ms,
                   runs, rmse, max_err, extra)

    try:
        if tech.interleave:
            prepared = [prepare(method) for method in tech.methods]
            for scene_name in scene_names:  # a scene's rows as soon as it is timed: the dock's progress moves
                progress(f"{scene_name}: every method's frames in turn, {runs} rounds")
                draws = {(k, value): draw(method, p, scene_name, value)
                         for k, (method, p) in enumerate(zip(tech.methods, prepared)) for value in p.values}
                for (k, value), timing in frame_timings(ctx, draws, runs).items():
                    draws[(k, value)]()  # the target holds another method's frame by now
                    rows.append(row(tech.methods[k], prepared[k], scene_name, value, timing))
        else:
            for method in tech.methods:
                p = prepare(method)
                for scene_name in scene_names:
                    for value in p.values:
                        timing = frame_timings(ctx, {"": draw(method, p, scene_name, value)}, runs)[""]
                        rows.append(row(method, p, scene_name, value, timing))
    finally:
        for target in targets.values():
            target.release()
    if tech.gl_rows is not None:
        rows += tech.gl_rows(ctx, quick, size, runs, progress)
    if tech.extra_rows is not None:
        rows += tech.extra_rows(quick, size, runs, progress)
    return rows
