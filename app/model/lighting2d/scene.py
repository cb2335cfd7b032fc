"""2D lights and hulls (seed 000, Penumbra): every property with its constraint, validity, winding,
local -> world transforms. numpy only. Lights, hulls and scenes are values: an edit makes a new one (undo keeps
the old ones as they are), and what a hull's points imply (validity, convex pieces) is worked out once.

Conventions: world units, y up; angles in radians; colours are (r, g, b) floats 0..1 (alpha ignored,
as in Penumbra)."""
from __future__ import annotations

import hashlib
import math
from dataclasses import dataclass, field, replace
from functools import cached_property, lru_cache

import numpy as np
import shapely

SHADOW_TYPES = ("solid", "illuminated", "occluded")
LIGHT_KINDS = ("point", "spot", "textured")
SHADOW_METHODS = ("hard", "penumbra", "jitter", "blur", "exact")  # how soft shadows are drawn; exact is the default


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


def signed_area(points: np.ndarray) -> float:
    x, y = points[:, 0], points[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))


def centroid(points: np.ndarray) -> tuple[float, float]:
    """A polygon's area centroid; its points' mean where it has no area (too few points, all on a line)."""
    x, y = points[:, 0], points[:, 1]
    cross = x * np.roll(y, -1) - np.roll(x, -1) * y
    area = 0.5 * float(cross.sum())
    if len(points) < 3 or abs(area) <= 1e-12 * float(np.ptp(points, axis=0).prod()):
        mean = points.mean(axis=0)
        return float(mean[0]), float(mean[1])
    return (float(((x + np.roll(x, -1)) * cross).sum()) / (6 * area),
            float(((y + np.roll(y, -1)) * cross).sum()) / (6 * area))


def validity(points: np.ndarray) -> str | None:
    """None for a valid hull, else the reason: fewer than 3 points, no area, or edges that cross.
    GEOS decides simplicity in O(n log n), so 1,000-vertex hulls validate in well under a millisecond."""
    n = len(points)
    if n < 3:
        return f"a hull needs at least 3 points, it has {n}"
    centred = points - points.mean(axis=0)
    if np.linalg.matrix_rank(centred, tol=1e-9 * max(1.0, float(np.abs(centred).max()))) < 2:
        return "all points are collinear (no area)"
    ring = shapely.LinearRing(points)
    if not shapely.is_simple(ring):
        where = shapely.is_valid_reason(shapely.Polygon(points)).partition("[")[2].rstrip("]").split()
        at = f" near ({float(where[0]):g}, {float(where[1]):g})" if len(where) == 2 else ""
        return f"edges cross{at} (not a simple polygon)"
    if abs(signed_area(points)) < 1e-12 * max(1.0, float(np.abs(centred).max())) ** 2:
        return "the outline encloses no area"
    return None


def inside_convex(points: np.ndarray, piece: np.ndarray, tol: float = 0.0) -> np.ndarray:
    """Which points (n, 2) lie inside a convex counter-clockwise piece, or within tol (relative to
    its edges' lengths) outside it."""
    e = np.roll(piece, -1, axis=0) - piece
    cross = (e[None, :, 0] * (points[:, None, 1] - piece[None, :, 1])
             - e[None, :, 1] * (points[:, None, 0] - piece[None, :, 0]))
    return np.all(cross >= -tol * np.hypot(e[:, 0], e[:, 1])[None, :], axis=1)


def outlines_overlap(outlines: list[np.ndarray]) -> bool:
    """Do two of the (valid) outlines share interior? Their union is then smaller than their areas' sum."""
    if len(outlines) < 2:
        return False
    polygons = [shapely.Polygon(outline) for outline in outlines]
    areas = shapely.area(polygons)
    return bool(shapely.union_all(polygons).area < areas.sum() - 1e-9 * areas.max())


def distance_to_convex(points: np.ndarray, piece: np.ndarray) -> np.ndarray:
    """Distance from each point (n, 2) to a convex counter-clockwise piece (0 inside it)."""
    e = np.roll(piece, -1, axis=0) - piece
    t = np.einsum("pkd,kd->pk", points[:, None, :] - piece[None], e) / np.maximum(np.einsum("kd,kd->k", e, e), 1e-300)
    nearest = piece[None] + np.clip(t, 0.0, 1.0)[..., None] * e[None]
    dist = np.linalg.norm(points[:, None, :] - nearest, axis=2).min(axis=1)
    return np.where(inside_convex(points, piece), 0.0, dist)


