"""The clouds workspace's model (seed 001, after Nubis): its parameters, its view and sun, and the per-frame
constants that the GPU shader (resources/shaders/clouds.shl) and the CPU reference (app/reference/clouds.py)
both read, so the two render one model. docs/clouds.md, "The model", writes out the formulas.

Units are metres and seconds; y is up; the planet's centre is (0, -PLANET_RADIUS, 0) and the camera stands
above the origin at its altitude (the wind moves the clouds, not the camera)."""
from __future__ import annotations

import math
from typing import TYPE_CHECKING, get_type_hints
from dataclasses import dataclass, field, fields, replace

from app.model.clouds.atmosphere import Atmosphere, physical_light
from app.model.clouds.exposure import ToneSettings

if TYPE_CHECKING:
    import numpy as np

PLANET_RADIUS = 400_000.0
LAYER_BOTTOM = 1500.0          # altitude of the cloud layer's base
LAYER_TOP = 5500.0             # ... and of its top
CIRRUS_ALTITUDE = LAYER_TOP + 3000.0  # the high 2D clouds' shell (the seed's)
FOV_Y_DEG = 60.0               # vertical field of view
EXTINCTION = 0.02              # sigma_t per metre at density 1 and cloud sample 1 (the seed's light march scale)
MAX_MARCH = 80_000.0           # the longest cloud segment marched, metres (a grazing ray through the shell)
MAX_ALTITUDE = 20_000.0
SHEAR = 700.0                  # metres of wind-direction offset from the layer's base to its top (the seed's)
CONE_VECTORS = ((-0.6, -0.8, -0.2), (1.0, -0.3, 0.0), (-0.7, 0.0, 0.7), (-0.2, 0.6, -0.8), (0.4, 0.3, 0.9))
FAR_LIGHT_STEPS = 32.0         # the far light sample, in light steps beyond the cone (the seed's)
FAR_WEIGHT = 3.0               # ... and the light steps it stands for
LONG_LIGHT_SAMPLES = 30        # light_samples 30: the cone, then 25 samples 4 light steps apart
LONG_SPACING = 4.0
OCTAVES = 3                    # multiple scattering (Wrenninge): octave i scales by a^i, b^i, c^i (the octave_* params)
GROUND_SHADOW_SAMPLES = 8      # density samples along the sun ray through the layer above a ground point
# The seed's cloud-type height profiles (its camera prefab's gradients): smoothstep(x, y) - smoothstep(z, w)
# of the height fraction, stratus / stratocumulus / cumulus at type 0 / 0.5 / 1.
GRADIENTS = ((0.0, 0.0676, 0.1206, 0.2765), (0.0, 0.0765, 0.3882, 0.5941), (0.0, 0.0676, 0.8824, 1.0))
CLOUD_BASE_COLOR = (0.78, 0.86, 1.0)
CLOUD_TOP_COLOR = (1.0, 1.0, 1.0)
SUN_HIGH_COLOR = (1.0, 0.99, 0.82)
SUN_LOW_COLOR = (1.0, 0.31, 0.0)
SKY_ZENITH = (0.24, 0.45, 0.85)
SKY_HORIZON = (0.70, 0.80, 0.95)
GROUND_ALBEDO = (0.20, 0.21, 0.17)
# The physical sky's air: Earth's (Hillaire's preset, 100 km deep) over this planet (docs/clouds.md, "The sky
# and the atmosphere", says what the small planet changes).
ATMOSPHERE = Atmosphere(bottom=PLANET_RADIUS, top=PLANET_RADIUS + 100_000.0, ground_albedo=GROUND_ALBEDO)


@dataclass(frozen=True)
class Param:
    name: str
    default: float
    lo: float
    hi: float
    text: str
    integer: bool = False
    choices: tuple = ()


def _param(default: float, lo: float, hi: float, text: str, choices: tuple = (), added: bool = False):
    """A CloudParams field that carries its range and help text, so each parameter is written once. `added`: a
    parameter newer than recorded demos, which the digest leaves out while it keeps its default."""
    return field(default=default, metadata={"lo": lo, "hi": hi, "text": text, "choices": choices, "added": added})


