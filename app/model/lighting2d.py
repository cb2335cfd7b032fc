"""2D lights and hulls (seed 000, Penumbra): every property with its constraint, validity, winding,
local -> world transforms with dirty flags. numpy only.

Conventions: world units, y up; angles in radians; colours are (r, g, b) floats 0..1 (alpha ignored,
as in Penumbra)."""
from __future__ import annotations

import hashlib
import math
from dataclasses import dataclass, field

import numpy as np

SHADOW_TYPES = ("solid", "illuminated", "occluded")
LIGHT_KINDS = ("point", "spot", "textured")


class Lighting2DError(ValueError):
    """A value the 2D lighting model refuses; the message is for the user."""


def _finite(name: str, *values: float) -> None:
    if not all(math.isfinite(v) for v in values):
        raise Lighting2DError(f"{name} must be finite, got {values if len(values) > 1 else values[0]}")


def _non_negative(name: str, *values: float) -> None:
    _finite(name, *values)
    if any(v < 0 for v in values):
        raise Lighting2DError(f"{name} must be >= 0, got {values if len(values) > 1 else values[0]}")


def _colour(name: str, rgb) -> tuple[float, float, float]:
    try:
        r, g, b = (float(c) for c in rgb)
    except (TypeError, ValueError):
        raise Lighting2DError(f"{name} must be three numbers, got {rgb!r}") from None
    _finite(name, r, g, b)
    if not all(0.0 <= c <= 1.0 for c in (r, g, b)):
        raise Lighting2DError(f"{name} components must be within 0..1, got ({r:g}, {g:g}, {b:g})")
    return r, g, b


def _segments_cross(p1, p2, q1, q2) -> bool:
    """Proper or touching intersection of segments p1p2 and q1q2 (collinear overlaps included)."""
    def orient(a, b, c):
        v = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
        return 0 if abs(v) < 1e-12 else (1 if v > 0 else -1)

    def on(a, b, c):
        return min(a[0], b[0]) - 1e-12 <= c[0] <= max(a[0], b[0]) + 1e-12 and \
            min(a[1], b[1]) - 1e-12 <= c[1] <= max(a[1], b[1]) + 1e-12

    o1, o2, o3, o4 = orient(p1, p2, q1), orient(p1, p2, q2), orient(q1, q2, p1), orient(q1, q2, p2)
    if o1 != o2 and o3 != o4:
        return True
    return (o1 == 0 and on(p1, p2, q1)) or (o2 == 0 and on(p1, p2, q2)) or \
        (o3 == 0 and on(q1, q2, p1)) or (o4 == 0 and on(q1, q2, p2))


def signed_area(points: np.ndarray) -> float:
    x, y = points[:, 0], points[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))


def validity(points: np.ndarray) -> str | None:
    """None for a valid hull, else the reason: fewer than 3 points, zero area, or edges that cross."""
    n = len(points)
    if n < 3:
        return f"a hull needs at least 3 points, it has {n}"
    centred = points - points.mean(axis=0)
    if np.linalg.matrix_rank(centred, tol=1e-9 * max(1.0, float(np.abs(centred).max()))) < 2:
        return "all points are collinear (no area)"
    edges = [(points[i], points[(i + 1) % n]) for i in range(n)]
    for i in range(n):
        for j in range(i + 1, n):
            if j == i + 1 or (i == 0 and j == n - 1):
                continue  # neighbours share a corner
            if _segments_cross(*edges[i], *edges[j]):
                return f"edges {i} and {j} cross (not a simple polygon)"
    if abs(signed_area(points)) < 1e-12:
        return "the outline encloses no area"
    return None


