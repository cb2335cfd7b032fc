"""The 3D lights workspace's model (seeds 004 and 002): objects, lights, the scene holding them, the lighting
formulas both renderers use, and the orbit camera. numpy only.

Conventions: world units (the seed's scene is hundreds of units across), right-handed, +y up, the ground at
y = 0. An object's position is its mesh's centre (app/model/lights3d/mesh.py); colours are linear rgb, an object's
albedo within 0..1 and a light's colour within 0..MAX_INTENSITY. Only closed meshes cast shadows: the ground
plane receives them and casts none.

The light formulas (seed 004, a Czech XNA tutorial), per surface point P with unit shading normal N, unit
direction to the eye V, and for each light the unit direction L to it (-direction for a directional light):

    point        katt = 1 - saturate(d / r)^f       d = |Lpos - P|, r = range, f = falloff (seed default 2)
    spot         katt = 1 - saturate(a / c)^f       a = cos(angle), c = dot(normalize(P - Lpos), D), D the
                                                    unit spot direction; lit only where a < c (strictly
                                                    inside the cone), f = falloff (seed default 20)
    directional  katt = 1
    diffuse      = saturate(N . L)
    specular     = strength * saturate(N . H)^shininess, H = normalize(L + V), only where N . L > 0
    colour       = saturate(ambient * albedo + sum over lights of lit * katt * (albedo * diffuse + specular)
                            * light colour)

The spot's ratio is the tutorial's code, not its prose: the text writes katt = 1 - (dot(p - lp, ld) / cos(a))^f,
but the shader computes a = cos(angle) and d = dot(-lightDir, normalize(SpotLightDirection)) (the cosine of
the angle between the spot's axis and the direction to the pixel, called c here) and adds
`1-pow(saturate(a/d),f)*diffuse*color` where a < d. Its parentheses are misplaced: that adds 1 minus the
attenuated light, so everything inside the cone turns white. Here the whole attenuation multiplies the light,
(1 - pow(saturate(a/d), f)) * diffuse * color: 0 at the cone's edge, 1 - cos(angle)^f on its axis. The spot has
no attenuation by distance (the seed's has none), so its range is unused, as a directional light's is.

`lit` is 1 where the light reaches the point: for a light whose shadow is "none", everywhere (the formulas
alone); otherwise where the triangle's geometric normal faces the light and the segment from the point to the
light (towards a directional light, unbounded) hits no caster's triangle. Back faces are therefore in shadow,
as the stencil volumes' self-shadowing triangle (seed 002) makes them.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace
from functools import cached_property, lru_cache
from typing import ClassVar

import numpy as np

from app.model.lights3d import mesh as mesh3d
from app.model.camera3d import OrbitCamera
from app.model.lights3d.mesh import Mesh

OBJECT_KINDS = ("box", "sphere", "torus", "lprism", "plane")
# An object's size, by kind: its dimensions, then segment counts (whole numbers) where it has them.
SIZE_NAMES = {
    "box": ("sx", "sy", "sz"),
    "sphere": ("radius", "segments"),
    "torus": ("major", "minor", "segments", "sides"),
    "lprism": ("sx", "sy", "sz", "thickness"),
    "plane": ("size",),
}
COUNT_NAMES = ("segments", "sides")
LIGHT_KINDS = ("point", "spot", "directional")
# onepass: seed 002's orientation-free stencil, each triangle's volume closed; onepass-seed: open, as the seed's
SHADOW_METHODS = ("onepass", "onepass-seed", "zpass", "zfail", "map", "none")

MAX_OBJECTS = 64
MAX_LIGHTS = 8
MAX_TRIANGLES = 200_000  # the whole scene's: the bench goes to about 100k
MAX_COORD = 1e5          # positions; float32 still resolves 1/100 of a unit there
MAX_SIZE = 1e4           # an object's dimensions and a light's range
# An object's dimensions, and the gaps between them (a torus's hole, an L's arms), are at least this: the resolution
# float32 keeps at MAX_COORD. So every edge of its mesh has a length and every face an area that float64 holds
# (a box of 1e-200 has faces of area 1e-400, which is 0: its normals came out NaN and every frame failed), and the
# GPU still tells its corners apart.
MIN_SIZE = 1e-2
MAX_INTENSITY = 16.0     # a light colour's components (over-bright lights are allowed)
MAX_FALLOFF = 1000.0
MAX_SHININESS = 4096.0
MAX_SPECULAR = 16.0
BACKGROUND = (0.08, 0.09, 0.11)  # where no object is: the renderers' clear colour


class Lights3DError(ValueError):
    """A value the 3D lights model refuses; the message is for the user."""


def _floats(name: str, values, count: int) -> tuple[float, ...]:
    try:
        if isinstance(values, (str, bytes)):  # "123" would pass as three digits
            raise TypeError
        out = tuple(float(v) for v in values)
    except (TypeError, ValueError):
        raise Lights3DError(f"{name} must be {count} numbers, got {values!r}") from None
    if len(out) != count:
        raise Lights3DError(f"{name} must be {count} numbers, got {len(out)}")
    if not all(math.isfinite(v) for v in out):
        raise Lights3DError(f"{name} must be finite, got {_show(out)}")
    return out


def _show(values: tuple) -> str:
    return "(" + ", ".join(f"{v:g}" for v in values) + ")"


def _within(name: str, values: tuple, lo: float, hi: float) -> None:
    if not all(lo <= v <= hi for v in values):
        raise Lights3DError(f"{name} must be within {lo:g}..{hi:g}, got {_show(values)}")


def _number(name: str, value, lo: float, hi: float, above: bool = False) -> float:
    """One finite number within lo..hi (above: lo itself refused, as for a radius)."""
    (v,) = _floats(name, (value,), 1)
    if above and not lo < v <= hi:
        raise Lights3DError(f"{name} must be > {lo:g} and <= {hi:g}, got {v:g}")
    if not lo <= v <= hi:
        raise Lights3DError(f"{name} must be within {lo:g}..{hi:g}, got {v:g}")
    return v


def _position(name: str, values) -> tuple[float, float, float]:
    xyz = _floats(name, values, 3)
    _within(name, xyz, -MAX_COORD, MAX_COORD)
    return xyz


def _kind(what: str, kind, kinds: tuple) -> str:
    if kind not in kinds:
        raise Lights3DError(f"{what} must be one of {', '.join(kinds)}, got {kind!r}")
    return kind


# ---- objects --------------------------------------------------------------------------------------------


def triangle_count(kind: str, size: tuple) -> int:
    """Triangles of an object's mesh, known without building it."""
    if kind == "sphere":
        return mesh3d.sphere_triangles(size[1])
    if kind == "torus":
        return mesh3d.torus_triangles(size[2], size[3])
    return {"box": mesh3d.BOX_TRIANGLES, "lprism": mesh3d.LPRISM_TRIANGLES, "plane": mesh3d.PLANE_TRIANGLES}[kind]


