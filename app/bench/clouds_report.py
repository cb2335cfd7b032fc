"""The clouds bench's own outputs beside clouds.csv and clouds.png (app/bench/clouds.py makes the rows):

- clouds-samples-<i>-<step>.png: the r_cloudDebugSamples view (texture lookups per pixel, black 0 .. white
  1000) with each optimisation added in turn, Figure 39's order (i = 0 is none);
- clouds-samples.md: Figure 39's table, mean lookups per output pixel at each step;
- clouds-integration.png, clouds-buffers.png, clouds-settings.png: the bench chart of each part's rows
  (chart_parts, Technique.charts: the cli draws them);
- clouds-report.md: the issue's five measures as tables with their verdicts (also printed): the GPU against
  the CPU reference, Figure 41, Figure 39, each optimisation's error against its time with all of them
  against none (timed again, interleaved), and the seed's integration beside the energy one; then reprojection
  through a turn, and the reduced buffer where the view moves and the clock runs (clouds_motion.py).
"""
from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path
from typing import Callable, Iterable

import numpy as np

from app.bench import clouds_motion, harness
from app.bench.clouds_frames import ALL, ALL_BUT, BUFFERS, NONE, OPTIMISATIONS, SAVING, CloudState, stages
from app.bench.harness import Row
from app.io.atomic import write_text
from app.io.png import write_png

SPEEDUP_GOAL = 10.0      # all optimisations against none, at the same steps
MEAN_GOAL = 2 / 255      # ... within this mean error
REFERENCE_MEAN, REFERENCE_MAX = 2 / 255, 8 / 255  # the GPU's energy at fine steps against the CPU reference
FINE_STEPS = 512


def slug(label: str) -> str:
    """A stage's label as part of its sample-count image's file name."""
    return "".join(c if c.isalnum() else "-" for c in label.strip("+ ").lower()).strip("-").replace("--", "-")


def find(rows: Iterable[Row], method: str, steps: float | None = None) -> Row | None:
    return next((r for r in rows if r.method == method and (steps is None or r.knob == steps)), None)


def by_method(rows: Iterable[Row], method: str) -> list[Row]:
    return sorted((r for r in rows if r.method == method), key=lambda r: r.knob)


def e255(x: float) -> str:
    return "n/a" if x is None or not math.isfinite(x) else f"{x * 255:.3f}"


def ms(x: float) -> str:
    return "n/a" if x is None or not math.isfinite(x) else f"{x:.1f}"


def col(row: Row, name: str) -> float:
    value = row.extra.get(name)
    return math.nan if value is None else float(value)


def mean_err(row: Row) -> float:
    return col(row, "mean_abs_error")


def samples(row: Row) -> float:
    return float(row.extra.get("samples_per_px", math.nan))


def table(header: list[str], lines: list[list[str]]) -> list[str]:
    out = ["| " + " | ".join(header) + " |", "|" + "|".join("---" for _ in header) + "|"]
    return out + ["| " + " | ".join(line) + " |" for line in lines]


# ---- the sections ------------------------------------------------------------------------------------------


