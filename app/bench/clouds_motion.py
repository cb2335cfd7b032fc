"""The clouds bench's measure 7 (clouds_report.py writes it): the reduced cloud buffer where the view moves and the
clock runs, against full-size traces of the same frame (docs/clouds.md, "Upsampling and reprojection").

- ground pixels more than 10/255 off (the clouds never belong on the ground seen from below the layer): the
  buffer stretched (still, d = 2 and 4), reprojected through a 6 degree a frame turn (d = 4, frame 12), and at
  each level of the host's frame budget through a drag (1 degree a frame);
- a sustained slow turn (0.5 degrees a frame, d = 4): the mean error at frames 4, 16 and 40;
- the clock running (the winds 5x, 5 frames a second): the mean error against the truth at the clock's time and at
  one second of wind before (a ghost is as near the one as the other);
- a still view's frames until it settles (TAA converged: a frame changes the clouds by less than 0.1/255).

Every picture is drawn with the bench's scene at its settings size and first step count, no optimisation but the
buffer, reprojection and (for the drag and the settling) the renderer's defaults."""
from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from app.bench.clouds_frames import NONE, CloudState
from app.model.clouds.scene import FOV_Y_DEG, PLANET_RADIUS, CloudRenderSettings, camera_basis

OFF = 10 / 255
FAST_TURN, FAST_FRAMES = 6.0, 12
SLOW_TURN, SLOW_FRAMES, SLOW_AT = 0.5, 40, (4, 16, 40)
DRAG_TURN, DRAG_FRAMES = 1.0, 8
WIND_SCALE, WIND_DT, WIND_FRAMES = 5.0, 0.2, 20


def ground(view, size: tuple[int, int]) -> np.ndarray:
    """Which pixels (rows from the top) look at the ground: the planet's sphere ahead of the camera."""
    f, r, u = (np.array(v) for v in camera_basis(view))
    t, aspect = math.tan(math.radians(FOV_Y_DEG) / 2), size[0] / size[1]
    y, x = np.mgrid[0:size[1], 0:size[0]]
    d = f + ((x + 0.5) / size[0] * 2 - 1)[..., None] * t * aspect * r + ((y + 0.5) / size[1] * 2 - 1)[..., None] * t * u
    d /= np.linalg.norm(d, axis=-1, keepdims=True)
    o = np.array([0.0, view.altitude + PLANET_RADIUS, 0.0])
    b, c = d @ o, o @ o - PLANET_RADIUS ** 2
    disc = b * b - c
    return ((disc >= 0) & (-b - np.sqrt(np.maximum(disc, 0)) > 0))[::-1]


def smear(image: np.ndarray, truth: np.ndarray, view) -> tuple[float, float]:
    """(share of ground pixels more than OFF off in some channel, the largest error there), 0..1."""
    mask = ground(view, image.shape[1::-1])
    if not mask.any():
        return math.nan, math.nan
    off = np.abs(image - truth).max(axis=2)[mask]
    return float((off > OFF).mean()), float(off.max())


