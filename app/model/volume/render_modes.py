"""Tex3Dtrace's render modes (seed 003) as data: what the GPU shader and the CPU reference both obey.

Every mode marches S = cl_steps * |AB| samples from the ray's entry A to its exit B (texture space), at
the middle of each step, trilinear, clamped at the edges. A sample's intensity is I = (r + g + b) * a.
"""
from __future__ import annotations

from dataclasses import dataclass

from app.model.volume.labels import DEFAULT_OPACITY
from app.model.volume.scalar_modes import MIP_ATTENUATION

THRESHOLD = 0.3      # a surface: the first sample whose intensity exceeds this (of 3)
AMBIENT = 0.2        # the seed's 10-20 % ambient
DIFFUSE = 0.85
SPECULAR = 0.35
SHININESS = 24.0
ATTENUATION = 0.02   # 1 / (1 + k d^2), d in world units
SHADOW_OFFSET = 1.5  # voxels along the normal before a shadow ray starts (the seed's offset)
REFINE = 5           # bisection steps that place a hit between its sample and the one before
LIGHTS = ((0.4, 0.7, 2.6), (-2.5, 1.5, 1.5))  # world positions, in front: into the open Cornell box


@dataclass(frozen=True)
class Mode:
    number: int
    name: str
    kind: str                  # "translucent", "pure" or "phong"
    two_pass: bool = False     # ray entry/exit from rasterised back/front faces instead of the slab test
    shadows: str = "none"      # "none", "constant" (cl_shadowSteps) or "correct" (steps by length)
    translucency: bool = False  # phong hits blended with what lies behind, by alpha
    lights: int = 1
    distance: bool = False     # empty-space skipping with the distance texture
    dual: bool = False         # linear and nearest filtering blended
    reflections: bool = False


MODES = {m.number: m for m in (
    Mode(1, "two-pass translucent", "translucent", two_pass=True),
    Mode(2, "two-pass pure colour", "pure", two_pass=True),
    Mode(3, "two-pass Phong + shadows", "phong", two_pass=True, shadows="constant"),
    Mode(4, "translucent", "translucent"),
    Mode(5, "Phong + shadows", "phong", shadows="constant"),
    Mode(6, "Phong + shadows + translucency", "phong", shadows="constant", translucency=True),
    Mode(7, "distance-accelerated Phong + shadows", "phong", shadows="constant", distance=True),
    Mode(8, "correct shadows", "phong", shadows="correct", distance=True),
    Mode(9, "dual view (linear + nearest)", "pure", dual=True),
    Mode(10, "two lights", "phong", shadows="constant", lights=2),
    Mode(11, "reflections", "phong", shadows="constant", reflections=True),
)}


@dataclass(frozen=True)
class TraceSettings:
    """The ray tracer's settings (built from cvars and the view by the commands, or by a bench)."""
    mode: int = 5
    steps: float = 128.0
    shadow_steps: int = 20
    sample_range: float = 1.0
    distance_scale: float = 1.0
    shadows: bool = True
    lights: tuple = LIGHTS
    debug_samples: bool = False  # output each pixel's texture-sample count (a float target is needed)
    slice_planes: bool = True    # the edited and picked slices drawn over the volume (off to compare)
    shadow_offset: float = SHADOW_OFFSET
    eye_distance: float = 0.12   # world units between the eyes of the anaglyph pair
    # a scalar volume's mode (app/model/volume/scalar_modes.py; colour: the F-mode above), its iso value (data units)
    # and attenuated MIP's attenuation
    scalar_mode: str = "colour"
    iso: float = 0.0
    mip_attenuation: float = MIP_ATTENUATION
    label_opacity: float = DEFAULT_OPACITY  # a scan's labels over it (r_labelOpacity)
