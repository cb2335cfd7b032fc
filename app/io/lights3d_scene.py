"""3D lights scene JSON: the objects, the lights and the lighting settings.
{"format": "shadelab.lights3d", "version": 1, "ambient": [r, g, b], "shininess": s, "specular": k,
 "objects": [{"kind", "size": [...], "position": [x, y, z], "colour": [r, g, b]}],
 "lights": [{"kind", "position", "direction", "colour", "range", "falloff", "angle", "shadow"}]}.
A missing optional field takes the model's default (app/model/lights3d/scene.py)."""
from __future__ import annotations

import json
import os

from app.io import json_file as jf
from app.io.atomic import write_text
from app.model.lights3d import scene as lm
from app.model.lights3d.scene import Light3D, Lights3DError, Object3D, Scene3D

FORMAT = "shadelab.lights3d"
VERSION = 1


class Lights3DSceneError(ValueError):
    pass


_COORD = jf.number(-lm.MAX_COORD, lm.MAX_COORD)
_OBJECT = jf.obj({
    "kind": {"enum": list(lm.OBJECT_KINDS)},
    "size": jf.array(jf.number(), 4, 1, title="numbers"),
    "position": jf.numbers(3, _COORD),
    "colour": jf.numbers(3, jf.number(0.0, 1.0)),
}, required=["kind", "size", "position"])
_LIGHT = jf.obj({
    "kind": {"enum": list(lm.LIGHT_KINDS)},
    "position": jf.numbers(3, _COORD),
    "direction": jf.numbers(3, _COORD),
    "colour": jf.numbers(3, jf.number(0.0, lm.MAX_INTENSITY)),
    "range": jf.number(above=0.0, hi=lm.MAX_SIZE),
    "falloff": jf.number(above=0.0, hi=lm.MAX_FALLOFF),
    "angle": jf.number(above=0.0, hi=90.0),
    "shadow": {"enum": list(lm.SHADOW_METHODS)},
}, required=["kind", "position"])
VALIDATOR = jf.validator({
    "ambient": jf.numbers(3, jf.number(0.0, 1.0)),
    "shininess": jf.number(above=0.0, hi=lm.MAX_SHININESS),
    "specular": jf.number(0.0, lm.MAX_SPECULAR),
    "objects": jf.array(_OBJECT, lm.MAX_OBJECTS, title="objects"),
    "lights": jf.array(_LIGHT, lm.MAX_LIGHTS, title="lights"),
}, required=["objects", "lights"])


def _made(path, where: str, make, *args, **values):
    """make(*args, **values), its refusal named by the file and the JSON path."""
    try:
        return make(*args, **values)
    except Lights3DError as exc:
        raise Lights3DSceneError(f"{path}: {where}: {exc}") from None


def load(path: str | os.PathLike) -> Scene3D:
    """Parse and validate the whole file, then every value through the model, before anything changes."""
    data = jf.read_versioned(path, FORMAT, VERSION, Lights3DSceneError, VALIDATOR)
    objects = [_made(path, f"objects[{i}]", Object3D, **item) for i, item in enumerate(data["objects"])]
    lights = [_made(path, f"lights[{i}]", Light3D, **item) for i, item in enumerate(data["lights"])]
    settings = {k: data[k] for k in ("ambient", "shininess", "specular") if k in data}
    return _made(path, "scene", Scene3D, objects, lights, **settings)


def save(path: str | os.PathLike, scene: Scene3D) -> None:
    data = {
        "format": FORMAT, "version": VERSION,
        "ambient": list(scene.ambient), "shininess": scene.shininess, "specular": scene.specular,
        "objects": [{"kind": o.kind, "size": list(o.size), "position": list(o.position), "colour": list(o.colour)}
                    for o in scene.objects],
        "lights": [{"kind": li.kind, "position": list(li.position), "direction": list(li.direction),
                    "colour": list(li.colour), "range": li.range, "falloff": li.falloff, "angle": li.angle,
                    "shadow": li.shadow} for li in scene.lights],
    }
    write_text(path, json.dumps(data, indent=2) + "\n")
