"""Where the shipped resources live (shaders, configs, scenes), beside the package."""
from pathlib import Path

RESOURCES = Path(__file__).resolve().parent.parent / "resources"
SHADERS = RESOURCES / "shaders"
SCENES = RESOURCES / "scenes"
