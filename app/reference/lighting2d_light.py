"""What a 2D light gives a pixel before shadows (seed 000's light shaders, evaluated in numpy), and the
texture sampling the GPU does, texel for texel (bilinear, texel centres at i + 0.5)."""
from __future__ import annotations

import math

import numpy as np

from app.io.textures2d import image
from app.model.lighting2d.scene import Light, Scene2D


def pixel_world(view, width: int, height: int, flip_y: bool = False) -> np.ndarray:
    """World coordinates (height * width, 2) of pixel centres, row 0 at the top of the image."""
    cx, cy, h = view
    unit = h / height
    x = cx + (np.arange(width) + 0.5 - width / 2) * unit
    y = cy - (np.arange(height) + 0.5 - height / 2) * unit
    if flip_y:
        y = y[::-1]
    xx, yy = np.meshgrid(x, y)
    return np.stack([xx.ravel(), yy.ravel()], axis=1)


def textures_for(scene: Scene2D) -> dict[str, np.ndarray]:
    names = {light.texture for light in scene.lights if light.kind == "textured"}
    if scene.normal_map:
        names.add(scene.normal_map)
    return {name: image(name).astype(np.float64) / 255.0 for name in names}


def sample(tex: np.ndarray, uv: np.ndarray, repeat: bool) -> np.ndarray:
    """Bilinear sample of (h, w, c) at uv (n, 2) with v = 0 at the image's BOTTOM row (GL's upload of a
    top-first image flipped), repeat or clamp to edge."""
    h, w = tex.shape[:2]
    x = uv[:, 0] * w - 0.5
    y = (1.0 - uv[:, 1]) * h - 0.5  # image rows run down
    x0, y0 = np.floor(x), np.floor(y)
    fx, fy = (x - x0)[:, None], (y - y0)[:, None]

    def fetch(ix, iy):
        ix = np.mod(ix, w) if repeat else np.clip(ix, 0, w - 1)
        iy = np.mod(iy, h) if repeat else np.clip(iy, 0, h - 1)
        return tex[iy.astype(int), ix.astype(int)]

    top = fetch(x0, y0) * (1 - fx) + fetch(x0 + 1, y0) * fx
    bottom = fetch(x0, y0 + 1) * (1 - fx) + fetch(x0 + 1, y0 + 1) * fx
    return top * (1 - fy) + bottom * fy


def light_uv(light: Light, world: np.ndarray) -> np.ndarray:
    """Coordinates in the light's quad: world = position + R(rotation) ((uv - origin) * scale)."""
    c, s = math.cos(light.rotation), math.sin(light.rotation)
    d = world - light.position
    local = np.stack([c * d[:, 0] + s * d[:, 1], -s * d[:, 0] + c * d[:, 1]], axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        return local / np.asarray(light.scale) + light.origin


def light_value(light: Light, world: np.ndarray, textures) -> np.ndarray:
    """Colour (n, 3) the light adds where nothing shadows it: pow(color * a, intensity) inside its quad."""
    uv = light_uv(light, world)
    inside = np.all((uv >= 0.0) & (uv <= 1.0), axis=1)
    uv = np.where(inside[:, None], uv, 0.5)
    if light.kind == "point":
        a = np.clip(1.0 - 2.0 * np.hypot(uv[:, 0] - 0.5, uv[:, 1] - 0.5), 0.0, 1.0)
    elif light.kind == "spot":
        v = uv - (0.0, 0.5)
        length = np.hypot(v[:, 0], v[:, 1])
        half = np.arccos(np.clip(v[:, 0] / np.maximum(length, 1e-30), -1.0, 1.0))
        cone = light.cone_half_angle()
        a = np.clip(1.0 - length, 0.0, 1.0) * (1.0 - np.power(half / cone, light.cone_decay)) * (half <= cone)
    else:
        a = sample(textures[light.texture], uv, repeat=False)[:, 1]
    a = np.where(inside, a, 0.0)
    base = np.asarray(light.color)[None, :] * a[:, None]
    with np.errstate(divide="ignore"):
        return np.where(base > 0, np.power(np.maximum(base, 1e-300), light.intensity), 0.0)


def normal_factor(light: Light, world: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """max(N . L, 0) with N from the normal map (1 texel per world unit, repeating) and L towards the light
    raised `height` above the plane."""
    h, w = normals.shape[:2]
    n = sample(normals, world / np.array([w, h]), repeat=True)[:, :3] * 2.0 - 1.0
    n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-12)
    to_light = np.concatenate([np.asarray(light.position) - world, np.full((len(world), 1), light.height)], axis=1)
    to_light /= np.linalg.norm(to_light, axis=1, keepdims=True)
    return np.maximum(np.einsum("nd,nd->n", n, to_light), 0.0)
