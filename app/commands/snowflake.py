"""Snowflake verbs: every edit of the Koch scene and its view goes through these commands, and every
edit of the scene is one undo step (the moves of one drag together)."""
from __future__ import annotations

from app.console.console import Console
from app.console.demo import ArgChecks
from app.console.registry import SCRIPTS, CommandError
from app.console.text import count, number
from app.io import snowflake_scene
from app.io.json_file import storable
from app.io.snowflake_scene import MAX_FLAKES
from app.model.snowflake import MAX_LEVEL, Flake, SceneError, check_level
from app.model.snowflake_workspace import SnowflakeWorkspace
from app.model.workspace import SceneFiles

DEFAULT_RADIUS = 0.3


def register(console: Console, state: SnowflakeWorkspace, checks: ArgChecks) -> None:
    """The commands, and their checks for demos (`checks`)."""
    reg = console.registry.scoped(state.name)
    scene, camera, history = state.scene, state.camera, state.history
    checks.reshaped_by("snowflake", "snow.add", "snow.remove", "snow.clear", "scene.load", "undo", "redo")

    def load(path: str) -> str:
        try:
            flakes, level = snowflake_scene.load(path)
        except SceneError as exc:
            raise CommandError(str(exc)) from None
        history.checkpoint("Load Scene")
        scene.replace(flakes, level)
        console.print(f"loaded {count(len(flakes), 'flake')} from {path}")
        return path

    state.files = SceneFiles(load, lambda path: snowflake_scene.save(path, scene), (".json",),
                             snowflake_scene.FORMAT, new=lambda: clear())

    @checks.add("snow.level")
    def level_value(value: float | None = None) -> float | None:
        if value is not None and not 0 <= value <= MAX_LEVEL:
            raise CommandError(f"level must be within 0..{MAX_LEVEL:g}, got {value:g}")
        return value

    @checks.add("snow.move", "snowflake")
    @checks.add("snow.remove", "snowflake")
    def flake_at(index: int, *position: float) -> Flake:
        """The flake `index` (moved to `position` if given) or a refusal."""
        if not 0 <= index < len(scene.flakes):
            raise CommandError(f"no flake {index} (there are {len(scene.flakes)})")
        return new_flake(*position, scene.flakes[index].radius) if position else scene.flakes[index]

    @checks.add("snow.add")
    def new_flake(x: float, y: float, radius: float = DEFAULT_RADIUS) -> Flake:
        storable("a flake's centre and radius", x, y, radius)
        return Flake(x, y, radius)

    @reg.command("snow.level", "[level:float]",
                 f"Show or set the Koch level (0..{MAX_LEVEL:g}, fractional levels blend)", allow=SCRIPTS)
    def level(value: float | None = None) -> None:
        if level_value(value) is None:
            console.print(f"snow.level is {number(scene.level)}")
        elif value != scene.level:
            check_level(len(scene.flakes), value)
            history.checkpoint("Set Level")
            scene.level = value

    @reg.command("snow.step", "delta:float", "Change the level by delta, clamped to the valid range (keys w/s)",
                 allow=SCRIPTS)
    def step(delta: float) -> None:
        target = min(MAX_LEVEL, max(0.0, round(scene.level + delta, 6)))
        if target != scene.level:
            check_level(len(scene.flakes), target)
            history.checkpoint("Step Level")
            scene.level = target

    @reg.command("snow.add", "x:float y:float [radius:float]", "Add a flake centred at (x, y)", allow=SCRIPTS)
    def add(x: float, y: float, radius: float = DEFAULT_RADIUS) -> None:
        new_flake(x, y, radius)
        if len(scene.flakes) >= MAX_FLAKES:
            raise CommandError(f"a scene holds at most {MAX_FLAKES} flakes")
        check_level(len(scene.flakes) + 1, scene.level)
        history.checkpoint("Add Flake")
        console.print(f"flake {scene.add(x, y, radius)} at ({number(x)}, {number(y)})")

    @reg.command("snow.move", "index:int x:float y:float", "Move a flake's centre", quiet=True, allow=SCRIPTS)
    def move(index: int, x: float, y: float) -> None:
        flake_at(index, x, y)
        history.checkpoint("Move Flake", ("snow.move", index))  # a drag's moves: one step
        scene.move(index, x, y)

    @reg.command("snow.remove", "index:int", "Remove a flake", allow=SCRIPTS)
    def remove(index: int) -> None:
        flake_at(index)
        history.checkpoint("Remove Flake")
        scene.remove(index)

    @reg.command("snow.clear", "", "Remove every flake", allow=SCRIPTS)
    def clear() -> None:
        history.checkpoint("Clear Flakes")
        scene.clear()

    @reg.command("snow.list", "", "List the flakes", allow=SCRIPTS)
    def list_() -> None:
        for i, f in enumerate(scene.flakes):
            console.print(f"{i}: ({number(f.x)}, {number(f.y)}) radius {number(f.radius)}")
        console.print(f"{count(len(scene.flakes), 'flake')}, level {number(scene.level)}")

    @checks.add("snow.view")
    def view_values(cx: float, cy: float, height: float) -> tuple[float, float, float]:
        if height <= 0:
            raise CommandError(f"height must be > 0, got {height:g}")
        return cx, cy, height

    @reg.command("snow.view", "cx:float cy:float height:float", "Centre the 2D view and set the world height it shows",
                 quiet=True, allow=SCRIPTS)
    def view(*values: float) -> None:
        camera.cx, camera.cy, camera.height = view_values(*values)
