"""Screen-space math for the 3D lights views: the translate gizmo drawn on the selected item (three handles
along the world's x, y and z) and picking what lies under the mouse. numpy only.

Pixels are the view's, origin top left (OrbitCamera.ray's); `size` is the view's (width, height) in pixels.
A drag moves the item along one axis by how far the point of that axis under the mouse moved, so the item never
jumps to the mouse: `drag_along` is given the item's position when the drag began and the press pixel."""
from __future__ import annotations

import numpy as np

from app.model.camera3d import OrbitCamera
from app.model.lights3d.scene import MAX_COORD, Scene3D

HANDLE_FRACTION = 0.12  # a handle's length as a share of the view's height, the same at any distance
# A handle seen about end-on is shorter than this on screen: it is not offered, since the world distance a pixel
# of mouse motion means along it grows without bound.
MIN_HANDLE_PX = 8.0
PARALLEL = 1e-9         # 1 - cos^2 between the mouse ray and the axis below which they count as parallel
AXES = np.identity(3)


class Projection:
    """World points to the view's pixels (origin top left, OrbitCamera.ray's) for one camera and view size."""

    def __init__(self, camera: OrbitCamera, size: tuple[int, int]) -> None:
        self.size, self.near = size, camera.NEAR
        self.clip_from_world = camera.clip_from_world(size)
        # f, the projection's vertical scale: row 1 is f times the view's up row, a unit vector
        self.scale = float(np.linalg.norm(self.clip_from_world[1, :3]))

    def clip(self, points) -> np.ndarray:
        p = np.asarray(points, np.float64)
        return np.concatenate([p, np.ones(p.shape[:-1] + (1,))], axis=-1) @ self.clip_from_world.T

    def pixels(self, clip: np.ndarray) -> np.ndarray:
        """Pixels (..., 2) of clip coordinates (..., 4); meaningless where w <= 0 (behind the eye)."""
        with np.errstate(divide="ignore", invalid="ignore"):
            ndc = clip[..., :2] / clip[..., 3:]
        return np.stack([(ndc[..., 0] + 1) * self.size[0] / 2, (1 - ndc[..., 1]) * self.size[1] / 2], axis=-1)

    def in_front(self, point) -> bool:
        """In front of the near plane (a NaN point is not)."""
        return bool(self.clip(point)[3] > self.near)

    def world_length(self, point, fraction: float) -> float:
        """The world length at `point` that spans `fraction` of the view's height on screen: the view is
        2 depth / f world units tall there."""
        return float(fraction * 2 * self.clip(point)[3] / self.scale)

    def segment(self, a, b) -> np.ndarray | None:
        """The pixels (2, 2) of the part of segment a-b in front of the near plane, or None."""
        ca, cb = self.clip(a), self.clip(b)
        wa, wb = ca[3] - self.near, cb[3] - self.near
        if wa <= 0 and wb <= 0:
            return None
        if wa <= 0 or wb <= 0:
            cut = ca + wa / (wa - wb) * (cb - ca)
            ca, cb = (cut, cb) if wa <= 0 else (ca, cut)
        return self.pixels(np.stack([ca, cb]))


def project(camera: OrbitCamera, size: tuple[int, int], points) -> tuple[np.ndarray, np.ndarray]:
    """Pixels (..., 2) of world points (..., 3), and each point's depth in front of the eye (<= 0: behind it,
    where the pixel means nothing)."""
    view = Projection(camera, size)
    clip = view.clip(points)
    return view.pixels(clip), clip[..., 3]


def handle_length(camera: OrbitCamera, size: tuple[int, int], origin) -> float | None:
    """The handles' world length at `origin`, HANDLE_FRACTION of the view's height on screen; None when the
    origin is not in front of the near plane."""
    view = Projection(camera, size)
    return view.world_length(origin, HANDLE_FRACTION) if view.in_front(origin) else None


def gizmo_axes(camera: OrbitCamera, size: tuple[int, int], origin) -> np.ndarray | None:
    """The x, y and z handles' screen segments, (3, 2, 2): [axis][from the origin's pixel, to the tip's];
    None when the gizmo is not wholly in front of the near plane."""
    length = handle_length(camera, size, origin)
    if length is None:
        return None
    origin = np.asarray(origin, dtype=np.float64)
    pixels, depth = project(camera, size, np.vstack([origin, origin + length * AXES]))
    if not (depth > camera.NEAR).all():
        return None
    return np.stack([np.stack([pixels[0], pixels[axis + 1]]) for axis in range(3)])


