"""What the 3D lights renderer is told besides the scene and the camera: the shadow map's size, its PCF kernel,
depth bias and a directional light's cascades, and a debug view. The r_shadow* cvars build it
(app/commands/lights3d.py: render_settings). Stencil-shadowed lights (onepass, zpass, zfail) ignore the map
settings."""
from __future__ import annotations

from dataclasses import dataclass

MIN_MAP_SIZE, MAX_MAP_SIZE = 256, 4096
PCF_KERNELS = (1, 3, 5)  # taps per side of the percentage-closer filter: 1 is a single hardware-filtered tap
MAX_BIAS = 0.1
MAX_CASCADES = 4  # a directional light's maps over the view's depths (app/gl/lights3d/map_fitting.py)
# none: the lit scene; stencil: the first stencil-shadowed light's stencil values after its volume pass, as
# grey levels; mask: white where the first light reaches a pixel and black where it does not (its shadow and
# its range or cone), the picture the reference's `facing & visible` gives.
DEBUG_VIEWS = ("none", "stencil", "mask")


@dataclass(frozen=True)
class Lights3DRenderSettings:
    map_size: int = 1024     # shadow map texels per side (a cube face's for point lights)
    pcf: int = 3             # PCF_KERNELS
    # Depth offset before the shadow map's comparison, in its 0..1 depth: the smallest one used, grown on
    # slopes as max(10 bias (1 - N.L), bias) (docs/lights3d.md); too little gives acne, too much peter-panning.
    # The map holds the casters' back faces, so a lit face needs next to none: 0.005 lit 1.9 % of the shadowed
    # pixels by peter-panning (`shadelab bench shadows`, the bias series), 0.0002 is within the texels' error.
    bias: float = 0.0002
    cascades: int = 3        # a directional light's maps, each over a slice of the view's depths: 1..MAX_CASCADES
    debug: str = "none"      # DEBUG_VIEWS
    overlays: bool = True    # the editor's marks: light markers, the selection and its gizmo (not in a render)

    def __post_init__(self) -> None:
        if not MIN_MAP_SIZE <= self.map_size <= MAX_MAP_SIZE:
            raise ValueError(f"the shadow map's size must be within {MIN_MAP_SIZE}..{MAX_MAP_SIZE}, "
                             f"got {self.map_size}")
        if self.pcf not in PCF_KERNELS:
            raise ValueError(f"the PCF kernel must be one of {', '.join(map(str, PCF_KERNELS))}, got {self.pcf}")
        if not 0.0 <= self.bias <= MAX_BIAS:
            raise ValueError(f"the shadow bias must be within 0..{MAX_BIAS:g}, got {self.bias:g}")
        if not 1 <= self.cascades <= MAX_CASCADES:
            raise ValueError(f"the shadow cascades must be within 1..{MAX_CASCADES}, got {self.cascades}")
        if self.debug not in DEBUG_VIEWS:
            raise ValueError(f"the debug view must be one of {', '.join(DEBUG_VIEWS)}, got {self.debug!r}")