@dataclass(frozen=True)
class CloudParams:
    """Every parameter of the seed's demo UI (its prefab's values as defaults), and ours after them; an `int`
    field is a whole number (a switch or a choice)."""
    coverage: float = _param(1.05, 0.0, 2.0, "weather coverage (0 clear .. 2 overcast)")
    density: float = _param(1.0, 0.0, 2.0, "optical density: extinction multiplier")
    shape_scale: float = _param(0.3, 0.0, 1.0, "shape noise frequency")
    detail_scale: float = _param(13.9, 0.0, 50.0, "detail noise frequency, relative to the shape's")
    shape_min: float = _param(0.47, 0.0, 1.0, "shape modifier: the shape noise's low end, remapped to 0")
    shape_max: float = _param(0.8, 0.0, 1.0, "shape modifier: the shape noise's high end, remapped to 1")
    detail_modifier: float = _param(0.4, 0.0, 1.0, "how far the detail noise erodes the edges")
    curl_scale: float = _param(2.9, 0.0, 20.0, "curl noise frequency, relative to the shape's")
    curl_amount: float = _param(231.0, 0.0, 1000.0, "curl distortion at the layer's top, metres (+150)")
    weather_scale: float = _param(0.1, 0.01, 1.0, "weather map frequency")
    high_coverage: float = _param(1.24, 0.0, 2.0, "high (cirrus) cloud coverage")
    high_coverage_scale: float = _param(0.18, 0.01, 2.0, "high cloud coverage frequency")
    high_scale: float = _param(0.028, 0.001, 1.0, "high cloud texture frequency")
    ambient: float = _param(0.3, 0.0, 1.0, "ambient light factor")
    direct: float = _param(1.0, 0.0, 1.5, "sun light factor")
    hg_forward: float = _param(0.54, 0.0, 0.99, "Henyey-Greenstein forward lobe g")
    hg_back: float = _param(0.5, 0.0, 0.99, "Henyey-Greenstein back lobe g (used as -g)")
    hg_back_weight: float = _param(0.5, 0.0, 1.0, "the back lobe's weight in the phase, the forward's 1 minus it",
                                   added=True)
    light_step: float = _param(48.0, 1.0, 200.0, "light march step length, metres")
    cone_radius: float = _param(0.4, 0.0, 2.0, "light cone radius, in light steps")
    octave_scattering: float = _param(0.5, 0.0, 1.0, "multiple scattering: octave i's weight a^i (a <= b)",
                                      added=True)
    octave_extinction: float = _param(0.5, 0.0, 1.0, "multiple scattering: octave i's optical depth to the sun x b^i",
                                      added=True)
    octave_eccentricity: float = _param(0.5, 0.0, 1.0, "multiple scattering: octave i's phase g x c^i",
                                        added=True)
    wind_speed: float = _param(15.9, 0.0, 200.0, "low cloud (noise) wind speed, m/s")
    wind_dir: float = _param(-22.4, -360.0, 360.0, "low cloud wind direction, degrees")
    weather_wind_speed: float = _param(25.0, 0.0, 200.0, "weather map wind speed, m/s")
    weather_wind_dir: float = _param(5.0, -360.0, 360.0, "weather map wind direction, degrees")
    high_wind_speed: float = _param(49.2, 0.0, 400.0, "high cloud wind speed, m/s")
    high_wind_dir: float = _param(77.8, -360.0, 360.0, "high cloud wind direction, degrees")
    time_scale: float = _param(1.0, -25.0, 25.0, "wind time multiplier")
    weather_blend: float = _param(30.0, 0.0, 60.0, "seconds a new weather takes to blend in")
    shape_noise: int = _param(1, 0, 1, "sample the shape noise (0: a constant 0.7, the seed's debug toggle)")
    detail_noise: int = _param(1, 0, 1, "erode with the detail noise")
    curl_noise: int = _param(1, 0, 1, "distort the detail with curl noise")
    light_samples: int = _param(6, 6, 30,
                                "light march samples: 6 (5 cone + 1 far) or 30 (clouds shadow each other)", (6, 30))
    multiscatter: int = _param(1, 0, 1, "multiple scattering by octaves (0: the seed's double Beer)")
    phase_max: int = _param(0, 0, 1, "phase: 0 the two lobes' normalised mix, 1 the seed's max of them (makes "
                                     "light; for comparison)", (0, 1), added=True)
    ground_shadows: int = _param(1, 0, 1, "cloud shadows on the ground")
    physical_sky: int = _param(1, 0, 1, "sky, sun and ambient light from a physical atmosphere (Hillaire 2020); "
                                        "0: the seed's colours from the sun's height", added=True)

    def __repr__(self) -> str:
        """The state digests hash this: an added parameter shows only when set, so a demo recorded before it
        existed replays to the digest it had."""
        shown = (f for f in fields(self) if not (f.metadata["added"] and getattr(self, f.name) == f.default))
        return f"CloudParams({', '.join(f'{f.name}={getattr(self, f.name)!r}' for f in shown)})"

    def with_value(self, name: str, value: float) -> "CloudParams":
        """A copy with `name` set, or ParamError saying what is allowed (nothing changes)."""
        return self.with_values({name: value})

    def with_values(self, values: dict[str, float]) -> "CloudParams":
        """A copy with every value of `values` set, all checked first, or ParamError."""
        checked = {name: _checked(name, value) for name, value in values.items()}
        out = replace(self, **checked)
        if out.shape_min >= out.shape_max:
            raise ParamError("shape_min must stay below shape_max")
        if out.octave_scattering > out.octave_extinction:
            raise ParamError("octave_scattering must not exceed octave_extinction (Wrenninge's a <= b: an octave "
                             "would scatter more light than it extinguishes)")
        return out

    def values(self) -> dict[str, float]:
        return {f.name: getattr(self, f.name) for f in fields(self)}


