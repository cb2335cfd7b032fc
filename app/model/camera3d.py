"""An orbit camera around a centre (the origin here): yaw and pitch in degrees, a distance, a vertical field of
view. The distance limits and the clip planes are class attributes, so a workspace of another scale subclasses
the camera with its own (app/model/lights3d/scene.py: Lights3DCamera)."""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from app.model.transforms import look_at, perspective

PITCH_LIMIT = 89.0  # straight up or down would make "up" undefined
UP = (0.0, 1.0, 0.0)


@dataclass
class OrbitCamera:
    yaw: float = 25.0
    pitch: float = 18.0
    distance: float = 5.2  # the whole [-1, 1] box fits the 40-degree view
    fov: float = 40.0  # vertical, degrees
    shift: float = 0.0  # sideways along the camera's right, world units (one eye of a stereo pair)

    MIN_DISTANCE: ClassVar[float] = 0.5
    MAX_DISTANCE: ClassVar[float] = 100.0
    NEAR: ClassVar[float] = 0.05  # clip planes of projection()
    FAR: ClassVar[float] = 200.0

    def __post_init__(self) -> None:
        if not all(math.isfinite(v) for v in (self.yaw, self.pitch, self.distance, self.fov)):
            raise ValueError("camera values must be finite")
        if not self.MIN_DISTANCE <= self.distance <= self.MAX_DISTANCE:
            raise ValueError(f"distance must be within {self.MIN_DISTANCE:g}..{self.MAX_DISTANCE:g}, "
                             f"got {self.distance:g}")
        if not abs(self.pitch) <= PITCH_LIMIT:
            raise ValueError(f"pitch must be within -{PITCH_LIMIT:g}..{PITCH_LIMIT:g}, got {self.pitch:g}")

    def centre(self) -> np.ndarray:
        """The point the camera orbits and looks at."""
        return np.zeros(3)

    def _orbit(self) -> np.ndarray:
        yaw, pitch = math.radians(self.yaw), math.radians(self.pitch)
        return self.distance * np.array([math.cos(pitch) * math.sin(yaw), math.sin(pitch),
                                         math.cos(pitch) * math.cos(yaw)])

    def _axes(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        forward = -self._orbit() / self.distance
        right = np.cross(forward, UP)
        right /= np.linalg.norm(right)
        return forward, right, np.cross(right, forward)

    def position(self) -> np.ndarray:
        return self.centre() + self._orbit() + self._axes()[1] * self.shift

    def view(self) -> np.ndarray:
        """World -> camera (4x4, row-major numpy): looking along the orbit's direction with +y up (a
        shifted eye looks parallel to the other, as anaglyph pairs do)."""
        return look_at(self.position(), self._axes()[0], UP)

    def projection(self, aspect: float, near: float | None = None, far: float | None = None) -> np.ndarray:
        near = self.NEAR if near is None else near
        far = self.FAR if far is None else far
        # In a tall view the field of view is kept horizontally, so the volume still fits.
        return perspective(min(1.0, aspect) / math.tan(math.radians(self.fov) / 2), aspect, near, far)

    def clip_from_world(self, size: tuple[int, int]) -> np.ndarray:
        """World -> clip (4x4, row-major) for a view `size` (width, height) pixels: the matrix ray() inverts."""
        return self.projection(size[0] / max(size[1], 1)) @ self.view()

    def ray(self, px: float, py: float, width: int, height: int) -> tuple[np.ndarray, np.ndarray]:
        """World-space origin and unit direction through pixel (px, py), origin top-left."""
        inv = np.linalg.inv(self.clip_from_world((width, height)))
        ndc = np.array([2 * px / width - 1, 1 - 2 * py / height, 1.0, 1.0])
        far = inv @ ndc
        origin = self.position()
        d = far[:3] / far[3] - origin
        return origin, d / np.linalg.norm(d)
