"""A 2D orthographic camera: a centre and the world height the view shows."""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np


@dataclass
class Camera2D:
    cx: float = 0.0
    cy: float = 0.0
    height: float = 2.6  # world units from bottom to top of the view

    def __post_init__(self) -> None:
        if not (math.isfinite(self.cx) and math.isfinite(self.cy)):
            raise ValueError("camera centre must be finite")
        if not (math.isfinite(self.height) and self.height > 0):
            raise ValueError(f"camera height must be > 0, got {self.height}")

    def key(self) -> tuple[float, float, float]:
        """What the view shows: its part of a workspace's version and digest."""
        return self.cx, self.cy, self.height

    def scale_offset(self, width: int, height: int) -> tuple[np.ndarray, np.ndarray]:
        """clip = world * scale + offset; y up in world and in clip space. In double: a centre near 1e6
        times the scale must not round to float32 before a renderer subtracts what it needs."""
        sy = 2.0 / self.height
        sx = sy * height / max(width, 1)
        return np.array([sx, sy]), np.array([-self.cx * sx, -self.cy * sy])

    def view_rect(self, width: int, height: int) -> tuple[float, float, float, float]:
        """The world rectangle (x0, y0, x1, y1) a width x height view shows."""
        half_h = self.height / 2
        half_w = half_h * width / max(height, 1)
        return self.cx - half_w, self.cy - half_h, self.cx + half_w, self.cy + half_h

    def to_world(self, px: float, py: float, width: int, height: int) -> tuple[float, float]:
        """Pixel (origin top-left, y down) to world coordinates."""
        units = self.height / max(height, 1)
        return self.cx + (px - width / 2) * units, self.cy - (py - height / 2) * units

    def world_per_pixel(self, height: int) -> float:
        return self.height / max(height, 1)

    def zoomed_about(self, x: float, y: float, wheel_steps: float, step: float = 1.15,
                     lo: float = 1e-3, hi: float = 1e4) -> tuple[float, float, float]:
        """(cx, cy, height) after zooming by `step` per wheel notch, keeping world point (x, y) in place."""
        h = min(hi, max(lo, self.height * step ** -wheel_steps))
        k = h / self.height
        return x + (self.cx - x) * k, y + (self.cy - y) * k, h