# The parameters as the console, the panel and the scene file read them: CloudParams' fields, in order.
_TYPES = get_type_hints(CloudParams)
PARAMS: tuple[Param, ...] = tuple(Param(f.name, f.default, f.metadata["lo"], f.metadata["hi"], f.metadata["text"],
                                        _TYPES[f.name] is int, f.metadata["choices"]) for f in fields(CloudParams))
PARAM = {p.name: p for p in PARAMS}


class ParamError(ValueError):
    pass


def _checked(name: str, value: float) -> float:
    p = PARAM.get(name)
    if p is None:
        raise ParamError(f"no cloud parameter {name!r} (clouds.list shows them)")
    if not math.isfinite(value):
        raise ParamError(f"{name} must be a finite number")
    if p.integer:
        if value != int(value):
            raise ParamError(f"{name} must be a whole number, got {value:g}")
        value = int(value)
        if p.choices and value not in p.choices:
            raise ParamError(f"{name} must be one of {', '.join(map(str, p.choices))}, got {value}")
    if not p.lo <= value <= p.hi:
        raise ParamError(f"{name} must be within {p.lo:g}..{p.hi:g}, got {value:g}")
    return value


@dataclass(frozen=True)
class CloudView:
    """The camera: altitude above the ground and look direction (degrees; yaw 0 looks along +z, pitch 90
    straight up), and the sun's azimuth and elevation (degrees)."""
    altitude: float = 200.0
    yaw: float = 0.0
    pitch: float = 12.0
    sun_azimuth: float = 30.0
    sun_elevation: float = 25.0


def clamp_altitude(metres: float) -> float:
    return min(max(metres, 1.0), MAX_ALTITUDE)


def direction(yaw_deg: float, pitch_deg: float) -> tuple[float, float, float]:
    yaw, pitch = math.radians(yaw_deg), math.radians(pitch_deg)
    return (math.sin(yaw) * math.cos(pitch), math.sin(pitch), math.cos(yaw) * math.cos(pitch))


def camera_basis(view: CloudView) -> tuple[tuple, tuple, tuple]:
    """(forward, right, up): right depends on the yaw only, so looking straight up or down is defined."""
    f = direction(view.yaw, view.pitch)
    yaw = math.radians(view.yaw)
    r = (-math.cos(yaw), 0.0, math.sin(yaw))
    u = (r[1] * f[2] - r[2] * f[1], r[2] * f[0] - r[0] * f[2], r[0] * f[1] - r[1] * f[0])
    return f, r, u


def sun_at_hour(hour: float) -> tuple[float, float]:
    """(azimuth, elevation) of the time-of-day slider: sunrise at 6 in the east (azimuth 90), noon 65 degrees
    high in the south (180), sunset at 18 in the west, below the horizon at night."""
    angle = math.pi * (hour - 6.0) / 12.0
    return (90.0 + 180.0 * (hour - 6.0) / 12.0) % 360.0, 65.0 * math.sin(angle)


def _lerp3(a, b, t: float) -> tuple[float, float, float]:
    return tuple(x + (y - x) * t for x, y in zip(a, b))


