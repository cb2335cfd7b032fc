"""The 2D lighting verbs (seed 000). Every edit of lights, hulls and the view is one of these commands,
so demos record it, Lua scripts it and `undo` takes it back. Angles are radians; colours are 0..1;
hull vertex commands take the hull's local coordinates. The scene is a value: each edit puts a new one in
place, after undo's checkpoint (one key for a run of edits, a drag: one step)."""
from __future__ import annotations

import dataclasses
import math
from dataclasses import replace
from functools import partial
from pathlib import Path

import numpy as np

from app.console import files
from app.console.command_set import CommandSet, Context
from app.console.console import Console
from app.console.demo import ArgChecks
from app.console.registry import SCRIPTS, CommandError, Cvar
from app.console.text import count, number
from app.io import lighting2d_scene as scene_file
from app.io.json_file import storable
from app.io.textures2d import BUILTIN, image
from app.model.lighting2d.scene import LIGHT_KINDS, SHADOW_METHODS as METHODS, Hull, Light, Lighting2DError, Scene2D, \
    Shading2D, centroid
from app.model.lighting2d.workspace import HULL_KEYS, Lighting2DWorkspace, fmt
from app.model.history import setting_name
from app.model.workspace import SceneFiles
from app.resources import SCENES

DEFAULT_SCENE = SCENES / "j_concave_three_lights.json"
START_ASPECT = 0.9  # framed for a view at least this wide per unit of height (the default window's is 0.96)
LIGHT_TUPLES = {"position", "origin", "scale", "color"}
LIGHT_FLOATS = {"rotation", "intensity", "radius", "cone_decay", "height"}
LIGHT_BOOLS = {"enabled", "casts_shadows"}
LIGHT_WORDS = {"kind", "shadow_type", "texture"}
LIGHT_PROPERTIES = sorted(LIGHT_TUPLES | LIGHT_FLOATS | LIGHT_BOOLS | LIGHT_WORDS | {"ignored_hulls"})
COMMANDS = CommandSet("lighting2d")
Ctx = Context[Lighting2DWorkspace]


def sample_names() -> list[str]:
    return sorted(p.stem for p in SCENES.glob("*.json"))


def register(console: Console, state: Lighting2DWorkspace, checks: ArgChecks) -> None:
    """The cvars, the commands and their checks for demos (`checks`); the workspace opens on a sample scene."""
    ctx = Ctx(console, state)
    # Index checks read the light and hull counts, a light.set check the light's other properties (a
    # texture for kind textured): after any of these a demo's checker cannot know them.
    checks.reshaped_by("lighting2d", "light.add", "light.remove", "light.set", "hull.add", "hull.draw", "hull.remove",
                       "hull.points", "hull.insert", "hull.delete", "lighting.clear", "lighting.sample",
                       "scene.load", "undo", "redo")
    reg = console.registry.scoped(state.name)
    reg.add_cvar(Cvar("r_shadowMethod", str, "exact", "2D soft shadows: " + ", ".join(METHODS), archive=True,
                      choices=METHODS))
    reg.add_cvar(Cvar("r_shadowSamples", int, 16, "jitter: hard shadows averaged", min=1, max=64, archive=True))
    reg.add_cvar(Cvar("r_shadowBlur", float, 0.25, "blur: Gaussian sigma as a share of the light radius",
                      min=0.01, max=4.0, archive=True))
    reg.add_cvar(Cvar("r_lightmapScale", float, 1.0, "2D lightmap resolution relative to the screen",
                      min=0.125, max=1.0, archive=True))
    reg.add_cvar(Cvar("r_normalMaps", bool, True, "normal-mapped 2D lighting where lights have a height", archive=True))
    reg.add_cvar(Cvar("r_flipY", bool, False, "2D world with y pointing down (screen coordinates)"))
    reg.add_cvar(Cvar("r_debug2d", bool, False, "draw hulls, lights and their reach as wireframe", archive=True))
    state.files = SceneFiles(partial(load, ctx), partial(save, ctx), (".json",), scene_file.FORMAT,
                             new=partial(clear, ctx), replacing=("lighting.sample",))
    state.replace(scene_file.load(DEFAULT_SCENE))  # the workspace opens on a sample scene, framed whole
    state.camera.cx, state.camera.cy, state.camera.height = state.framed_view(START_ASPECT)
    COMMANDS.register(console.registry, ctx, checks)


