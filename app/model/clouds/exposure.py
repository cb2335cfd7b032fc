"""How the clouds' linear radiance becomes a picture (docs/clouds.md, "Exposure and tone mapping"): an exposure in
EV (manual, or automatic from the frame's log-average luminance), a tone curve, then sRGB encoding. The GPU's
tone-map passes (resources/shaders/tone_map.shl) and the CPU reference (app/reference/tone_map.py) read these
constants; the curves are named in the r_cloudToneMap cvar's order."""
from __future__ import annotations

import math
from dataclasses import dataclass

# aces: Hill's fit of the ACES RRT + sRGB ODT (with its input and output matrices); agx: Sobotka's AgX (Wrensch's
# polynomial fit of its default contrast); clamp: the seed's look, the radiance clamped to 0..1 and shown as it is
# (no sRGB encoding: the seed's colours were picked as display values).
TONE_MAPS = ("aces", "agx", "clamp")
LUMINANCE = (0.2126, 0.7152, 0.0722)  # Rec. 709 / sRGB primaries
KEY = 0.18                 # automatic exposure maps the frame's log-average luminance to middle grey
AUTO_RANGE = 8.0           # ... within this many EV either way (a black frame is not lifted into noise)
MIN_LUMINANCE = 2.0 ** -14  # a pixel's luminance in the log average at least this (no log of 0)
ADAPT = 0.5                # the adapted log-average moves this share of the way to the frame's each frame
SETTLED_EV = 0.01          # ... and counts as adapted once within this many EV
EV_RANGE = (-10.0, 10.0)   # the manual exposure (or the automatic one's compensation)


@dataclass(frozen=True)
class ToneSettings:
    """From the r_cloudExposure, r_cloudAutoExposure and r_cloudToneMap cvars."""
    ev: float = 0.0          # +1 doubles the light shown (with `auto`, added to the automatic exposure)
    auto: bool = True        # expose for the frame's log-average luminance
    curve: str = TONE_MAPS[0]


def auto_ev(log2_average: float) -> float:
    """The automatic exposure (EV) for a frame whose mean of log2 luminance is `log2_average`."""
    return min(max(math.log2(KEY) - log2_average, -AUTO_RANGE), AUTO_RANGE)