@dataclass(frozen=True)
class Frame:
    """Everything both renderers need for one frame, in world units; the shader's uniforms by these names."""
    camera: tuple
    forward: tuple
    right: tuple
    up: tuple
    tan_half_fov: float
    sun_dir: tuple
    sun_light: tuple          # sun colour x direct factor x the sun's height fade
    ambient_base: tuple       # cloud base colour x ambient factor x fade
    ambient_top: tuple
    sky_zenith: tuple
    sky_horizon: tuple
    physical_sky: int         # 1: the sky, the light on the clouds and the ground, and the haze from the air
    sun_illuminance: float    # the physical sky's radiance per unit of its tables
    direct: float             # the sun's light on the ground, times (the physical sky's)
    sun_light_top: tuple      # the sun's light at the layer's top (sun_light: at its base)
    cirrus_light: tuple       # the sun's light at the cirrus (the physical sky's)
    cirrus_ambient: tuple     # the sky's light there
    g_forward: float
    g_back: float             # negative: the back lobe
    back_weight: float        # the back lobe's weight in the phase's mix (the forward's is 1 - back_weight)
    phase_max: int            # 1: the seed's max of the two lobes instead of their mix
    octave_scattering: float  # Wrenninge's a, b, c (app.model.clouds.scene.OCTAVES octaves)
    octave_extinction: float
    octave_eccentricity: float
    extinction: float         # sigma_t per metre per unit cloud sample
    shape_freq: float         # texture repeats per metre
    detail_freq: float
    curl_freq: float
    curl_amount: float
    weather_freq: float
    high_coverage_freq: float
    high_freq: float
    coverage_shift: float     # subtracted from the weather's R (the seed's 1 - coverage)
    high_coverage_shift: float
    shape_min: float
    shape_max: float
    detail_modifier: float
    wind_dir: tuple           # unit xz with the seed's -0.25 y: the noise drifts up as it moves
    wind_offset: tuple
    weather_offset: tuple
    high_offset: tuple
    light_step: float
    cone_radius: float
    light_samples: int
    shape_noise: int
    detail_noise: int
    curl_noise: int
    multiscatter: int
    ground_shadows: int
    blend: float              # weight of the new weather map, 0..1
    furnace: int = 0          # 1: the white furnace's unit environment (furnace(), a test of energy conservation)


def _wind(speed: float, deg: float) -> tuple[float, float]:
    a = math.radians(deg)
    return speed * math.cos(a), speed * math.sin(a)


def frame(params: CloudParams, view: CloudView, wind_time: float = 0.0, blend: float = 1.0) -> Frame:
    """The frame's constants from the model: `wind_time` is the scaled clock (seconds x time_scale, summed),
    `blend` the new weather's weight."""
    f, r, u = camera_basis(view)
    sun = direction(view.sun_azimuth, view.sun_elevation)
    # The seed fades the sun and the ambient over its last 30 degrees above the horizon, reddens the sun as
    # it sinks and weakens the back lobe with it.
    fade = min(max(view.sun_elevation / 30.0, 0.0), 1.0)
    sun_color = _lerp3(SUN_LOW_COLOR, SUN_HIGH_COLOR, fade * fade)
    ambient = max(0.02, params.ambient * fade)
    noise = 0.00001 + params.shape_scale * 0.0004
    weather = params.weather_scale * 0.00025
    wx, wz = _wind(params.wind_speed, params.wind_dir)
    cx, cz = _wind(params.weather_wind_speed, params.weather_wind_dir)
    hx, hz = _wind(params.high_wind_speed, params.high_wind_dir)
    a = math.radians(params.wind_dir)
    sky = max(0.05, fade)
    seed_sun = tuple(c * params.direct * fade for c in sun_color)
    if params.physical_sky:
        light = physical_light(ATMOSPHERE, sun[1], params.direct, params.ambient / PARAM["ambient"].default,
                               (LAYER_BOTTOM, LAYER_TOP, CIRRUS_ALTITUDE))
    else:
        light = dict(sun_light=seed_sun, sun_light_top=seed_sun, cirrus_light=seed_sun,
                     ambient_base=tuple(c * ambient for c in CLOUD_BASE_COLOR),
                     ambient_top=tuple(c * ambient for c in CLOUD_TOP_COLOR),
                     cirrus_ambient=tuple(c * ambient for c in CLOUD_TOP_COLOR), sun_illuminance=1.0)
    return Frame(
        camera=(0.0, view.altitude, 0.0), forward=f, right=r, up=u,
        tan_half_fov=math.tan(math.radians(FOV_Y_DEG) / 2), sun_dir=sun, **light,
        sky_zenith=tuple(c * sky for c in SKY_ZENITH),
        sky_horizon=tuple(c * sky for c in _lerp3(sun_color, SKY_HORIZON, 0.5 + 0.5 * fade)),
        physical_sky=params.physical_sky, direct=params.direct,
        g_forward=params.hg_forward, g_back=-params.hg_back * fade ** 3, back_weight=params.hg_back_weight,
        phase_max=params.phase_max, octave_scattering=params.octave_scattering,
        octave_extinction=params.octave_extinction, octave_eccentricity=params.octave_eccentricity,
        extinction=EXTINCTION * params.density, shape_freq=noise, detail_freq=noise * params.detail_scale,
        curl_freq=noise * params.curl_scale, curl_amount=150.0 + params.curl_amount, weather_freq=weather,
        high_coverage_freq=params.high_coverage_scale * params.weather_scale * 0.001,
        high_freq=params.high_scale * 0.002, coverage_shift=1.0 - params.coverage,
        high_coverage_shift=1.0 - params.high_coverage, shape_min=params.shape_min, shape_max=params.shape_max,
        detail_modifier=params.detail_modifier,
        wind_dir=(math.cos(a), -0.25, math.sin(a)),
        wind_offset=(wx * wind_time, -0.25 * params.wind_speed * wind_time, wz * wind_time),
        # the seed starts the weather map at its middle and the high clouds at (1500, -900)
        weather_offset=(0.5 / weather + cx * wind_time, 0.5 / weather + cz * wind_time),
        high_offset=(1500.0 + hx * wind_time, -900.0 + hz * wind_time),
        light_step=params.light_step, cone_radius=params.cone_radius, light_samples=params.light_samples,
        shape_noise=params.shape_noise, detail_noise=params.detail_noise, curl_noise=params.curl_noise,
        multiscatter=params.multiscatter, ground_shadows=params.ground_shadows, blend=blend)