class Motion:
    """The measures on one bench's scene and GL context (the scene's view and clock are put back after each)."""

    def __init__(self, bench, ctx) -> None:
        self.bench, self.ctx = bench, ctx
        self.scene = bench.scene
        self.clock = bench.scene.wind_time
        self.size = bench.plan.settings_size
        self.steps = bench.plan.settings_steps[0]
        self._states: list[CloudState] = []

    def state(self) -> CloudState:
        state = CloudState(self.ctx, self.bench.shared)
        self._states.append(state)
        return state

    def truth(self) -> np.ndarray:
        state = self.state()
        state.draw(self.scene, replace(NONE, steps=self.steps), self.size)
        return state.image(self.size)

    def shown(self, state: CloudState, size: tuple[int, int]) -> np.ndarray:
        """The state's last picture at the bench's size: stretched back (bilinear, as the host's reduced levels
        are) when drawn smaller."""
        image = state.image(size)
        if size == self.size:
            return image
        y = np.clip((np.arange(self.size[1]) + 0.5) * size[1] / self.size[1] - 0.5, 0, size[1] - 1)
        x = np.clip((np.arange(self.size[0]) + 0.5) * size[0] / self.size[0] - 0.5, 0, size[0] - 1)
        y0, x0 = np.floor(y).astype(int), np.floor(x).astype(int)
        y1, x1 = np.minimum(y0 + 1, size[1] - 1), np.minimum(x0 + 1, size[0] - 1)
        fy, fx = (y - y0)[:, None, None], (x - x0)[None, :, None]
        top = image[y0][:, x0] * (1 - fx) + image[y0][:, x1] * fx
        bottom = image[y1][:, x0] * (1 - fx) + image[y1][:, x1] * fx
        return top * (1 - fy) + bottom * fy

    def release(self) -> None:
        for state in self._states:
            for target in state.targets.values():
                target.release()
        self._states.clear()

    def turn(self, settings, degrees: float, frames: int, at=(), size=None) -> tuple[np.ndarray, dict[int, float]]:
        """A steady view turned `degrees` a frame for `frames` frames (drawn at `size`): the last picture at the
        bench's size, and the mean error at the frames `at`."""
        size = size or self.size
        state = self.state()
        state.steady(self.scene, settings, size)
        errors = {}
        for frame in range(1, frames + 1):
            self.scene.view = replace(self.scene.view, yaw=self.scene.view.yaw + degrees)
            state.draw(self.scene, settings, size)
            if frame in at:
                errors[frame] = float(np.abs(self.shown(state, size) - self.truth()).mean())
        return self.shown(state, size), errors

    def measure(self) -> dict:
        start, params = self.scene.view, self.scene.params
        base = replace(NONE, steps=self.steps)
        out = {}
        try:
            truth = self.truth()
            for d in (2, 4):
                state = self.state()
                state.draw(self.scene, replace(base, downsample=d), self.size)
                out[f"stretched, d = {d}"] = smear(state.image(self.size), truth, self.scene.view)
            image, _ = self.turn(replace(base, downsample=4, reproject=True), FAST_TURN, FAST_FRAMES)
            out[f"turning {FAST_TURN:g} degrees a frame, d = 4, frame {FAST_FRAMES}"] = smear(
                image, self.truth(), self.scene.view)
            for level, settings in self.drag_levels():
                self.scene.view = start
                size = (max(1, math.ceil(self.size[0] * level.scale)), max(1, math.ceil(self.size[1] * level.scale)))
                image, _ = self.turn(settings, DRAG_TURN, DRAG_FRAMES, size=size)
                picture = (f" of a 1/{settings.reproject_downsample} size picture"
                           if settings.reproject_downsample > 1 else "")
                out[f"drag, level {level.scale:g} x size, cheap {level.cheap} (d = {settings.downsample}{picture}, "
                    f"{settings.steps} steps)"] = smear(image, self.truth(), self.scene.view)
            self.scene.view = start
            _state, slow = self.turn(replace(base, downsample=4, reproject=True), SLOW_TURN, SLOW_FRAMES, SLOW_AT)
            self.scene.view = start
            wind = self.wind(replace(base, downsample=4, reproject=True)), self.wind(
                replace(base, downsample=2, reproject=True))
            settled = self.settle(CloudRenderSettings(steps=self.steps))
        finally:
            self.scene.view, self.scene.wind_time, self.scene.params = start, self.clock, params
            self.release()
        return {"smear": out, "slow": slow, "wind": wind, "settled": settled}

    def drag_levels(self):
        """The clouds' levels of the host's frame budget and the settings each draws a drag with."""
        from app.gl.clouds.workspace import CloudsWorkspaceRenderer

        renderer = CloudsWorkspaceRenderer(self.ctx, self.bench.shared.shaders(self.ctx))
        try:
            base = CloudRenderSettings(steps=self.steps)
            return [(level, replace(renderer.cheaper(base, level.cheap), taa=False))
                    for level in CloudsWorkspaceRenderer.LEVELS[1:]]
        finally:
            renderer.release()

    def wind(self, settings) -> tuple[int, float, float]:
        """(d, mean error against the truth at the clock's time, against the truth a second of wind before)."""
        self.scene.params = self.scene.params.with_value("time_scale", WIND_SCALE)
        self.scene.wind_time = self.clock
        state = self.state()
        state.steady(self.scene, settings, self.size)
        for _ in range(WIND_FRAMES):
            self.scene.wind_time += WIND_DT * WIND_SCALE
            state.draw(self.scene, settings, self.size)
        image = state.image(self.size)
        now = float(np.abs(image - self.truth()).mean())
        self.scene.wind_time -= WIND_SCALE
        before = float(np.abs(image - self.truth()).mean())
        return settings.downsample, now, before

    def settle(self, settings) -> int:
        """Frames a still view draws until the renderer settles (at most its own cap)."""
        state = self.state()
        frames = 0
        while True:
            state.draw(self.scene, settings, self.size)
            frames += 1
            if not state.renderer.settling(settings):
                return frames


def section(measured: dict, plan) -> list[str]:
    w, h = plan.settings_size
    text = ["## 7. Upsampling and reprojection", "",
            f"{w}x{h}, {plan.settings_steps[0]} steps, against a full-size trace of the same frame (docs/clouds.md, "
            "\"Upsampling and reprojection\"). Ground pixels more than 10/255 off in some channel, and the largest "
            "error there (1/255):", ""]
    text += ["| case | ground pixels off | max |", "|---|---|---|"]
    text += [f"| {case} | {share * 100:.2f} % | {worst * 255:.0f} |"
             for case, (share, worst) in measured["smear"].items()]
    slow = measured["slow"]
    text += ["", f"A sustained turn of {SLOW_TURN:g} degrees a frame (d = 4), mean error (1/255) at frames "
             + ", ".join(f"{k}: {v * 255:.2f}" for k, v in slow.items())
             + f" ({slow[max(slow)] / slow[min(slow)]:.2f}x the first)."]
    text += ["", f"The clock running (winds {WIND_SCALE:g}x, {1 / WIND_DT:g} frames a second, {WIND_FRAMES} frames), "
             "mean error (1/255) against the truth at the clock's time and a second of wind before: "
             + "; ".join(f"d = {d}: {now * 255:.2f} against {before * 255:.2f}" for d, now, before in measured["wind"])
             + "."]
    text += ["", f"A still view with the renderer's defaults settles (TAA converged) after {measured['settled']} "
             "frames."]
    return text
