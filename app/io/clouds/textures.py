"""The clouds' noise textures, made once per machine (app.model.clouds.noise, blue_noise) and cached on disk
(app.io.clouds.noise_cache), loaded once per process. Making them takes a few seconds the very first time: the
editor shows a progress bar, `shadelab render` and `bench` print one; nothing makes them at start-up."""
from __future__ import annotations

from dataclasses import dataclass
from functools import partial
from pathlib import Path
from typing import Callable

import numpy as np

from app.io.cache import cache_root
from app.io.clouds.noise_cache import load_or_build
from app.model.clouds import noise as cloud_noise
from app.model.clouds.blue_noise import blue_noise

Progress = Callable[[str, float], None]  # (texture name, fraction of it done)


@dataclass(frozen=True)
class NoiseTextures:
    shape: np.ndarray
    detail: np.ndarray
    curl: np.ndarray
    cirrus: np.ndarray
    blue: np.ndarray


# name: (recipe version, shape, the range of its values, builder taking a progress callback or None)
RECIPES = {
    "shape": (1, (128, 128, 128), (0.0, 1.0), lambda progress: cloud_noise.shape_noise(128, progress=progress)),
    "detail": (1, (32, 32, 32), (0.0, 1.0), lambda progress: cloud_noise.detail_noise(32, progress=progress)),
    "curl": (1, (128, 128, 2), (-1.0, 1.0), lambda progress: cloud_noise.curl_noise(128, progress=progress)),
    "cirrus": (1, (256, 256), (0.0, 1.0), lambda progress: cloud_noise.cirrus_noise(256, progress=progress)),
    "blue": (1, (64, 64), (0.0, 1.0), lambda progress: blue_noise(64)),
}
_loaded: dict[Path, NoiseTextures] = {}


def noise_dir() -> Path:
    return cache_root() / "noise"


def noise_textures(progress: Progress | None = None, cache_dir: Path | None = None,
                   warn: Callable[[str], None] | None = None) -> NoiseTextures:
    """The textures, from this process's copy, else the disk cache, else built (reporting `progress`); a cached
    one that cannot be used (damaged, or with values outside its range) is made again and said to `warn`."""
    folder = cache_dir or noise_dir()
    if folder not in _loaded:
        arrays = {}
        for name, (version, shape, within, build) in RECIPES.items():
            report = None if progress is None else partial(progress, name)
            arrays[name] = load_or_build(name, partial(build, report), folder, version, shape=shape, within=within,
                                         warn=warn)
            if progress is not None:
                progress(name, 1.0)
        _loaded[folder] = NoiseTextures(**arrays)
    return _loaded[folder]