def furnace(fr: Frame) -> Frame:
    """The white furnace: the frame under a uniform environment of radiance 1 (the sky 1 in every direction,
    no ground, the ambient 1, no atmosphere between), the sun left as it is (`direct` 0 turns it off). Clouds of
    albedo 1 that conserve energy vanish in it with the sun off (docs/clouds.md, "Energy"); r_cloudFurnace shows
    it. The physical sky's tables play no part: its sky and ambient give way to the unit ones, its haze to none."""
    one = (1.0, 1.0, 1.0)
    return replace(fr, ambient_base=one, ambient_top=one, cirrus_ambient=one, sky_zenith=one, sky_horizon=one,
                   physical_sky=0, furnace=1)


@dataclass(frozen=True)
class CloudTextures:
    """The arrays both renderers sample (docs/clouds.md, "Textures and sampling"), all float32:
    shape (n, n, n), detail (m, m, m), curl (k, k, 2), cirrus (q, q), weather_old and weather_new (w, w, 3)."""
    shape: "np.ndarray"
    detail: "np.ndarray"
    curl: "np.ndarray"
    cirrus: "np.ndarray"
    weather_old: "np.ndarray"
    weather_new: "np.ndarray"


INTEGRATIONS = ("energy", "seed")


@dataclass(frozen=True)
class CloudRenderSettings:
    """The renderer's settings, from the r_cloud* cvars: each optimisation can be switched off."""
    steps: int = 128              # view-ray steps at the horizon (half straight up)
    downsample: int = 2           # the cloud buffer is 1/downsample of the output on each axis
    jitter: bool = True           # blue-noise start offset, a new one each frame
    taa: bool = True              # blend each frame into a history (neighbourhood-clamped)
    early_exit: bool = True       # stop once the clouds are 99 % opaque
    big_steps: bool = True        # 3 steps at once after 10 empty samples, one back on a hit
    light_skip: bool = True       # the light march only where the density is above 0
    detail_skip: bool = True      # detail and curl only where the shape is above 0, nothing where coverage is 0
    reproject: bool = True        # trace one pixel of each downsample^2 block a frame, reproject the rest
    debug_samples: bool = False   # texture lookups per pixel, black 0 .. white 1000
    furnace: bool = False         # the white furnace test's environment (furnace()), not the scene's sky
    integration: str = "energy"   # or "seed"
    reproject_downsample: int = 1  # the reprojected picture is 1/this of the output on each axis (no cvar: the
                                   # host's cheapest full-size level of a drag)
    tone: ToneSettings = ToneSettings()  # exposure and the tone curve (app/model/clouds/exposure.py)