def is_convex(points: np.ndarray) -> bool:
    """Counter-clockwise points turning left (or straight) at every corner."""
    d = np.roll(points, -1, axis=0) - points
    turns = d[:, 0] * np.roll(d, -1, axis=0)[:, 1] - d[:, 1] * np.roll(d, -1, axis=0)[:, 0]
    return bool(np.all(turns >= -1e-12 * float(np.abs(d).max()) ** 2))


def convex_pieces(points: np.ndarray) -> list[np.ndarray]:
    """A valid counter-clockwise polygon as convex counter-clockwise pieces whose union is the polygon:
    itself when convex, else a constrained triangulation merged greedily across diagonals while the
    merge stays convex (Hertel-Mehlhorn: at most 4x the minimum number of pieces)."""
    if is_convex(points):
        return [points]
    index = {tuple(p): i for i, p in enumerate(points.tolist())}
    pieces = []
    for tri in shapely.constrained_delaunay_triangles(shapely.Polygon(points)).geoms:
        ids = [index[tuple(p)] for p in np.asarray(tri.exterior.coords)[:3].tolist()]
        if signed_area(points[ids]) < 0:
            ids.reverse()
        pieces.append(ids)
    owner = {}
    for k, ids in enumerate(pieces):
        owner.update({(a, b): k for a, b in zip(ids, ids[1:] + ids[:1])})
    alive = dict(enumerate(pieces))
    for (a, b), k in list(owner.items()):
        p, q = owner[(a, b)], owner.get((b, a))
        if q is None or p == q or a > b:
            continue  # a boundary edge, or each diagonal once
        joined = _join(alive[p], alive[q], a, b)
        if is_convex(points[joined]):
            alive[p] = joined
            del alive[q]
            owner.update({(u, v): p for u, v in zip(joined, joined[1:] + joined[:1])})
    pieces = list(alive.values())
    return [points[ids] for ids in pieces]


def _join(first: list[int], second: list[int], a: int, b: int) -> list[int]:
    """Merge two ccw index loops: `first` holds the edge a->b, `second` the same edge as b->a."""
    i = first.index(b)
    j = second.index(a)
    return first[i:] + first[:i] + (second[j:] + second[:j])[1:-1]


def _read_only(array: np.ndarray) -> np.ndarray:
    array.flags.writeable = False
    return array


@dataclass(frozen=True, eq=False)
class Outline:
    """A hull's local points, counter-clockwise, with their validity and (once asked) their convex pieces."""
    points: np.ndarray
    invalid_reason: str | None

    @cached_property
    def pieces(self) -> list[np.ndarray]:
        return [_read_only(p) for p in convex_pieces(self.points)] if self.invalid_reason is None else []


@lru_cache(maxsize=256)
def outline_of(data: bytes) -> Outline:
    """The outline of the points (float64 x, y pairs as bytes), kept for the hulls that share them: a hull moved,
    turned or disabled is a new value, but its points are validated and decomposed once."""
    points = np.frombuffer(data, np.float64).reshape(-1, 2)
    reason = validity(points)
    if reason is None and signed_area(points) < 0:
        # Penumbra detects the winding and normalises to counter-clockwise: the outline of those points, which
        # a hull made from this one's (moved, say) looks up
        return outline_of(np.ascontiguousarray(points[::-1]).tobytes())
    return Outline(_read_only(points.copy()), reason)