def render_settings(console: Console, state: Lighting2DWorkspace) -> Shading2D:
    """The 2D renderer's settings from the cvars."""
    cvars = console.registry.cvars
    return Shading2D(method=cvars["r_shadowMethod"].value, samples=cvars["r_shadowSamples"].value,
                     blur=cvars["r_shadowBlur"].value, lightmap_scale=cvars["r_lightmapScale"].value,
                     flip_y=cvars["r_flipY"].value, normal_maps=cvars["r_normalMaps"].value,
                     debug=cvars["r_debug2d"].value)


# ---- helpers ---------------------------------------------------------------------------------------


def _built(build, *args, **values):
    """`build(*args, **values)`: a model's constructor or `replace`, its refusal as the command's message."""
    try:
        return build(*args, **values)
    except Lighting2DError as exc:
        raise CommandError(str(exc)) from None


def _room(items: tuple, limit: int) -> None:
    if len(items) >= limit:
        raise CommandError(f"a scene holds at most {limit} of them")


def _check_image(name: str) -> None:
    if len(name) > scene_file.MAX_IMAGE_NAME:
        raise CommandError(f"an image name has at most {scene_file.MAX_IMAGE_NAME} characters")
    try:
        image(name)
    except Lighting2DError as exc:
        raise CommandError(str(exc)) from None


@COMMANDS.check("lighting.background")
def check_image(ctx: Ctx, name: str) -> None:
    """An image a scene may name; a script, demo or config may name only files it may read."""
    if not name.startswith(BUILTIN):
        files.readable(ctx.console, name)
    _check_image(name)


# ---- scene -----------------------------------------------------------------------------------------


@COMMANDS.command("lighting.clear", "", "Empty the 2D scene (ambient, view and images stay)", allow=SCRIPTS)
def clear(ctx: Ctx) -> None:
    ctx.state.history.checkpoint("Clear Scene")
    ctx.state.scene = ctx.state.scene.cleared()


@COMMANDS.check("lighting.sample")
def sample_path(ctx: Ctx, name: str) -> Path:
    path = SCENES / f"{name}.json"
    if not path.is_file():
        raise CommandError(f"no sample scene {name!r}; there are {', '.join(sample_names())}")
    return path


def _samples_from(ctx: Ctx, prefix: str) -> list[str]:
    return [n for n in sample_names() if n.startswith(prefix)]


@COMMANDS.command("lighting.sample", "name", "Load a sample 2D scene: " + ", ".join(sample_names()),
                  completer=_samples_from, allow=SCRIPTS)
def sample(ctx: Ctx, name: str) -> None:
    load(ctx, sample_path(ctx, name))


def load(ctx: Ctx, path: str | Path) -> str:
    try:
        loaded = scene_file.load(path, may_read=lambda name: files.readable(ctx.console, name))
    except (Lighting2DError, OSError) as exc:
        raise CommandError(str(exc)) from None
    for _where, name in loaded.images():
        check_image(ctx, name)
    ctx.state.history.checkpoint("Load Scene")
    ctx.state.replace(loaded)
    ctx.console.print(f"loaded {count(len(loaded.lights), 'light')} and {count(len(loaded.hulls), 'hull')} "
                      f"from {Path(path).name}")
    return str(path)


def save(ctx: Ctx, path) -> None:
    """The scene with the view the camera shows (a file keeps its view)."""
    cam = ctx.state.camera
    scene_file.save(path, replace(ctx.state.scene, view=(cam.cx, cam.cy, cam.height)))


@COMMANDS.check("ambient")
def ambient_value(ctx: Ctx, r: float, g: float, b: float) -> tuple[float, float, float]:
    return _built(Scene2D, ambient=(r, g, b)).ambient


@COMMANDS.command("ambient", "r:float g:float b:float", "Set the 2D ambient colour (0..1 each)", allow=SCRIPTS)
def ambient(ctx: Ctx, *rgb: float) -> None:
    value = ambient_value(ctx, *rgb)
    ctx.state.history.checkpoint("Set Ambient")
    ctx.state.scene = replace(ctx.state.scene, ambient=value)


@COMMANDS.command("lighting.background", "image", "The 2D scene's diffuse map: builtin:NAME or a PNG path",
                  allow=SCRIPTS)
def background(ctx: Ctx, name: str) -> None:
    check_image(ctx, name)
    ctx.state.history.checkpoint("Set Background")
    ctx.state.scene = replace(ctx.state.scene, background=name)


