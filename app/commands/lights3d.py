"""3D lights verbs (issue 17): objects, lights, the scene's lighting settings, the selection and the orbit
camera, and the r_shadow* cvars of the shadow maps. Names are a contract (docs/lights3d.md, "Commands").

Every edit is checked whole before anything changes and is one undo step, the moves of one drag together; the
camera and the selection are no undo steps (undo puts back the selection that went with the scene)."""
from __future__ import annotations

from dataclasses import replace
from functools import partial

from app.console.command_set import CommandSet, Context
from app.console.console import Console
from app.console.demo import ArgChecks
from app.console.registry import SCRIPTS, CommandError, Cvar
from app.console.text import count, number
from app.io import lights3d_scene
from app.io.lights3d_scene import Lights3DSceneError
from app.model.lights3d.scene import (LIGHT_KINDS, OBJECT_KINDS, SHADOW_METHODS, SIZE_NAMES, Light3D, Lights3DCamera,
                                      Scene3D, default_scene, new_object)
from app.model.lights3d.placement import ground_spot
from app.model.lights3d.render_settings import (DEBUG_VIEWS, MAX_BIAS, MAX_CASCADES, MAX_MAP_SIZE, MIN_MAP_SIZE,
                                                PCF_KERNELS, Lights3DRenderSettings)
from app.model.lights3d.workspace import ITEM_KINDS, Lights3DWorkspace
from app.model.history import setting_name
from app.model.workspace import SceneFiles

# What a field takes: the names of its numbers, or the words it may be.
LIGHT_FIELDS = {"position": "x y z", "direction": "x y z", "colour": "r g b", "range": "units",
                "falloff": "exponent", "angle": "degrees", "shadow": SHADOW_METHODS, "kind": LIGHT_KINDS}
SETTINGS = {"ambient": "r g b", "shininess": "exponent", "specular": "strength"}


def _numbers(what: str, words: list[str], names: str) -> tuple[float, ...]:
    """`words` as the numbers `names` names ("x y z"); else CommandError. Ranges are the model's to check."""
    count = len(names.split())
    if len(words) != count:
        raise CommandError(f"{what} takes {count} number{'s' if count > 1 else ''} ({names}), got {len(words)}")
    try:
        return tuple(float(word) for word in words)
    except ValueError:
        raise CommandError(f"{what} takes numbers ({names}), got {' '.join(words)!r}") from None


def _value(what: str, words: list[str], spec: str | tuple[str, ...]):
    """A field's value: one of the words `spec` lists, or the numbers it names (one number alone)."""
    if isinstance(spec, tuple):
        if len(words) != 1:
            raise CommandError(f"{what} takes one word ({'|'.join(spec)}), got {len(words)}")
        return words[0]  # the model refuses a word not in the list
    numbers = _numbers(what, words, spec)
    return numbers if len(numbers) > 1 else numbers[0]


def _field(table: dict, what: str, field: str) -> str | tuple[str, ...]:
    if field not in table:
        raise CommandError(f"{what} have no field {field!r}; there are {', '.join(table)}")
    return table[field]


def _words(values) -> str:
    return " ".join(map(number, values))


def _starting(words, prefix: str) -> list[str]:
    return [w for w in words if w.startswith(prefix)]


COMMANDS = CommandSet("lights3d")
Ctx = Context[Lights3DWorkspace]


def register(console: Console, state: Lights3DWorkspace, checks: ArgChecks) -> None:
    """The commands and the r_shadow* cvars, and their checks for demos (`checks`)."""
    ctx = Ctx(console, state)
    # Index checks read the object and light counts, size checks the objects' kinds and the triangles they
    # add up to: after any of these a demo's checker cannot know them.
    checks.reshaped_by("lights3d", "object.add", "object.remove", "object.set", "light3d.add", "light3d.remove",
                       "lights3d.reset", "scene.load", "undo", "redo")
    reg = console.registry
    defaults = Lights3DRenderSettings()
    reg.add_cvar(Cvar("r_shadowMapSize", int, defaults.map_size, "3D lights: shadow map texels per side",
                      min=MIN_MAP_SIZE, max=MAX_MAP_SIZE, archive=True))
    reg.add_cvar(Cvar("r_shadowPCF", int, defaults.pcf, "3D lights: shadow map filter taps per side",
                      choices=PCF_KERNELS, archive=True))
    reg.add_cvar(Cvar("r_shadowBias", float, defaults.bias, "3D lights: shadow map depth bias (of 0..1 depth; "
                      "more on slopes)", min=0.0, max=MAX_BIAS, archive=True))
    reg.add_cvar(Cvar("r_shadowCascades", int, defaults.cascades, "3D lights: a directional light's shadow maps, "
                      "each over a slice of the view's depths", min=1, max=MAX_CASCADES, archive=True))
    reg.add_cvar(Cvar("r_shadowDebug", str, defaults.debug, "3D lights: a debug view instead of the lit scene",
                      choices=DEBUG_VIEWS))
    state.files = SceneFiles(partial(load, ctx), lambda path: lights3d_scene.save(path, state.scene), (".json",),
                             lights3d_scene.FORMAT, new=partial(reset, ctx))
    COMMANDS.register(reg, ctx, checks)


