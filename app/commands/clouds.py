"""Cloud verbs: the model's parameters, the camera, the sun, the weather and the clock, and the r_cloud*
cvars that switch the renderer's optimisations. Names are a contract (docs/clouds.md, "Commands")."""
from __future__ import annotations

import math
from functools import partial

from app.console import files
from app.console.command_set import CommandSet, Context
from app.console.console import Console
from app.console.demo import ArgChecks
from app.console.quoting import quote
from app.console.registry import SCRIPTS, CommandError, Cvar
from app.console.text import number
from app.io.clouds import scene_file as clouds_scene
from app.io.clouds.scene_file import MAX_SEED, CloudScene, CloudSceneError
from app.io.clouds.weather_image import WeatherError, load_weather
from app.model.clouds.exposure import EV_RANGE, TONE_MAPS, ToneSettings
from app.model.clouds.weather import resample, weather_map
from app.model.clouds.scene import (INTEGRATIONS, MAX_ALTITUDE, PARAMS, CloudParams, CloudRenderSettings, ParamError,
                                    sun_at_hour)
from app.model.clouds.workspace import MAX_TIME, WEATHER_SIZE, CloudsWorkspace, check_times
from app.model.workspace import SceneFiles

# The cvars of the optimisations, each switching one off (docs/clouds.md, "Optimisations").
SWITCHES = (  # (cvar, settings field, panel label, help)
    ("r_cloudJitter", "jitter", "Jitter", "blue-noise jittered ray start, a new offset each frame"),
    ("r_cloudTAA", "taa", "TAA", "temporal anti-aliasing of the cloud buffer"),
    ("r_cloudEarlyExit", "early_exit", "Early exit", "stop a ray once the clouds are 99 % opaque"),
    ("r_cloudBigSteps", "big_steps", "Big steps", "triple steps through empty space, one back on a hit"),
    ("r_cloudLightSkip", "light_skip", "Light skip", "march towards the sun only where the density is above 0"),
    ("r_cloudDetailSkip", "detail_skip", "Detail skip",
     "detail and curl only inside the shape; nothing where coverage is 0"),
    ("r_cloudReproject", "reproject", "Reprojection",
     "trace one pixel of each r_cloudDownsample^2 block a frame, reproject the rest"),
    ("r_cloudDebugSamples", "debug_samples", "Sample count view",
     "show texture lookups per pixel, black 0 .. white 1000"),
)

COMMANDS = CommandSet("clouds")
Ctx = Context[CloudsWorkspace]


def _finite(what: str, *values: float) -> None:
    if not all(math.isfinite(v) for v in values):
        raise CommandError(f"{what} must be finite numbers")


def _direction(what: str, around: float, up: float) -> tuple[float, float]:
    """A direction in degrees as (around modulo 360, up), up within -90..90; else CommandError."""
    _finite(what, around, up)
    if not -90 <= up <= 90:
        raise CommandError(f"{what}: the second must be within -90..90 degrees, got {up:g}")
    return around % 360.0, up


def register(console: Console, state: CloudsWorkspace, checks: ArgChecks) -> None:
    """The commands and the r_cloud* cvars, and their checks for demos (`checks`)."""
    ctx = Ctx(console, state)
    reg = console.registry
    defaults = CloudRenderSettings()
    reg.add_cvar(Cvar("r_cloudSteps", int, defaults.steps, "cloud ray steps at the horizon (half straight up)",
                      min=1, max=1024, archive=True))
    reg.add_cvar(Cvar("r_cloudDownsample", int, defaults.downsample, "the cloud buffer is 1/N of the view per axis",
                      min=1, max=4, archive=True))
    for name, field, _label, text in SWITCHES:
        reg.add_cvar(Cvar(name, bool, getattr(defaults, field), text, archive=True))
    reg.add_cvar(Cvar("r_cloudIntegration", str, defaults.integration,
                      "energy: exp(-sigma dt) per step (converges); seed: the seed's density-as-alpha sum",
                      choices=INTEGRATIONS, archive=True))
    reg.add_cvar(Cvar("r_cloudFurnace", bool, defaults.furnace,
                      "white furnace test: sky and ambient 1 everywhere, no ground (with direct 0 the clouds vanish)"))
    tone = ToneSettings()
    reg.add_cvar(Cvar("r_cloudExposure", float, tone.ev, "exposure in EV: +1 shows twice the light (with "
                      "r_cloudAutoExposure, added to the automatic one)", min=EV_RANGE[0], max=EV_RANGE[1],
                      archive=True))
    reg.add_cvar(Cvar("r_cloudAutoExposure", bool, tone.auto, "expose for the frame's log-average luminance "
                      "(adapting over frames while the scene stays)", archive=True))
    reg.add_cvar(Cvar("r_cloudToneMap", str, tone.curve, "the tone curve: aces (Hill's fit), agx or clamp (the "
                      "seed's look: clamped, no sRGB encoding)", choices=TONE_MAPS, archive=True))
    state.files = SceneFiles(partial(load, ctx), partial(save, ctx), (".json",), clouds_scene.FORMAT,
                             new=partial(clouds_reset, ctx))
    COMMANDS.register(reg, ctx, checks)