@COMMANDS.check("lighting.normalmap")
def normal_map_name(ctx: Ctx, name: str) -> str | None:
    """The normal map `name` stands for (None for `none`), or a refusal."""
    if name == "none":
        return None
    check_image(ctx, name)
    return name


@COMMANDS.command("lighting.normalmap", "image",
                  "Normals for lights with a height: builtin:NAME, a PNG path, or none", allow=SCRIPTS)
def normalmap(ctx: Ctx, name: str) -> None:
    value = normal_map_name(ctx, name)
    ctx.state.history.checkpoint("Set Normal Map")
    ctx.state.scene = replace(ctx.state.scene, normal_map=value)


@COMMANDS.check("lighting.view")
def view_values(ctx: Ctx, cx: float, cy: float, height: float) -> tuple[float, float, float]:
    if not (math.isfinite(cx) and math.isfinite(cy) and math.isfinite(height)) or height <= 0:
        raise CommandError(f"the view needs a finite centre and a height > 0, got {cx:g} {cy:g} {height:g}")
    storable("the view", cx, cy, height)
    return cx, cy, height


@COMMANDS.command("lighting.view", "cx:float cy:float height:float",
                  "Centre the 2D view and set the world height shown", quiet=True, allow=SCRIPTS)
def view(ctx: Ctx, *values: float) -> None:
    cam = ctx.state.camera
    cam.cx, cam.cy, cam.height = view_values(ctx, *values)


# ---- lights ----------------------------------------------------------------------------------------


@COMMANDS.check("light.remove", "lighting2d")
def light_at(ctx: Ctx, index: int) -> Light:
    lights = ctx.state.scene.lights
    if not 0 <= index < len(lights):
        raise CommandError(f"no light {index}; there are {len(lights)}")
    return lights[index]


@COMMANDS.check("light.add")
def new_light(ctx: Ctx, kind: str, x: float, y: float, texture: str | None = None) -> Light:
    extra = {"origin": (0.0, 0.5), "scale": (300.0, 200.0)} if kind == "spot" else {}
    if kind == "textured":
        texture = texture or "builtin:window"
        check_image(ctx, texture)
        extra["radius"] = 5.0
    storable("the light position", x, y)
    return _built(Light, kind=kind, position=(x, y), texture=texture, **extra)


def _kinds_from(ctx: Ctx, prefix: str) -> list[str]:
    return [k for k in LIGHT_KINDS if k.startswith(prefix)]


@COMMANDS.command("light.add", "kind x:float y:float [texture]", "Add a light (point, spot or textured) at (x, y)",
                  completer=_kinds_from, allow=SCRIPTS)
def light_add(ctx: Ctx, kind: str, x: float, y: float, texture: str | None = None) -> None:
    light = new_light(ctx, kind, x, y, texture)
    scene = ctx.state.scene
    _room(scene.lights, scene_file.MAX_LIGHTS)
    ctx.state.history.checkpoint("Add Light")
    ctx.state.scene = scene.add_light(light)
    ctx.console.print(f"light {len(scene.lights)}: {light.kind} at ({number(light.position[0])}, "
                      f"{number(light.position[1])})")


def _parse_light_value(key: str, values: list[str]):
    try:
        if key in LIGHT_TUPLES:
            want = 3 if key == "color" else 2
            if len(values) != want:
                raise CommandError(f"light {key} takes {want} numbers")
            return tuple(float(v) for v in values)
        if len(values) != 1 and key != "ignored_hulls":
            raise CommandError(f"light {key} takes one value")
        if key in LIGHT_FLOATS:
            return float(values[0])
        if key in LIGHT_BOOLS:
            return values[0] not in ("0", "false", "off")
        if key in LIGHT_WORDS:
            return None if key == "texture" and values[0] == "none" else values[0]
        if key == "ignored_hulls":
            hulls = () if values == ["none"] else tuple(int(v) for v in values)
            if not all(0 <= i < scene_file.MAX_HULLS for i in hulls):
                raise CommandError(f"light ignored_hulls must be hull numbers 0..{scene_file.MAX_HULLS - 1}")
            return hulls
    except ValueError:
        raise CommandError(f"light {key}: cannot read {' '.join(values)!r}") from None
    raise CommandError(f"lights have no property {key!r}; there are {', '.join(LIGHT_PROPERTIES)}")


