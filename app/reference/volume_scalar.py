"""CPU reference of a scalar volume's render modes (app/model/volume/scalar_modes.py), numpy and scipy.

The rays, samples, bisection and Phong lighting of app/reference/volume.py, on the values in data units (trilinear,
clamped at the faces, in float64): the greatest, least and mean value along the ray, vispy's attenuated MIP, the
first crossing of the iso value and front-to-back compositing through the exact opacity curve (no early stop);
a scan's labels laid over them in front of where each ray stopped (app/reference/volume_labels.py). Rays go a chunk
at a time, so many steps (the bench's reference) stay within memory. Meant for small images."""
from __future__ import annotations

import numpy as np
from scipy.ndimage import map_coordinates

from app.model.camera3d import OrbitCamera
from app.model.volume import render_modes as rm
from app.model.volume.scalar_modes import SCALAR_MODES, colour_of, drawable, finite_span
from app.model.volume.scalars import TransferFunction
from app.model.volume.view import box_extents, voxel_extent
from app.model.volume.voxels import DEFAULT_SPACING, Spacing
from app.reference.volume import Scene, _march, _phong, camera_rays
from app.reference.volume_labels import LabelLayer, over

CHUNK_SAMPLES = 1 << 21  # samples in flight at once (about 50 MiB of positions)


class ScalarScene(Scene):
    """The values as float64, with the box; a surface is where the value first exceeds `iso`."""

    def __init__(self, values: np.ndarray, iso: float = 0.0, sample_range: float = 1.0,
                 shadow_offset: float = rm.SHADOW_OFFSET, spacing: Spacing = DEFAULT_SPACING) -> None:
        self.values = drawable(values, finite_span(values)).astype(np.float64)  # as the GPU holds them
        self.size = np.array(values.shape[::-1], dtype=np.float64)  # (w, h, d)
        voxels = tuple(int(s) for s in self.size)
        self.extent = np.array(box_extents(voxels, spacing))
        self.voxel = voxel_extent(voxels, spacing)  # world size of a voxel's shortest side
        self.sample_range, self.shadow_offset, self.level = sample_range, shadow_offset, float(iso)

    def field(self, t: np.ndarray) -> np.ndarray:
        """Values at texture coordinates t (..., 3): texel centres at (i + 0.5) / size, clamped to the edge."""
        coords = [t[..., 2] * self.size[2] - 0.5, t[..., 1] * self.size[1] - 0.5, t[..., 0] * self.size[0] - 0.5]
        return map_coordinates(self.values, coords, order=1, mode="nearest")