def _apply(ctx: Ctx, scene: Scene3D, name: str, key=None) -> None:
    """Put an edited scene in place as one undo step called `name`; edits with the same key (one drag's) as one."""
    if scene != ctx.state.scene:
        ctx.state.history.checkpoint(name, key)
        ctx.state.scene = scene


def _remove(ctx: Ctx, kind: str, index: int) -> None:
    ctx.state.item(kind, index)
    ctx.state.history.checkpoint(f"Remove {kind.title()}")
    ctx.state.remove(kind, index)


def _position(coords: tuple) -> tuple | None:
    given = tuple(v for v in coords if v is not None)
    if len(given) not in (0, 3):
        raise CommandError(f"give the position as x y z, got {len(given)} number{'s' if len(given) > 1 else ''}")
    return given or None


# ---- files and the whole scene ---------------------------------------------------------------------

def load(ctx: Ctx, path: str) -> str:
    try:
        scene = lights3d_scene.load(path)
    except Lights3DSceneError as exc:
        raise CommandError(str(exc)) from None
    ctx.state.history.checkpoint("Load Scene")
    ctx.state.replace(scene)
    ctx.console.print(f"loaded {count(len(scene.objects), 'object')} and {count(len(scene.lights), 'light')} "
                      f"from {path}")
    return path


@COMMANDS.command("lights3d.reset", "", "Put the default scene back (seed 004's two lights over five objects)",
                  allow=SCRIPTS)
def reset(ctx: Ctx) -> None:
    scene = default_scene()
    if (ctx.state.scene, ctx.state.selection) != (scene, None):
        ctx.state.history.checkpoint("Reset Scene")
        ctx.state.replace(scene)


@COMMANDS.check("lights3d.set")
def set_scene(ctx: Ctx, field: str, words: list[str]) -> Scene3D:
    value = _value(field, words, _field(SETTINGS, "the scene's settings", field))
    return ctx.state.scene.with_settings(**{field: value})


@COMMANDS.command("lights3d.set", "field values...", "Set the scene's ambient r g b (0..1), shininess S (the "
                  "specular exponent) or specular K (its strength)", completer=lambda ctx, p: _starting(SETTINGS, p),
                  allow=SCRIPTS)
def lights3d_set(ctx: Ctx, field: str, words: list[str]) -> None:
    _apply(ctx, set_scene(ctx, field, words), f"Set {field}", ("lights3d.set", field))


@COMMANDS.check("lights3d.select", "lights3d")
def selection(ctx: Ctx, kind: str, index: int | None = None):
    return ctx.state.checked_selection(kind, index)


@COMMANDS.command("lights3d.select", "what [index:int]", "Select object I or light I (the gizmo moves it), or none",
                  completer=lambda ctx, p: _starting((*ITEM_KINDS, "none"), p), allow=SCRIPTS)
def select(ctx: Ctx, kind: str, index: int | None = None) -> None:
    ctx.state.selection = selection(ctx, kind, index)


# ---- the camera ------------------------------------------------------------------------------------

@COMMANDS.check("view.orbit")
def orbit_camera(ctx: Ctx, yaw: float, pitch: float, distance: float | None = None) -> Lights3DCamera:
    cam = ctx.state.camera
    return replace(cam, yaw=yaw % 360.0, pitch=pitch, distance=cam.distance if distance is None else distance)