def changed_light(ctx: Ctx, index: int, key: str, value) -> tuple[Light, Light]:
    """Light `index` and the light it would become with property `key` set to `value`, or a refusal."""
    light = light_at(ctx, index)
    if key == "texture" and value:
        check_image(ctx, value)
    if key in LIGHT_TUPLES | LIGHT_FLOATS:
        storable(f"light {key}", *(value if isinstance(value, tuple) else (value,)))
    return light, _built(replace, light, **{key: value})


@COMMANDS.check("light.set", "lighting2d")
def light_change(ctx: Ctx, index: int, key: str, values: list[str]) -> tuple[Light, Light]:
    """Light `index` and the light it would become."""
    light_at(ctx, index)
    return changed_light(ctx, index, key, _parse_light_value(key, values))


def _put_light(ctx: Ctx, index: int, key: str, light: Light, changed: Light) -> None:
    """Light `index` becomes `changed` (its property `key` set), one undo step with the edits of `key` before."""
    if changed == light:
        return
    ctx.state.history.checkpoint(setting_name("Light", key), ("light.set", index, key))
    ctx.state.scene = ctx.state.scene.with_light(index, changed)


def _light_properties_from(ctx: Ctx, prefix: str) -> list[str]:
    return [k for k in LIGHT_PROPERTIES if k.startswith(prefix)]


@COMMANDS.command("light.set", "index:int property values...", "Set a light's property (light.list shows them)",
                  completer=_light_properties_from, allow=SCRIPTS)
def light_set(ctx: Ctx, index: int, key: str, values: list[str]) -> None:
    _put_light(ctx, index, key, *light_change(ctx, index, key, values))


@COMMANDS.check("light.move", "lighting2d")
def moved_light(ctx: Ctx, index: int, x: float, y: float) -> tuple[Light, Light]:
    return changed_light(ctx, index, "position", (x, y))


@COMMANDS.command("light.move", "index:int x:float y:float", "Move a light's centre (a drag is one undo step)",
                  quiet=True, allow=SCRIPTS)
def light_move(ctx: Ctx, index: int, x: float, y: float) -> None:
    _put_light(ctx, index, "position", *moved_light(ctx, index, x, y))


@COMMANDS.command("light.remove", "index:int", "Remove a light", allow=SCRIPTS)
def light_remove(ctx: Ctx, index: int) -> None:
    light_at(ctx, index)
    ctx.state.history.checkpoint("Remove Light")
    ctx.state.scene = ctx.state.scene.remove_light(index)


@COMMANDS.command("light.list", "", "List the lights and their properties", recorded=False, allow=SCRIPTS)
def light_list(ctx: Ctx) -> None:
    lights = ctx.state.scene.lights
    for i, light in enumerate(lights):
        props = ", ".join(f"{f.name} {fmt(getattr(light, f.name))}" for f in dataclasses.fields(Light))
        ctx.console.print(f"light {i}: {props}")
    ctx.console.print(count(len(lights), "light"))


# ---- hulls -----------------------------------------------------------------------------------------


@COMMANDS.check("hull.remove", "lighting2d")
def hull_at(ctx: Ctx, index: int) -> Hull:
    hulls = ctx.state.scene.hulls
    if not 0 <= index < len(hulls):
        raise CommandError(f"no hull {index}; there are {len(hulls)}")
    return hulls[index]


def coords(values: list[float], at_least: int = 1) -> np.ndarray:
    if len(values) % 2 or len(values) < 2 * at_least:
        raise CommandError("give points as x1 y1 [x2 y2 ...]")
    return np.array(values, dtype=np.float64).reshape(-1, 2)


def _storable_points(points: np.ndarray) -> None:
    """Refuse more points, or larger ones, than a scene file holds."""
    if len(points) > scene_file.MAX_HULL_POINTS:
        raise CommandError(f"a hull has at most {scene_file.MAX_HULL_POINTS} points, got {len(points)}")
    storable("hull points", *points.ravel().tolist())


def report(ctx: Ctx, index: int) -> None:
    hull = ctx.state.scene.hulls[index]
    if not hull.valid:
        ctx.console.print(f"hull {index} is invalid and ignored: {hull.invalid_reason}")


@COMMANDS.check("hull.add")
def new_hull(ctx: Ctx, values: list[float]) -> Hull:
    """A hull through the points, refused if non-finite, or more or larger than a scene file holds."""
    points = coords(values)
    _storable_points(points)
    return _built(Hull, points=points)


