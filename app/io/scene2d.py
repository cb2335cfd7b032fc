"""2D lighting scene JSON (docs/lighting2d.md): checked whole before the model is touched; saved atomically."""
from __future__ import annotations

import json
import os

from app.io.atomic import write_text
from app.io.json_file import read_versioned
from app.model.lighting2d import Hull, Light, Lighting2DError, Scene2D

FORMAT = "shadelab.lighting2d"
VERSION = 1
LIGHT_KEYS = ("kind", "position", "origin", "rotation", "scale", "color", "intensity", "radius", "enabled",
              "casts_shadows", "shadow_type", "cone_decay", "height", "texture", "ignored_hulls")
SCENE_KEYS = ("ambient", "view", "background", "normal_map")
HULL_KEYS = ("points", "position", "origin", "rotation", "scale", "enabled")


def load(path: str | os.PathLike) -> Scene2D:
    data = read_versioned(path, FORMAT, VERSION, Lighting2DError)
    try:
        lights = [_make(Light, item, LIGHT_KEYS, f"light {i}") for i, item in enumerate(data.get("lights", []))]
        hulls = [_make(Hull, item, HULL_KEYS, f"hull {i}") for i, item in enumerate(data.get("hulls", []))]
        unknown = set(data) - {"format", "version", *SCENE_KEYS, "lights", "hulls"}
        if unknown:
            raise Lighting2DError(f"unknown keys: {', '.join(sorted(unknown))}")
        return Scene2D(lights=lights, hulls=hulls, **{k: data[k] for k in SCENE_KEYS if k in data})
    except Lighting2DError as exc:
        raise Lighting2DError(f"{path}: {exc}") from None
    except TypeError as exc:
        raise Lighting2DError(f"{path}: invalid scene: {exc}") from None


def _make(kind, item, keys: tuple[str, ...], what: str):
    if not isinstance(item, dict):
        raise Lighting2DError(f"{what} must be an object")
    unknown = set(item) - set(keys)
    if unknown:
        raise Lighting2DError(f"{what} has unknown keys: {', '.join(sorted(unknown))}")
    try:
        return kind(**item)
    except Lighting2DError as exc:
        raise Lighting2DError(f"{what}: {exc}") from None
    except (TypeError, ValueError) as exc:
        raise Lighting2DError(f"{what} is invalid: {exc}") from None


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