def reference_section(rows: list[Row], plan) -> tuple[list[str], list[str]]:
    """Measure 1: the GPU's energy integration (no optimisation) against the CPU reference."""
    w, h = plan.reference_size
    text = [f"## 1. GPU `energy` against the CPU reference ({w}x{h})", "",
            f"The CPU reference (float64, app/reference/clouds.py) at its own {plan.reference_steps} steps; the GPU "
            "with every optimisation off. Errors in 1/255 over the RGB channels.", ""]
    lines = [[f"{r.knob:g}", ms(r.ms_median), e255(mean_err(r)), e255(r.max_abs_error), e255(r.rmse),
              e255(col(r, "same_steps_mean_error")), e255(col(r, "same_steps_max_error"))]
             for r in by_method(rows, "energy")]
    text += table(["GPU steps", "ms", "mean", "max", "RMSE", "mean, CPU at the same steps",
                   "max, CPU at the same steps"], lines)
    cpu = by_method(rows, "cpu energy")
    if cpu:
        text += ["", f"The reference converging: `cpu energy` at fewer steps against itself at {plan.reference_steps}.",
                 ""]
        text += table(["CPU steps", "ms", "mean", "max", "samples/px"],
                      [[f"{r.knob:g}", ms(r.ms_median), e255(mean_err(r)), e255(r.max_abs_error), f"{samples(r):.0f}"]
                       for r in cpu])
    energy = by_method(rows, "energy")
    fine = [r for r in energy if r.knob >= FINE_STEPS] or energy[-1:]
    verdicts = []
    for r in fine:
        ok = mean_err(r) <= REFERENCE_MEAN and r.max_abs_error <= REFERENCE_MAX
        own = find(cpu, "cpu energy", r.knob)
        why = "" if own is None else (f" (the CPU reference itself at {r.knob:g} steps: mean {e255(mean_err(own))}, "
                                      f"max {e255(own.max_abs_error)}/255)")
        verdicts.append(f"{'PASS' if ok else 'FAIL'}: GPU energy at {r.knob:g} steps against the CPU reference: "
                        f"mean {e255(mean_err(r))}/255 (goal 2), max {e255(r.max_abs_error)}/255 (goal 8){why}; "
                        f"against the CPU at the same steps: max {e255(col(r, 'same_steps_max_error'))}/255")
    return text, verdicts


def buffer_section(rows: list[Row], plan) -> list[str]:
    """Figure 41: frame time against steps per cloud buffer size."""
    w, h = plan.buffer_size
    names = list(BUFFERS.values())
    text = [f"## 2. Figure 41: frame time against steps, per cloud buffer ({w}x{h} output)", "",
            "The renderer's default optimisations (jitter, TAA, early exit, big steps, light and detail skip; no "
            "reprojection), steady state. Wall ms per frame (GPU-query ms in brackets).", ""]

    def grid(cell) -> list[str]:  # a row per step count, a column per buffer
        return table(["steps", *names], [[f"{steps}", *("n/a" if (r := find(rows, name, steps)) is None else cell(r)
                                                          for name in names)] for steps in plan.buffer_steps])
    text += grid(lambda r: f"{ms(r.ms_median)} ({ms(r.gpu_ms_median)})")
    text += ["", f"Mean error (1/255) against the no-optimisation image at {max(plan.buffer_steps)} steps, full "
             "buffer; lookups per output pixel in brackets.", ""]
    return text + grid(lambda r: f"{e255(mean_err(r))} ({samples(r):.0f})")


def stage_rows(rows: list[Row], plan) -> list[tuple[int, str, str, Row | None]]:
    return [(i, label, method, find(rows, method, plan.stage_steps)) for i, (label, method, _s) in enumerate(stages())]


def samples_table(rows: list[Row], plan) -> list[str]:
    """Figure 39's table: each optimisation added in turn, mean lookups per output pixel."""
    none = find(rows, "none", plan.stage_steps)
    lines = []
    for i, label, method, r in stage_rows(rows, plan):
        if r is None:
            lines.append([str(i), label, f"`{method}`", "n/a", "n/a", "n/a", "n/a", ""])
            continue
        speed = none.ms_median / r.ms_median if none is not None and r.ms_median > 0 else math.nan
        lines.append([str(i), label, f"`{method}`", f"{samples(r):.1f}", ms(r.ms_median), f"{speed:.1f}x",
                      e255(mean_err(r)), f"clouds-samples-{i}-{slug(label)}.png"])
    return table(["#", "step", "CSV method", "samples/px", "ms", "speed-up", "mean err /255", "image"], lines)


