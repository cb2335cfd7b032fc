"""The 3D lights gizmo and picking: handles the same size on screen at any distance, hits on the handle under
the mouse, drags that follow the mouse along one axis without a jump, and picks of lights and objects."""
from __future__ import annotations

import numpy as np
import pytest
from hypothesis import assume, example, given, settings, strategies as st

from app.gl.lights3d.overlay import gizmo_marks
from app.model.lights3d.scene import Light3D, Lights3DCamera, Object3D, Scene3D, default_scene
from app.model.lights3d.gizmo import (HANDLE_FRACTION, drag_along, gizmo_axes, handle_length, hit_axis, pick_light,
                                      pick_object, project)

SIZE = (320, 200)
FAST = settings(max_examples=60, deadline=None)

cameras = st.builds(Lights3DCamera, yaw=st.floats(0, 360), pitch=st.floats(-80, 80), distance=st.floats(60, 1500))
origins = st.tuples(*[st.floats(-40, 40)] * 3)


def test_the_camera_target_projects_to_the_middle_of_the_view():
    pixels, depth = project(Lights3DCamera(), SIZE, Lights3DCamera().target)
    assert np.allclose(pixels, (160, 100)) and depth == pytest.approx(Lights3DCamera().distance)


@pytest.mark.parametrize("distance", [30.0, 450.0, 1900.0])
def test_a_handle_across_the_view_is_the_same_share_of_its_height_at_any_distance(distance):
    camera = Lights3DCamera(yaw=0.0, pitch=0.0, distance=distance)  # looking along -z: x and y lie across
    x, y, z = gizmo_axes(camera, SIZE, camera.target)
    assert np.linalg.norm(x[1] - x[0]) == pytest.approx(HANDLE_FRACTION * SIZE[1])
    assert np.allclose(y[1] - y[0], (0, -HANDLE_FRACTION * SIZE[1]))  # up on screen: pixel y grows downwards
    assert np.linalg.norm(z[1] - z[0]) < 1e-6  # end-on


def test_nothing_behind_the_eye_has_a_gizmo_or_a_pick():
    camera = Lights3DCamera(yaw=0.0, pitch=0.0, distance=100.0)  # the eye at z = 100, looking along -z
    behind = (0.0, 10.0, 150.0)
    assert handle_length(camera, SIZE, behind) is None and gizmo_axes(camera, SIZE, behind) is None
    assert hit_axis(camera, SIZE, behind, 160, 100) is None
    scene = Scene3D(lights=(Light3D("point", behind),))
    pixel = project(camera, SIZE, behind)[0]
    assert pick_light(scene, camera, SIZE, *pixel) is None


@FAST
@given(camera=cameras, origin=origins, t=st.floats(0.3, 1.0))
def test_hit_axis_finds_the_handle_under_the_mouse(camera, origin, t):
    segments = gizmo_axes(camera, SIZE, origin)
    assume(segments is not None)  # a near camera can have a handle's tip behind its near plane: no gizmo then
    for axis, (a, b) in enumerate(segments):
        if np.linalg.norm(b - a) < 20:  # seen about end-on: it may be passed over, or hide behind another
            continue
        others = [np.linalg.norm(a + t * (b - a) - (c + s * (d - c))) for j, (c, d) in enumerate(segments) if j != axis
                  for s in np.linspace(0, 1, 50)]
        if min(others) > 6:  # not where another handle lies as close
            assert hit_axis(camera, SIZE, origin, *(a + t * (b - a))) == axis


def test_an_end_on_handle_is_never_offered_and_far_pixels_hit_nothing():
    camera = Lights3DCamera(yaw=0.0, pitch=0.0, distance=300.0)
    origin = camera.target
    centre = project(camera, SIZE, origin)[0]
    assert hit_axis(camera, SIZE, origin, *centre) in (0, 1)  # the z handle is a dot there
    assert hit_axis(camera, SIZE, origin, *(centre + (0, 40))) is None  # below the origin: no handle


@FAST
@given(camera=cameras, origin=origins, axis=st.integers(0, 2), start=st.tuples(st.floats(0, 320), st.floats(0, 200)))
def test_a_drag_that_has_not_moved_leaves_the_item_where_it_was(camera, origin, axis, start):
    moved = drag_along(camera, SIZE, origin, axis, start, start)
    assert moved is None or moved == tuple(map(float, origin))


@FAST
@given(camera=cameras, origin=origins, axis=st.integers(0, 2), start=st.tuples(st.floats(0, 320), st.floats(0, 200)),
       now=st.tuples(st.floats(0, 320), st.floats(0, 200)))
def test_a_drag_along_one_axis_changes_only_that_coordinate(camera, origin, axis, start, now):
    moved = drag_along(camera, SIZE, origin, axis, start, now)
    if moved is not None:
        assert [moved[i] for i in range(3) if i != axis] == [float(origin[i]) for i in range(3) if i != axis]