def _size(kind: str, size) -> tuple:
    names = SIZE_NAMES[kind]
    values = _floats(f"a {kind}'s size ({', '.join(names)})", size, len(names))
    out = []
    for name, v in zip(names, values):
        if name in COUNT_NAMES:
            if v != int(v) or not mesh3d.MIN_SEGMENTS <= v <= mesh3d.MAX_SEGMENTS:
                raise Lights3DError(f"{kind} {name} must be a whole number within "
                                    f"{mesh3d.MIN_SEGMENTS}..{mesh3d.MAX_SEGMENTS}, got {v:g}")
            out.append(int(v))
        else:
            out.append(_number(f"{kind} {name}", v, MIN_SIZE, MAX_SIZE))
    if kind == "torus" and not out[1] + MIN_SIZE <= out[0]:
        raise Lights3DError(f"torus minor radius must be below its major radius by at least {MIN_SIZE:g}, got "
                            f"{out[1]:g} and {out[0]:g}")
    if kind == "lprism" and not out[3] + MIN_SIZE <= min(out[0], out[1]):
        raise Lights3DError(f"lprism thickness must be below its sx and sy by at least {MIN_SIZE:g}, got {out[3]:g}")
    triangles = triangle_count(kind, tuple(out))
    if triangles > MAX_TRIANGLES:
        raise Lights3DError(f"a {kind} of {triangles} triangles is more than {MAX_TRIANGLES}")
    return tuple(out)