def hit_axis(camera: OrbitCamera, size: tuple[int, int], origin, px: float, py: float,
             tolerance_px: float = 6.0) -> int | None:
    """The handle (0 x, 1 y, 2 z) within tolerance_px of pixel (px, py), the nearest if several; else None."""
    segments = gizmo_axes(camera, size, origin)
    if segments is None:
        return None
    mouse = np.array([px, py], dtype=np.float64)
    best, found = np.inf, None
    for axis, (a, b) in enumerate(segments):
        ab = b - a
        if ab @ ab < MIN_HANDLE_PX ** 2:
            continue
        t = np.clip((mouse - a) @ ab / (ab @ ab), 0.0, 1.0)
        distance = float(np.linalg.norm(mouse - (a + t * ab)))
        if distance <= tolerance_px and distance < best:
            best, found = distance, axis
    return found


def _along(camera: OrbitCamera, size: tuple[int, int], origin: np.ndarray, axis: int, pixel) -> float | None:
    """t of the point origin + t AXES[axis] nearest the mouse ray through `pixel`; None where the ray runs
    parallel to the axis or that nearest point of the ray lies behind the eye."""
    eye, d = camera.ray(pixel[0], pixel[1], *size)
    e, w = AXES[axis], origin - eye
    b, dw, ew = e @ d, d @ w, e @ w
    denom = 1.0 - b * b  # both unit vectors: 1 - cos^2 of the angle between them
    if denom < PARALLEL:
        return None
    t = (b * dw - ew) / denom
    if not dw + t * b > 0:  # the ray's own parameter: the nearest point must be in front of the eye
        return None
    return float(t)


def drag_along(camera: OrbitCamera, size: tuple[int, int], origin, axis: int, start_px,
               now_px) -> tuple[float, float, float] | None:
    """Where an item that was at `origin` when handle `axis` was pressed at pixel start_px goes with the mouse now
    at now_px: moved along the axis by the change of the axis point nearest the mouse ray. None where the mouse
    gives no position (its ray parallel to the axis, the nearest point behind the eye, or beyond the model's
    coordinates): the drag keeps its last one."""
    origin = np.asarray(origin, dtype=np.float64)
    start, now = _along(camera, size, origin, axis, start_px), _along(camera, size, origin, axis, now_px)
    if start is None or now is None:
        return None
    moved = origin + (now - start) * AXES[axis]
    if not (np.abs(moved) <= MAX_COORD).all():
        return None
    return tuple(float(v) for v in moved)


def pick_light(scene: Scene3D, camera: OrbitCamera, size: tuple[int, int], px: float, py: float,
               radius_px: float = 8.0) -> int | None:
    """The light whose marker (drawn at its position, whatever its kind) is within radius_px of pixel (px, py):
    the nearest to the mouse, then to the eye; lights behind the eye are never picked."""
    if not scene.lights:
        return None
    pixels, depth = project(camera, size, [light.position for light in scene.lights])
    with np.errstate(invalid="ignore"):
        distance = np.linalg.norm(pixels - [px, py], axis=1)
    near = (depth > camera.NEAR) & (distance <= radius_px)
    if not near.any():
        return None
    candidates = np.flatnonzero(near)
    return int(candidates[np.lexsort((depth[candidates], distance[candidates]))[0]])


def pick_object(scene: Scene3D, camera: OrbitCamera, size: tuple[int, int], px: float, py: float) -> int | None:
    """The object seen at pixel (px, py): the one whose triangle the ray through it meets first; None where it
    meets none. Objects whose bounding sphere the ray misses are skipped unread."""
    eye, d = camera.ray(px, py, *size)
    best, found = np.inf, None
    for index, obj in enumerate(scene.objects):
        to_centre = np.asarray(obj.position) - eye
        along, radius = to_centre @ d, obj.radius
        if to_centre @ to_centre - along * along > radius * radius or along + radius < 0:
            continue
        hit = _first_hit(obj.mesh().corners(), eye, d)
        if hit < best:
            best, found = hit, index
    return found


def _first_hit(corners: np.ndarray, eye: np.ndarray, d: np.ndarray) -> float:
    """The ray's smallest t > 0 on triangles (T, 3, 3), either side (Moller-Trumbore); inf if none."""
    e1, e2 = corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]
    p = np.cross(d, e2)
    det = np.einsum("ij,ij->i", e1, p)
    with np.errstate(divide="ignore", invalid="ignore"):
        inv = 1.0 / det
        s = eye - corners[:, 0]
        u = np.einsum("ij,ij->i", s, p) * inv
        q = np.cross(s, e1)
        v = (q @ d) * inv
        t = np.einsum("ij,ij->i", e2, q) * inv
        hit = (np.abs(det) > 1e-12) & (u >= 0) & (v >= 0) & (u + v <= 1) & (t > 0)  # NaN where det is 0: no hit
    return float(t[hit].min()) if hit.any() else np.inf
