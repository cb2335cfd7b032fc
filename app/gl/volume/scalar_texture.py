"""A scalar volume on the GPU for its render modes (app/model/volume/scalar_modes.py): its values as a one-channel 3D
texture the shader reads in data units, the colour map's table and the opacity curve's.

16- and 8-bit integers upload as unsigned normalised integers of their size (R16, R8; signed ones with the sign bit
flipped, value + 32768 or + 128: the shader scales and shifts them back exactly; moderngl's signed normalised
formats read negative values as 0 on Mesa), so a 512x512x300 int16 CT takes its own 150 MiB on the GPU, not twice
that; the other types go up as float32 (int32 and uint32 beyond 2^24 lose their last digits; NaN and infinities as
scalar_modes.drawable says). Each is converted a slab at a time. The values are
read-only in the model and never change in place (labels are painted over them; a rotation or load makes new ones): a
new array is uploaded whole, once; a window change uploads the 256 colours alone."""
from __future__ import annotations

import moderngl
import numpy as np

from app.model.volume.scalar_modes import (BRICK, COLOUR_LEVELS, brick_maxima, clear_below, drawable, finite_span,
                                          opacity_table)
from app.model.volume.scalars import Scalars, TransferFunction

# dtype -> (moderngl's format, scale and offset from the texture's 0..1 to data units, the bits that flip the sign)
NORMALISED = {np.dtype("int16"): ("nu2", 65535.0, -32768.0, 0x8000), np.dtype("uint16"): ("nu2", 65535.0, 0.0, 0),
              np.dtype("int8"): ("f1", 255.0, -128.0, 0x80)}
FLOAT = ("f4", 1.0, 0.0, 0)
SLAB_VOXELS = 1 << 22  # float32 conversions go up in slabs of about this many voxels (16 MiB)


class ScalarTexture:
    def __init__(self, ctx: moderngl.Context) -> None:
        self.ctx = ctx
        self.values: moderngl.Texture3D | None = None
        self.bricks: moderngl.Texture3D | None = None  # each brick's greatest value (scalar_modes.brick_maxima)
        self.colours: moderngl.Texture | None = None
        self.opacity: moderngl.Texture | None = None
        self.scale, self.offset = 1.0, 0.0
        self.uploaded_voxels = 0  # what tests count
        self._source: np.ndarray | None = None  # the values array uploaded
        self._colormap: str | None = None
        self._curve: tuple | None = None
        self._span = (0.0, 1.0)
        self._clear_below = 0.0

    def sync(self, scalars: Scalars) -> None:
        if scalars.values is not self._source:
            self._upload(scalars.values)
        self._sync_transfer(scalars.transfer)

    def uniforms(self, transfer: TransferFunction) -> dict:
        return {"u_value_scale": self.scale, "u_value_offset": self.offset, "u_window": (transfer.low, transfer.high),
                "u_opacity_span": self._span, "u_opacity_entries": float(self.opacity.width), "u_brick": float(BRICK),
                "u_clear_below": self._clear_below}

    def _upload(self, values: np.ndarray) -> None:
        d, h, w = values.shape
        kind, self.scale, self.offset, sign = NORMALISED.get(values.dtype, FLOAT)
        if self.values is not None:
            self.values.release()
            self.bricks.release()
        self.values = self.ctx.texture3d((w, h, d), 1, dtype=kind)
        self.values.filter = (moderngl.LINEAR, moderngl.LINEAR)
        self.values.repeat_x = self.values.repeat_y = self.values.repeat_z = False  # clamped to the edge
        slab = max(1, SLAB_VOXELS // (w * h))
        span = finite_span(values) if kind == "f4" else None
        for z in range(0, d, slab):
            part = values[z:z + slab]
            if sign:
                part = part.view(f"u{part.itemsize}") ^ sign
            elif kind == "f4":
                part = drawable(part, span)
            self.values.write(np.ascontiguousarray(part), viewport=(0, 0, z, w, h, part.shape[0]))
        maxima = brick_maxima(values)
        self.bricks = self.ctx.texture3d(maxima.shape[::-1], 1, maxima, dtype="f4")
        self.bricks.filter = (moderngl.NEAREST, moderngl.NEAREST)
        self.uploaded_voxels += values.size
        self._source = values

    def _sync_transfer(self, transfer: TransferFunction) -> None:
        if transfer.colormap != self._colormap:
            self.colours = self._table(self.colours, COLOUR_LEVELS, 4, "f1", transfer.table())
            self._colormap = transfer.colormap
        curve = transfer.opacity()
        if curve != self._curve:
            first, last, table = opacity_table(curve)
            self.opacity = self._table(self.opacity, len(table), 1, "f4", table)
            self._curve, self._span, self._clear_below = curve, (first, last), clear_below(first, last, table)

    def _table(self, texture, width: int, components: int, dtype: str, data: np.ndarray) -> moderngl.Texture:
        if texture is None:
            texture = self.ctx.texture((width, 1), components, dtype=dtype)
            texture.filter = (moderngl.LINEAR, moderngl.LINEAR)
            texture.repeat_x = texture.repeat_y = False
        texture.write(np.ascontiguousarray(data))
        return texture
