"""Where the shipped resources live (shaders, configs, scenes), beside the package."""
from pathlib import Path

RESOURCES = Path(__file__).resolve().parent.parent / "resources"
SHADERS = RESOURCES / "shaders"
SCENES = RESOURCES / "scenes"


def shipped(path: str | Path) -> bool:
    """Whether `path` lies among the shipped resources (a sample scene): never saved over, nor the user's folder."""
    return Path(path).is_relative_to(RESOURCES)