# ---- files -----------------------------------------------------------------------------------------

def load(ctx: Ctx, path: str) -> str:
    try:
        scene = clouds_scene.load(path)
    except CloudSceneError as exc:
        raise CommandError(str(exc)) from None
    state = ctx.state
    state.history.checkpoint("Load Clouds")
    state.params = scene.params
    if scene.sun is not None:
        state.set_sun(*scene.sun)
    if scene.weather_seed is not None:
        state.new_weather(weather_map(scene.weather_seed, WEATHER_SIZE), f"new {scene.weather_seed}")
    ctx.console.print(f"loaded clouds from {path}")
    return path


def save(ctx: Ctx, path: str) -> None:
    state = ctx.state
    source = state.weather_source.split()
    seed = int(source[1]) if source[0] == "new" else None
    clouds_scene.save(path, CloudScene(state.params, (state.view.sun_azimuth, state.view.sun_elevation), seed))


# ---- parameters ------------------------------------------------------------------------------------

@COMMANDS.check("clouds.set")
def checked_params(ctx: Ctx, name: str, value: float) -> CloudParams:
    try:
        return ctx.state.params.with_value(name, value)
    except ParamError as exc:
        raise CommandError(str(exc)) from None


@COMMANDS.command("clouds.set", "name value:float", "Set a cloud parameter (clouds.list names them)",
                  completer=lambda ctx, prefix: [p.name for p in PARAMS if p.name.startswith(prefix)], allow=SCRIPTS)
def clouds_set(ctx: Ctx, name: str, value: float) -> None:
    params = checked_params(ctx, name, value)
    if params != ctx.state.params:  # a slider's drag: one step
        ctx.state.history.checkpoint(f"Set {name.replace('_', ' ')}", ("clouds.set", name))
        ctx.state.params = params


@COMMANDS.command("clouds.list", "", "List the cloud parameters with their values and ranges", recorded=False,
                  allow=SCRIPTS)
def clouds_list(ctx: Ctx) -> None:
    for p in PARAMS:
        choices = "|".join(map(str, p.choices)) if p.choices else f"{p.lo:g}..{p.hi:g}"
        ctx.console.print(f"{p.name:<20} {number(getattr(ctx.state.params, p.name)):<8} {choices:<12} {p.text}")


@COMMANDS.command("clouds.reset", "", "Set every cloud parameter back to its default", allow=SCRIPTS)
def clouds_reset(ctx: Ctx) -> None:
    if ctx.state.params != CloudParams():
        ctx.state.history.checkpoint("Reset Clouds")
        ctx.state.params = CloudParams()


# ---- camera and sun --------------------------------------------------------------------------------

@COMMANDS.check("camera.alt")
def altitude(ctx: Ctx, metres: float) -> float:
    _finite("the altitude", metres)
    if not 1 <= metres <= MAX_ALTITUDE:
        raise CommandError(f"the altitude must be within 1..{MAX_ALTITUDE:g} m, got {metres:g}")
    return metres


@COMMANDS.command("camera.alt", "metres:float", f"Put the camera at this altitude (1..{MAX_ALTITUDE:g} m; the "
                  "layer lies between 1500 and 5500)", allow=SCRIPTS)
def camera_alt(ctx: Ctx, metres: float) -> None:
    ctx.state.set_camera(altitude=altitude(ctx, metres))


@COMMANDS.check("camera.look")
def look(ctx: Ctx, yaw: float, pitch: float) -> tuple[float, float]:
    return _direction("the view's yaw and pitch", yaw, pitch)


@COMMANDS.command("camera.look", "yaw:float pitch:float", "Look towards yaw (degrees, 0 along +z) and pitch "
                  "(-90 down .. 90 up)", allow=SCRIPTS)
def camera_look(ctx: Ctx, yaw: float, pitch: float) -> None:
    yaw, pitch = look(ctx, yaw, pitch)
    ctx.state.set_camera(yaw=yaw, pitch=pitch)


@COMMANDS.check("sun.dir")
def sun(ctx: Ctx, azimuth: float, elevation: float) -> tuple[float, float]:
    return _direction("the sun's azimuth and elevation", azimuth, elevation)


@COMMANDS.command("sun.dir", "azimuth:float elevation:float", "Put the sun at this azimuth and elevation "
                  "(degrees)", allow=SCRIPTS)
