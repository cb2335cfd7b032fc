"""Snowflake bench: frame time against level and flake count; geometry error against the CPU polyline.

Methods: `gs` builds the outline in the geometry shader (chunked, the product's path); `cpu` builds it
in numpy every frame and uploads it, what one would do without a geometry shader.
"""
from __future__ import annotations

import math

import numpy as np

from app.bench.harness import Method, Technique
from app.gl.core.lines2d import Lines2D
from app.gl.core.shaders import ShaderLibrary
from app.gl.snowflake.renderer import BACKGROUND, LINE_COLOR, SnowflakeRenderer
from app.model.camera2d import Camera2D
from app.model.snowflake import Flake, SnowflakeScene
from app.reference.snowflake import segments
from app.resources import SHADERS

LEVELS = (0, 1, 2, 3, 4, 5, 5.5, 6, 7)
QUICK_LEVELS = (0, 1, 2, 3, 4, 5, 6)


def grid_scene(count: int) -> tuple[SnowflakeScene, Camera2D]:
    """`count` flakes on a square grid that fills the view."""
    side = math.ceil(math.sqrt(count))
    flakes = (Flake(i % side - (side - 1) / 2, i // side - (side - 1) / 2, 0.45) for i in range(count))
    return SnowflakeScene(flakes, 0.0), Camera2D(0.0, 0.0, side + 0.2)


def _gs_render(renderer: SnowflakeRenderer, target, level, sc) -> None:
    scene, camera = sc
    renderer.render(target.fbo, scene.with_level(level), camera)  # the flakes stay uploaded: the tuple is shared


def _gs_output(renderer: SnowflakeRenderer, target, level, sc) -> np.ndarray:
    scene, camera = sc
    return renderer.capture(scene.with_level(level), camera) / camera.height


def _cpu_render(lines: Lines2D, target, level, sc) -> None:
    scene, camera = sc
    target.fbo.use()
    target.fbo.clear(*BACKGROUND)
    lines.upload(segments(scene.flakes, level))
    lines.draw(target.fbo, camera, LINE_COLOR)


def _cpu_output(lines: Lines2D, target, level, sc) -> np.ndarray:
    _cpu_render(lines, target, level, sc)
    return lines.uploaded() / sc[1].height


def _reference(sc, level, _size) -> np.ndarray:
    scene, camera = sc
    return segments(scene.flakes, level) / camera.height


def technique(quick: bool = False) -> Technique:  # the harness picks the quick subsets
    return Technique(
        name="snowflake",
        methods=[
            Method("gs", "level", LEVELS, lambda ctx: SnowflakeRenderer(ctx, ShaderLibrary(ctx, [SHADERS])),
                   _gs_render, _gs_output, QUICK_LEVELS),
            Method("cpu", "level", LEVELS, lambda ctx: Lines2D(ctx, ShaderLibrary(ctx, [SHADERS])),
                   _cpu_render, _cpu_output, QUICK_LEVELS),
        ],
        scenes={"1 flake": grid_scene(1), "16 flakes": grid_scene(16), "64 flakes": grid_scene(64)},
        reference=_reference,
        quick_scenes=("1 flake", "16 flakes"),
    )
