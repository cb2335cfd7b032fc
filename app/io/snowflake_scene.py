"""Snowflake scene JSON: {"format": "shadelab.snowflake", "version": 1, "level": 4, "flakes": [{"x", "y", "radius"}]}."""
from __future__ import annotations

import json
import os

from app.io.atomic import write_text
from app.io.json_file import read_versioned
from app.model.snowflake import MAX_LEVEL, Flake, SceneError, SnowflakeScene

FORMAT = "shadelab.snowflake"
VERSION = 1


def load(path: str | os.PathLike) -> tuple[list[Flake], float]:
    """Parse and validate the whole file before anything reaches the model."""
    data = read_versioned(path, FORMAT, VERSION, SceneError)
    level = data.get("level", 2)
    if not isinstance(level, (int, float)) or isinstance(level, bool) or not 0 <= level <= MAX_LEVEL:
        raise SceneError(f"{path}: level must be a number within 0..{MAX_LEVEL:g}")
    items = data.get("flakes")
    if not isinstance(items, list):
        raise SceneError(f"{path}: 'flakes' must be a list")
    flakes = []
    for i, item in enumerate(items):
        try:
            flakes.append(Flake(float(item["x"]), float(item["y"]), float(item.get("radius", 0.5))))
        except (TypeError, KeyError, ValueError) as exc:
            raise SceneError(f"{path}: flake {i} is invalid: {exc}") from None
    return flakes, float(level)


def save(path: str | os.PathLike, scene: SnowflakeScene) -> None:
    data = {
        "format": FORMAT,
        "version": VERSION,
        "level": scene.level,
        "flakes": [{"x": f.x, "y": f.y, "radius": f.radius} for f in scene.flakes],
    }
    write_text(path, json.dumps(data, indent=2) + "\n")
