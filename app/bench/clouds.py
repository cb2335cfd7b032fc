"""Volumetric clouds bench (seed 001, after Nubis): the GPU against the float64 CPU reference, the seed's
Figures 39 and 41 re-made, and every optimisation's error against its time.

One scene (the workspace's defaults: camera 200 m up looking 12 degrees above the horizon, sun at 25 degrees,
weather map 1, still clock), the knob is r_cloudSteps throughout, each part at its own output size:

- `energy`, `seed`: the GPU with no optimisation (full buffer, no jitter, TAA, early exit, big steps, light
  or detail skip) at small sizes against the CPU reference (app/reference/clouds.py, energy integration) at
  its own converged step count; `cpu energy` rows show that reference converging (the issue's measures 1
  and 5: the seed's alpha-per-sample integration never converges);
- `buffer 1` .. `buffer 1/4`: the renderer's default optimisations with the cloud buffer 1/N of the output
  on each axis, at a larger size (Figure 41: frame time against steps), against the no-optimisation image
  at the largest step count;
- `none`, `only <optimisation>`, `+ <optimisation>` (each added to the ones before it, Figure 39's order)
  and `all`: against the no-optimisation GPU image at the same steps and size (measure 4).

Every GPU row is a steady-state frame of a still camera: before timing, frames are drawn until the renderer
no longer settles (TAA and reprojection histories full). Frames are drawn into a float RGBA target (no 8-bit
rounding in the errors). `samples_per_px` is the texture lookups per output pixel of a frame (the
r_cloudDebugSamples count, CloudRenderer.lookups), `mean_abs_error` the mean absolute error over the RGB
channels (0..1). app/bench/clouds_frames.py holds the scene, the settings and the frames drawn;
app/bench/clouds_report.py writes the sample-count images, the tables and the verdicts.
"""
from __future__ import annotations

from dataclasses import dataclass, replace
from functools import lru_cache
from typing import Callable

import numpy as np

from app.bench import clouds_report
from app.bench.clouds_frames import ALL, ALL_BUT, BUFFERS, NONE, OPTIMISATIONS, CloudScene, CloudState, Shared, stages
from app.bench.harness import Method, Row, Technique
from app.model.clouds.scene import CloudRenderSettings

KNOB = "steps"
SCENE = "default"


@dataclass(frozen=True)
class Plan:
    """Sizes, step counts and rounds of one run."""
    reference_size: tuple[int, int] = (96, 54)
    reference_steps: int = 4096             # the CPU reference's own step count (converged)
    gpu_steps: tuple[int, ...] = (64, 128, 256, 512, 1024)
    cpu_steps: tuple[int, ...] = (512, 1024, 2048)
    buffer_size: tuple[int, int] = (640, 360)
    buffer_steps: tuple[int, ...] = (16, 32, 64, 128, 256)
    settings_size: tuple[int, int] = (320, 180)
    settings_steps: tuple[int, ...] = (128, 512)
    stage_steps: int = 512                  # Figure 39 and the all-against-none verdict (big steps miss less)
    converged_steps: int = 1024             # the no-optimisation GPU image that settings rows also meet
    interleaved_rounds: int = 7             # frames of none and all, in turn, for the verdict's speed-up


FULL = Plan()
QUICK = Plan(reference_size=(32, 18), reference_steps=1024, gpu_steps=(64, 256), cpu_steps=(256,),
             buffer_size=(96, 54), buffer_steps=(16, 64), settings_size=(64, 36), settings_steps=(64,),
             stage_steps=64, converged_steps=256, interleaved_rounds=3)