def stage_section(rows: list[Row], plan) -> tuple[list[str], list[str]]:
    w, h = plan.settings_size
    text = [f"## 3. Figure 39: texture lookups with each optimisation added in turn ({w}x{h}, "
            f"{plan.stage_steps} steps)", "",
            "samples/px: texture lookups per output pixel of one steady-state frame (r_cloudDebugSamples counts: "
            "weather, shape, curl, detail, the cirrus's two; a reduced buffer's lookups are shared by the pixels it "
            "covers). The images show the debug view, black 0 .. white 1000 lookups per pixel.", ""]
    text += samples_table(rows, plan)
    verdicts = []
    staged = stage_rows(rows, plan)
    for (_i, _label, _m, before), (_j, label, _method, after) in zip(staged, staged[1:]):
        name = label[2:]
        if name in SAVING and before is not None and after is not None:
            ok = samples(after) <= samples(before) * (1 + 1e-6)
            if not ok:
                verdicts.append(f"FAIL: {label} raised the lookups per pixel: {samples(before):.1f} -> "
                                f"{samples(after):.1f}")
    return text, verdicts


def settings_section(rows: list[Row], plan, interleaved: dict | None) -> tuple[list[str], list[str]]:
    """Measure 4: each optimisation alone and all together against none, at the same steps."""
    w, h = plan.settings_size
    text = [f"## 4. Each optimisation alone and all together ({w}x{h})", "",
            "Error against the no-optimisation GPU image at the same steps, still camera, after the temporal "
            "histories filled; steady-state frame times (wall ms, median), speed-up against `none`. `converged`: "
            f"the mean error against the no-optimisation image at {plan.converged_steps} steps instead (what the "
            "steps converge to: jitter and TAA move towards it). All errors in 1/255.", ""]
    names = ["none", *["only " + label for label, _c in OPTIMISATIONS], "all", *ALL_BUT]
    for steps in plan.settings_steps:
        none = find(rows, "none", steps)
        lines = []
        for name in names:
            r = find(rows, name, steps)
            if r is None:
                continue
            speed = none.ms_median / r.ms_median if none is not None and r.ms_median > 0 else math.nan
            lines.append([f"`{name}`", ms(r.ms_median), ms(r.gpu_ms_median), f"{speed:.1f}x", e255(mean_err(r)),
                          e255(r.max_abs_error), e255(col(r, "converged_mean_error")), f"{samples(r):.1f}"])
        text += [f"{steps} steps:", ""]
        text += table(["method", "ms", "GPU ms", "speed-up", "mean", "max", "converged", "samples/px"], lines)
        text.append("")
    verdicts = []
    none, every = find(rows, "none", plan.stage_steps), find(rows, "all", plan.stage_steps)
    if none is not None and every is not None:
        speed = none.ms_median / every.ms_median
        ok = speed >= SPEEDUP_GOAL and mean_err(every) <= MEAN_GOAL
        verdicts.append(f"{'PASS' if ok else 'FAIL'}: all optimisations against none at {plan.stage_steps} steps: "
                        f"{speed:.1f}x faster ({ms(none.ms_median)} -> {ms(every.ms_median)} ms, goal >= "
                        f"{SPEEDUP_GOAL:g}x) at mean error {e255(mean_err(every))}/255 (goal <= 2), max "
                        f"{e255(every.max_abs_error)}/255")
    for name in ALL_BUT:
        r = find(rows, name, plan.stage_steps)
        if none is not None and r is not None:
            speed = none.ms_median / r.ms_median
            verdicts.append(f"(for comparison) {name}: {speed:.1f}x faster at mean error {e255(mean_err(r))}/255")
    if interleaved:
        speed = interleaved["none"][0] / interleaved["all"][0]
        gpu = interleaved["none"][1] / interleaved["all"][1] if interleaved["all"][1] > 0 else math.nan
        ok = speed >= SPEEDUP_GOAL and interleaved["mean"] <= MEAN_GOAL
        text += [f"Timed again interleaved ({interleaved['rounds']} rounds of one `none` and one `all` frame, "
                 f"{plan.stage_steps} steps): none {ms(interleaved['none'][0])} ms, all {ms(interleaved['all'][0])} "
                 f"ms (GPU queries: {ms(interleaved['none'][1])} and {ms(interleaved['all'][1])} ms)."]
        verdicts.append(f"{'PASS' if ok else 'FAIL'}: interleaved, all against none: {speed:.1f}x faster "
                        f"(GPU queries {gpu:.1f}x) at mean error {e255(interleaved['mean'])}/255, max "
                        f"{e255(interleaved['max'])}/255")
    return text, verdicts


