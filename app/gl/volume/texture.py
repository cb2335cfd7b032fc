"""An RGBA volume's 3D texture, kept in step with the model by sub-box uploads (a scan has none: its values' texture
is app/gl/volume/scalar_texture.py's)."""
from __future__ import annotations

import moderngl
import numpy as np

from app.model.volume.voxels import VolumeWatch, Voxels

_ITEM_BYTES = {"f1": 1, "u1": 1, "i1": 1, "nu1": 1, "f2": 2, "u2": 2, "i2": 2, "nu2": 2, "f4": 4, "u4": 4, "i4": 4}


def texture3d_bytes(texture: moderngl.Texture3D) -> int:
    """What a 3D texture holds: its texels times their components and bytes (no mipmaps are made here)."""
    return texture.width * texture.height * texture.depth * texture.components * _ITEM_BYTES[texture.dtype]


class VolumeTexture:
    """A 3D texture mirroring a volume's Voxels: re-uploads only what changed since it last looked."""

    def __init__(self, ctx: moderngl.Context) -> None:
        self.ctx = ctx
        self.texture: moderngl.Texture3D | None = None
        self.watch = VolumeWatch()
        self.uploaded_voxels = 0  # since the last reset: what the bench and tests count

    def sync(self, voxels: Voxels) -> moderngl.Texture3D:
        box = self.watch.changes(voxels)
        if self.texture is None or self.texture.size != voxels.size:
            if self.texture is not None:
                self.texture.release()
            self.texture = self.ctx.texture3d(voxels.size, 4, voxels.data)
            self.texture.filter = (moderngl.LINEAR, moderngl.LINEAR)
            self.texture.repeat_x = self.texture.repeat_y = self.texture.repeat_z = False
            self.uploaded_voxels += voxels.data.shape[0] * voxels.data.shape[1] * voxels.data.shape[2]
        elif box is not None:
            w, h, d = box.shape
            part = np.ascontiguousarray(voxels.data[box.slices()])
            self.texture.write(part, viewport=(box.x0, box.y0, box.z0, w, h, d))
            self.uploaded_voxels += w * h * d
        return self.texture

    def release(self) -> None:
        """Hold no texture (a scan is shown); the next sync uploads the volume whole."""
        if self.texture is not None:
            self.texture.release()
        self.texture, self.watch = None, VolumeWatch()

    def write_all(self, voxels: Voxels) -> None:
        """Re-upload every voxel (the paint bench's baseline against sync's sub-box)."""
        if self.texture is None or self.texture.size != voxels.size:
            self.sync(voxels)  # a new texture takes every voxel anyway
            return
        self.watch.changes(voxels)  # the full upload covers every change
        self.texture.write(voxels.data)
        self.uploaded_voxels += voxels.data.shape[0] * voxels.data.shape[1] * voxels.data.shape[2]

    def read(self) -> np.ndarray:
        """The texture's contents as (d, h, w, 4) uint8: what the GPU really holds."""
        w, h, d = self.texture.size
        return np.frombuffer(self.texture.read(), np.uint8).reshape(d, h, w, 4)
