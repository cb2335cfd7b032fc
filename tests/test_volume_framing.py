"""A loaded volume is framed: its box spans about 80 % of the view's height or width (whichever binds), whole in view;
view.frame frames it again; the painter opens on the middle slice."""
import numpy as np
import pytest

from app.model.framing import EDGE, FILL, box_in_view, box_span
from app.model.volume.view import box_extents


def framed(editor, aspect: float) -> np.ndarray:
    state = editor.current
    extent = np.array(box_extents(state.volume.voxels.size))
    camera = state.view.camera
    assert box_in_view(camera, -extent, extent, aspect, EDGE)
    return box_span(camera, -extent, extent, aspect)


@pytest.mark.parametrize("aspect", [1.6, 1.0, 0.6])
@pytest.mark.parametrize("shape", [(32, 32, 32), (16, 16, 64), (64, 8, 8)])  # (d, h, w): a cube, deep, wide
def test_a_loaded_volume_fills_about_80_percent_of_the_view(volume_editor, tmp_path, aspect, shape):
    volume_editor.workspaces.view_aspect = aspect
    np.save(tmp_path / "scan.npy", np.arange(np.prod(shape), dtype=np.int16).reshape(shape))
    assert volume_editor.execute("orbit 25 18 60")  # far off: the load brings it in
    assert volume_editor.execute(f"load {tmp_path / 'scan.npy'}")
    span = framed(volume_editor, aspect)
    # the box's near corners reach EDGE first where perspective moves its picture off the middle: a little short of
    # FILL, most for a long box seen end-on
    assert (0.65 if max(shape) > 2 * min(shape) else 0.75) <= span.max() <= FILL + 1e-6
    view = volume_editor.current.view
    assert view.index == shape[0] // 2  # the painter's z slice: the middle one


def test_view_frame_frames_again_from_any_orbit(volume_editor):
    volume_editor.workspaces.view_aspect = 1.4
    assert volume_editor.execute("view.frame")
    framed_distance = volume_editor.current.view.camera.distance
    for line in ("orbit 25 18 40", "orbit 25 18 1.2"):
        assert volume_editor.execute(line) and volume_editor.execute("view.frame")
        assert volume_editor.current.view.camera.distance == pytest.approx(framed_distance)
    assert 0.75 <= framed(volume_editor, 1.4).max() <= FILL + 1e-6
    assert volume_editor.execute("orbit 80 -60") and volume_editor.execute("view.frame 0.5")
    assert 0.75 <= framed(volume_editor, 0.5).max() <= FILL + 1e-6