def sun_dir(ctx: Ctx, azimuth: float, elevation: float) -> None:
    state = ctx.state
    azimuth, elevation = sun(ctx, azimuth, elevation)
    if (azimuth, elevation) != (state.view.sun_azimuth, state.view.sun_elevation):
        state.history.checkpoint("Move Sun", "sun")
        state.set_sun(azimuth, elevation)


@COMMANDS.check("sun.time")
def hour_of(ctx: Ctx, hour: float) -> float:
    _finite("the hour", hour)
    if not 0 <= hour <= 24:
        raise CommandError(f"the hour must be within 0..24, got {hour:g}")
    return hour


@COMMANDS.command("sun.time", "hour:float", "Put the sun where it stands at this hour (0..24: rises at 6 in "
                  "the east, sets at 18 in the west)", allow=SCRIPTS)
def sun_time(ctx: Ctx, hour: float) -> None:
    sun_dir(ctx, *sun_at_hour(hour_of(ctx, hour)))


# ---- weather and time ------------------------------------------------------------------------------

@COMMANDS.check("weather.new")
def seed_of(ctx: Ctx, seed: int | None = None) -> int | None:
    if seed is not None and not 0 <= seed <= MAX_SEED:
        raise CommandError(f"the seed must be within 0..{MAX_SEED}, got {seed}")
    return seed


@COMMANDS.command("weather.new", "[seed:int]", "Make a new weather map (the next seed if none is given) and "
                  "blend to it over weather_blend seconds", allow=SCRIPTS)
def weather_new(ctx: Ctx, seed: int | None = None) -> None:
    state = ctx.state
    if seed_of(ctx, seed) is None:
        source = state.weather_source.split()
        seed = (int(source[1]) + 1) % (MAX_SEED + 1) if source[0] == "new" else 1
    state.history.checkpoint("New Weather")
    state.new_weather(weather_map(seed, WEATHER_SIZE), f"new {seed}")
    ctx.console.print(f"weather {seed}, blending in over {number(state.params.weather_blend)} s")


@COMMANDS.command("weather.load", "path", "Blend to a weather map from a PNG (R coverage, G type, B rain)",
                  completer=lambda ctx, prefix: files.complete(prefix, (".png",)), allow=SCRIPTS)
def weather_load(ctx: Ctx, path: str) -> None:
    try:
        weather = load_weather(files.readable(ctx.console, path))
    except WeatherError as exc:
        raise CommandError(str(exc)) from None
    ctx.state.history.checkpoint("Load Weather")
    ctx.state.new_weather(resample(weather, WEATHER_SIZE), f"load {quote(path)}")
    ctx.console.print(f"weather from {path}, blending in over {number(ctx.state.params.weather_blend)} s")


@COMMANDS.command("weather.blend", "[seconds:float]", "Show or set how long a new weather takes to blend in",
                  allow=SCRIPTS)
def weather_blend(ctx: Ctx, seconds: float | None = None) -> None:
    if seconds is None:
        ctx.console.print(f"weather.blend is {number(ctx.state.params.weather_blend)} s")
    else:
        clouds_set(ctx, "weather_blend", seconds)


@COMMANDS.check("clouds.time")
def times(ctx: Ctx, seconds: float | None = None, wind: float | None = None) -> None:
    if seconds is None:
        return
    try:  # a wind time not given is the clock times time_scale, which the demo may set before: the command checks
        check_times(seconds, 0.0 if wind is None else wind)
    except ValueError as exc:
        raise CommandError(str(exc)) from None


@COMMANDS.command("clouds.time", "[seconds:float] [wind:float]", "Show or set the clock (the weather blend runs "
                  f"on it, 0..{MAX_TIME:g} s) and the wind's time (default: the clock times time_scale; within "
                  f"-{MAX_TIME:g}..{MAX_TIME:g} s)", allow=SCRIPTS)
def clouds_time(ctx: Ctx, seconds: float | None = None, wind: float | None = None) -> None:
    state = ctx.state
    times(ctx, seconds, wind)
    if seconds is None:
        ctx.console.print(f"clock {number(state.clock)} s, wind time {number(state.wind_time)} s, "
                          f"weather blend {state.blend():.0%}")
        return
    state.set_times(seconds, seconds * state.params.time_scale if wind is None else wind)


def render_settings(console: Console, state: CloudsWorkspace) -> CloudRenderSettings:
    cvars = console.registry.cvars
    return CloudRenderSettings(
        steps=cvars["r_cloudSteps"].value, downsample=cvars["r_cloudDownsample"].value,
        integration=cvars["r_cloudIntegration"].value, furnace=bool(cvars["r_cloudFurnace"].value),
        tone=ToneSettings(cvars["r_cloudExposure"].value, cvars["r_cloudAutoExposure"].value,
                          cvars["r_cloudToneMap"].value),
        **{field: bool(cvars[name].value) for name, field, _label, _text in SWITCHES})