@dataclass(frozen=True, eq=False)
class Hull:
    """A polygon light cannot pass. Points are local; the world outline follows position, origin,
    rotation and scale. Points may come clockwise: they are stored counter-clockwise. A value: an edit
    (`dataclasses.replace`) makes a new hull, whose world outline is worked out again when asked."""

    points: np.ndarray
    position: tuple[float, float] = (0.0, 0.0)
    origin: tuple[float, float] = (0.0, 0.0)
    rotation: float = 0.0
    scale: tuple[float, float] = (1.0, 1.0)
    enabled: bool = True
    outline: Outline = field(init=False, repr=False)

    def __post_init__(self) -> None:
        pts = np.asarray(self.points, dtype=np.float64).reshape(-1, 2)
        _finite("hull points", *pts.ravel())
        _finite("hull position", *self.position)
        _finite("hull origin", *self.origin)
        _finite("hull rotation", self.rotation)
        _non_negative("hull scale", *self.scale)
        shape = outline_of(np.ascontiguousarray(pts).tobytes())
        for name, value in (("outline", shape), ("points", shape.points),
                            ("position", tuple(map(float, self.position))), ("origin", tuple(map(float, self.origin))),
                            ("rotation", float(self.rotation)), ("scale", tuple(map(float, self.scale)))):
            object.__setattr__(self, name, value)

    @property
    def invalid_reason(self) -> str | None:
        """None for a valid hull, else why it is not (it is kept, marked, and casts no shadow)."""
        return self.outline.invalid_reason

    @property
    def valid(self) -> bool:
        return self.invalid_reason is None

    def to_world(self, local: np.ndarray) -> np.ndarray:
        c, s = math.cos(self.rotation), math.sin(self.rotation)
        return ((local - self.origin) * self.scale) @ np.array([[c, s], [-s, c]]) + self.position

    def world(self) -> np.ndarray:
        """World points (n, 2), worked out once per hull."""
        return self._world

    @cached_property
    def _world(self) -> np.ndarray:
        return _read_only(self.to_world(self.points))

    @cached_property
    def _world_pieces(self) -> list[np.ndarray]:
        return [_read_only(self.to_world(p)) for p in self.outline.pieces]

    def world_pieces(self) -> list[np.ndarray]:
        """Convex counter-clockwise world pieces covering the hull (one when it is convex; none when it is
        invalid); the decomposition is the outline's, so a moved hull only transforms it again."""
        return self._world_pieces

    @cached_property
    def _bounds(self) -> tuple[float, float, float, float]:
        pts = self.world()
        (x0, y0), (x1, y1) = pts.min(axis=0), pts.max(axis=0)
        return float(x0), float(y0), float(x1), float(y1)

    def bounds(self) -> tuple[float, float, float, float]:
        """The world outline's box, kept like the outline (the scene index asks every hull's after an edit)."""
        return self._bounds

    def contains(self, x: float, y: float) -> bool:
        """Even-odd test on the world outline (a light inside a hull is not drawn)."""
        pts = self.world()
        xs, ys = pts[:, 0], pts[:, 1]
        xj, yj = np.roll(xs, 1), np.roll(ys, 1)
        with np.errstate(divide="ignore", invalid="ignore"):
            crosses = ((ys > y) != (yj > y)) & (x < (xj - xs) * (y - ys) / (yj - ys) + xs)
        return bool(np.count_nonzero(crosses) % 2)


@dataclass(frozen=True)
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
        color = _colour("light color", self.color)
        if self.kind == "textured" and not self.texture:
            raise Lighting2DError("a textured light needs a texture")
        normal = {"color": color, "position": tuple(map(float, self.position)),
                  "origin": tuple(map(float, self.origin)), "scale": tuple(map(float, self.scale)),
                  # 18 and 18.0 are one value
                  **{name: float(getattr(self, name)) for name in ("rotation", "intensity", "radius", "cone_decay",
                                                                   "height")},
                  "enabled": bool(self.enabled), "casts_shadows": bool(self.casts_shadows),
                  "ignored_hulls": tuple(int(i) for i in self.ignored_hulls)}
        for name, value in normal.items():
            object.__setattr__(self, name, value)

    def cone_half_angle(self) -> float:
        """Penumbra's spot cone: alpha = pi - 2 atan(2x / y) from the quad's sides; half of it."""
        x, y = self.scale
        return 0.5 * (math.pi - 2.0 * math.atan2(2.0 * x, y))


def _index(index: int, count: int, what: str) -> int:
    if not 0 <= index < count:
        raise Lighting2DError(f"no {what} {index}; there are {count}")
    return index


