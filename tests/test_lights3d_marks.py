"""The geometry behind the 3D lights renderer's culling and marks, numpy only: a light's reach against the view
and the objects, its box on screen, and the markers and gizmo cut at the near plane."""
import numpy as np
import pytest

from app.gl.lights3d.light_reach import frustum_planes, light_in_view, reach_box, reaches, screen_rect
from app.gl.lights3d.overlay import AXIS_COLOURS, HIGHLIGHT, overlay_vertices
from app.model.lights3d.scene import Light3D, Lights3DCamera, default_scene
from app.model.lights3d.gizmo import Projection

CAMERA = Lights3DCamera(distance=250.0)
SIZE = (128, 96)
VIEW = CAMERA.clip_from_world(SIZE)


def test_a_point_light_behind_the_eye_or_a_spot_turned_away_is_out_of_view():
    planes = frustum_planes(VIEW)
    eye, target = CAMERA.position(), np.asarray(CAMERA.target)
    behind = tuple(eye + 200 * (eye - target) / np.linalg.norm(eye - target))
    assert light_in_view(Light3D("point", (0, 20, 0), range=30.0), planes)
    assert not light_in_view(Light3D("point", behind, range=30.0), planes)
    assert light_in_view(Light3D("point", behind, range=400.0), planes)  # its range reaches into the view
    assert not light_in_view(Light3D("spot", behind, direction=tuple(eye - target), angle=20.0), planes)
    assert light_in_view(Light3D("spot", behind, direction=tuple(target - eye), angle=20.0), planes)
    assert light_in_view(Light3D("directional", behind), planes)


def test_reach_meets_bounding_spheres_conservatively():
    spot = Light3D("spot", (0, 100, 0), (0, -1, 0), angle=10.0)
    assert reaches(spot, (0, 0, 0), 1.0)
    assert reaches(spot, (20, 0, 0), 5.0)  # 11.3 degrees off the axis, the sphere's edge within the cone
    assert not reaches(spot, (40, 0, 0), 5.0)
    point = Light3D("point", (0, 0, 0), range=10.0)
    assert reaches(point, (14, 0, 0), 5.0) and not reaches(point, (16, 0, 0), 5.0)


def test_reach_box_and_its_pixels():
    lo, hi = reach_box(Light3D("point", (0, 10, 0), range=5.0), (-100, 0, -100), (100, 50, 100))
    np.testing.assert_allclose([lo, hi], [(-5, 5, -5), (5, 15, 5)])
    spot_lo, spot_hi = reach_box(Light3D("spot", (0, 100, 0), (0, -1, 0), angle=10.0), (-100, 0, -100),
                                 (100, 50, 100))
    # the cone cut at the farthest corner's distance, 173: tan 10 degrees x 173 = 30.5 around the axis
    assert (spot_hi[[0, 2]] < 31).all() and (spot_lo[[0, 2]] > -31).all() and spot_hi[1] == 50
    empty = reach_box(Light3D("point", (0, 300, 0), range=5.0), (-100, 0, -100), (100, 50, 100))
    assert screen_rect(VIEW, CAMERA.NEAR, *empty, SIZE) is None
    x, y, w, h = screen_rect(VIEW, CAMERA.NEAR, lo, hi, SIZE)
    assert 0 < w < SIZE[0] / 4 and 0 < h < SIZE[1] / 4
    assert screen_rect(VIEW, CAMERA.NEAR, (-1e4, -1e4, -1e4), (1e4, 1e4, 1e4), SIZE) == (0, 0, *SIZE)  # eye inside


def colours(vertices: np.ndarray) -> set:
    return {tuple(np.round(c.astype(np.float64), 3)) for c in vertices[:, 2:]}


def test_markers_and_the_gizmo_on_the_selection():
    scene = default_scene()
    plain = overlay_vertices(scene, CAMERA, SIZE, None)
    assert len(plain) % 3 == 0 and HIGHLIGHT not in colours(plain)
    on_object = overlay_vertices(scene, CAMERA, SIZE, ("object", 2))
    assert {tuple(np.round(c, 3)) for c in (*AXIS_COLOURS, HIGHLIGHT)} <= colours(on_object)
    on_light = overlay_vertices(scene, CAMERA, SIZE, ("light", 0))
    assert {tuple(np.round(c, 3)) for c in (*AXIS_COLOURS, HIGHLIGHT)} <= colours(on_light)
    assert np.isfinite(on_light).all()


def test_a_stroke_is_cut_at_the_near_plane_and_a_mark_behind_the_eye_is_left_out():
    view = Projection(CAMERA, SIZE)
    eye, target = CAMERA.position(), np.asarray(CAMERA.target)
    behind = eye + 50 * (eye - target) / np.linalg.norm(eye - target)
    ends = view.segment(target, behind)
    assert ends is not None and np.isfinite(ends).all()
    assert view.segment(behind, behind + 1) is None
    scene = default_scene().with_light(0, position=tuple(behind))
    assert len(overlay_vertices(scene, CAMERA, SIZE, None)) < len(overlay_vertices(default_scene(), CAMERA, SIZE,
                                                                                   None))


@pytest.mark.parametrize("pitch", [0.0, 50.0, -70.0])
def test_a_world_length_spans_its_share_of_the_view_height_at_any_pitch(pitch):
    """A light's stroke, and the gizmo's handles, are one share of the view's height however the camera tilts."""
    camera = Lights3DCamera(yaw=0.0, pitch=pitch, distance=300.0)  # yaw 0: world x runs across the view
    view = Projection(camera, SIZE)
    length = view.world_length(camera.target, 0.1)
    ends = view.segment(camera.target, np.add(camera.target, (length, 0.0, 0.0)))
    assert np.linalg.norm(ends[1] - ends[0]) == pytest.approx(0.1 * SIZE[1])
