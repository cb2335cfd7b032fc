"""Snowflake scene JSON:
{"format": "shadelab.snowflake", "version": 1, "level": 4, "flakes": [{"x", "y", "radius"}]}."""
from __future__ import annotations

import json
import os

from app.io import json_file as jf
from app.io.atomic import write_text
from app.model.snowflake import MAX_LEVEL, Flake, SceneError, SnowflakeScene, check_level

FORMAT = "shadelab.snowflake"
VERSION = 1
MAX_FLAKES = 4096  # one instance each, up to 3 * 4**8 segments apiece

_FLAKE = jf.obj({"x": jf.number(), "y": jf.number(), "radius": jf.number(above=0)}, required=["x", "y"])
VALIDATOR = jf.validator({"level": jf.number(0, MAX_LEVEL), "flakes": jf.array(_FLAKE, MAX_FLAKES, title="flakes")},
                         required=["flakes"])


def load(path: str | os.PathLike) -> tuple[list[Flake], float]:
    """Parse and validate the whole file before anything reaches the model."""
    data = jf.read_versioned(path, FORMAT, VERSION, SceneError, VALIDATOR)
    flakes = [Flake(float(item["x"]), float(item["y"]), float(item.get("radius", 0.5))) for item in data["flakes"]]
    level = float(data.get("level", 2))
    try:
        check_level(len(flakes), level)  # the count and the level may each be fine and together too much work
    except SceneError as exc:
        raise SceneError(f"{path}: {exc}") from None
    return flakes, level


def save(path: str | os.PathLike, scene: SnowflakeScene) -> None:
    data = {
        "format": FORMAT,
        "version": VERSION,
        "level": scene.level,
        "flakes": [{"x": f.x, "y": f.y, "radius": f.radius} for f in scene.flakes],
    }
    write_text(path, json.dumps(data, indent=2) + "\n")
