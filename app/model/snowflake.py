"""Koch snowflake scene (seed 003, G80test): flake centres plus one global, possibly fractional, level."""
from __future__ import annotations

import hashlib
import math
from dataclasses import dataclass, replace

import numpy as np

MAX_LEVEL = 8.0  # 3 * 4**8 segments per flake: already more than a screen can show
# Segments a frame draws, all flakes together: the bench's 64 flakes at level 7 (3.1 million) fit, and so do 21 at
# level 8. Each flake and level is cheap alone; 4,096 flakes at level 8 (805 million) took minutes a frame.
MAX_SEGMENTS = 1 << 22


class SceneError(ValueError):
    """A value the snowflake scene refuses; the message is meant for the user."""


@dataclass(frozen=True)
class Flake:
    x: float
    y: float
    radius: float  # circumradius of the level-0 triangle

    def __post_init__(self) -> None:
        if not all(math.isfinite(v) for v in (self.x, self.y, self.radius)):
            raise SceneError(f"flake values must be finite, got ({self.x}, {self.y}, {self.radius})")
        if self.radius <= 0:
            raise SceneError(f"flake radius must be > 0, got {self.radius}")


def segment_count(flakes: int, level: float) -> int:
    """Segments drawn for `flakes` flakes at `level`: 3 * 4**ceil(level) each."""
    return flakes * 3 * 4 ** math.ceil(level)


def check_level(flakes: int, level: float) -> None:
    """SceneError unless `level` is within 0..MAX_LEVEL and `flakes` flakes at it keep to the segment budget."""
    if not (0.0 <= level <= MAX_LEVEL):
        raise SceneError(f"level must be within 0..{MAX_LEVEL:g}, got {level:g}")
    count = segment_count(flakes, level)
    if count > MAX_SEGMENTS:
        raise SceneError(f"{flakes} flakes at level {level:g} draw {count:,} segments, more than the budget of "
                         f"{MAX_SEGMENTS:,} (flakes x 3 x 4^level); use fewer flakes or a lower level")


def split_level(level: float) -> tuple[int, float]:
    """(m, t): subdivide m times, the last subdivision's peak scaled by t in (0, 1].

    Level 2.25 = level 3 with the newest bumps at a quarter of their height, so it lies
    between levels 2 (t -> 0) and 3 (t = 1) and matches both exactly at integers.
    """
    m = math.ceil(level)
    if m == 0:
        return 0, 1.0
    return m, level - (m - 1)


@dataclass(frozen=True, eq=False)
class SnowflakeScene:
    """Flakes and the level, a frozen value: an edit returns a new scene, so a scene is its own version (hosts
    redraw when the scene is another object, undo keeps the scenes themselves) and the flakes tuple is shared
    by scenes that differ only in level (the renderer uploads flakes only when that tuple changes)."""
    flakes: tuple[Flake, ...] = ()
    level: float = 2.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "flakes", tuple(self.flakes))
        object.__setattr__(self, "level", float(self.level))
        check_level(len(self.flakes), self.level)

    def with_level(self, level: float) -> SnowflakeScene:
        return replace(self, level=level)

    def added(self, x: float, y: float, radius: float) -> SnowflakeScene:
        """The scene with a new flake last (its index: the old scene's flake count)."""
        return replace(self, flakes=(*self.flakes, Flake(float(x), float(y), float(radius))))

    def moved(self, index: int, x: float, y: float) -> SnowflakeScene:
        old = self.flakes[self._check(index)]
        return replace(self, flakes=_put(self.flakes, index, Flake(float(x), float(y), old.radius)))

    def removed(self, index: int) -> SnowflakeScene:
        self._check(index)
        return replace(self, flakes=self.flakes[:index] + self.flakes[index + 1:])

    def cleared(self) -> SnowflakeScene:
        return replace(self, flakes=())

    def pick(self, x: float, y: float, slack: float) -> int | None:
        """The nearest flake whose inner half, or a `slack` radius round its centre, holds (x, y)."""
        best = None
        for i, f in enumerate(self.flakes):
            d = math.hypot(f.x - x, f.y - y)
            if d <= max(slack, 0.5 * f.radius) and (best is None or d < best[0]):
                best = (d, i)
        return None if best is None else best[1]

    def instances(self) -> np.ndarray:
        """Per-flake GPU attributes: x, y, radius as float32 rows."""
        return np.array([(f.x, f.y, f.radius) for f in self.flakes], dtype="f4").reshape(-1, 3)

    def digest(self) -> str:
        h = hashlib.sha256(f"level={self.level!r}".encode())
        for f in self.flakes:
            h.update(f"{f.x!r},{f.y!r},{f.radius!r};".encode())
        return h.hexdigest()[:16]

    def _check(self, index: int) -> int:
        if not 0 <= index < len(self.flakes):
            raise SceneError(f"no flake {index} (there are {len(self.flakes)})")
        return index


def _put(items: tuple, index: int, item) -> tuple:
    return items[:index] + (item,) + items[index + 1:]


def default_scene() -> SnowflakeScene:
    """The embedded scene the editor opens on: one large flake ringed by six small ones."""
    angles = (math.pi / 6 + k * math.pi / 3 for k in range(6))
    ring = (Flake(0.95 * math.cos(a), 0.95 * math.sin(a), 0.18) for a in angles)
    return SnowflakeScene((Flake(0.0, 0.0, 0.55), *ring), 4.0)
