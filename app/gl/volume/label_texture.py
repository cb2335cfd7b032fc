"""A scan's labels on the GPU (app/model/volume/labels.py), read by resources/shaders/labels.shl: an integer 3D
texture kept in step by sub-box uploads, the colour table, and the box that holds every label (the rays walk only
through it)."""
from __future__ import annotations

import moderngl
import numpy as np

from app.gl.core.texture_units import TextureUnits
from app.model.volume.labels import Labels
from app.model.volume.voxels import Box, VolumeWatch


def label_bounds(data: np.ndarray) -> Box | None:
    """The smallest box holding every label of `data` (d, h, w); None if every voxel is clear."""
    spans = []
    for axis in range(3):
        hit = np.flatnonzero(data.any(axis=tuple(a for a in range(3) if a != axis)))
        if not len(hit):
            return None
        spans.append((int(hit[0]), int(hit[-1]) + 1))
    (z0, z1), (y0, y1), (x0, x1) = spans
    return Box(x0, y0, z0, x1, y1, z1)


class LabelTexture:
    """Mirrors a scan's labels: R8UI (texelFetch, so nearest and exact), each label's colour in a 256 x 1 texture.
    `bounds` holds every label: exact after a whole upload, then grown by each changed box (an erased label
    leaves it as it was, which only costs a few empty steps)."""

    def __init__(self, ctx: moderngl.Context) -> None:
        self.ctx = ctx
        self.texture: moderngl.Texture3D | None = None
        self.colours = ctx.texture((256, 1), 4)
        self.colours.filter = (moderngl.NEAREST, moderngl.NEAREST)
        self.watch = VolumeWatch()
        self.bounds: Box | None = None
        self._colour_key: tuple | None = None
        self.uploaded_voxels = 0  # since the last reset: what tests count

    def sync(self, labels: Labels | None) -> bool:
        """Bring the textures in line with `labels`; False when there is no label to draw."""
        if labels is None or labels.data is None:
            self._drop()
            self.watch = VolumeWatch()
            return False
        if self.texture is None or self.texture.size != labels.size:
            self._drop()
            self.texture = self.ctx.texture3d(labels.size, 1, dtype="u1")
            self.texture.filter = (moderngl.NEAREST, moderngl.NEAREST)  # an integer texture takes no other
            self.watch = VolumeWatch()  # a new texture takes every label
        box = self.watch.changes(labels)
        if box == labels.full_box():  # new labels (or turned): all of them, and their exact bounds
            self.texture.write(labels.data)
            self.bounds = label_bounds(labels.data)
            self.uploaded_voxels += labels.data.size
        elif box is not None:
            w, h, d = box.shape
            self.texture.write(np.ascontiguousarray(labels.data[box.slices()]), viewport=(box.x0, box.y0, box.z0,
                                                                                          w, h, d))
            self.bounds = box if self.bounds is None else self.bounds.union(box)
            self.uploaded_voxels += w * h * d
        key = (id(labels), labels.colour_version)
        if key != self._colour_key:
            table = np.full((256, 4), 255, np.uint8)
            table[:, :3] = labels.colours
            self.colours.write(table)
            self._colour_key = key
        return self.bounds is not None

    def uniforms(self, labels: Labels | None, opacity: float, units: TextureUnits) -> dict:
        """The labels' uniforms for labels.shl, their textures bound at their units (while drawn)."""
        drawn = self.sync(labels) and opacity > 0.0
        values = units.bind(u_labels=self.texture, u_label_colours=self.colours) if drawn else \
            units.uniforms("u_labels", "u_label_colours")  # unread: their own units all the same
        box = self.bounds if drawn else Box(0, 0, 0, 0, 0, 0)
        values.update(u_labels_on=int(drawn), u_label_opacity=float(opacity),
                      u_label_lo=(float(box.x0), float(box.y0), float(box.z0)),
                      u_label_hi=(float(box.x1), float(box.y1), float(box.z1)))
        return values

    def _drop(self) -> None:
        if self.texture is not None:
            self.texture.release()
        self.texture, self.bounds = None, None
