"""Cloud scene JSON: the model's parameters, the sun and the weather's seed.
{"format": "shadelab.clouds", "version": 1, "params": {NAME: number}, "sun": [azimuth, elevation],
 "weather_seed": int}. A weather map loaded from an image is not stored (the file names no image)."""
from __future__ import annotations

import json
import os
from dataclasses import dataclass

from app.io import json_file as jf
from app.io.atomic import write_text
from app.model.clouds.scene import PARAMS, CloudParams, ParamError

FORMAT = "shadelab.clouds"
VERSION = 1
MAX_SEED = 2**31 - 1


class CloudSceneError(ValueError):
    pass


VALIDATOR = jf.validator({
    "params": jf.obj({p.name: jf.number(p.lo, p.hi) for p in PARAMS}),
    "sun": jf.numbers(2, jf.number(-360, 360)),
    "weather_seed": {"type": "integer", "minimum": 0, "maximum": MAX_SEED},
}, required=["params"])


@dataclass(frozen=True)
class CloudScene:
    params: CloudParams
    sun: tuple[float, float] | None
    weather_seed: int | None


def load(path: str | os.PathLike) -> CloudScene:
    """Parse and validate the whole file, then every value through the model, before anything changes."""
    data = jf.read_versioned(path, FORMAT, VERSION, CloudSceneError, VALIDATOR)
    try:
        params = CloudParams().with_values(data["params"])
    except ParamError as exc:
        raise CloudSceneError(f"{path}: params: {exc}") from None
    sun = data.get("sun")
    if sun is not None and not -90 <= sun[1] <= 90:
        raise CloudSceneError(f"{path}: sun: the elevation must be within -90..90, got {sun[1]:g}")
    return CloudScene(params, None if sun is None else (float(sun[0]), float(sun[1])), data.get("weather_seed"))


def save(path: str | os.PathLike, scene: CloudScene) -> None:
    data: dict = {"format": FORMAT, "version": VERSION, "params": scene.params.values()}
    if scene.sun is not None:
        data["sun"] = list(scene.sun)
    if scene.weather_seed is not None:
        data["weather_seed"] = scene.weather_seed
    write_text(path, json.dumps(data, indent=2) + "\n")
