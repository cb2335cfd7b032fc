"""2D lighting scene JSON (docs/lighting2d.md): checked whole before the model is touched; saved atomically."""
from __future__ import annotations

import json
import os
from typing import Callable

from app.io import json_file as jf
from app.io.atomic import write_text
from app.io.textures2d import BUILTIN, image
from app.model.lighting2d.scene import LIGHT_KINDS, SHADOW_TYPES, Hull, Light, Lighting2DError, Scene2D

FORMAT = "shadelab.lighting2d"
VERSION = 1
MAX_LIGHTS = 256  # each light is a pass per frame: hundreds already take seconds
MAX_HULLS = 4096
MAX_HULL_POINTS = 4096
MAX_IMAGE_NAME = 1024  # characters of an image name, a path included

_PAIR = jf.numbers(2)
_IMAGE = jf.text(MAX_IMAGE_NAME)
_FLAG = {"type": "boolean"}
# The shape and size of every field; what the values mean (colours 0..1, sizes >= 0) the model says.
_LIGHT = jf.obj({
    "kind": {"enum": list(LIGHT_KINDS)}, "position": _PAIR, "origin": _PAIR, "rotation": jf.number(),
    "scale": _PAIR, "color": jf.numbers(3), "intensity": jf.number(), "radius": jf.number(), "enabled": _FLAG,
    "casts_shadows": _FLAG, "shadow_type": {"enum": list(SHADOW_TYPES)}, "cone_decay": jf.number(),
    "height": jf.number(), "texture": {**_IMAGE, "type": ["string", "null"]},
    "ignored_hulls": jf.array({"type": "integer", "minimum": 0, "maximum": MAX_HULLS - 1}, MAX_HULLS)})
_HULL = jf.obj({
    "points": jf.array(_PAIR, MAX_HULL_POINTS, at_least=1, title="points"), "position": _PAIR, "origin": _PAIR,
    "rotation": jf.number(), "scale": _PAIR, "enabled": _FLAG}, required=["points"])
_SCENE = {"ambient": jf.numbers(3), "view": jf.numbers(3), "background": _IMAGE,
          "normal_map": {**_IMAGE, "type": ["string", "null"]}}
VALIDATOR = jf.validator({**_SCENE, "lights": jf.array(_LIGHT, MAX_LIGHTS, title="lights"),
                          "hulls": jf.array(_HULL, MAX_HULLS, title="hulls")})


def load(path: str | os.PathLike, may_read: Callable[[str], None] | None = None) -> Scene2D:
    """The scene in the file, once every field has the right shape, every value the model's range and
    every image it names can be read; otherwise Lighting2DError naming the field. `may_read(name)` is asked for
    each image before it is opened (the file policy: it raises for a file the caller may not read, so an image
    outside says the same whether or not it exists)."""
    data = jf.read_versioned(path, FORMAT, VERSION, Lighting2DError, VALIDATOR)
    try:
        lights = [_make(Light, item, f"lights[{i}]") for i, item in enumerate(data.get("lights", []))]
        hulls = [_make(Hull, item, f"hulls[{i}]") for i, item in enumerate(data.get("hulls", []))]
        scene = Scene2D(lights=lights, hulls=hulls, **{k: data[k] for k in _SCENE if k in data})
        _check_images(scene, may_read)
    except Lighting2DError as exc:
        raise Lighting2DError(f"{path}: {exc}") from None
    return scene


def _make(kind, item: dict, where: str):
    """The model's constructor on values the schema passed; its refusal names the field."""
    try:
        return kind(**item)
    except Lighting2DError as exc:
        raise Lighting2DError(f"{where}: {exc}") from None


def _check_images(scene: Scene2D, may_read: Callable[[str], None] | None) -> None:
    """Every image a scene names must load now, not fail every frame later."""
    for where, name in scene.images():
        try:
            if may_read is not None and not name.startswith(BUILTIN):
                may_read(name)
            image(name)
        except Lighting2DError as exc:
            raise Lighting2DError(f"{where}: {exc}") from None


def dumps(scene: Scene2D) -> str:
    data = {
        "format": FORMAT,
        "version": VERSION,
        "ambient": list(scene.ambient),
        "view": list(scene.view),
        "background": scene.background,
        "normal_map": scene.normal_map,
        "lights": [{k: (list(v) if isinstance(v, tuple) else v) for k, v in vars(light).items()}
                   for light in scene.lights],
        "hulls": [{"points": hull.points.tolist(), "position": list(hull.position), "origin": list(hull.origin),
                   "rotation": hull.rotation, "scale": list(hull.scale), "enabled": hull.enabled}
                  for hull in scene.hulls],
    }
    return json.dumps(data, indent=2) + "\n"


def save(path: str | os.PathLike, scene: Scene2D) -> None:
    write_text(path, dumps(scene))
