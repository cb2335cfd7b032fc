"""Snowflake verbs: every edit of the Koch scene and its view goes through these commands."""
from __future__ import annotations

from app.console.console import Console
from app.console.registry import CommandError
from app.model.camera2d import Camera2D
from app.model.snowflake import MAX_LEVEL, SnowflakeScene

DEFAULT_RADIUS = 0.3


def state_commands(scene: SnowflakeScene, camera: Camera2D) -> list[str]:
    """Commands that rebuild the scene and its view exactly (floats as repr)."""
    return ["snow.clear", *(f"snow.add {f.x!r} {f.y!r} {f.radius!r}" for f in scene.flakes),
            f"snow.level {scene.level!r}", f"snow.view {camera.cx!r} {camera.cy!r} {camera.height!r}"]


def register(console: Console, scene: SnowflakeScene, camera: Camera2D) -> None:
    reg = console.registry

    @reg.command("snow.level", "[level:float]", f"Show or set the Koch level (0..{MAX_LEVEL:g}, fractional levels blend)")
    def level(value: float | None = None) -> None:
        if value is None:
            console.print(f"snow.level is {scene.level:g}")
        else:
            scene.level = value

    @reg.command("snow.step", "delta:float", "Change the level by delta, clamped to the valid range (keys w/s)")
    def step(delta: float) -> None:
        target = min(MAX_LEVEL, max(0.0, round(scene.level + delta, 6)))
        if target != scene.level:
            scene.level = target

    @reg.command("snow.add", "x:float y:float [radius:float]", "Add a flake centred at (x, y)")
    def add(x: float, y: float, radius: float = DEFAULT_RADIUS) -> None:
        console.print(f"flake {scene.add(x, y, radius)} at ({x:g}, {y:g})")

    @reg.command("snow.move", "index:int x:float y:float", "Move a flake's centre", quiet=True)
    def move(index: int, x: float, y: float) -> None:
        scene.move(index, x, y)

    @reg.command("snow.remove", "index:int", "Remove a flake")
    def remove(index: int) -> None:
        scene.remove(index)

    @reg.command("snow.clear", "", "Remove every flake")
    def clear() -> None:
        scene.clear()

    @reg.command("snow.list", "", "List the flakes")
    def list_() -> None:
        for i, f in enumerate(scene.flakes):
            console.print(f"{i}: ({f.x:g}, {f.y:g}) radius {f.radius:g}")
        console.print(f"{len(scene.flakes)} flakes, level {scene.level:g}")

    @reg.command("snow.view", "cx:float cy:float height:float", "Centre the 2D view and set the world height it shows",
                 quiet=True)
    def view(cx: float, cy: float, height: float) -> None:
        if height <= 0:
            raise CommandError(f"height must be > 0, got {height:g}")
        camera.cx, camera.cy, camera.height = cx, cy, height
