"""The clouds' physical sky on the CPU (physical_sky 1): resources/shaders/clouds_sky.shl line for line, from the
atmosphere's tables as app/reference/atmosphere.py builds them (float64, the shaders' recipes). Directions d are
(N, 3) arrays; app/reference/clouds.py calls these where the shader does."""
from __future__ import annotations

import math

import numpy as np

from app.model.clouds import atmosphere as am
from app.model.clouds import scene as cm
from app.model.clouds.scene import ATMOSPHERE, Frame
from app.reference import atmosphere as ra
from app.reference.clouds_medium import hg

CIRRUS_G_FORWARD, CIRRUS_G_BACK, CIRRUS_BACK_WEIGHT = 0.8, -0.3, 0.15   # the ice's two lobes
SUN_COS_RADIUS = math.cos(math.radians(ATMOSPHERE.sun_radius_deg))


def tables(frame: Frame) -> ra.Tables:
    return ra.tables(ATMOSPHERE, float(frame.camera[1]), float(frame.sun_dir[1]))


def cos_azimuth(frame: Frame, d: np.ndarray) -> np.ndarray:
    """The cosine between d's and the sun's horizontal directions (1 where either is vertical)."""
    a = np.linalg.norm(d[..., [0, 2]], axis=-1)
    sun = np.array(frame.sun_dir)
    b = math.hypot(sun[0], sun[2])
    if b <= 1e-6:
        return np.ones(d.shape[:-1])
    c = (d[..., 0] * sun[0] + d[..., 2] * sun[2]) / np.where(a > 1e-6, a * b, 1.0)
    return np.where(a > 1e-6, np.clip(c, -1.0, 1.0), 1.0)


def physical_sky(frame: Frame, t: ra.Tables, d: np.ndarray, cos: np.ndarray) -> np.ndarray:
    """The sky's radiance from directions d, and the sun's disc where cos (d . sun) is within its radius."""
    sky = frame.sun_illuminance * t.sky(d[..., 1], cos_azimuth(frame, d))
    disc = frame.sun_illuminance * t.sun_transmittance(t.camera_radius, frame.sun_dir[1]) / (
        2 * math.pi * (1 - SUN_COS_RADIUS))
    return sky + np.where((cos > SUN_COS_RADIUS)[..., None], disc, 0.0)


def aerial_perspective(frame: Frame, t: ra.Tables, seen: np.ndarray, d: np.ndarray, depth: np.ndarray
                       ) -> np.ndarray:
    """Premultiplied rgba `seen` at distance `depth` along d through the air: rgb T + alpha L_air(0..depth)."""
    if not frame.physical_sky:
        return seen
    lum, throughput = ra.scatter(t, t.camera_radius, d[..., 1], frame.sun_dir[1], d @ np.array(frame.sun_dir),
                                 depth, am.AERIAL_STEPS)
    out = np.concatenate([seen[..., :3] * throughput + seen[..., 3:] * frame.sun_illuminance * lum, seen[..., 3:]],
                         -1)
    return np.where(seen[..., 3:] > 0, out, seen)


def physical_ground(frame: Frame, t: ra.Tables, normal: np.ndarray, shadow: np.ndarray) -> np.ndarray:
    """A Lambertian ground lit by the sun's transmitted light (shadowed by the clouds) and pi Psi_ms."""
    r = ATMOSPHERE.bottom + am.MIN_ALTITUDE
    mu_s = normal @ np.array(frame.sun_dir)
    sun = frame.direct * t.sun_transmittance(r, mu_s) * (np.maximum(mu_s, 0.0) * shadow / math.pi)[..., None]
    return np.array(cm.GROUND_ALBEDO) * frame.sun_illuminance * (sun + t.multiple(r, mu_s))


def cirrus_light(frame: Frame, cos: np.ndarray) -> np.ndarray:
    """The light a thin ice cloud scatters towards the camera per unit of its opacity."""
    phase = hg(cos, CIRRUS_G_FORWARD) * (1 - CIRRUS_BACK_WEIGHT) + hg(cos, CIRRUS_G_BACK) * CIRRUS_BACK_WEIGHT
    return np.array(frame.cirrus_light) * (4 * math.pi * phase)[..., None] + np.array(frame.cirrus_ambient)
