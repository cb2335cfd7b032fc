"""pygame-light2d (PyPI pygame-light2d 2.1.3) drawing a 2D lighting scene, for the lighting bench (an optional extra).

Headless: SDL's "offscreen" video driver gives `pygame.display.set_mode(..., OPENGL)` an EGL pbuffer context
(Mesa llvmpipe here), which pygame_render's `moderngl.create_context()` picks up as the current context.
`render` runs the engine in a child process (`python -m app.bench.pygame_light2d_peer`), as the vispy peer
does: SDL shares the process's EGL display with ours and eglTerminate()s it in pygame.quit(), which would
destroy the caller's contexts, and in a process that already has a moderngl context create_context()
would look for a GLX one instead.

What the engine draws, per pixel (measured; it is not linear in the lights): ambient + lightmap, clamped to
1 on the 8-bit screen. One light of colour c, power P and spline falloff I adds c * (P * I)**3 to the
lightmap: the light pass adds rgb * alpha with alpha = P * I, and the blend onto the blurred lightmap
multiplies by the summed alpha once more (so several lights do not add up either). The whole lightmap,
shadows included, is blurred by a 7x7 Gaussian (shadow_blur_radius 3, in lightmap pixels).
"""
from __future__ import annotations

import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

MAX_HULL_VERTICES = 1024  # fragment_light.glsl: `float hullV[2048]`, x and y of every hull vertex
MAX_HULLS = 256           # fragment_light.glsl: `int hullInd[256]`, one end index per hull
_ENV = {"SDL_VIDEODRIVER": "offscreen", "SDL_AUDIODRIVER": "dummy",  # dummy audio: pygame.init() stays off ALSA
        "PYGAME_HIDE_SUPPORT_PROMPT": "1"}


def available() -> str | None:
    """None when pygame-light2d can run here, else a one-line reason (import error etc.)."""
    os.environ.setdefault("PYGAME_HIDE_SUPPORT_PROMPT", "1")
    try:
        import ctypes

        import pygame_light2d  # noqa: F401  (imports pygame, pygame_render, moderngl and PyOpenGL)
        ctypes.CDLL("libEGL.so.1")  # SDL's offscreen driver makes its GL context through EGL
    except Exception as exc:  # ImportError, OSError, or PyOpenGL failing to load libGL
        return f"pygame-light2d unavailable: {type(exc).__name__}: {exc}".splitlines()[0]
    return None


@dataclass
class PeerResult:
    image: np.ndarray    # float32 (H, W, 3), 0..1, row 0 = top: light reaching a white background, ambient included
    ms_per_frame: float  # median of engine.render() + ctx.finish(), after 2 warm-up frames


def render(size: tuple[int, int], ambient: tuple[float, float, float], lights: list[dict],
           hulls: list[np.ndarray], frames: int = 5) -> PeerResult:
    """Screen pixels, x right, y down, origin top-left (pygame's convention, which the engine takes as is)."""
    hulls = [np.asarray(h, dtype=np.float64).reshape(-1, 2) for h in hulls]
    vertices = sum(len(h) for h in hulls)
    # The shader has fixed arrays; past them it reads out of bounds and draws garbage, so refuse instead.
    if len(hulls) > MAX_HULLS or vertices > MAX_HULL_VERTICES:
        raise ValueError(f"pygame-light2d takes at most {MAX_HULLS} hulls and {MAX_HULL_VERTICES} hull vertices "
                         f"in all; this scene has {len(hulls)} hulls and {vertices} vertices")
    job = {"size": [int(v) for v in size], "ambient": [float(c) for c in ambient], "frames": int(frames),
           "hulls": [h.tolist() for h in hulls],
           "lights": [{"position": [float(v) for v in spec["position"]], "radius": float(spec["radius"]),
                       "color": [float(c) for c in spec["color"]], "power": float(spec["power"]),
                       "casts_shadows": bool(spec["casts_shadows"])} for spec in lights]}
    with tempfile.TemporaryDirectory(prefix="pl2d-") as tmp:
        out = Path(tmp) / "out.npz"
        done = subprocess.run([sys.executable, "-m", __name__, str(out)], input=json.dumps(job), text=True,
                              capture_output=True, timeout=600, env={**os.environ, **_ENV},
                              cwd=Path(__file__).resolve().parents[2])  # where `app` imports from
        if done.returncode != 0:
            raise RuntimeError(f"pygame-light2d peer failed: {done.stderr.strip()[-2000:]}")
        with np.load(out) as result:
            return PeerResult(image=result["image"], ms_per_frame=float(result["ms"]))


def _render_here(job: dict) -> tuple[np.ndarray, float]:
    """In the child process: one engine, the job's scene, timed frames and the last one read back."""
    import pygame
    from pygame_light2d import Hull, LightingEngine, PointLight

    size = tuple(job["size"])
    pygame.init()  # LightingEngine asserts it; set_mode happens inside the engine
    engine = LightingEngine(screen_res=size, native_res=size, lightmap_res=size)
    engine.set_ambient(*(255.0 * c for c in job["ambient"]), 255)  # alpha 1 keeps the final blend from dimming
    for spec in job["lights"]:
        light = PointLight(position=tuple(spec["position"]), power=spec["power"], radius=spec["radius"])
        light.set_color(*(255.0 * c for c in spec["color"]), 255)  # takes 0..255 and divides by 255
        light.cast_shadows = spec["casts_shadows"]
        engine.lights.append(light)
    engine.hulls.extend(Hull([tuple(v) for v in h]) for h in job["hulls"])
    engine.clear(255, 255, 255)  # the white background layer; render() only reads it
    ctx, times = engine.ctx, []
    for i in range(2 + job["frames"]):  # 2 warm-up frames (first uploads, driver shader variants)
        start = time.perf_counter()
        engine.render()
        ctx.finish()
        if i >= 2:
            times.append((time.perf_counter() - start) * 1e3)
    data = np.frombuffer(ctx.screen.read(components=3), np.uint8).reshape(size[1], size[0], 3)
    image = (data[::-1] / np.float32(255)).astype(np.float32)  # GL rows start at the bottom
    return image, statistics.median(times)


if __name__ == "__main__":
    image, ms = _render_here(json.load(sys.stdin))
    np.savez(sys.argv[1], image=image, ms=ms)