@dataclass(frozen=True, eq=False)
class Scene2D:
    """The lights and hulls and what they are drawn over. A value: every edit (`with_*`, `add_*`, `remove_*`,
    `dataclasses.replace`) returns a new scene, so a scene's identity is its version (the index, the renderer
    and the document digest key their caches on it) and undo keeps the scenes themselves."""
    ambient: tuple[float, float, float] = (0.15, 0.15, 0.18)
    lights: tuple[Light, ...] = ()
    hulls: tuple[Hull, ...] = ()
    view: tuple[float, float, float] = (0.0, 0.0, 500.0)   # centre x, y and world height shown
    background: str = "builtin:tiles"   # the diffuse map the lightmap multiplies: a builtin or a PNG
    normal_map: str | None = None       # optional normals for height-lit lights: a builtin or a PNG

    def __post_init__(self) -> None:
        ambient = _colour("ambient color", self.ambient)
        _finite("view", *self.view)
        if len(self.view) != 3 or self.view[2] <= 0:
            raise Lighting2DError(f"view must be (centre x, centre y, height > 0), got {self.view!r}")
        if not isinstance(self.background, str) or not self.background:
            raise Lighting2DError("background must be a builtin name or an image path")
        lights, hulls = tuple(self.lights), tuple(self.hulls)
        if not all(isinstance(light, Light) for light in lights) or not all(isinstance(h, Hull) for h in hulls):
            raise Lighting2DError("a 2D scene holds Light lights and Hull hulls")
        for name, value in (("ambient", ambient), ("lights", lights),
                            ("hulls", hulls), ("view", tuple(float(v) for v in self.view))):
            object.__setattr__(self, name, value)

    def images(self) -> list[tuple[str, str]]:
        """(field, name) of every image the scene names: the background, the normal map and the lights' textures."""
        named = [("background", self.background), ("normal_map", self.normal_map),
                 *((f"lights[{i}].texture", light.texture) for i, light in enumerate(self.lights))]
        return [(where, name) for where, name in named if name]

    def with_light(self, index: int, light: Light) -> Scene2D:
        i = _index(index, len(self.lights), "light")
        return replace(self, lights=self.lights[:i] + (light,) + self.lights[i + 1:])

    def with_hull(self, index: int, hull: Hull) -> Scene2D:
        i = _index(index, len(self.hulls), "hull")
        return replace(self, hulls=self.hulls[:i] + (hull,) + self.hulls[i + 1:])

    def add_light(self, light: Light) -> Scene2D:
        return replace(self, lights=self.lights + (light,))

    def add_hull(self, hull: Hull) -> Scene2D:
        return replace(self, hulls=self.hulls + (hull,))

    def remove_light(self, index: int) -> Scene2D:
        i = _index(index, len(self.lights), "light")
        return replace(self, lights=self.lights[:i] + self.lights[i + 1:])

    def remove_hull(self, index: int) -> Scene2D:
        """The scene without hull `index`; the lights' ignored hulls follow the hulls that stay."""
        i = _index(index, len(self.hulls), "hull")
        lights = tuple(light if not light.ignored_hulls else
                       replace(light, ignored_hulls=tuple(k - (k > i) for k in light.ignored_hulls if k != i))
                       for light in self.lights)
        return replace(self, lights=lights, hulls=self.hulls[:i] + self.hulls[i + 1:])

    def cleared(self) -> Scene2D:
        """No lights, no hulls; the ambient, view and images stay."""
        return replace(self, lights=(), hulls=())

    def digest(self) -> str:
        h = hashlib.sha256(repr((self.ambient, self.background, self.normal_map)).encode())
        for light in self.lights:
            h.update(repr(sorted(vars(light).items())).encode())
        for hull in self.hulls:
            h.update(hull.points.tobytes())
            h.update(repr((hull.position, hull.origin, hull.rotation, hull.scale, hull.enabled)).encode())
        return h.hexdigest()[:16]


@dataclass(frozen=True)
class Shading2D:
    """The 2D renderer's settings (built from cvars by the commands, or by a bench)."""
    method: str = "exact"
    samples: int = 16             # jitter: hard shadows averaged
    blur: float = 0.5             # blur: Gaussian sigma as a share of the light's radius
    lightmap_scale: float = 1.0   # the lightmap's resolution relative to the screen
    flip_y: bool = False          # a y-down world (screen coordinates), as with Penumbra's SpriteBatch transform
    normal_maps: bool = True
    debug: bool = False           # the editor's overlay: hulls, lights and their reach as wireframe
    overlays: bool = True         # the editor's marks: light icons, hull outlines, the selection (not in a render)