# Found by hypothesis: the camera 60 from its target (0, 10, 0) and the item 73 from it, so 43 to the side of the
# eye and 0.96 in front of it: nearer than the near plane (1), and ~5,700 pixels off a 320-pixel view.
BESIDE_THE_EYE = dict(camera=Lights3DCamera(yaw=115.0, pitch=-8.0, distance=60.0), origin=(40.0, -36.0, -40.0))


def test_an_item_beside_the_eye_has_no_gizmo_and_no_handle_to_press():
    camera, origin = BESIDE_THE_EYE["camera"], BESIDE_THE_EYE["origin"]
    assert handle_length(camera, SIZE, origin) is None and gizmo_axes(camera, SIZE, origin) is None
    assert gizmo_marks(camera, SIZE, origin) == []  # nothing drawn...
    assert all(hit_axis(camera, SIZE, origin, x, y) is None for x in (0, 160, 320) for y in (0, 100, 200))  # or hit


@FAST
@given(camera=cameras, origin=origins, axis=st.integers(0, 2), k=st.floats(-30, 30))
@example(**BESIDE_THE_EYE, axis=0, k=10.0)
def test_the_grabbed_point_of_the_handle_follows_the_mouse_without_a_jump(camera, origin, axis, k):
    """Pressing on the handle's tip and moving to where the tip would show k units further moves the item k."""
    segments = gizmo_axes(camera, SIZE, origin)
    # An item the view cannot show (behind or beside the eye, nearer than the near plane; a near camera's orbit
    # passes items within reach) has no gizmo, so no handle to press: the case above.
    assume(segments is not None)
    (a, b) = segments[axis]
    if np.linalg.norm(b - a) < 20:
        return  # end-on: the handle is not offered
    length = handle_length(camera, SIZE, origin)
    tip = np.array(origin) + length * np.identity(3)[axis]
    (start, now), depth = project(camera, SIZE, [tip, tip + k * np.identity(3)[axis]])
    if depth.min() <= camera.NEAR:
        return
    moved = drag_along(camera, SIZE, origin, axis, start, now)
    assert moved is not None
    assert moved[axis] == pytest.approx(origin[axis] + k, abs=1e-6 * (1 + abs(k)) * camera.distance)


def test_a_mouse_ray_along_the_axis_gives_no_position():
    camera = Lights3DCamera(yaw=0.0, pitch=0.0, distance=300.0)  # the middle pixel's ray runs along z
    assert drag_along(camera, SIZE, camera.target, 2, (160, 100), (160, 100)) is None


def test_pick_light_takes_the_nearest_marker_in_front_of_the_eye():
    camera = Lights3DCamera()
    scene = default_scene()
    for index, light in enumerate(scene.lights):
        pixel = project(camera, SIZE, light.position)[0]
        assert pick_light(scene, camera, SIZE, *(pixel + 3)) == index
        assert pick_light(scene, camera, SIZE, *(pixel + 30), radius_px=8) is None
    assert pick_light(Scene3D(), camera, SIZE, 0, 0) is None
    # two lights on one pixel: the one nearer the eye
    eye = camera.position()
    near, far = (eye + camera.target) / 2, camera.target
    scene = Scene3D(lights=(Light3D("point", tuple(far)), Light3D("point", tuple(near))))
    assert pick_light(scene, camera, SIZE, *project(camera, SIZE, far)[0]) == 1


def test_pick_object_takes_the_first_object_the_ray_meets():
    camera = Lights3DCamera()
    scene = default_scene()
    # box, sphere, torus, L-prism, each aimed at a point inside it: their centres, but the torus's hole and
    # the L's notch, so its tube and its column
    for index, offset in ((1, (0, 0, 0)), (2, (0, 0, 0)), (3, (20, 0, 0)), (4, (-14, 0, 0))):
        inside = np.add(scene.objects[index].position, offset)
        assert pick_object(scene, camera, SIZE, *project(camera, SIZE, inside)[0]) == index
    assert pick_object(scene, camera, SIZE, 160, 2) is None  # the sky above the ground
    ground = project(camera, SIZE, (-150.0, 0.0, 150.0))[0]
    assert pick_object(scene, camera, SIZE, *ground) == 0
    # a ball in front of a box: the ball
    pair = Scene3D(objects=(Object3D("box", (20, 20, 20), (0, 10, 0)), Object3D("sphere", (5, 16), (0, 10, 40))))
    side = Lights3DCamera(yaw=0.0, pitch=0.0, distance=200.0, target=(0.0, 10.0, 0.0))
    assert pick_object(pair, side, SIZE, 160, 100) == 1