@COMMANDS.command("view.orbit", "yaw:float pitch:float [distance:float]",
                  f"Place the camera around its target: yaw and pitch in degrees (pitch within -89..89), distance "
                  f"{Lights3DCamera.MIN_DISTANCE:g}..{Lights3DCamera.MAX_DISTANCE:g}", quiet=True, allow=SCRIPTS)
def view_orbit(ctx: Ctx, *args: float) -> None:
    ctx.state.camera = orbit_camera(ctx, *args)


@COMMANDS.check("view.target")
def targeted_camera(ctx: Ctx, x: float, y: float, z: float) -> Lights3DCamera:
    return replace(ctx.state.camera, target=(x, y, z))  # the camera checks the point (finite, within reach)


@COMMANDS.command("view.target", "x:float y:float z:float", "Orbit the camera around this point (View > Frame "
                  "All puts it at the scene's middle)", quiet=True, allow=SCRIPTS)
def view_target(ctx: Ctx, x: float, y: float, z: float) -> None:
    ctx.state.camera = targeted_camera(ctx, x, y, z)


# ---- objects ---------------------------------------------------------------------------------------

@COMMANDS.check("object.add", "lights3d")
def added_object(ctx: Ctx, kind: str, x: float | None = None, y: float | None = None, z: float | None = None,
                 size: list[float] | None = None) -> Scene3D:
    at = _position((x, y, z))
    obj = new_object(kind, at, tuple(size) if size else None)
    if at is None:
        obj = replace(obj, position=ground_spot(ctx.state.scene, ctx.state.camera, obj))
    return ctx.state.scene.add_object(obj)


@COMMANDS.command("object.add", "kind [x:float] [y:float] [z:float] [size:float...]",
                  "Add a box, sphere, torus, lprism or plane at its centre x y z (default: standing on the ground in "
                  "front of the camera, clear of the other objects) with its size (object.set has the numbers by "
                  "kind)", completer=lambda ctx, p: _starting(OBJECT_KINDS, p), allow=SCRIPTS)
def object_add(ctx: Ctx, kind: str, *args) -> None:
    _apply(ctx, added_object(ctx, kind, *args), "Add Object")
    objects = ctx.state.scene.objects
    obj = objects[-1]
    if not args:  # recorded with the spot it took: a replay does not depend on the camera
        ctx.console.record_args([kind, *map(number, obj.position)])
    ctx.console.print(f"object {len(objects) - 1}: {obj.kind} at {_words(obj.position)}")


@COMMANDS.check("object.move", "lights3d")
def moved_object(ctx: Ctx, index: int, x: float, y: float, z: float) -> Scene3D:
    return ctx.state.scene.with_object(index, position=(x, y, z))


@COMMANDS.command("object.move", "index:int x:float y:float z:float", "Move an object's centre (a drag is one "
                  "undo step)", quiet=True, allow=SCRIPTS)
def object_move(ctx: Ctx, index: int, x: float, y: float, z: float) -> None:
    _apply(ctx, moved_object(ctx, index, x, y, z), "Move Object", ("object.move", index))


@COMMANDS.check("object.set", "lights3d")
def set_object(ctx: Ctx, index: int, field: str, words: list[str]) -> Scene3D:
    kind = ctx.state.item("object", index).kind
    sizes = {"size": " ".join(SIZE_NAMES[kind]), "colour": "r g b"}
    return ctx.state.scene.with_object(index, **{field: _numbers(f"a {kind}'s {field}", words,
                                                                 _field(sizes, "objects", field))})


@COMMANDS.command("object.set", "index:int field values...", "Set an object's size (box sx sy sz; sphere radius "
                  "segments; torus major minor segments sides; lprism sx sy sz thickness; plane size) or colour "
                  "r g b (0..1)", allow=SCRIPTS)
def object_set(ctx: Ctx, index: int, field: str, words: list[str]) -> None:
    _apply(ctx, set_object(ctx, index, field, words), setting_name("Object", field), ("object.set", index, field))


@COMMANDS.check("object.remove", "lights3d")
def object_at(ctx: Ctx, index: int):
    return ctx.state.item("object", index)


@COMMANDS.command("object.remove", "index:int", "Remove an object (the selection follows the objects that stay)",
                  allow=SCRIPTS)
def object_remove(ctx: Ctx, index: int) -> None:
    _remove(ctx, "object", index)


