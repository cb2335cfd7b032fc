"""Argument checks shared by the volume's commands: the painter's colour verbs (app/commands/volume.py) and its
label verbs (app/commands/volume_labels.py). Each returns what it checked, or raises CommandError."""
from __future__ import annotations

from app.console.console import Console
from app.console.registry import CommandError
from app.model.volume.painting import MAX_COORD
from app.model.volume.voxels import AXES, MAX_SIDE, Voxels


def check_rgba(r: int, g: int, b: int, a: int) -> tuple[int, int, int, int]:
    rgba = (r, g, b, a)
    if not all(0 <= c <= 255 for c in rgba):
        raise CommandError(f"colour components must be 0..255, got {' '.join(map(str, rgba))}")
    return rgba


def check_axis(axis: str) -> str:
    if axis not in AXES:
        raise CommandError(f"axis must be x, y or z, got {axis!r}")
    return axis


def check_tolerance(tolerance: int) -> int:
    if not 0 <= tolerance <= 255:
        raise CommandError(f"fill tolerance must be within 0..255, got {tolerance}")
    return tolerance


def stroke_points(coords: list[int]) -> list[tuple[int, int]]:
    if not coords or len(coords) % 2:
        raise CommandError("give the stroke's points as x1 y1 [x2 y2 ...]")
    if max(map(abs, coords)) > MAX_COORD:
        raise CommandError(f"stroke points must be within -{MAX_COORD}..{MAX_COORD}")
    return list(zip(coords[0::2], coords[1::2]))


def check_brush(voxels: Voxels, axis: str, index: int, size: int) -> None:
    """A brush of `size` on slice `index` along `axis` of these voxels."""
    voxels.slice(check_axis(axis), index)  # refuses an index past the depth
    if not 1 <= size <= MAX_SIDE:
        raise CommandError(f"brush size must be within 1..{MAX_SIDE}, got {size}")


def round_brush(console: Console) -> bool:
    return console.registry.cvars["brush_round"].value
