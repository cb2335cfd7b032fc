"""Paint bench: one brush stroke end to end (console command -> model -> GPU texture), uploading only the
changed sub-box against re-uploading the whole volume. The knob is the brush size.

The error compares what the GPU texture holds with the model after the stroke (read back): any upload
that misses a voxel shows as a non-zero error. It is reported per z slice (the largest difference in
each), to keep the comparison small for a 256^3 volume.
"""
from __future__ import annotations

import numpy as np

from app.bench.harness import Method, Technique
from app.commands import volume as volume_commands
from app.console.console import Console
from app.console.demo import ArgChecks
from app.gl.volume.texture import VolumeTexture
from app.model.volume.workspace import VolumeWorkspace

SIZES = (1, 4, 16, 64)
QUICK_SIZES = (1, 16)


class PaintState:
    """A console with the volume commands on a fresh sample volume, and a texture mirroring it."""

    def __init__(self, ctx, full_upload: bool) -> None:
        self.console = Console()
        self.workspace = VolumeWorkspace()
        volume_commands.register(self.console, self.workspace, ArgChecks())
        self.texture = VolumeTexture(ctx)
        self.full_upload = full_upload
        self.frame = 0
        self.loaded = None

    def prepare(self, side: int) -> None:
        if self.loaded != side:
            self.console.execute(f"sample cornell_box {side}", echo=False)
            self.texture.sync(self.workspace.volume.voxels)
            self.loaded = side

    def stroke(self, size: int) -> None:
        """A short stroke at a new place each frame, so no frame repeats the last one's work."""
        side = self.workspace.volume.voxels.size[0]
        self.frame += 1
        z, u, v = (self.frame * 7) % side, (self.frame * 13) % side, (self.frame * 29) % side
        assert self.console.execute(f"stroke z {z} {size} 255 {self.frame % 256} 0 255 {u} {v} {u + 5} {v + 3}",
                                    echo=False)
        if self.full_upload:
            self.texture.write_all(self.workspace.volume.voxels)
        else:
            self.texture.sync(self.workspace.volume.voxels)


def _render(state: PaintState, _target, size, side) -> None:
    state.prepare(side)
    state.stroke(int(size))


def _output(state: PaintState, _target, _size, _side) -> np.ndarray:
    gpu, cpu = state.texture.read(), state.workspace.volume.voxels.data
    return np.abs(gpu.astype(np.int16) - cpu).reshape(gpu.shape[0], -1).max(axis=1) / 255.0


def _reference(side, _size, _image) -> np.ndarray:
    return np.zeros(side)  # the model is the truth: no difference anywhere


def technique(quick: bool = False) -> Technique:  # the harness picks the quick subsets
    return Technique(
        name="paint",
        methods=[
            Method("subbox", "brush size", SIZES, lambda ctx: PaintState(ctx, full_upload=False), _render, _output,
                   QUICK_SIZES),
            Method("full", "brush size", SIZES, lambda ctx: PaintState(ctx, full_upload=True), _render, _output,
                   QUICK_SIZES),
        ],
        scenes={"256^3": 256, "128^3": 128},
        reference=_reference,
        size=(64, 64),
        quick_size=(64, 64),
        quick_scenes=("128^3",),
    )