@lru_cache(maxsize=32)
def local_mesh(kind: str, size: tuple) -> Mesh:
    """The object's mesh centred on the origin (cached: moving an object reuses it)."""
    build = {"box": mesh3d.box, "sphere": mesh3d.sphere, "torus": mesh3d.torus, "lprism": mesh3d.l_prism,
             "plane": mesh3d.plane}[kind]
    return build(*size)


@dataclass(frozen=True)
class Object3D:
    kind: str = "box"
    size: tuple = (30.0, 30.0, 30.0)        # by kind: SIZE_NAMES
    position: tuple = (0.0, 15.0, 0.0)      # the mesh's centre in the world
    colour: tuple = (0.8, 0.8, 0.8)         # albedo

    def __post_init__(self) -> None:
        kind = _kind("object kind", self.kind, OBJECT_KINDS)
        object.__setattr__(self, "size", _size(kind, self.size))
        object.__setattr__(self, "position", _position(f"{kind} position", self.position))
        colour = _floats(f"{kind} colour", self.colour, 3)
        _within(f"{kind} colour", colour, 0.0, 1.0)
        object.__setattr__(self, "colour", colour)

    @property
    def triangles(self) -> int:
        return triangle_count(self.kind, self.size)

    def mesh(self) -> Mesh:
        """The mesh in world space (built once per object)."""
        return self._world

    @cached_property
    def _world(self) -> Mesh:
        return local_mesh(self.kind, self.size).moved(self.position)

    @cached_property
    def radius(self) -> float:
        """The bounding sphere's radius about the position (the mesh's centre)."""
        return float(np.linalg.norm(self.mesh().positions - np.asarray(self.position), axis=1).max())

    @cached_property
    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """The bounding box's lowest and highest corners."""
        positions = self.mesh().positions
        return positions.min(0), positions.max(0)


# A new object's size where none is given (object.add), by kind.
DEFAULT_SIZES = {"box": (30.0, 30.0, 30.0), "sphere": (15.0, 32), "torus": (20.0, 6.0, 48, 16),
                 "lprism": (40.0, 40.0, 16.0, 12.0), "plane": (400.0,)}


def new_object(kind: str, position=None, size=None) -> Object3D:
    """An object of `kind`, DEFAULT_SIZES[kind] where no size is given; where no position is given it stands on
    the ground at the origin (its mesh's lowest point at y = 0: a box half its height up, a plane at y = 0)."""
    kind = _kind("object kind", kind, OBJECT_KINDS)
    size = _size(kind, DEFAULT_SIZES[kind] if size is None else size)
    if position is None:
        position = (0.0, 0.0 - float(local_mesh(kind, size).positions[:, 1].min()), 0.0)  # 0 - 0: no -0 shown
    return Object3D(kind, size, position)


# ---- lights ---------------------------------------------------------------------------------------------


def _direction(name: str, values) -> tuple[float, float, float]:
    xyz = _floats(name, values, 3)
    length = math.hypot(*xyz)
    if length == 0:
        raise Lights3DError(f"{name} must not be zero")
    # Unit vectors pass unchanged, so a saved direction loads bit for bit.
    return xyz if abs(length - 1.0) < 1e-12 else tuple(v / length for v in xyz)