TURN_DEGREES = (0.5, 2.0, 6.0)  # a frame's turn of the camera
TURN_FRAMES = 4


def turns(bench, ctx) -> list[tuple[int, float, float, float]]:
    """Reprojection through a turn: (d, degrees a frame, mean error of the reprojected picture, of the bilinear
    buffer alone) against a full trace of the view turned to, after TURN_FRAMES frames of turning."""
    plan, scene = bench.plan, bench.scene
    size, steps = plan.settings_size, plan.settings_steps[0]
    start, out = scene.view, []
    for down in (2, 4):
        settings = replace(NONE, steps=steps, downsample=down, reproject=True)
        for degrees in TURN_DEGREES:
            scene.view = start
            state, fresh = CloudState(ctx, bench.shared), CloudState(ctx, bench.shared)
            state.steady(scene, settings, size)
            for _ in range(TURN_FRAMES):
                scene.view = replace(scene.view, yaw=scene.view.yaw + degrees)
                state.draw(scene, settings, size)
            shown = state.image(size)
            fresh.draw(scene, settings, size)  # no history: the bilinear buffer
            bilinear = fresh.image(size)
            fresh.draw(scene, replace(settings, downsample=1), size)
            truth = fresh.image(size)
            out.append((down, degrees, float(np.abs(shown - truth).mean()), float(np.abs(bilinear - truth).mean())))
            for s in (state, fresh):
                for t in s.targets.values():
                    t.release()
    scene.view = start
    return out


def turn_section(measured, plan) -> list[str]:
    """Measure 6: reprojection keeps its history through a turn; is it better than the buffer alone?"""
    w, h = plan.settings_size
    text = ["## 6. Reprojection through a turn", "",
            f"{w}x{h}, {plan.settings_steps[0]} steps, no other optimisation: after a still view's history is full, "
            f"{TURN_FRAMES} frames turning the camera; the mean error (1/255) of the picture shown against a full "
            "trace of the view turned to, beside that of this frame's buffer stretched bilinear (what a restarted "
            "history shows).", ""]
    lines = [[f"{d}", f"{deg:g}", e255(shown), e255(bilinear)] for d, deg, shown, bilinear in measured]
    return text + table(["d", "degrees a frame", "reprojected", "bilinear buffer"], lines)


def integration_section(rows: list[Row], plan) -> list[str]:
    """Measure 5: the seed's alpha-per-sample integration beside the energy one, against the reference."""
    text = ["## 5. The `seed` integration beside `energy`", "",
            f"Both on the GPU with no optimisation ({plan.reference_size[0]}x{plan.reference_size[1]}), against "
            f"the CPU reference's energy image at {plan.reference_steps} steps; errors in 1/255. The seed's "
            "density is an alpha per sample, with no step length: more steps only make it more opaque.", ""]
    lines = []
    for steps in plan.gpu_steps:
        e, s = find(rows, "energy", steps), find(rows, "seed", steps)
        lines.append([f"{steps}", *(["n/a"] * 2 if e is None else [e255(mean_err(e)), e255(e.max_abs_error)]),
                      *(["n/a"] * 3 if s is None else [e255(mean_err(s)), e255(s.max_abs_error),
                                                        e255(col(s, "same_steps_max_error"))])])
    return text + table(["steps", "energy mean", "energy max", "seed mean", "seed max",
                         "seed max, CPU seed at the same steps"], lines)


