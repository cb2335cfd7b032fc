"""The 4x4 transforms of the 3D workspaces, written once: numpy float64, row-major, acting on column vectors
(clip = projection @ view @ world), with GL's conventions (the camera looks down -z, clip depth -w..w).
`gl_matrix` turns one into the column-major order a GL mat4 uniform takes.

Each is the exact arithmetic its callers always used, so a camera or a light's view gives the same bits (the
renders' pixels depend on them)."""
from __future__ import annotations

import numpy as np


def perspective(focal: float, aspect: float, near: float, far: float) -> np.ndarray:
    """A symmetric frustum: `focal` is 1 / tan(half the vertical field of view), `aspect` width over height,
    `near` and `far` the clip planes' distances (0 < near < far)."""
    m = np.zeros((4, 4))
    m[0, 0], m[1, 1] = focal / aspect, focal
    m[2, 2], m[2, 3] = (far + near) / (near - far), 2 * far * near / (near - far)
    m[3, 2] = -1.0
    return m


def frustum(lo, hi, near: float, far: float) -> np.ndarray:
    """An off-centre frustum (glFrustum): its window `lo` (x, y) .. `hi` given as tangents, the view-space
    x / depth and y / depth its edges pass, onto the clip square; `near` and `far` the clip planes' distances."""
    (x0, y0), (x1, y1) = lo, hi
    m = np.zeros((4, 4))
    m[0, 0], m[0, 2] = 2 / (x1 - x0), (x1 + x0) / (x1 - x0)
    m[1, 1], m[1, 2] = 2 / (y1 - y0), (y1 + y0) / (y1 - y0)
    m[2, 2], m[2, 3] = (far + near) / (near - far), 2 * far * near / (near - far)
    m[3, 2] = -1.0
    return m


def orthographic(lo, hi) -> np.ndarray:
    """The view-space box lo..hi onto the clip cube: (x, y, depth) corners, depth measured along -z."""
    (x0, y0, n), (x1, y1, f) = lo, hi
    m = np.identity(4)
    m[0, 0], m[1, 1], m[2, 2] = 2 / (x1 - x0), 2 / (y1 - y0), -2 / (f - n)
    m[:3, 3] = -(x1 + x0) / (x1 - x0), -(y1 + y0) / (y1 - y0), -(f + n) / (f - n)
    return m


def least_axis(forward) -> np.ndarray:
    """The world axis least along `forward`: an up vector never parallel to it."""
    return np.eye(3)[np.argmin(np.abs(forward))]


def look_at(eye, forward, up=None) -> np.ndarray:
    """World -> view for an eye at `eye` looking along `forward` (a unit direction, not a point), with `up`
    (any vector not along `forward`; None: least_axis) as near the view's +y as it can be."""
    forward = np.asarray(forward, np.float64)
    right = np.cross(forward, least_axis(forward) if up is None else up)
    right /= np.linalg.norm(right)
    m = np.identity(4)
    m[0, :3], m[1, :3], m[2, :3] = right, np.cross(right, forward), -forward
    m[:3, 3] = -m[:3, :3] @ np.asarray(eye, np.float64)
    return m


def gl_matrix(m) -> tuple:
    """A row-major 4x4 (numpy, any float type) as the value of a GL mat4 uniform: column-major, the float64
    values GL rounds to float32 (so every program given one matrix gets the same float32 one)."""
    return tuple(np.asarray(m, np.float64).T.flatten())