@dataclass(eq=False)
class Hull:
    """A polygon light cannot pass. Points are local; the world outline follows position, origin,
    rotation and scale. Points may come clockwise: they are stored counter-clockwise."""

    points: np.ndarray
    position: tuple[float, float] = (0.0, 0.0)
    origin: tuple[float, float] = (0.0, 0.0)
    rotation: float = 0.0
    scale: tuple[float, float] = (1.0, 1.0)
    enabled: bool = True
    invalid_reason: str | None = field(init=False, default=None)
    _world: np.ndarray | None = field(init=False, default=None, repr=False)

    def __post_init__(self) -> None:
        self.set_points(self.points)
        self.set_transform(self.position, self.origin, self.rotation, self.scale)

    @property
    def valid(self) -> bool:
        return self.invalid_reason is None

    def set_points(self, points) -> None:
        pts = np.asarray(points, dtype=np.float64).reshape(-1, 2)
        _finite("hull points", *pts.ravel())
        self.invalid_reason = validity(pts)
        if self.invalid_reason is None and signed_area(pts) < 0:
            pts = pts[::-1].copy()  # Penumbra detects the winding and normalises to counter-clockwise
        self.points = pts
        self._world = None  # dirty

    def set_transform(self, position, origin, rotation: float, scale) -> None:
        _finite("hull position", *position)
        _finite("hull origin", *origin)
        _finite("hull rotation", rotation)
        _non_negative("hull scale", *scale)
        self.position, self.origin = tuple(map(float, position)), tuple(map(float, origin))
        self.rotation, self.scale = float(rotation), tuple(map(float, scale))
        self._world = None

    def world(self) -> np.ndarray:
        """World points (n, 2), rebuilt only after a change."""
        if self._world is None:
            c, s = math.cos(self.rotation), math.sin(self.rotation)
            local = (self.points - self.origin) * self.scale
            self._world = local @ np.array([[c, s], [-s, c]]) + self.position
        return self._world

    def contains(self, x: float, y: float) -> bool:
        """Even-odd test on the world outline (a light inside a hull is not drawn)."""
        pts = self.world()
        xs, ys = pts[:, 0], pts[:, 1]
        xj, yj = np.roll(xs, 1), np.roll(ys, 1)
        with np.errstate(divide="ignore", invalid="ignore"):
            crosses = ((ys > y) != (yj > y)) & (x < (xj - xs) * (y - ys) / (yj - ys) + xs)
        return bool(np.count_nonzero(crosses) % 2)


@dataclass
class Light:
    kind: str = "point"
    position: tuple[float, float] = (0.0, 0.0)
    origin: tuple[float, float] = (0.5, 0.5)   # normalised in the light's quad; may leave 0..1
    rotation: float = 0.0
    scale: tuple[float, float] = (200.0, 200.0)  # size of the lit area
    color: tuple[float, float, float] = (1.0, 1.0, 1.0)
    intensity: float = 1.0
    radius: float = 20.0        # the emitting disc: larger = wider penumbra
    enabled: bool = True
    casts_shadows: bool = True
    shadow_type: str = "solid"
    cone_decay: float = 1.5     # spot: higher = brighter towards the cone edges
    height: float = 0.0         # above the plane, for normal-mapped lighting
    texture: str | None = None  # textured lights: intensity from the image's green channel
    ignored_hulls: tuple[int, ...] = ()

    def __post_init__(self) -> None:
        if self.kind not in LIGHT_KINDS:
            raise Lighting2DError(f"light kind must be one of {', '.join(LIGHT_KINDS)}, got {self.kind!r}")
        if self.shadow_type not in SHADOW_TYPES:
            raise Lighting2DError(f"shadow type must be one of {', '.join(SHADOW_TYPES)}, got {self.shadow_type!r}")
        _finite("light position", *self.position)
        _finite("light origin", *self.origin)
        _finite("light rotation", self.rotation)
        _non_negative("light scale", *self.scale)
        _non_negative("light intensity", self.intensity)
        _non_negative("light radius", self.radius)
        _non_negative("cone decay", self.cone_decay)
        _non_negative("light height", self.height)
        self.color = _colour("light color", self.color)
        if self.kind == "textured" and not self.texture:
            raise Lighting2DError("a textured light needs a texture")
        self.position, self.origin = tuple(map(float, self.position)), tuple(map(float, self.origin))
        self.scale = tuple(map(float, self.scale))
        self.ignored_hulls = tuple(int(i) for i in self.ignored_hulls)

    def cone_half_angle(self) -> float:
        """Penumbra's spot cone: alpha = pi - 2 atan(2x / y) from the quad's sides; half of it."""
        x, y = self.scale
        return 0.5 * (math.pi - 2.0 * math.atan2(2.0 * x, y))


@dataclass
class Scene2D:
    ambient: tuple[float, float, float] = (0.15, 0.15, 0.18)
    lights: list[Light] = field(default_factory=list)
    hulls: list[Hull] = field(default_factory=list)
    version: int = 0

    def __post_init__(self) -> None:
        self.ambient = _colour("ambient color", self.ambient)

    def touch(self) -> None:
        self.version += 1

    def digest(self) -> str:
        h = hashlib.sha256(repr(self.ambient).encode())
        for light in self.lights:
            h.update(repr(sorted(vars(light).items())).encode())
        for hull in self.hulls:
            h.update(hull.points.tobytes())
            h.update(repr((hull.position, hull.origin, hull.rotation, hull.scale, hull.enabled)).encode())
        return h.hexdigest()[:16]