def report(rows: list[Row], plan, interleaved: dict | None = None, renderer: str = "",
           turned: list | None = None, motion: dict | None = None) -> tuple[str, list[str]]:
    """The markdown report and its verdict lines."""
    s1, v1 = reference_section(rows, plan)
    s3, v3 = stage_section(rows, plan)
    s4, v4 = settings_section(rows, plan, interleaved)
    verdicts = v1 + v4 + v3
    head = ["# Clouds bench", "", f"Measured on {renderer or 'an unnamed GL renderer'}.", "",
            *[f"- {v}" for v in verdicts], ""]
    body = [*s1, "", *buffer_section(rows, plan), "", *s3, "", *s4, "", *integration_section(rows, plan), "",
            *(turn_section(turned, plan) + [""] if turned else []),
            *(clouds_motion.section(motion, plan) + [""] if motion else [])]
    return "\n".join(head + body), verdicts


# ---- the files ----------------------------------------------------------------------------------------------


def interleave(bench, ctx, rounds: int) -> dict:
    """All optimisations and none, one frame of each in turn, steady state, with the error between them."""
    plan, scene = bench.plan, bench.scene
    size, steps = plan.settings_size, plan.stage_steps
    states = {"none": CloudState(ctx, bench.shared), "all": CloudState(ctx, bench.shared)}
    settings = {"none": replace(NONE, steps=steps), "all": replace(ALL, steps=steps)}
    draws = {name: (lambda s=state, name=name: s.steady(scene, settings[name], size)) for name, state in states.items()}
    timed = harness.time_interleaved(ctx, draws, rounds)
    diff = np.abs(states["all"].image(size) - states["none"].image(size))
    for state in states.values():
        for t in state.targets.values():
            t.release()
    return {**timed, "rounds": rounds, "mean": float(diff.mean()), "max": float(diff.max())}


def write_samples_images(bench, out: Path) -> list[Path]:
    paths = []
    for i, (label, method, _s) in enumerate(stages()):
        capture = bench.captures.get((method, float(bench.plan.stage_steps)))
        if capture is None:
            continue
        grey = capture["image"]
        rgba = np.dstack([grey, grey, grey, np.full_like(grey, 255)])
        path = out / f"clouds-samples-{i}-{slug(label)}.png"
        write_png(path, rgba)
        paths.append(path)
    return paths


# Each part's rows in a chart of its own (the harness's chart of all of them has two dozen curves).
PARTS = {"clouds-integration.png": ("energy", "seed", "cpu energy"),
         "clouds-buffers.png": tuple(BUFFERS.values()),
         "clouds-settings.png": ("none", *("only " + label for label, _c in OPTIMISATIONS), "all", *ALL_BUT)}


def chart_parts(rows: list[dict]) -> dict[str, list[dict]]:
    """Technique.charts: each part's rows (read_csv's), for a chart of its own beside clouds.png."""
    parts = {name: [r for r in rows if r["method"] in methods] for name, methods in PARTS.items()}
    return {name: part for name, part in parts.items() if part}


def write(bench, ctx, out: Path, rows: list[Row], progress: Callable[[str], None]) -> None:
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    plan = bench.plan
    images = write_samples_images(bench, out)
    w, h = plan.settings_size
    write_text(out / "clouds-samples.md", "\n".join([
        f"# Clouds: texture lookups per pixel, each optimisation added in turn ({w}x{h}, {plan.stage_steps} steps)",
        "", *samples_table(rows, plan), ""]))
    progress(f"timing none and all interleaved ({plan.interleaved_rounds} rounds)")
    interleaved = interleave(bench, ctx, plan.interleaved_rounds) if plan.interleaved_rounds > 0 else None
    progress("reprojection through a turn")
    turned = turns(bench, ctx)
    progress("the reduced buffer where the view moves and the clock runs")
    motion = clouds_motion.Motion(bench, ctx).measure()
    text, _verdicts = report(rows, plan, interleaved, ctx.info.get("GL_RENDERER", ""), turned, motion)
    write_text(out / "clouds-report.md", text)
    progress(text)
    progress(f"wrote {len(images)} sample-count images, clouds-samples.md and clouds-report.md in {out}")