def render(values: np.ndarray, transfer: TransferFunction, camera: OrbitCamera, size: tuple[int, int], mode: str,
           steps: float, iso: float = 0.0, mip_attenuation: float = 0.05, background=(0.0, 0.0, 0.0),
           lights=rm.LIGHTS, shadows: bool = True, shadow_steps: int = 20, sample_range: float = 1.0,
           shadow_offset: float = rm.SHADOW_OFFSET, spacing: Spacing = DEFAULT_SPACING,
           labels: LabelLayer | None = None) -> np.ndarray:
    """The image (height, width, 3), floats 0..1, top row first, of `values` (d, h, w) in scalar mode `mode`, its
    voxels `spacing` (x, y, z) apart, a scan's `labels` laid over it."""
    if mode not in SCALAR_MODES[1:]:
        raise ValueError(f"no scalar reference for mode {mode!r}")
    w, h = size
    scene = ScalarScene(values, iso, sample_range, shadow_offset, spacing)
    eye, dirs = camera_rays(camera, size)
    background = np.asarray(background, dtype=np.float64)
    out = np.tile(background, (len(dirs), 1))
    near, far = scene.box(np.broadcast_to(eye, dirs.shape), dirs)
    rays = np.flatnonzero(near < far)
    a_all = scene.to_texture(eye + dirs[rays] * near[rays, None])
    b_all = scene.to_texture(eye + dirs[rays] * far[rays, None])
    longest = max(1, int(np.ceil(steps * np.linalg.norm(b_all - a_all, axis=-1).max()))) if len(rays) else 1
    chunk = max(1, CHUNK_SAMPLES // longest)
    lights = [np.asarray(p, float) for p in lights]
    for start in range(0, len(rays), chunk):
        part = slice(start, start + chunk)
        a, b = a_all[part], b_all[part]
        pos, valid = _march(scene, a, b, steps)
        v = scene.field(pos)
        at = np.ones(len(a))  # where each ray stopped: all the way through but on an iso surface
        if mode == "iso":
            shade, at = _iso(scene, transfer, a, b, pos, valid, v, dirs[rays[part]], lights, steps, shadow_steps,
                             shadows)
        elif mode == "translucent":
            shade = _composite(scene, transfer, a, b, valid, v, background)
        else:
            rgba = colour_of(transfer.table(), _projection(scene, transfer, mode, a, b, valid, v, mip_attenuation))
            shade = rgba[:, :3] * rgba[:, 3:] + (1.0 - rgba[:, 3:]) * background
        shade = np.where(np.isnan(shade), background, shade)  # iso: rays that met no surface
        out[rays[part]] = shade if labels is None else over(labels, shade, a, b, at, dirs[rays[part]])
    return out.reshape(h, w, 3)


def _window_t(transfer: TransferFunction, v: np.ndarray) -> np.ndarray:
    return (v - transfer.low) / (transfer.high - transfer.low)


def _voxels_a_step(scene: ScalarScene, a: np.ndarray, b: np.ndarray, valid: np.ndarray) -> np.ndarray:
    """A step's world length in voxels' shortest sides."""
    return np.linalg.norm((b - a) * 2.0 * scene.extent, axis=-1) / (valid.sum(-1) * scene.voxel)


def _projection(scene, transfer, mode: str, a, b, valid, v, attenuation: float) -> np.ndarray:
    """The window units t each ray shows in mip, minip, average and attenuated_mip."""
    if mode == "mip":
        return _window_t(transfer, np.where(valid, v, -np.inf).max(-1))
    if mode == "minip":
        return _window_t(transfer, np.where(valid, v, np.inf).min(-1))
    if mode == "average":
        return _window_t(transfer, (v * valid).sum(-1) / valid.sum(-1))
    t = _window_t(transfer, v)
    accumulated = np.cumsum(np.clip(t, 0.0, 1.0) * valid, -1)
    scaled = t * np.exp(-attenuation * (accumulated * _voxels_a_step(scene, a, b, valid)[:, None] - 1.0))
    return np.where(valid, scaled, -np.inf).max(-1)


def _iso(scene, transfer, a, b, pos, valid, v, d, lights, steps, shadow_steps,
         shadows) -> tuple[np.ndarray, np.ndarray]:
    """The first sample over the iso value, bisected against the one before (or the entry), lit as F5; and how far
    along a -> b each ray met it (1: no surface)."""
    over = (v > scene.level) & valid
    hit = over.any(-1)
    index = over.argmax(-1)
    rows = np.arange(len(pos))
    lo = np.where((index > 0)[:, None], pos[rows, np.maximum(index - 1, 0)], a)
    hi = pos[rows, index]
    for _ in range(rm.REFINE):
        mid = 0.5 * (lo + hi)
        inside = (scene.field(mid) > scene.level)[:, None]
        hi, lo = np.where(inside, mid, hi), np.where(inside, lo, mid)
    out = np.full((len(pos), 3), np.nan)  # no hit: the background
    if hit.any():
        colour = np.tile(colour_of(transfer.table(), _window_t(transfer, np.array(scene.level)))[:3], (hit.sum(), 1))
        out[hit] = _phong(scene, hi[hit], colour, d[hit], rm.MODES[5], lights, steps, shadow_steps, shadows)
    ab = b - a
    at = np.where(hit, ((hi - a) * ab).sum(-1) / np.maximum((ab * ab).sum(-1), 1e-300), 1.0)
    return out, at


def _composite(scene, transfer, a, b, valid, v, background: np.ndarray) -> np.ndarray:
    """Front to back through the opacity curve, each sample's alpha corrected for its step's length in voxels."""
    curve = transfer.opacity()
    alpha = np.interp(v, [p[0] for p in curve], [p[1] for p in curve]) * valid
    alpha = 1.0 - (1.0 - alpha) ** _voxels_a_step(scene, a, b, valid)[:, None]
    through = np.cumprod(1.0 - alpha, -1)  # what passes each sample and all before it
    before = np.concatenate([np.ones((len(v), 1)), through[:, :-1]], -1)
    colour = colour_of(transfer.table(), _window_t(transfer, v))[..., :3]
    total = (before * alpha)[..., None] * colour
    return total.sum(1) + through[:, -1:] * background