class CloudsBench:
    """The technique's methods and references; `captures` keeps each row's sample-count view for the report."""

    def __init__(self, plan: Plan) -> None:
        self.plan = plan
        self.shared = Shared()
        self.scene = CloudScene(SCENE)
        self.captures: dict[tuple[str, float], dict] = {}
        self._gpu_references: dict[tuple, np.ndarray] = {}

    # ---- references ---------------------------------------------------------------------------------

    def cpu_reference(self, steps: int, size: tuple[int, int], early_exit: bool = False):
        return _cpu_render(self.scene, int(steps), tuple(size), early_exit)

    def converged(self, _scene=None, _value=None, size=None) -> np.ndarray:
        """The CPU reference's image at its own step count."""
        return self.cpu_reference(self.plan.reference_steps, size or self.plan.reference_size).rgb

    def gpu_reference(self, steps: int, size: tuple[int, int]) -> np.ndarray:
        """The no-optimisation GPU image (deterministic: no jitter, no history), on the methods' context."""
        key = (int(steps), tuple(size))
        if key not in self._gpu_references:
            if self.shared.ctx is None:
                raise RuntimeError("the GPU reference draws on the methods' GL context: set a method up first")
            state = CloudState(self.shared.ctx, self.shared)
            state.steady(self.scene, replace(NONE, steps=int(steps)), tuple(size))
            self._gpu_references[key] = state.image(tuple(size))
            for t in state.targets.values():
                t.release()
        return self._gpu_references[key]

    # ---- methods ------------------------------------------------------------------------------------

    def same_steps(self, integration: str) -> Callable[[float, tuple, np.ndarray], dict]:
        """The error against the CPU reference at the same steps and integration: the GPU's and the
        reference's implementations compared, with the step count's own error taken out."""
        def extra(steps: float, size: tuple[int, int], image: np.ndarray) -> dict:
            diff = np.abs(image - _cpu_render(self.scene, int(steps), tuple(size), False, integration).rgb)
            return {"same_steps_mean_error": float(diff.mean()), "same_steps_max_error": float(diff.max())}
        return extra

    def against_converged(self, _steps: float, size: tuple[int, int], image: np.ndarray) -> dict:
        """The mean error against the no-optimisation image at many steps (what the steps should converge to)."""
        fine = self.gpu_reference(self.plan.converged_steps, size)
        return {"converged_mean_error": float(np.abs(image - fine).mean())}

    def method(self, name: str, settings_for: Callable[[float], CloudRenderSettings], values, size,
               reference: Callable[[CloudScene, float, tuple[int, int]], np.ndarray],
               extra: Callable[[float, tuple, np.ndarray], dict] | None = None) -> Method:
        def setup(ctx) -> CloudState:
            return CloudState(ctx, self.shared)

        def render(state: CloudState, target, value, scene) -> None:
            state.steady(scene, settings_for(value), target.size)

        def output(state: CloudState, target, value, scene) -> np.ndarray:
            return state.image(target.size)

        def stats(state: CloudState, target, value, scene) -> dict:
            samples, grey = state.samples(scene, settings_for(value), target.size)
            self.captures[(name, float(value))] = {"samples": samples, "image": grey}
            error = float(np.abs(state.output - reference(scene, value, target.size)).mean())
            more = extra(value, target.size, state.output) if extra is not None else {}
            return {"samples_per_px": samples, "mean_abs_error": error, **more}

        return Method(name, KNOB, tuple(values), setup, render, output, quick_values=tuple(values),
                      reference=reference, stats=stats, size=size, quick_size=size)

    def methods(self) -> list[Method]:
        p = self.plan
        out = [self.method(integration, lambda v, i=integration: replace(NONE, steps=int(v), integration=i),
                           p.gpu_steps, p.reference_size, self.converged, self.same_steps(integration))
               for integration in ("energy", "seed")]
        finest = max(p.buffer_steps)
        # Figure 41 is the seed's: the renderer's defaults with the buffer stretched, not reprojected
        out += [self.method(name, lambda v, d=d: CloudRenderSettings(steps=int(v), downsample=d, reproject=False),
                            p.buffer_steps, p.buffer_size, lambda _sc, _v, size: self.gpu_reference(finest, size))
                for d, name in BUFFERS.items()]
        same_steps = lambda _sc, v, size: self.gpu_reference(int(v), size)  # noqa: E731
        settings = [("none", NONE, p.settings_steps)]
        settings += [("only " + label, replace(NONE, **changes), p.settings_steps) for label, changes in OPTIMISATIONS]
        settings += [(method, s, (p.stage_steps,)) for _label, method, s in stages()[2:-1]]
        settings.append(("all", ALL, p.settings_steps))
        settings += [(name, replace(ALL, **changes), p.settings_steps) for name, changes in ALL_BUT.items()]
        out += [self.method(name, lambda v, s=s: replace(s, steps=int(v)), values, p.settings_size, same_steps,
                            self.against_converged)
                for name, s, values in settings]
        return out

    # ---- the CPU reference's own rows ---------------------------------------------------------------

    def cpu_rows(self, quick: bool, _size, _runs: int, progress: Callable[[str], None]) -> list[Row]:
        """`cpu energy` at coarser steps against itself at its own step count: it converges."""
        import time

        size = self.plan.reference_size
        truth = self.converged(size=size)
        rows = []
        for steps in self.plan.cpu_steps:
            start = time.perf_counter()
            image = _cpu_render.__wrapped__(self.scene, int(steps), size, False)  # timed: never cached
            ms = (time.perf_counter() - start) * 1e3
            diff = np.abs(image.rgb - truth)
            rows.append(Row("clouds", "cpu energy", KNOB, float(steps), SCENE, size[0], size[1], ms, float("nan"), 1,
                            float(np.sqrt(np.mean(diff * diff))), float(diff.max()),
                            {"samples_per_px": float(image.samples.mean()), "mean_abs_error": float(diff.mean())}))
            progress(f"{'cpu energy':>14} {SCENE} {KNOB}={steps}: {ms:8.0f} ms  mean {diff.mean() * 255:.3f}/255  "
                     f"max {diff.max() * 255:.3f}/255 (against itself at {self.plan.reference_steps})")
        return rows


@lru_cache(maxsize=32)
def _cpu_render(scene: CloudScene, steps: int, size: tuple[int, int], early_exit: bool = False,
                integration: str = "energy"):
    from app.reference.clouds import render

    return render(scene.params, scene.view, scene.textures(), size, steps, integration, scene.wind_time, 1.0,
                  early_exit)


def technique(quick: bool = False, plan: Plan | None = None) -> Technique:
    return make_technique(CloudsBench(plan or (QUICK if quick else FULL)))


def make_technique(bench: CloudsBench) -> Technique:
    p = bench.plan
    return Technique(
        name="clouds",
        methods=bench.methods(),
        scenes={SCENE: bench.scene},
        reference=bench.converged,
        size=p.settings_size,
        quick_size=p.settings_size,
        extra_rows=bench.cpu_rows,
        charts=clouds_report.chart_parts,
        extra_outputs=lambda ctx, out, quick_, rows, progress: clouds_report.write(bench, ctx, out, rows, progress),
    )
