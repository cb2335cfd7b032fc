"""The volume's 3D view: a 3D texture kept in step with the model by sub-box uploads, ray-marched."""
from __future__ import annotations

import moderngl
import numpy as np

from app.gl.vertex_arrays import VertexArrays
from app.model.volume_view import VolumeView, box_extents

AXIS_INDEX = {"x": 0, "y": 1, "z": 2}
EDITED_SLICE = (0.35, 0.85, 1.0, 0.10)   # faint: where the painter works
PICKED_SLICE = (1.0, 0.85, 0.2, 0.35)    # the slice picker's hovered slice


class VolumeTexture:
    """A 3D texture mirroring a Volume: re-uploads only what changed since it last looked."""

    def __init__(self, ctx: moderngl.Context) -> None:
        self.ctx = ctx
        self.texture: moderngl.Texture3D | None = None
        self.seen = -1
        self.uploaded_voxels = 0  # since the last reset: what the bench and tests count

    def sync(self, volume) -> moderngl.Texture3D:
        if self.texture is None or self.texture.size != volume.size:
            if self.texture is not None:
                self.texture.release()
            self.texture = self.ctx.texture3d(volume.size, 4, volume.data)
            self.texture.filter = (moderngl.LINEAR, moderngl.LINEAR)
            self.texture.repeat_x = self.texture.repeat_y = self.texture.repeat_z = False
            self.uploaded_voxels += volume.data.shape[0] * volume.data.shape[1] * volume.data.shape[2]
        elif (box := volume.changed_since(self.seen)) is not None:
            w, h, d = box.shape
            part = np.ascontiguousarray(volume.data[box.slices()])
            self.texture.write(part, viewport=(box.x0, box.y0, box.z0, w, h, d))
            self.uploaded_voxels += w * h * d
        self.seen = volume.version
        return self.texture

    def read(self) -> np.ndarray:
        """The texture's contents as (d, h, w, 4) uint8: what the GPU really holds."""
        w, h, d = self.texture.size
        return np.frombuffer(self.texture.read(), np.uint8).reshape(d, h, w, 4)


class VolumeRenderer:
    def __init__(self, ctx: moderngl.Context, shaders) -> None:
        self.ctx = ctx
        self.shaders = shaders
        self.texture = VolumeTexture(ctx)
        self._vaos = VertexArrays(lambda program: ctx.vertex_array(program, []))  # the triangle needs no buffer

    def render(self, fbo: moderngl.Framebuffer, volume, view: VolumeView, steps: float) -> None:
        program = self.shaders.program("volume")
        texture = self.texture.sync(volume)
        w, h = fbo.size
        cam = view.camera
        inv = np.linalg.inv(cam.projection(w / max(h, 1)) @ cam.view())
        planes = [(view.axis, view.index, EDITED_SLICE)]
        planes.append((*view.highlight, PICKED_SLICE) if view.highlight else ("", 0, PICKED_SLICE))
        values = {
            "u_inv_view_proj": tuple(inv.T.flatten()),  # GL wants column-major
            "u_eye": tuple(cam.position()),
            "u_extent": box_extents(volume.size),
            "u_voxels": tuple(float(s) for s in volume.size),
            "u_steps": float(steps),
            "u_background": tuple(c / 255 for c in view.background),
            "u_plane_axis": [AXIS_INDEX.get(a, -1) for a, _i, _c in planes],
            "u_plane_pos": [(i + 0.5) / volume.size[AXIS_INDEX.get(a, 0)] for a, i, _c in planes],
            "u_plane_color": [c for _a, _i, c in planes],
        }
        for name, value in values.items():
            if name in program:
                program[name].value = value
        texture.use(0)
        fbo.use()
        fbo.clear(*values["u_background"], 1.0)
        self._vaos.get(program).render(moderngl.TRIANGLES, vertices=3)