@dataclass(frozen=True)
class Light3D:
    kind: str = "point"
    position: tuple = (0.0, 100.0, 0.0)
    direction: tuple = (0.0, -1.0, 0.0)   # unit (normalised on the way in): where a spot or directional light shines
    colour: tuple = (1.0, 1.0, 1.0)
    range: float = 100.0                  # r: a point light's reach (katt falls to 0 there)
    falloff: float = 2.0                  # f: the attenuation's exponent
    angle: float = 15.0                   # a spot's half-angle, degrees
    shadow: str = "onepass"               # SHADOW_METHODS

    def __post_init__(self) -> None:
        kind = _kind("light kind", self.kind, LIGHT_KINDS)
        object.__setattr__(self, "position", _position(f"{kind} light position", self.position))
        object.__setattr__(self, "direction", _direction(f"{kind} light direction", self.direction))
        colour = _floats(f"{kind} light colour", self.colour, 3)
        _within(f"{kind} light colour", colour, 0.0, MAX_INTENSITY)
        object.__setattr__(self, "colour", colour)
        object.__setattr__(self, "range", _number("light range", self.range, 0.0, MAX_SIZE, above=True))
        object.__setattr__(self, "falloff", _number("light falloff", self.falloff, 0.0, MAX_FALLOFF, above=True))
        angle = _number("spot angle", self.angle, 0.0, 90.0, above=True)
        if angle == 90.0:
            raise Lights3DError("spot angle must be below 90 degrees (a half-angle), got 90")
        object.__setattr__(self, "angle", angle)
        _kind("shadow method", self.shadow, SHADOW_METHODS)


# ---- the scene ------------------------------------------------------------------------------------------


def _index(i, count: int, what: str) -> int:
    if not isinstance(i, (int, np.integer)) or isinstance(i, bool) or not 0 <= i < count:
        raise Lights3DError(f"no {what} {i!r} (there {'is' if count == 1 else 'are'} {count})")
    return int(i)


def _replaced(thing, what: str, changes: dict):
    try:
        return replace(thing, **changes)
    except TypeError:
        names = [f for f in type(thing).__dataclass_fields__ if f not in changes]
        unknown = sorted(set(changes) - set(type(thing).__dataclass_fields__))
        raise Lights3DError(f"{what} has no {', '.join(unknown)} (it has {', '.join(names)})") from None


@dataclass(frozen=True)
class Scene3D:
    objects: tuple = ()
    lights: tuple = ()
    ambient: tuple = (0.1, 0.1, 0.1)
    shininess: float = 32.0
    specular: float = 0.5            # the specular strength

    def __post_init__(self) -> None:
        try:
            objects, lights = tuple(self.objects), tuple(self.lights)
        except TypeError:
            raise Lights3DError("a scene's objects and lights must be sequences") from None
        if not all(isinstance(o, Object3D) for o in objects) or not all(isinstance(li, Light3D) for li in lights):
            raise Lights3DError("a scene holds Object3D objects and Light3D lights")
        if len(objects) > MAX_OBJECTS:
            raise Lights3DError(f"a scene holds at most {MAX_OBJECTS} objects, got {len(objects)}")
        if len(lights) > MAX_LIGHTS:
            raise Lights3DError(f"a scene holds at most {MAX_LIGHTS} lights, got {len(lights)}")
        triangles = sum(o.triangles for o in objects)
        if triangles > MAX_TRIANGLES:
            raise Lights3DError(f"the scene's objects have {triangles} triangles, more than {MAX_TRIANGLES}")
        object.__setattr__(self, "objects", objects)
        object.__setattr__(self, "lights", lights)
        ambient = _floats("ambient", self.ambient, 3)
        _within("ambient", ambient, 0.0, 1.0)
        object.__setattr__(self, "ambient", ambient)
        object.__setattr__(self, "shininess", _number("shininess", self.shininess, 0.0, MAX_SHININESS, above=True))
        object.__setattr__(self, "specular", _number("specular strength", self.specular, 0.0, MAX_SPECULAR))

    @property
    def triangles(self) -> int:
        return sum(o.triangles for o in self.objects)

    def with_object(self, i: int, **changes) -> Scene3D:
        """Object i with `changes` (kind, size, position, colour), all checked, or Lights3DError."""
        i = _index(i, len(self.objects), "object")
        changed = _replaced(self.objects[i], "an object", changes)
        return replace(self, objects=self.objects[:i] + (changed,) + self.objects[i + 1:])

    def with_object_moved(self, i: int, xyz) -> Scene3D:
        return self.with_object(i, position=xyz)

    def with_light(self, i: int, **changes) -> Scene3D:
        """Light i with `changes` (any Light3D field), all checked, or Lights3DError."""
        i = _index(i, len(self.lights), "light")
        changed = _replaced(self.lights[i], "a light", changes)
        return replace(self, lights=self.lights[:i] + (changed,) + self.lights[i + 1:])

    def with_settings(self, **changes) -> Scene3D:
        """The scene with ambient, shininess or specular changed."""
        if set(changes) - {"ambient", "shininess", "specular"}:
            raise Lights3DError(f"the scene's settings are ambient, shininess and specular, not "
                                f"{', '.join(sorted(set(changes) - {'ambient', 'shininess', 'specular'}))}")
        return replace(self, **changes)

    def add_object(self, obj: Object3D) -> Scene3D:
        return replace(self, objects=self.objects + (obj,))

    def add_light(self, light: Light3D) -> Scene3D:
        return replace(self, lights=self.lights + (light,))

    def remove_object(self, i: int) -> Scene3D:
        i = _index(i, len(self.objects), "object")
        return replace(self, objects=self.objects[:i] + self.objects[i + 1:])

    def remove_light(self, i: int) -> Scene3D:
        i = _index(i, len(self.lights), "light")
        return replace(self, lights=self.lights[:i] + self.lights[i + 1:])