@COMMANDS.command("object.list", "", "List the objects", recorded=False, allow=SCRIPTS)
def object_list(ctx: Ctx) -> None:
    scene = ctx.state.scene
    for i, o in enumerate(scene.objects):
        ctx.console.print(f"object {i}: {o.kind} size {_words(o.size)} at {_words(o.position)} "
                          f"colour {_words(o.colour)}")
    ctx.console.print(f"{count(len(scene.objects), 'object')}, {count(scene.triangles, 'triangle')}")


# ---- lights ----------------------------------------------------------------------------------------

@COMMANDS.check("light3d.add", "lights3d")
def added_light(ctx: Ctx, kind: str, x: float | None = None, y: float | None = None,
                z: float | None = None) -> Scene3D:
    at = _position((x, y, z))
    return ctx.state.scene.add_light(Light3D(kind) if at is None else Light3D(kind, at))


@COMMANDS.command("light3d.add", "kind [x:float] [y:float] [z:float]", "Add a point, spot or directional light "
                  "at x y z (default: the model's, 100 above the origin, shining down)",
                  completer=lambda ctx, p: _starting(LIGHT_KINDS, p), allow=SCRIPTS)
def light_add(ctx: Ctx, *args) -> None:
    _apply(ctx, added_light(ctx, *args), "Add Light")
    lights = ctx.state.scene.lights
    ctx.console.print(f"light {len(lights) - 1}: {lights[-1].kind} at {_words(lights[-1].position)}")


@COMMANDS.check("light3d.set", "lights3d")
def set_light(ctx: Ctx, index: int, field: str, words: list[str]) -> Scene3D:
    ctx.state.item("light", index)  # a bad index is named before a bad field
    value = _value(field, words, _field(LIGHT_FIELDS, "lights", field))
    return ctx.state.scene.with_light(index, **{field: value})


@COMMANDS.command("light3d.set", "index:int field values...", "Set a light's position x y z, direction x y z, "
                  "colour r g b (0..16), range, falloff, angle (a spot's half-angle, degrees), shadow (" +
                  "|".join(SHADOW_METHODS) + ") or kind (" + "|".join(LIGHT_KINDS) + ")", allow=SCRIPTS)
def light_set(ctx: Ctx, index: int, field: str, words: list[str]) -> None:
    _apply(ctx, set_light(ctx, index, field, words), setting_name("Light", field), ("light3d.set", index, field))


@COMMANDS.check("light3d.move", "lights3d")
def moved_light(ctx: Ctx, index: int, x: float, y: float, z: float) -> Scene3D:
    return ctx.state.scene.with_light(index, position=(x, y, z))


@COMMANDS.command("light3d.move", "index:int x:float y:float z:float", "Move a light (a drag is one undo step; "
                  "as light3d.set I position)", quiet=True, allow=SCRIPTS)
def light_move(ctx: Ctx, index: int, x: float, y: float, z: float) -> None:
    # the undo step of light3d.set I position: a drag's moves and sets of one light's position are one
    _apply(ctx, moved_light(ctx, index, x, y, z), setting_name("Light", "position"),
           ("light3d.set", index, "position"))


@COMMANDS.check("light3d.remove", "lights3d")
def light_at(ctx: Ctx, index: int):
    return ctx.state.item("light", index)


@COMMANDS.command("light3d.remove", "index:int", "Remove a light (the selection follows the lights that stay)",
                  allow=SCRIPTS)
def light_remove(ctx: Ctx, index: int) -> None:
    _remove(ctx, "light", index)


@COMMANDS.command("light3d.list", "", "List the lights", recorded=False, allow=SCRIPTS)
def light_list(ctx: Ctx) -> None:
    for i, li in enumerate(ctx.state.scene.lights):
        ctx.console.print(f"light {i}: {li.kind} at {_words(li.position)} direction {_words(li.direction)} "
                          f"colour {_words(li.colour)} range {number(li.range)} falloff {number(li.falloff)} "
                          f"angle {number(li.angle)} shadow {li.shadow}")
    ctx.console.print(count(len(ctx.state.scene.lights), "light"))


def render_settings(console: Console, state: Lights3DWorkspace) -> Lights3DRenderSettings:
    cvars = console.registry.cvars
    return Lights3DRenderSettings(map_size=cvars["r_shadowMapSize"].value, pcf=cvars["r_shadowPCF"].value,
                                  bias=cvars["r_shadowBias"].value, cascades=cvars["r_shadowCascades"].value,
                                  debug=cvars["r_shadowDebug"].value)