def add_hull(ctx: Ctx, hull: Hull) -> None:
    scene = ctx.state.scene
    _room(scene.hulls, scene_file.MAX_HULLS)
    ctx.state.history.checkpoint("Add Hull")
    ctx.state.scene = scene.add_hull(hull)
    ctx.console.print(f"hull {len(scene.hulls)}: {count(len(hull.points), 'point')}")
    report(ctx, len(scene.hulls))


@COMMANDS.command("hull.add", "coords:float...", "Add a hull through the points x1 y1 x2 y2 ... (world units)",
                  allow=SCRIPTS)
def hull_add(ctx: Ctx, values: list[float]) -> None:
    add_hull(ctx, new_hull(ctx, values))


@COMMANDS.check("hull.draw")
def drawn_hull(ctx: Ctx, values: list[float]) -> Hull:
    hull = new_hull(ctx, values)
    centre = centroid(hull.points)
    # the same outline, turning and scaling about it
    return replace(hull, position=centre, origin=centre, rotation=0.0, scale=(1.0, 1.0))


@COMMANDS.command("hull.draw", "coords:float...", "Add a hull through the points x1 y1 x2 y2 ... (world units) "
                  "whose origin and position are its centroid, where its handles sit (the draw tool's hulls)",
                  allow=SCRIPTS)
def hull_draw(ctx: Ctx, values: list[float]) -> None:
    add_hull(ctx, drawn_hull(ctx, values))


def changed_hull(ctx: Ctx, index: int, key: str, value) -> tuple[Hull, Hull]:
    """Hull `index` and the hull it would become with property `key` set to `value`, or a refusal."""
    hull = hull_at(ctx, index)
    if key != "enabled":
        storable(f"hull {key}", *(value if isinstance(value, tuple) else (value,)))
    return hull, _built(replace, hull, **{key: value})


@COMMANDS.check("hull.set", "lighting2d")
def hull_change(ctx: Ctx, index: int, key: str, values: list[str]) -> tuple[Hull, Hull]:
    """Hull `index` and the hull it would become."""
    hull_at(ctx, index)
    if key not in HULL_KEYS:
        raise CommandError(f"hulls have no property {key!r}; there are {', '.join(HULL_KEYS)}")
    if key == "enabled":
        return changed_hull(ctx, index, key, values == ["1"] or values == ["true"] or values == ["on"])
    try:
        numbers = [float(v) for v in values]
    except ValueError:
        raise CommandError(f"hull {key}: cannot read {' '.join(values)!r}") from None
    if len(numbers) != (1 if key == "rotation" else 2):
        raise CommandError(f"hull {key} takes {1 if key == 'rotation' else 2} numbers")
    return changed_hull(ctx, index, key, numbers[0] if key == "rotation" else tuple(numbers))


def _put_hull(ctx: Ctx, index: int, key: str, hull: Hull, changed: Hull) -> None:
    """Hull `index` becomes `changed` (its property `key` set), one undo step with the edits of `key` before."""
    if getattr(changed, key) == getattr(hull, key):
        return
    ctx.state.history.checkpoint(setting_name("Hull", key), ("hull.set", index, key))
    ctx.state.scene = ctx.state.scene.with_hull(index, changed)


def _hull_keys_from(ctx: Ctx, prefix: str) -> list[str]:
    return [k for k in HULL_KEYS if k.startswith(prefix)]


@COMMANDS.command("hull.set", "index:int property values...",
                  "Set a hull's position, origin, rotation, scale or enabled", completer=_hull_keys_from,
                  allow=SCRIPTS)
def hull_set(ctx: Ctx, index: int, key: str, values: list[str]) -> None:
    _put_hull(ctx, index, key, *hull_change(ctx, index, key, values))


@COMMANDS.check("hull.move", "lighting2d")
def moved_hull(ctx: Ctx, index: int, x: float, y: float) -> tuple[Hull, Hull]:
    return changed_hull(ctx, index, "position", (x, y))


@COMMANDS.command("hull.move", "index:int x:float y:float", "Move a hull's position (a drag is one undo step)",
                  quiet=True, allow=SCRIPTS)
def hull_move(ctx: Ctx, index: int, x: float, y: float) -> None:
    _put_hull(ctx, index, "position", *moved_hull(ctx, index, x, y))


def reshaped_hull(ctx: Ctx, index: int, points: np.ndarray) -> Hull:
    """Hull `index` through `points` instead, refused before anything changes."""
    hull = hull_at(ctx, index)
    _storable_points(points)
    return _built(replace, hull, points=points)


