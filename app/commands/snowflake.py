"""Snowflake verbs: every edit of the Koch scene and its view goes through these commands, and every
edit of the scene is one undo step (the moves of one drag together)."""
from __future__ import annotations

from functools import partial

from app.console.command_set import CommandSet, Context
from app.console.console import Console
from app.console.demo import ArgChecks
from app.console.registry import SCRIPTS, CommandError
from app.console.text import count, number
from app.io import snowflake_scene
from app.io.json_file import storable
from app.io.snowflake_scene import MAX_FLAKES
from app.model.snowflake import MAX_LEVEL, Flake, SceneError, SnowflakeScene, check_level
from app.model.snowflake_workspace import SnowflakeWorkspace
from app.model.workspace import SceneFiles

DEFAULT_RADIUS = 0.3
COMMANDS = CommandSet("snowflake")
Ctx = Context[SnowflakeWorkspace]


def register(console: Console, state: SnowflakeWorkspace, checks: ArgChecks) -> None:
    """The commands, and their checks for demos (`checks`)."""
    ctx = Ctx(console, state)
    checks.reshaped_by("snowflake", "snow.add", "snow.remove", "snow.clear", "scene.load", "undo", "redo")
    state.files = SceneFiles(partial(load, ctx), lambda path: snowflake_scene.save(path, state.scene), (".json",),
                             snowflake_scene.FORMAT, new=partial(clear, ctx))
    COMMANDS.register(console.registry, ctx, checks)


def load(ctx: Ctx, path: str) -> str:
    try:
        flakes, level = snowflake_scene.load(path)
    except SceneError as exc:
        raise CommandError(str(exc)) from None
    ctx.state.history.checkpoint("Load Scene")
    ctx.state.scene = SnowflakeScene(flakes, level)
    ctx.console.print(f"loaded {count(len(flakes), 'flake')} from {path}")
    return path


@COMMANDS.check("snow.level")
def level_value(ctx: Ctx, value: float | None = None) -> float | None:
    if value is not None and not 0 <= value <= MAX_LEVEL:
        raise CommandError(f"level must be within 0..{MAX_LEVEL:g}, got {value:g}")
    return value


@COMMANDS.check("snow.move", "snowflake")
@COMMANDS.check("snow.remove", "snowflake")
def flake_at(ctx: Ctx, index: int, *position: float) -> Flake:
    """The flake `index` (moved to `position` if given) or a refusal."""
    flakes = ctx.state.scene.flakes
    if not 0 <= index < len(flakes):
        raise CommandError(f"no flake {index} (there are {len(flakes)})")
    return new_flake(ctx, *position, flakes[index].radius) if position else flakes[index]


@COMMANDS.check("snow.add")
def new_flake(ctx: Ctx, x: float, y: float, radius: float = DEFAULT_RADIUS) -> Flake:
    storable("a flake's centre and radius", x, y, radius)
    return Flake(x, y, radius)


@COMMANDS.command("snow.level", "[level:float]",
                  f"Show or set the Koch level (0..{MAX_LEVEL:g}, fractional levels blend)", allow=SCRIPTS)
def level(ctx: Ctx, value: float | None = None) -> None:
    scene = ctx.state.scene
    if level_value(ctx, value) is None:
        ctx.console.print(f"snow.level is {number(scene.level)}")
    elif value != scene.level:
        check_level(len(scene.flakes), value)
        ctx.state.history.checkpoint("Set Level")
        ctx.state.scene = scene.with_level(value)


@COMMANDS.command("snow.step", "delta:float", "Change the level by delta, clamped to the valid range (keys w/s)",
                  allow=SCRIPTS)
def step(ctx: Ctx, delta: float) -> None:
    scene = ctx.state.scene
    target = min(MAX_LEVEL, max(0.0, round(scene.level + delta, 6)))
    if target != scene.level:
        check_level(len(scene.flakes), target)
        ctx.state.history.checkpoint("Step Level")
        ctx.state.scene = scene.with_level(target)


@COMMANDS.command("snow.add", "x:float y:float [radius:float]", "Add a flake centred at (x, y)", allow=SCRIPTS)
def add(ctx: Ctx, x: float, y: float, radius: float = DEFAULT_RADIUS) -> None:
    scene = ctx.state.scene
    new_flake(ctx, x, y, radius)
    if len(scene.flakes) >= MAX_FLAKES:
        raise CommandError(f"a scene holds at most {MAX_FLAKES} flakes")
    check_level(len(scene.flakes) + 1, scene.level)
    ctx.state.history.checkpoint("Add Flake")
    ctx.state.scene = scene.added(x, y, radius)
    ctx.console.print(f"flake {len(scene.flakes)} at ({number(x)}, {number(y)})")


@COMMANDS.command("snow.move", "index:int x:float y:float", "Move a flake's centre", quiet=True, allow=SCRIPTS)
def move(ctx: Ctx, index: int, x: float, y: float) -> None:
    flake_at(ctx, index, x, y)
    ctx.state.history.checkpoint("Move Flake", ("snow.move", index))  # a drag's moves: one step
    ctx.state.scene = ctx.state.scene.moved(index, x, y)


@COMMANDS.command("snow.remove", "index:int", "Remove a flake", allow=SCRIPTS)
def remove(ctx: Ctx, index: int) -> None:
    flake_at(ctx, index)
    ctx.state.history.checkpoint("Remove Flake")
    ctx.state.scene = ctx.state.scene.removed(index)


@COMMANDS.command("snow.clear", "", "Remove every flake", allow=SCRIPTS)
def clear(ctx: Ctx) -> None:
    ctx.state.history.checkpoint("Clear Flakes")
    ctx.state.scene = ctx.state.scene.cleared()


@COMMANDS.command("snow.list", "", "List the flakes", allow=SCRIPTS)
def list_flakes(ctx: Ctx) -> None:
    scene = ctx.state.scene
    for i, f in enumerate(scene.flakes):
        ctx.console.print(f"{i}: ({number(f.x)}, {number(f.y)}) radius {number(f.radius)}")
    ctx.console.print(f"{count(len(scene.flakes), 'flake')}, level {number(scene.level)}")


@COMMANDS.check("snow.view")
def view_values(ctx: Ctx, cx: float, cy: float, height: float) -> tuple[float, float, float]:
    if height <= 0:
        raise CommandError(f"height must be > 0, got {height:g}")
    return cx, cy, height


@COMMANDS.command("snow.view", "cx:float cy:float height:float",
                  "Centre the 2D view and set the world height it shows", quiet=True, allow=SCRIPTS)
def view(ctx: Ctx, *values: float) -> None:
    camera = ctx.state.camera
    camera.cx, camera.cy, camera.height = view_values(ctx, *values)