def default_scene() -> Scene3D:
    """Seed 004's two lights over a ground 400 units wide, with objects each light shadows onto the ground
    and onto another object: the sphere shades the box from both lights, the torus and the L-prism throw the
    point light's shadow on the ground, and the spot's cone reaches them all but the torus."""
    spot_axis = (-200.0, -150.0, 0.0)  # the seed's: from (200, 150, 0) to the origin
    return Scene3D(
        objects=(
            Object3D("plane", (400.0,), (0.0, 0.0, 0.0), (0.75, 0.75, 0.72)),
            Object3D("box", (30.0, 30.0, 30.0), (-25.0, 15.0, 0.0), (0.85, 0.35, 0.25)),
            Object3D("sphere", (18.0, 32), (10.0, 18.0, 0.0), (0.3, 0.55, 0.85)),
            Object3D("torus", (20.0, 6.0, 48, 16), (60.0, 6.0, 45.0), (0.9, 0.75, 0.3)),
            Object3D("lprism", (40.0, 40.0, 16.0, 12.0), (55.0, 20.0, -45.0), (0.4, 0.75, 0.4)),
        ),
        lights=(
            Light3D("point", (50.0, 40.0, 0.0), colour=(1.0, 1.0, 1.0), range=100.0, falloff=2.0),
            Light3D("spot", (200.0, 150.0, 0.0), spot_axis, (1.0, 1.0, 1.0), falloff=20.0, angle=15.0),
        ),
    )


# ---- the lighting formulas (mirrored in the GLSL) -------------------------------------------------------


def saturate(x):
    """HLSL's saturate: x clamped to 0..1."""
    return np.clip(x, 0.0, 1.0)


