"""Where Shadelab keeps what it can make again (preprocessed shaders, noise textures): never beside the
sources, which may be read-only."""
from __future__ import annotations

import os
from pathlib import Path


def cache_root() -> Path:
    """$SHADELAB_CACHE_DIR, else $XDG_CACHE_HOME/shadelab, else ~/.cache/shadelab."""
    if explicit := os.environ.get("SHADELAB_CACHE_DIR"):
        return Path(explicit)
    base = os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache"
    return Path(base) / "shadelab"
