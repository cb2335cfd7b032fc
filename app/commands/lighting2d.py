"""The 2D lighting verbs (seed 000). Every edit of lights, hulls and the view is one of these commands,
so demos record it, Lua scripts it and `undo` takes it back. Angles are radians; colours are 0..1;
hull vertex commands take the hull's local coordinates."""
from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np

from app.console import files
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


def sample_names() -> list[str]:
    return sorted(p.stem for p in SCENES.glob("*.json"))


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
    fields = sorted(LIGHT_TUPLES | LIGHT_FLOATS | LIGHT_BOOLS | LIGHT_WORDS | {"ignored_hulls"})
    raise CommandError(f"lights have no property {key!r}; there are {', '.join(fields)}")


def register(console: Console, state: Lighting2DWorkspace, checks: ArgChecks) -> None:
    reg = console.registry.scoped(state.name)
    # Index checks read the light and hull counts, a light.set check the light's other properties (a
    # texture for kind textured): after any of these a demo's checker cannot know them.
    checks.reshaped_by("lighting2d", "light.add", "light.remove", "light.set", "hull.add", "hull.draw", "hull.remove",
                       "hull.points", "hull.insert", "hull.delete", "lighting.clear", "lighting.sample",
                       "scene.load", "undo", "redo")
    history = state.history

    def scene() -> Scene2D:
        return state.scene

    @checks.add("light.remove", "lighting2d")
    def light_at(index: int) -> Light:
        if not 0 <= index < len(scene().lights):
            raise CommandError(f"no light {index}; there are {len(scene().lights)}")
        return scene().lights[index]

    @checks.add("hull.remove", "lighting2d")
    def hull_at(index: int) -> Hull:
        if not 0 <= index < len(scene().hulls):
            raise CommandError(f"no hull {index}; there are {len(scene().hulls)}")
        return scene().hulls[index]

    edit = history.checkpoint  # undo's snapshot before an edit; one key for a run of edits (a drag): one step

    def refused(exc: Lighting2DError):
        return CommandError(str(exc))

    def make(model, **values):
        """The model's constructor, its refusal as the command's message."""
        try:
            return model(**values)
        except Lighting2DError as exc:
            raise refused(exc) from None

    def append(items: list, item, limit: int, name: str) -> int:
        if len(items) >= limit:
            raise CommandError(f"a scene holds at most {limit} of them")
        edit(name)
        items.append(item)
        scene().touch()
        return len(items) - 1

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

    # ---- scene -------------------------------------------------------------------------------------

    @reg.command("lighting.clear", "", "Empty the 2D scene (ambient, view and images stay)", allow=SCRIPTS)
    def clear() -> None:
        edit("Clear Scene")
        scene().lights.clear()
        scene().hulls.clear()
        scene().touch()

    @checks.add("lighting.sample")
    def sample_path(name: str) -> Path:
        path = SCENES / f"{name}.json"
        if not path.is_file():
            raise CommandError(f"no sample scene {name!r}; there are {', '.join(sample_names())}")
        return path

    @reg.command("lighting.sample", "name", "Load a sample 2D scene: " + ", ".join(sample_names()),
                 completer=lambda p: [n for n in sample_names() if n.startswith(p)], allow=SCRIPTS)
    def sample(name: str) -> None:
        load(sample_path(name))

    def load(path: str | Path) -> str:
        try:
            loaded = scene_file.load(path, may_read=lambda name: files.readable(console, name))
        except (Lighting2DError, OSError) as exc:
            raise CommandError(str(exc)) from None
        for _where, name in loaded.images():
            check_image(name)
        edit("Load Scene")
        state.replace(loaded)
        console.print(f"loaded {count(len(loaded.lights), 'light')} and {count(len(loaded.hulls), 'hull')} "
                      f"from {Path(path).name}")
        return str(path)

    def save(path) -> None:
        cam = state.camera
        scene().view = (cam.cx, cam.cy, cam.height)
        scene_file.save(path, scene())

    state.files = SceneFiles(load, save, (".json",), scene_file.FORMAT, new=clear,
                             replacing=("lighting.sample",))
    state.replace(scene_file.load(DEFAULT_SCENE))  # the workspace opens on a sample scene, framed whole
    state.camera.cx, state.camera.cy, state.camera.height = state.framed_view(START_ASPECT)

    @checks.add("ambient")
    def ambient_value(r: float, g: float, b: float) -> tuple[float, float, float]:
        return make(Scene2D, ambient=(r, g, b)).ambient

    @reg.command("ambient", "r:float g:float b:float", "Set the 2D ambient colour (0..1 each)", allow=SCRIPTS)
    def ambient(*rgb: float) -> None:
        value = ambient_value(*rgb)
        edit("Set Ambient")
        scene().ambient = value
        scene().touch()

    def check_image(name: str) -> None:
        """An image a scene may name; a script, demo or config may name only files it may read."""
        if not name.startswith(BUILTIN):
            files.readable(console, name)
        _check_image(name)

    checks.add("lighting.background")(check_image)
    checks.add("lighting.normalmap")(lambda name: name == "none" or check_image(name))

    @reg.command("lighting.background", "image", "The 2D scene's diffuse map: builtin:NAME or a PNG path",
                 allow=SCRIPTS)
    def background(name: str) -> None:
        check_image(name)
        edit("Set Background")
        scene().background = name
        scene().touch()

    @reg.command("lighting.normalmap", "image", "Normals for lights with a height: builtin:NAME, a PNG path, or none",
                 allow=SCRIPTS)
    def normalmap(name: str) -> None:
        if name != "none":
            check_image(name)
        edit("Set Normal Map")
        scene().normal_map = None if name == "none" else name
        scene().touch()

    @checks.add("lighting.view")
    def view_values(cx: float, cy: float, height: float) -> tuple[float, float, float]:
        if not (math.isfinite(cx) and math.isfinite(cy) and math.isfinite(height)) or height <= 0:
            raise CommandError(f"the view needs a finite centre and a height > 0, got {cx:g} {cy:g} {height:g}")
        storable("the view", cx, cy, height)
        return cx, cy, height

    @reg.command("lighting.view", "cx:float cy:float height:float", "Centre the 2D view and set the world height shown",
                 quiet=True, allow=SCRIPTS)
    def view(*values: float) -> None:
        cam = state.camera
        cam.cx, cam.cy, cam.height = view_values(*values)

    # ---- lights ------------------------------------------------------------------------------------

    @checks.add("light.add")
    def new_light(kind: str, x: float, y: float, texture: str | None = None) -> Light:
        extra = {"origin": (0.0, 0.5), "scale": (300.0, 200.0)} if kind == "spot" else {}
        if kind == "textured":
            texture = texture or "builtin:window"
            check_image(texture)
            extra["radius"] = 5.0
        storable("the light position", x, y)
        return make(Light, kind=kind, position=(x, y), texture=texture, **extra)

    @reg.command("light.add", "kind x:float y:float [texture]", "Add a light (point, spot or textured) at (x, y)",
                 completer=lambda p: [k for k in LIGHT_KINDS if k.startswith(p)], allow=SCRIPTS)
    def light_add(*args) -> None:
        light = new_light(*args)
        index = append(scene().lights, light, scene_file.MAX_LIGHTS, "Add Light")
        console.print(f"light {index}: {light.kind} at ({number(light.position[0])}, {number(light.position[1])})")

    @checks.add("light.set", "lighting2d")
    def light_change(index: int, key: str, values: list[str]) -> tuple[Light, Light]:
        """Light `index` and the light it would become."""
        light = light_at(index)
        value = _parse_light_value(key, values)
        if key == "texture" and value:
            check_image(value)
        if key in LIGHT_TUPLES | LIGHT_FLOATS:
            storable(f"light {key}", *(value if isinstance(value, tuple) else (value,)))
        try:
            return light, dataclasses.replace(light, **{key: value})
        except Lighting2DError as exc:
            raise refused(exc) from None

    @reg.command("light.set", "index:int property values...", "Set a light's property (light.list shows them)",
                 completer=lambda p: [k for k in sorted(LIGHT_TUPLES | LIGHT_FLOATS | LIGHT_BOOLS | LIGHT_WORDS
                                                         | {"ignored_hulls"}) if k.startswith(p)], allow=SCRIPTS)
    def light_set(index: int, key: str, values: list[str]) -> None:
        light, changed = light_change(index, key, values)
        if changed == light:
            return
        edit(setting_name("Light", key), ("light.set", index, key))
        scene().lights[index] = changed
        scene().touch()

    checks.add("light.move", "lighting2d")(lambda index, x, y: light_change(index, "position", [repr(x), repr(y)]))

    @reg.command("light.move", "index:int x:float y:float", "Move a light's centre (a drag is one undo step)",
                 quiet=True, allow=SCRIPTS)
    def light_move(index: int, x: float, y: float) -> None:
        light_set(index, "position", [repr(x), repr(y)])

    @reg.command("light.remove", "index:int", "Remove a light", allow=SCRIPTS)
    def light_remove(index: int) -> None:
        light_at(index)
        edit("Remove Light")
        del scene().lights[index]
        scene().touch()

    @reg.command("light.list", "", "List the lights and their properties", recorded=False, allow=SCRIPTS)
    def light_list() -> None:
        for i, light in enumerate(scene().lights):
            props = ", ".join(f"{f.name} {fmt(getattr(light, f.name))}" for f in dataclasses.fields(Light))
            console.print(f"light {i}: {props}")
        console.print(count(len(scene().lights), "light"))

    # ---- hulls -------------------------------------------------------------------------------------

    def coords(values: list[float], at_least: int = 1) -> np.ndarray:
        if len(values) % 2 or len(values) < 2 * at_least:
            raise CommandError("give points as x1 y1 [x2 y2 ...]")
        return np.array(values, dtype=np.float64).reshape(-1, 2)

    def checked_hull(points: np.ndarray) -> Hull:
        """A hull through `points`, refused if non-finite, or more or larger than a scene file holds."""
        if len(points) > scene_file.MAX_HULL_POINTS:
            raise CommandError(f"a hull has at most {scene_file.MAX_HULL_POINTS} points, got {len(points)}")
        storable("hull points", *points.ravel().tolist())
        return make(Hull, points=points)

    def report(index: int) -> None:
        hull = scene().hulls[index]
        if not hull.valid:
            console.print(f"hull {index} is invalid and ignored: {hull.invalid_reason}")

    @checks.add("hull.add")
    def new_hull(values: list[float]) -> Hull:
        return checked_hull(coords(values))

    def add_hull(hull: Hull) -> None:
        index = append(scene().hulls, hull, scene_file.MAX_HULLS, "Add Hull")
        console.print(f"hull {index}: {count(len(hull.points), 'point')}")
        report(index)

    @reg.command("hull.add", "coords:float...", "Add a hull through the points x1 y1 x2 y2 ... (world units)",
                 allow=SCRIPTS)
    def hull_add(values: list[float]) -> None:
        add_hull(new_hull(values))

    @checks.add("hull.draw")
    def drawn_hull(values: list[float]) -> Hull:
        hull = new_hull(values)
        centre = centroid(hull.points)
        hull.set_transform(centre, centre, 0.0, (1.0, 1.0))  # the same outline, turning and scaling about it
        return hull

    @reg.command("hull.draw", "coords:float...", "Add a hull through the points x1 y1 x2 y2 ... (world units) "
                 "whose origin and position are its centroid, where its handles sit (the draw tool's hulls)",
                 allow=SCRIPTS)
    def hull_draw(values: list[float]) -> None:
        add_hull(drawn_hull(values))

    def transform(hull: Hull, **change) -> dict:
        return {**{k: getattr(hull, k) for k in ("position", "origin", "rotation", "scale")}, **change}

    @checks.add("hull.set", "lighting2d")
    def hull_value(index: int, key: str, values: list[str]) -> tuple[Hull, object]:
        """Hull `index` and the value its property `key` would take."""
        hull = hull_at(index)
        if key not in HULL_KEYS:
            raise CommandError(f"hulls have no property {key!r}; there are {', '.join(HULL_KEYS)}")
        if key == "enabled":
            return hull, values == ["1"] or values == ["true"] or values == ["on"]
        try:
            numbers = [float(v) for v in values]
        except ValueError:
            raise CommandError(f"hull {key}: cannot read {' '.join(values)!r}") from None
        if len(numbers) != (1 if key == "rotation" else 2):
            raise CommandError(f"hull {key} takes {1 if key == 'rotation' else 2} numbers")
        storable(f"hull {key}", *numbers)
        value = numbers[0] if key == "rotation" else tuple(numbers)
        make(Hull, points=hull.points, **transform(hull, **{key: value}))  # the model's refusal, nothing changed
        return hull, value

    @reg.command("hull.set", "index:int property values...",
                 "Set a hull's position, origin, rotation, scale or enabled",
                 completer=lambda p: [k for k in HULL_KEYS if k.startswith(p)], allow=SCRIPTS)
    def hull_set(index: int, key: str, values: list[str]) -> None:
        hull, value = hull_value(index, key, values)
        if getattr(hull, key) == value:
            return
        edit(setting_name("Hull", key), ("hull.set", index, key))
        if key == "enabled":
            hull.enabled = value
        else:
            hull.set_transform(**transform(hull, **{key: value}))
        scene().touch()

    checks.add("hull.move", "lighting2d")(lambda index, x, y: hull_value(index, "position", [repr(x), repr(y)]))

    @reg.command("hull.move", "index:int x:float y:float", "Move a hull's position (a drag is one undo step)",
                 quiet=True, allow=SCRIPTS)
    def hull_move(index: int, x: float, y: float) -> None:
        hull_set(index, "position", [repr(x), repr(y)])

    def valid_points(index: int, points: np.ndarray) -> np.ndarray:
        hull_at(index)
        checked_hull(points)  # refuse before anything changes
        return points

    def set_points(index: int, points: np.ndarray, name: str, key=None) -> None:
        edit(name, key)
        hull_at(index).set_points(points)
        scene().touch()
        report(index)

    @checks.add("hull.points", "lighting2d")
    def replaced_points(index: int, values: list[float]) -> np.ndarray:
        return valid_points(index, coords(values))

    @reg.command("hull.points", "index:int coords:float...", "Replace a hull's local points", allow=SCRIPTS)
    def hull_points(index: int, values: list[float]) -> None:
        set_points(index, replaced_points(index, values), "Set Hull Points")

    def vertex_at(index: int, vertex: int) -> np.ndarray:
        points = hull_at(index).points
        if not 0 <= vertex < len(points):
            raise CommandError(f"hull {index} has no vertex {vertex}; it has {len(points)}")
        return points

    @checks.add("hull.vertex", "lighting2d")
    def moved_vertex(index: int, vertex: int, x: float, y: float) -> np.ndarray:
        points = vertex_at(index, vertex).copy()
        points[vertex] = (x, y)
        return valid_points(index, points)

    @reg.command("hull.vertex", "index:int vertex:int x:float y:float", "Move one vertex (local coordinates)",
                 quiet=True, allow=SCRIPTS)
    def hull_vertex(index: int, vertex: int, x: float, y: float) -> None:
        set_points(index, moved_vertex(index, vertex, x, y), "Move Vertex", ("hull.vertex", index, vertex))

    @checks.add("hull.insert", "lighting2d")
    def inserted_vertex(index: int, vertex: int, x: float, y: float) -> np.ndarray:
        points = hull_at(index).points
        if not 0 <= vertex <= len(points):
            raise CommandError(f"hull {index}: insert position must be 0..{len(points)}, got {vertex}")
        return valid_points(index, np.insert(points, vertex, (x, y), axis=0))

    @reg.command("hull.insert", "index:int vertex:int x:float y:float", "Insert a vertex before `vertex` (local)",
                 allow=SCRIPTS)
    def hull_insert(*args) -> None:
        set_points(args[0], inserted_vertex(*args), "Insert Vertex")

    @checks.add("hull.delete", "lighting2d")
    def deleted_vertex(index: int, vertex: int) -> np.ndarray:
        return valid_points(index, np.delete(vertex_at(index, vertex), vertex, axis=0))

    @reg.command("hull.delete", "index:int vertex:int", "Delete one vertex of a hull", allow=SCRIPTS)
    def hull_delete(index: int, vertex: int) -> None:
        set_points(index, deleted_vertex(index, vertex), "Delete Vertex")

    @reg.command("hull.remove", "index:int", "Remove a hull", allow=SCRIPTS)
    def hull_remove(index: int) -> None:
        hull_at(index)
        edit("Remove Hull")
        del scene().hulls[index]
        for light in scene().lights:  # ignored-hull indices follow the hulls that stay
            light.ignored_hulls = tuple(i - (i > index) for i in light.ignored_hulls if i != index)
        scene().touch()

    @reg.command("hull.list", "", "List the hulls", recorded=False, allow=SCRIPTS)
    def hull_list() -> None:
        for i, hull in enumerate(scene().hulls):
            state = "valid" if hull.valid else f"INVALID ({hull.invalid_reason})"
            console.print(f"hull {i}: {count(len(hull.points), 'point')} at ({number(hull.position[0])}, "
                          f"{number(hull.position[1])}), rotation {number(hull.rotation)}, scale {fmt(hull.scale)}, "
                          f"{'enabled' if hull.enabled else 'disabled'}, {state}")
        console.print(count(len(scene().hulls), "hull"))


def _check_image(name: str) -> None:
    if len(name) > scene_file.MAX_IMAGE_NAME:
        raise CommandError(f"an image name has at most {scene_file.MAX_IMAGE_NAME} characters")
    try:
        image(name)
    except Lighting2DError as exc:
        raise CommandError(str(exc)) from None


def render_settings(console: Console, state: Lighting2DWorkspace) -> Shading2D:
    """The 2D renderer's settings from the cvars."""
    cvars = console.registry.cvars
    return Shading2D(method=cvars["r_shadowMethod"].value, samples=cvars["r_shadowSamples"].value,
                     blur=cvars["r_shadowBlur"].value, lightmap_scale=cvars["r_lightmapScale"].value,
                     flip_y=cvars["r_flipY"].value, normal_maps=cvars["r_normalMaps"].value,
                     debug=cvars["r_debug2d"].value)