def _dot(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.einsum("...i,...i->...", a, b)


def point_attenuation(distance, range_: float, falloff: float) -> np.ndarray:
    """katt = 1 - saturate(d / r)^f: 1 at the light, 0 from its range on."""
    return 1.0 - saturate(np.asarray(distance, dtype=np.float64) / range_) ** falloff


def spot_attenuation(cos_to_point, angle_deg: float, falloff: float) -> np.ndarray:
    """katt = 1 - saturate(a / c)^f with a = cos(half-angle) and c = cos of the angle between the spot's axis
    and the direction from the light to the point; 0 outside the cone (where c <= a)."""
    c = np.asarray(cos_to_point, dtype=np.float64)
    a = math.cos(math.radians(angle_deg))
    inside = c > a
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(inside, 1.0 - saturate(a / np.where(inside, c, 1.0)) ** falloff, 0.0)


def to_light(light: Light3D, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(L, d): the unit direction from each point (..., 3) to the light, and the distance (inf for a
    directional light). A point at a point or spot light's position gets L = 0."""
    if light.kind == "directional":
        shape = np.shape(points)[:-1]
        return np.broadcast_to(-np.asarray(light.direction), shape + (3,)), np.full(shape, np.inf)
    v = np.asarray(light.position) - points
    d = np.linalg.norm(v, axis=-1)
    return v / np.maximum(d, 1e-300)[..., None], d


def attenuation(light: Light3D, points: np.ndarray) -> np.ndarray:
    """katt of `light` at each point (..., 3): 0 beyond a point light's range and outside a spot's cone."""
    if light.kind == "directional":
        return np.ones(np.shape(points)[:-1])
    direction, distance = to_light(light, points)
    if light.kind == "point":
        return point_attenuation(distance, light.range, light.falloff)
    return spot_attenuation(_dot(-direction, np.asarray(light.direction)), light.angle, light.falloff)


def in_reach(light: Light3D, points: np.ndarray) -> np.ndarray:
    """Where katt > 0: inside a point light's range, inside a spot's cone, everywhere for a directional."""
    if light.kind == "directional":
        return np.ones(np.shape(points)[:-1], dtype=bool)
    direction, distance = to_light(light, points)
    if light.kind == "point":
        return distance < light.range
    return _dot(-direction, np.asarray(light.direction)) > math.cos(math.radians(light.angle))


def diffuse(normals: np.ndarray, to_light_dir: np.ndarray) -> np.ndarray:
    """saturate(N . L)."""
    return saturate(_dot(normals, to_light_dir))


def specular(normals: np.ndarray, to_light_dir: np.ndarray, to_eye: np.ndarray, shininess: float,
             strength: float) -> np.ndarray:
    """Blinn-Phong: strength * saturate(N . H)^shininess with H = normalize(L + V), 0 where N . L <= 0."""
    h = to_light_dir + to_eye
    h = h / np.maximum(np.linalg.norm(h, axis=-1, keepdims=True), 1e-300)  # L = -V: H = 0, and N . L < 0 there
    return np.where(_dot(normals, to_light_dir) > 0, strength * saturate(_dot(normals, h)) ** shininess, 0.0)


def shade(scene: Scene3D, albedo: np.ndarray, points: np.ndarray, normals: np.ndarray, eye,
          lit: np.ndarray) -> np.ndarray:
    """The colour (..., 3) of surface points with unit shading normals, seen from `eye`; lit (lights, ...) says
    where each light reaches (see the module's docstring). Clamped to 0..1."""
    to_eye = np.asarray(eye, dtype=np.float64) - points
    to_eye /= np.maximum(np.linalg.norm(to_eye, axis=-1, keepdims=True), 1e-300)
    out = np.asarray(scene.ambient) * albedo
    for light, where in zip(scene.lights, lit):
        direction, _ = to_light(light, points)
        k = where * attenuation(light, points)
        term = albedo * diffuse(normals, direction)[..., None] \
            + specular(normals, direction, to_eye, scene.shininess, scene.specular)[..., None]
        out = out + k[..., None] * term * np.asarray(light.colour)
    return saturate(out)


# ---- the camera -----------------------------------------------------------------------------------------


@dataclass
class Lights3DCamera(OrbitCamera):
    """The orbit camera at this scene's scale, orbiting `target` (the default scene's middle)."""
    yaw: float = 35.0
    pitch: float = 30.0
    distance: float = 450.0   # the 400-unit ground all but whole in the 40-degree view
    target: tuple = (0.0, 10.0, 0.0)

    MIN_DISTANCE: ClassVar[float] = 20.0
    MAX_DISTANCE: ClassVar[float] = 2000.0
    NEAR: ClassVar[float] = 1.0
    FAR: ClassVar[float] = 5000.0

    def __post_init__(self) -> None:
        super().__post_init__()
        self.target = _position("camera target", self.target)

    def centre(self) -> np.ndarray:
        return np.array(self.target)
