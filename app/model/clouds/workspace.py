"""The clouds workspace's state: the cloud model's parameters, the camera and sun, the weather maps and
their blend, and the clock that moves the wind and the blend."""
from __future__ import annotations

from dataclasses import replace
from typing import Callable

import numpy as np

from app.model.clouds.weather import WeatherBlend, weather_map
from app.model.clouds.scene import PARAMS, CloudParams, CloudView, Frame, frame
from app.model.history import SnapshotHistory
from app.model.workspace import Workspace, short_hash

WEATHER_SIZE = 256
DEFAULT_WEATHER_SEED = 1
# The clock runs within 0..MAX_TIME seconds and the wind's time within -MAX_TIME..MAX_TIME: a day, over which the
# fastest wind (400 m/s) moves the clouds 35,000 km, where the shaders' float32 still resolves 4 m, finer than the
# detail noise's texels (17 m). Far past it the sky is mush, and at inf or NaN it is gone.
MAX_TIME = 86_400.0


def check_times(clock: float, wind_time: float) -> None:
    """ValueError unless the clock and the wind's time are within their ranges."""
    if not 0.0 <= clock <= MAX_TIME:  # also refuses NaN
        raise ValueError(f"the clock must be within 0..{MAX_TIME:g} s, got {clock:g}")
    if not -MAX_TIME <= wind_time <= MAX_TIME:
        raise ValueError(f"the wind's time must be within -{MAX_TIME:g}..{MAX_TIME:g} s, got {wind_time:g}")


class CloudsWorkspace(Workspace):
    name = "clouds"

    def __init__(self) -> None:
        self.params = CloudParams()
        self.view = CloudView()
        self.clock = 0.0      # seconds shown: the weather blend runs on it
        self.wind_time = 0.0  # the clock times time_scale, summed: the winds' offsets grow with it
        # the weather command that made the newest map, "new 1" or "load PATH" (quoted): digests and demos
        self.weather_source = f"new {DEFAULT_WEATHER_SEED}"
        self._weather: WeatherBlend | None = None  # made on first use, never at start-up
        self.history = SnapshotHistory(self._snapshot, self._restore)

    def set_camera(self, **changes: float) -> None:
        self.view = replace(self.view, **changes)

    def set_sun(self, azimuth: float, elevation: float) -> None:
        self.view = replace(self.view, sun_azimuth=azimuth, sun_elevation=elevation)

    # ---- weather ------------------------------------------------------------------------------------

    @property
    def weather(self) -> WeatherBlend:
        if self._weather is None:
            self._weather = WeatherBlend(weather_map(DEFAULT_WEATHER_SEED, WEATHER_SIZE))
        return self._weather

    def new_weather(self, new_map: np.ndarray, source: str) -> None:
        """Blend to `new_map` over the parameters' weather_blend seconds, from what is on screen."""
        self.weather.begin(new_map, self.clock, self.params.weather_blend)
        self.weather_source = source

    def blend(self) -> float:
        return self.weather.weight(self.clock) if self._weather is not None else 1.0

    def frame(self) -> Frame:
        """The constants of the frame the state shows now (both renderers draw from them)."""
        return frame(self.params, self.view, self.wind_time, self.blend())

    # ---- time ---------------------------------------------------------------------------------------

    def set_times(self, clock: float, wind_time: float) -> None:
        check_times(clock, wind_time)
        self.clock, self.wind_time = clock, wind_time

    def advance(self, seconds: float) -> None:
        """Let `seconds` of real time pass: the blend goes on, the winds move by time_scale. Both times stop at
        the ends of their ranges (after a day of blowing wind), where the command that sets them takes them."""
        self.clock = min(self.clock + seconds, MAX_TIME)
        self.wind_time = min(max(self.wind_time + seconds * self.params.time_scale, -MAX_TIME), MAX_TIME)

    def animating(self) -> bool:
        """Whether frames change with the clock (winds blowing or a blend under way)."""
        moving = self.params.time_scale != 0 and any(
            getattr(self.params, n) for n in ("wind_speed", "weather_wind_speed", "high_wind_speed"))
        return moving or (self._weather is not None and not self._weather.done(self.clock))

    # ---- the workspace ------------------------------------------------------------------------------

    def _snapshot(self):
        w = self._weather
        return (self.params, self.view.sun_azimuth, self.view.sun_elevation, self.weather_source,
                None if w is None else w.snapshot())

    def _restore(self, state) -> None:
        self.params, azimuth, elevation, self.weather_source, weather = state
        self.view = replace(self.view, sun_azimuth=azimuth, sun_elevation=elevation)
        if weather is not None:
            self.weather.restore(weather)

    def version(self) -> tuple:
        w = self._weather
        return (self.params, self.view, self.clock, self.wind_time, None if w is None else w.version)

    def digest(self) -> dict[str, str]:
        v = self.view
        return {"clouds": short_hash(self.params, v.sun_azimuth, v.sun_elevation, self.weather_source,
                                     self.wind_time),
                "clouds.camera": short_hash(v.altitude, v.yaw, v.pitch)}

    def document_digest(self) -> str:
        """What a clouds file holds: the parameters, the sun and the weather (not the clock the wind moves)."""
        return short_hash(self.params, self.view.sun_azimuth, self.view.sun_elevation, self.weather_source)

    def load_frame_commands(self, aspect: float) -> list[str]:
        return []  # a clouds file holds no camera, and the sky no bounds: the view stays

    def frame_commands(self, aspect: float) -> list[str]:
        """The sky has no bounds: the camera where a new scene puts it, looking at the layer."""
        home = CloudView()
        return [f"camera.alt {home.altitude!r}", f"camera.look {home.yaw!r} {home.pitch!r}"]

    def opening_commands(self, snapshot: Callable[[], str]) -> list[str]:
        """Commands that rebuild the parameters, the view, the sun, the newest weather (blended in at once)
        and the clock; a blend under way starts finished."""
        p, v, default = self.params, self.view, CloudParams()
        lines = ["clouds.reset"]
        lines += [f"clouds.set {q.name} {getattr(p, q.name)!r}" for q in PARAMS
                  if q.name != "weather_blend" and getattr(p, q.name) != getattr(default, q.name)]
        lines += ["clouds.set weather_blend 0", f"weather.{self.weather_source}",
                  f"clouds.set weather_blend {p.weather_blend!r}",
                  f"camera.alt {v.altitude!r}", f"camera.look {v.yaw!r} {v.pitch!r}",
                  f"sun.dir {v.sun_azimuth!r} {v.sun_elevation!r}", f"clouds.time {self.clock!r} {self.wind_time!r}"]
        return lines
