"""The volume workspace's state: the 3D raster image (which keeps its own undo steps) and its view."""
from __future__ import annotations

from functools import cache
from typing import Callable

import numpy as np

from app.model.volume.volume import Volume
from app.model.volume.voxels import DEFAULT_SPACING, Voxels
from app.model.volume.samples import make
from app.model.framing import filling_distance
from app.model.volume.view import VolumeView, box_extents
from app.model.workspace import Workspace, short_hash

DEFAULT_SAMPLE = "coords3d"  # Tex3Dtrace opened coords3d by default


@cache
def _default_digest() -> str:
    """The opening volume's digest, made once: a demo recorded from it opens with `sample`, not a snapshot."""
    return Voxels(make(DEFAULT_SAMPLE)).digest()


class VolumeHistory:
    """The volume's own undo steps; after one, the edited slice is kept inside a volume that changed shape."""

    def __init__(self, state: "VolumeWorkspace") -> None:
        self.state = state

    def undo(self) -> bool:
        return self._after(self.state.volume.history.undo())

    def redo(self) -> bool:
        return self._after(self.state.volume.history.redo())

    def undo_name(self) -> str | None:
        return self.state.volume.history.undo_name()

    def redo_name(self) -> str | None:
        return self.state.volume.history.redo_name()

    def _after(self, done: bool) -> bool:
        if done:
            self.state.clamp_slice()
        return done


class VolumeWorkspace(Workspace):
    name = "volume"

    def __init__(self) -> None:
        self.volume = Volume(make(DEFAULT_SAMPLE))
        self.view = VolumeView()
        self.history = VolumeHistory(self)

    def clamp_slice(self) -> None:
        """After anything that may change the volume's shape, keep the edited slice inside it."""
        view, voxels = self.view, self.volume.voxels
        view.index = min(view.index, voxels.depth(view.axis) - 1)
        if view.highlight and view.highlight[1] >= voxels.depth(view.highlight[0]):
            view.highlight = None

    def middle_slice(self) -> None:
        """After a load: the painter edits the middle slice of its axis (slice 0 of a scan is mostly empty)."""
        self.view.index = self.volume.voxels.depth(self.view.axis) // 2
        self.clamp_slice()

    def iso_value(self) -> float:
        """The iso value iso mode draws: the one set (vol.iso), or the middle of the window (0 without scalars)."""
        scalars = self.volume.voxels.scalars
        if self.view.iso is not None:
            return self.view.iso
        return 0.0 if scalars is None else (scalars.transfer.low + scalars.transfer.high) / 2

    def version(self) -> tuple:
        labels = self.volume.voxels.labels
        drawn = None if labels is None else (id(labels), labels.version, labels.colour_version)
        scalars = self.volume.voxels.scalars  # an opacity curve changes no voxel, so not the voxels' version
        return (self.volume.voxels.version, self.volume.voxels.spacing, drawn, self.view.key(),
                scalars.transfer if scalars is not None else None)

    def digest(self) -> dict[str, str]:
        return {"volume": self.volume.voxels.digest(), "volume.view": short_hash(self.view.key())}

    def document_model(self) -> tuple[object, tuple]:
        return self.volume, self.volume.history.key

    def frame_commands(self, aspect: float) -> list[str]:
        cam = self.view.camera
        extent = np.array(box_extents(self.volume.voxels.size, self.volume.voxels.spacing))
        distance = filling_distance(cam, -extent, extent, aspect)  # the box spans 80 % of the view
        return [f"orbit {cam.yaw!r} {cam.pitch!r} {distance!r}"]

    def opening_commands(self, snapshot: Callable[..., str]) -> list[str]:
        """Commands that rebuild the volume and its view; voxels other than the default sample go into a
        snapshot file beside the demo, a scalar volume's scalars into an .npy (its labels beside it) and its window,
        label colours and spacing into commands."""
        v, scalars = self.view, self.volume.voxels.scalars
        if scalars is not None:
            t = scalars.transfer
            lines = [f"load {snapshot('.npy')}", f"vol.colormap {t.colormap}",
                     f"vol.window {t.low!r} {t.high!r}"]
            lines += [f"label.color {n} {' '.join(map(str, rgb))}"
                      for n, rgb in self.volume.voxels.labels.recoloured().items()]
            if t.points is not None:  # only then: a demo without a curve opens as it did before curves
                lines.append("vol.opacity " + " ".join(f"{v!r} {a!r}" for v, a in t.points))
        elif self.volume.voxels.digest() == _default_digest():
            lines = [f"sample {DEFAULT_SAMPLE}"]
        else:
            lines = [f"load {snapshot()}"]
        if (spacing := self.volume.voxels.spacing) != DEFAULT_SPACING:  # a snapshot keeps the voxels alone
            lines.append(f"vol.spacing {' '.join(map(repr, spacing))}")
        if v.iso is not None:
            lines.append(f"vol.iso {v.iso!r}")
        return lines + [
            f"slice {v.axis} {v.index}", f"brush.color {' '.join(map(str, v.brush))}",
            f"orbit {v.camera.yaw!r} {v.camera.pitch!r} {v.camera.distance!r}",
            f"vol.background {' '.join(map(str, v.background))}",
            f"mode {v.mode}", f"shadows {int(v.shadows)}", f"light {' '.join(map(repr, v.light))}",
            f"stereo {int(v.stereo)}", f"magnify {int(v.magnify)}", f"wireframe {int(v.wireframe)}",
        ]