def _put_points(ctx: Ctx, index: int, hull: Hull, name: str, key=None) -> None:
    ctx.state.history.checkpoint(name, key)
    ctx.state.scene = ctx.state.scene.with_hull(index, hull)
    report(ctx, index)


@COMMANDS.check("hull.points", "lighting2d")
def replaced_points(ctx: Ctx, index: int, values: list[float]) -> Hull:
    return reshaped_hull(ctx, index, coords(values))


@COMMANDS.command("hull.points", "index:int coords:float...", "Replace a hull's local points", allow=SCRIPTS)
def hull_points(ctx: Ctx, index: int, values: list[float]) -> None:
    _put_points(ctx, index, replaced_points(ctx, index, values), "Set Hull Points")


def vertex_at(ctx: Ctx, index: int, vertex: int) -> np.ndarray:
    """Hull `index`'s points, where it has a vertex `vertex`."""
    points = hull_at(ctx, index).points
    if not 0 <= vertex < len(points):
        raise CommandError(f"hull {index} has no vertex {vertex}; it has {len(points)}")
    return points


@COMMANDS.check("hull.vertex", "lighting2d")
def moved_vertex(ctx: Ctx, index: int, vertex: int, x: float, y: float) -> Hull:
    points = vertex_at(ctx, index, vertex).copy()
    points[vertex] = (x, y)
    return reshaped_hull(ctx, index, points)


@COMMANDS.command("hull.vertex", "index:int vertex:int x:float y:float", "Move one vertex (local coordinates)",
                  quiet=True, allow=SCRIPTS)
def hull_vertex(ctx: Ctx, index: int, vertex: int, x: float, y: float) -> None:
    _put_points(ctx, index, moved_vertex(ctx, index, vertex, x, y), "Move Vertex", ("hull.vertex", index, vertex))


@COMMANDS.check("hull.insert", "lighting2d")
def inserted_vertex(ctx: Ctx, index: int, vertex: int, x: float, y: float) -> Hull:
    points = hull_at(ctx, index).points
    if not 0 <= vertex <= len(points):
        raise CommandError(f"hull {index}: insert position must be 0..{len(points)}, got {vertex}")
    return reshaped_hull(ctx, index, np.insert(points, vertex, (x, y), axis=0))


@COMMANDS.command("hull.insert", "index:int vertex:int x:float y:float", "Insert a vertex before `vertex` (local)",
                  allow=SCRIPTS)
def hull_insert(ctx: Ctx, index: int, vertex: int, x: float, y: float) -> None:
    _put_points(ctx, index, inserted_vertex(ctx, index, vertex, x, y), "Insert Vertex")


@COMMANDS.check("hull.delete", "lighting2d")
def deleted_vertex(ctx: Ctx, index: int, vertex: int) -> Hull:
    return reshaped_hull(ctx, index, np.delete(vertex_at(ctx, index, vertex), vertex, axis=0))


@COMMANDS.command("hull.delete", "index:int vertex:int", "Delete one vertex of a hull", allow=SCRIPTS)
def hull_delete(ctx: Ctx, index: int, vertex: int) -> None:
    _put_points(ctx, index, deleted_vertex(ctx, index, vertex), "Delete Vertex")


@COMMANDS.command("hull.remove", "index:int", "Remove a hull", allow=SCRIPTS)
def hull_remove(ctx: Ctx, index: int) -> None:
    hull_at(ctx, index)
    ctx.state.history.checkpoint("Remove Hull")
    ctx.state.scene = ctx.state.scene.remove_hull(index)  # the lights' ignored hulls follow the hulls that stay


@COMMANDS.command("hull.list", "", "List the hulls", recorded=False, allow=SCRIPTS)
def hull_list(ctx: Ctx) -> None:
    hulls = ctx.state.scene.hulls
    for i, hull in enumerate(hulls):
        state = "valid" if hull.valid else f"INVALID ({hull.invalid_reason})"
        ctx.console.print(f"hull {i}: {count(len(hull.points), 'point')} at ({number(hull.position[0])}, "
                          f"{number(hull.position[1])}), rotation {number(hull.rotation)}, scale {fmt(hull.scale)}, "
                          f"{'enabled' if hull.enabled else 'disabled'}, {state}")
    ctx.console.print(count(len(hulls), "hull"))
