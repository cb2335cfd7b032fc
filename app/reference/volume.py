"""CPU reference of the volume ray tracer's modes (app/model/volume/render_modes.py), numpy and scipy.

Same rays, same sampling rule and the same shading as resources/shaders/raytrace_FS.glsl, but exact
entry and exit in float64 and as many steps as asked (the reference uses many more than the GPU).
Meant for small images (<= 128 x 128)."""
from __future__ import annotations

import numpy as np
from scipy.ndimage import map_coordinates

from app.model.volume import render_modes as rm
from app.model.camera3d import OrbitCamera
from app.model.volume.view import FLIP, box_extents, voxel_extent, world_to_texture
from app.reference.volume_labels import LabelLayer, over



class Scene:
    """The volume as float RGBA and intensity, with its box, for one reference render."""

    level = rm.THRESHOLD  # a surface lies where field() first exceeds this

    def __init__(self, data: np.ndarray, sample_range: float = 1.0, shadow_offset: float = rm.SHADOW_OFFSET,
                 spacing: tuple[float, float, float] = (1.0, 1.0, 1.0)) -> None:
        self.shadow_offset = shadow_offset
        self.rgba = data.astype(np.float64) / 255.0                  # (d, h, w, 4)
        self.size = np.array(data.shape[2::-1], dtype=np.float64)    # (w, h, d)
        voxels = tuple(int(s) for s in self.size)
        self.extent = np.array(box_extents(voxels, spacing))
        self.voxel = voxel_extent(voxels, spacing)                    # world size of a voxel's shortest side
        self.sample_range = sample_range

    def to_texture(self, p: np.ndarray) -> np.ndarray:
        return world_to_texture(p, self.extent)

    def sample(self, t: np.ndarray, nearest: bool = False) -> np.ndarray:
        """RGBA at texture coordinates t (..., 3): texel centres at (i + 0.5) / size; trilinear with a transparent
        border (the GPU's sampler), nearest clamped to the edge."""
        coords = [t[..., 2] * self.size[2] - 0.5, t[..., 1] * self.size[1] - 0.5, t[..., 0] * self.size[0] - 0.5]
        if nearest:
            coords = [np.floor(c + 0.5) for c in coords]
            return np.stack([map_coordinates(self.rgba[..., c], coords, order=0, mode="nearest") for c in range(4)], -1)
        return np.stack([map_coordinates(self.rgba[..., c], coords, order=1, mode="grid-constant") for c in range(4)],
                        -1)

    def material(self, t: np.ndarray) -> np.ndarray:
        """The colour and alpha under hits at t (n, 3): the 8 texels of the trilinear filter weighted by their
        weight times their alpha (associated colour), those beyond the edge empty; as the GPU's material_at."""
        u = t * self.size - 0.5
        base = np.floor(u)
        f = u - base
        total = np.zeros((len(t), 4))  # rgb: sum w a c, a: sum w a
        alpha = np.zeros(len(t))       # sum w a a
        for corner in np.ndindex(2, 2, 2):
            o = np.array(corner[::-1])  # (x, y, z) offsets
            p = (base + o).astype(np.int64)
            inside = ((p >= 0) & (p < self.size)).all(-1)
            q = np.where(inside[:, None], p, 0)
            v = self.rgba[q[:, 2], q[:, 1], q[:, 0]]
            wa = np.where(o == 1, f, 1.0 - f).prod(-1) * v[:, 3] * inside
            total += wa[:, None] * np.concatenate([v[:, :3], np.ones((len(t), 1))], -1)
            alpha += wa * v[:, 3]
        weight = total[:, 3:]
        with np.errstate(invalid="ignore", divide="ignore"):
            out = np.concatenate([total[:, :3] / weight, alpha[:, None] / weight], -1)
        return np.where(weight > 0, out, 0.0)

    @staticmethod
    def intensity(s: np.ndarray) -> np.ndarray:
        return s[..., :3].sum(-1) * s[..., 3]

    def field(self, t: np.ndarray) -> np.ndarray:
        """What a surface is in, at texture coordinates t (..., 3): the intensity (a scalar scene: the value)."""
        return self.intensity(self.sample(t))

    def box(self, origin: np.ndarray, direction: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Slab test: entry (>= 0: the camera may be inside) and exit distances; entry >= exit: a miss."""
        with np.errstate(divide="ignore", invalid="ignore"):
            inv = 1.0 / direction
            t0, t1 = (-self.extent - origin) * inv, (self.extent - origin) * inv
        t0, t1 = np.nan_to_num(t0, nan=-np.inf), np.nan_to_num(t1, nan=np.inf)
        near = np.maximum(np.minimum(t0, t1).max(-1), 0.0)
        far = np.maximum(t0, t1).min(-1)
        return near, far


def _march(scene: Scene, a: np.ndarray, b: np.ndarray, steps_per_unit: float, fixed: int | None = None):
    """Sample positions along a -> b (texture space): S = ceil(steps * |AB|) (or `fixed`) midpoints.
    Returns (positions (n, k, 3), valid (n, k)) padded to the longest ray."""
    length = np.linalg.norm(b - a, axis=-1)
    counts = np.full(len(a), fixed) if fixed else np.maximum(1, np.ceil(steps_per_unit * length)).astype(int)
    k = int(counts.max()) if len(counts) else 0
    i = np.arange(k)
    frac = (i[None, :] + 0.5) / counts[:, None]
    valid = i[None, :] < counts[:, None]
    return a[:, None, :] + (b - a)[:, None, :] * frac[..., None], valid


def _first_hit(scene: Scene, entry: np.ndarray, pos: np.ndarray, valid: np.ndarray, nearest: bool = False):
    """The first sample over the threshold, then bisected against the sample before it (as the GPU).
    Returns (hit, point, colour, index): the bisected point never lies past the sample at step `index`; the colour
    is its voxels' (Scene.material), or the nearest sample's."""
    s = scene.sample(pos, nearest)
    over = (scene.intensity(s) > rm.THRESHOLD) & valid
    hit = over.any(-1)
    index = over.argmax(-1)
    rows = np.arange(len(pos))
    t, colour = pos[rows, index], s[rows, index]
    if not nearest and hit.any():
        lo = np.where((index > 0)[:, None], pos[rows, np.maximum(index - 1, 0)], entry)
        hi = t.copy()
        for _ in range(rm.REFINE):
            mid = 0.5 * (lo + hi)
            m = scene.sample(mid)
            inside = scene.intensity(m) > rm.THRESHOLD
            hi = np.where(inside[:, None], mid, hi)
            lo = np.where(inside[:, None], lo, mid)
        t = hi
        colour = scene.material(t)
    return hit, t, colour, index


def _normal(scene: Scene, t: np.ndarray, view_dir: np.ndarray) -> np.ndarray:
    """-grad I from central differences at +-cl_sampleRange voxels, in world space."""
    g = np.zeros_like(t)
    for axis in range(3):
        d = np.zeros(3)
        d[axis] = scene.sample_range / scene.size[axis]
        g[:, axis] = scene.field(t + d) - scene.field(t - d)
    n = -(g * FLIP / scene.extent)
    length = np.linalg.norm(n, axis=-1, keepdims=True)
    return np.where(length > 1e-9, n / np.maximum(length, 1e-300), -view_dir)


def _shadow(scene: Scene, p: np.ndarray, n: np.ndarray, light: np.ndarray, mode: rm.Mode,
            steps: float, shadow_steps: int) -> np.ndarray:
    """1 where the light reaches p, 0 where a sample over the threshold lies between."""
    start = p + n * scene.shadow_offset * scene.voxel
    to_light = light - start
    dist = np.linalg.norm(to_light, axis=-1)
    direction = to_light / dist[:, None]
    near, far = scene.box(start, direction)
    far = np.minimum(far, dist)
    inside = near < far
    lit = np.ones(len(p))
    if not inside.any():
        return lit
    a = scene.to_texture(start[inside] + direction[inside] * near[inside, None])
    b = scene.to_texture(start[inside] + direction[inside] * far[inside, None])
    fixed = shadow_steps if mode.shadows == "constant" else None
    pos, valid = _march(scene, a, b, steps, fixed)
    blocked = ((scene.field(pos) > scene.level) & valid).any(-1)
    lit[inside] = np.where(blocked, 0.0, 1.0)
    return lit


def _phong(scene: Scene, t: np.ndarray, s: np.ndarray, view_dir: np.ndarray, mode: rm.Mode,
           lights: list[np.ndarray], steps: float, shadow_steps: int, shadows: bool) -> np.ndarray:
    p = (t * 2.0 - 1.0) * scene.extent * FLIP  # back to world
    n = _normal(scene, t, view_dir)
    base = s[:, :3]
    colour = base * rm.AMBIENT
    for light in lights[: mode.lights]:
        to_light = light - p
        d = np.linalg.norm(to_light, axis=-1)
        l_dir = to_light / d[:, None]
        diffuse = np.maximum((n * l_dir).sum(-1), 0.0)
        r = 2.0 * (n * l_dir).sum(-1, keepdims=True) * n - l_dir
        specular = np.maximum((r * -view_dir).sum(-1), 0.0) ** rm.SHININESS
        lit = _shadow(scene, p, n, light, mode, steps, shadow_steps) if shadows and mode.shadows != "none" \
            else np.ones(len(p))
        att = 1.0 / (1.0 + rm.ATTENUATION * d * d)
        colour = colour + (base * (rm.DIFFUSE * diffuse)[:, None] + rm.SPECULAR * specular[:, None]) \
            * (att * lit)[:, None]
    return np.clip(colour, 0.0, 1.0)


def render(data: np.ndarray, camera: OrbitCamera, size: tuple[int, int], mode: rm.Mode, steps: float,
           shadow_steps: int = 20, sample_range: float = 1.0, background=(0.0, 0.0, 0.0),
           lights=rm.LIGHTS, shadows: bool = True, shadow_offset: float = rm.SHADOW_OFFSET,
           spacing: tuple[float, float, float] = (1.0, 1.0, 1.0), labels: LabelLayer | None = None) -> np.ndarray:
    """The image (height, width, 3), floats 0..1, top row first; `spacing`: the voxels' sides (x, y, z); a scan's
    `labels` laid over it."""
    w, h = size
    scene = Scene(data, sample_range, shadow_offset, spacing)
    eye, dirs = camera_rays(camera, size)
    out = np.tile(np.asarray(background, dtype=np.float64), (len(dirs), 1))
    near, far_t = scene.box(np.broadcast_to(eye, dirs.shape), dirs)
    rays = np.flatnonzero(near < far_t)
    if len(rays):
        d = dirs[rays]
        a = scene.to_texture(eye + d * near[rays, None])
        b = scene.to_texture(eye + d * far_t[rays, None])
        out[rays], at = _shade(scene, a, b, d, mode, steps, shadow_steps, np.asarray(background, float),
                               [np.asarray(p, float) for p in lights])
        if labels is not None:
            out[rays] = over(labels, out[rays], a, b, at, d)
    return out.reshape(h, w, 3)


def camera_rays(camera: OrbitCamera, size: tuple[int, int]) -> tuple[np.ndarray, np.ndarray]:
    """The eye and the unit direction through each pixel's centre (w * h, 3), top row first."""
    w, h = size
    inv = np.linalg.inv(camera.clip_from_world((w, h)))
    px, py = np.meshgrid(np.arange(w) + 0.5, np.arange(h) + 0.5)
    ndc = np.stack([2 * px / w - 1, 1 - 2 * py / h, np.ones_like(px), np.ones_like(px)], -1).reshape(-1, 4)
    far = ndc @ inv.T
    eye = camera.position()
    dirs = far[:, :3] / far[:, 3:] - eye
    return eye, dirs / np.linalg.norm(dirs, axis=-1, keepdims=True)


def _translucent(scene: Scene, pos: np.ndarray, valid: np.ndarray, background: np.ndarray) -> np.ndarray:
    s = scene.sample(pos) * valid[..., None]
    count = valid.sum(-1, keepdims=True)
    colour = (s[..., :3] * s[..., 3:]).sum(1) / count
    alpha = s[..., 3].sum(1, keepdims=True) / count
    return colour + (1.0 - alpha) * background


def _shade(scene, a, b, d, mode, steps, shadow_steps, background, lights) -> tuple[np.ndarray, np.ndarray]:
    """The colours of rays a -> b, and how far along each its colour was found (1: all the way)."""
    pos, valid = _march(scene, a, b, steps)
    if mode.kind == "translucent":
        return _translucent(scene, pos, valid, background), np.ones(len(a))
    hit, t, s, index = _first_hit(scene, a, pos, valid)
    ab = b - a
    with np.errstate(invalid="ignore", divide="ignore"):
        at = np.where(hit, ((t - a) * ab).sum(-1) / (ab * ab).sum(-1), 1.0)
    out = np.tile(background, (len(a), 1))
    if mode.kind == "pure":
        out[hit] = s[hit, :3]
        if mode.dual:
            nhit, _nt, ns, *_ = _first_hit(scene, a, pos, valid, nearest=True)
            near_col = np.tile(background, (len(a), 1))
            near_col[nhit] = ns[nhit, :3]
            out = 0.5 * out + 0.5 * near_col
        return out, at
    if hit.any():
        shade = _phong(scene, t[hit], s[hit], d[hit], mode, lights, steps, shadow_steps, shadows=True)
        if mode.translucency:  # the surface's alpha over the mean of what lies behind it, its own sample on
            behind_pos, behind_valid = pos[hit], valid[hit] & (np.arange(pos.shape[1])[None, :] >= index[hit, None])
            empty = ~behind_valid.any(-1)
            behind_valid[empty, -1] = True  # nothing behind: the mean of one empty sample
            behind = _translucent(scene, behind_pos, behind_valid, background)
            behind[empty] = background
            shade = s[hit, 3:] * shade + (1.0 - s[hit, 3:]) * behind
        if mode.reflections:
            shade = 0.75 * shade + 0.25 * _reflection(scene, t[hit], d[hit], steps, background)
        out[hit] = shade
    return out, at


def _reflection(scene: Scene, t: np.ndarray, d: np.ndarray, steps: float, background: np.ndarray) -> np.ndarray:
    """The pure colour seen along the view ray mirrored about the normal (one bounce)."""
    n = _normal(scene, t, d)
    r = d - 2.0 * (d * n).sum(-1, keepdims=True) * n
    p = (t * 2.0 - 1.0) * scene.extent * FLIP + n * scene.shadow_offset * scene.voxel
    near, far = scene.box(p, r)
    out = np.tile(background, (len(t), 1))
    inside = np.flatnonzero(near < far)
    if len(inside):
        a = scene.to_texture(p[inside] + r[inside] * near[inside, None])
        b = scene.to_texture(p[inside] + r[inside] * far[inside, None])
        pos, valid = _march(scene, a, b, steps)
        hit, _t, s, *_ = _first_hit(scene, a, pos, valid)
        out[inside[hit]] = s[hit, :3]
    return out
