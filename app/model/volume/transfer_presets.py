"""Transfer-function presets after 3D Slicer's volume-rendering ones (its Resources/presets.xml): a window, a colour
map and an opacity curve set together (`vol.preset NAME`).

Slicer shades its volume rendering, so an opaque skin still shows what lies under its folds; the translucent mode
here composites unshaded, so these keep the soft tissue of the bone and air presets clear and the soft-tissue
preset's body faint where Slicer's is opaque. The CT presets are in Hounsfield units. MR intensities have no fixed
scale: the MR preset's window and points are fractions of the scan's own default window (Slicer's MR-Default is
written for values 0..1024), so it fits any MRI as Slicer's fits one of that range.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from app.model.volume.scalars import OpacityPoints, ScalarError, TransferFunction, default_window


@dataclass(frozen=True)
class Preset:
    title: str
    window: tuple[float, float]
    colormap: str
    points: OpacityPoints
    relative: bool = False  # window and point values as fractions of the scan's default window

    def transfer(self, values: np.ndarray) -> TransferFunction:
        if not self.relative:
            return TransferFunction(*self.window, self.colormap, self.points)
        low, high = default_window(values)
        at = lambda f: low + f * (high - low)  # noqa: E731
        return TransferFunction(at(self.window[0]), at(self.window[1]), self.colormap,
                                tuple((at(f), a) for f, a in self.points))


PRESETS: dict[str, Preset] = {
    # Slicer's CT-Bone colours (-16 dark red, 641 ivory) and opacity above 641; clear below 150 HU, not -16
    "ct_bone": Preset("CT bone", (-16.0, 1300.0), "ct_bone", ((150.0, 0.0), (641.0, 0.72), (3071.0, 0.71))),
    # Slicer's CT-Soft-Tissue window (-160..240 HU); fat and muscle faint, bone half opaque
    "ct_soft_tissue": Preset("CT soft tissue", (-160.0, 240.0), "ct_soft_tissue",
                             ((-250.0, 0.0), (-100.0, 0.005), (20.0, 0.015), (120.0, 0.015), (300.0, 0.25),
                              (3071.0, 0.3))),
    # Slicer's CT-Lung colours; the lungs' air and tissue (-950..-400 HU) shown, the air around the body and the
    # body itself clear
    "ct_air": Preset("CT air (lungs)", (-1000.0, -400.0), "ct_air",
                     ((-950.0, 0.0), (-900.0, 0.04), (-500.0, 0.04), (-400.0, 0.0))),
    # Slicer's MR-Default, its 0..1024 as the default window
    "mr_default": Preset("MR default", (0.0, 1.0), "mr_default",
                         ((0.0, 0.0), (0.02, 0.0), (0.04, 0.15), (0.12, 0.3), (0.21, 0.375), (1.0, 0.5)),
                         relative=True),
}


def check_preset(name: str) -> Preset:
    if name not in PRESETS:
        raise ScalarError(f"no preset {name!r}; choose one of {', '.join(PRESETS)}")
    return PRESETS[name]
