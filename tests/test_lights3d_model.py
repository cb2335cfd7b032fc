"""The 3D lights model: objects, lights and the scene refuse bad values with a message and change nothing,
edits are immutable, the default scene holds the seed's numbers, the light formulas give hand-computed
values, and the orbit camera works at this scale without changing the volume workspace's."""
import math

import numpy as np
import pytest

from app.model.lights3d import scene as lm
from app.model.camera3d import OrbitCamera
from app.model.lights3d.scene import Light3D, Lights3DCamera, Lights3DError, Object3D, Scene3D, default_scene


@pytest.mark.parametrize("kwargs, needle", [
    (dict(kind="cone"), "object kind must be one of box, sphere, torus, lprism, plane, got 'cone'"),
    (dict(kind="box", size=(1, 2)), r"a box's size \(sx, sy, sz\) must be 3 numbers, got 2"),
    (dict(kind="box", size=(1, -2, 3)), "box sy must be within 0.01..10000, got -2"),
    (dict(kind="box", size=(1e-200, 1, 1)), "box sx must be within 0.01..10000, got 1e-200"),  # its normals: NaN
    (dict(kind="torus", size=(1, 0.995, 16, 8)), "torus minor radius must be below its major radius by at least 0.01"),
    (dict(kind="lprism", size=(10, 20, 9.999, 10)), "lprism thickness must be below its sx and sy by at least 0.01"),
    (dict(kind="box", size=(1, math.inf, 3)), "must be finite"),
    (dict(kind="box", size="abc"), "must be 3 numbers"),
    (dict(kind="box", size="123"), "must be 3 numbers, got '123'"),
    (dict(kind="box", size=(1, "2", None)), "must be 3 numbers"),
    (dict(kind="sphere", size=(10, 12.5)), "sphere segments must be a whole number within 3..1024, got 12.5"),
    (dict(kind="sphere", size=(10, 2)), "sphere segments must be a whole number"),
    (dict(kind="sphere", size=(10, 1000)), "a sphere of 998000 triangles is more than 200000"),
    (dict(kind="torus", size=(10, 10, 16, 8)), "torus minor radius must be below its major radius"),
    (dict(kind="lprism", size=(10, 20, 5, 10)), "lprism thickness must be below its sx and sy"),
    (dict(position=(0, math.nan, 0)), "box position must be finite"),
    (dict(position=(0, 2e5, 0)), "box position must be within -100000..100000"),
    (dict(colour=(0.5, 1.5, 0)), "box colour must be within 0..1"),
])
def test_object_values_refused_with_a_message(kwargs, needle):
    with pytest.raises(Lights3DError, match=needle):
        Object3D(**kwargs)


@pytest.mark.parametrize("kwargs, needle", [
    (dict(kind="area"), "light kind must be one of point, spot, directional, got 'area'"),
    (dict(shadow="soft"), "shadow method must be one of onepass, onepass-seed, zpass, zfail, map, none, got 'soft'"),
    (dict(angle=0), "spot angle must be > 0 and <= 90, got 0"),
    (dict(angle=90), "spot angle must be below 90 degrees"),
    (dict(range=0), "light range must be > 0"),
    (dict(falloff=-2), "light falloff must be > 0"),
    (dict(colour=(1, -0.1, 1)), "point light colour must be within 0..16"),
    (dict(kind="spot", direction=(0, 0, 0)), "spot light direction must not be zero"),
    (dict(position=(1, 2)), "point light position must be 3 numbers, got 2"),
])
def test_light_values_refused_with_a_message(kwargs, needle):
    with pytest.raises(Lights3DError, match=needle):
        Light3D(**kwargs)


def test_sizes_and_directions_are_normalised():
    sphere = Object3D("sphere", (10, 24.0), (0, 10, 0))
    assert sphere.size == (10.0, 24) and isinstance(sphere.size[1], int)
    assert sphere.triangles == len(sphere.mesh().triangles) == 24 * 22
    spot = Light3D("spot", direction=(-200, -150, 0))
    assert spot.direction == pytest.approx((-0.8, -0.6, 0.0), abs=1e-15)
    unit = (0.6, 0.0, -0.8)
    assert Light3D("directional", direction=unit).direction == unit  # bit for bit, so files round-trip


def test_an_objects_world_mesh_is_cached_and_centred_on_its_position():
    box = Object3D("box", (20, 30, 40), (5, 15, -7))
    mesh = box.mesh()
    assert mesh is box.mesh()
    np.testing.assert_allclose((mesh.positions.min(0) + mesh.positions.max(0)) / 2, (5, 15, -7))
    assert mesh.positions[:, 1].min() == 0.0  # resting on the ground
    moved = Object3D("box", (20, 30, 40), (50, 15, 0))
    assert moved.mesh().triangles is mesh.triangles  # the local mesh is built once per kind and size
    assert mesh.closed and not Object3D("plane", (400,), (0, 0, 0)).mesh().closed  # the ground casts nothing


def test_scene_edits_return_a_new_scene_and_leave_the_old_one():
    scene = default_scene()
    moved = scene.with_object_moved(1, (0, 15, 30))
    assert moved.objects[1].position == (0.0, 15.0, 30.0) and scene.objects[1].position == (-25.0, 15.0, 0.0)
    assert moved.objects[2] is scene.objects[2]
    red = scene.with_light(0, colour=(1, 0, 0), shadow="map")
    assert red.lights[0].colour == (1.0, 0.0, 0.0) and red.lights[0].shadow == "map"
    assert scene.lights[0].colour == (1.0, 1.0, 1.0)
    assert len(scene.add_light(Light3D()).lights) == 3 and len(scene.remove_object(0).objects) == 4
    assert scene.remove_light(1).lights == scene.lights[:1]
    assert scene.add_object(Object3D()).objects[-1] == Object3D()
    assert scene.with_settings(shininess=8).shininess == 8.0
    assert scene.with_object(3, colour=(0, 0, 1)).objects[3].colour == (0.0, 0.0, 1.0)
    assert scene == default_scene()


@pytest.mark.parametrize("edit, needle", [
    (lambda s: s.with_object_moved(9, (0, 0, 0)), "no object 9 .there are 5."),
    (lambda s: s.with_object_moved(-1, (0, 0, 0)), "no object -1"),
    (lambda s: s.with_object_moved(1, (0, math.nan, 0)), "box position must be finite"),
    (lambda s: s.with_object(1, kind="sphere"), r"a sphere's size \(radius, segments\) must be 2 numbers, got 3"),
    (lambda s: s.with_object(1, spin=3), "an object has no spin"),
    (lambda s: s.with_light(2, range=5), "no light 2 .there are 2."),
    (lambda s: s.with_light(True, range=5), "no light True"),
    (lambda s: s.with_light(0, range=-5), "light range must be > 0"),
    (lambda s: s.with_light(0, brightness=5), "a light has no brightness"),
    (lambda s: s.with_settings(ambient=(2, 0, 0)), "ambient must be within 0..1"),
    (lambda s: s.with_settings(fog=1), "the scene's settings are ambient, shininess and specular, not fog"),
    (lambda s: s.with_settings(shininess=0), "shininess must be > 0"),
    (lambda s: s.remove_light(5), "no light 5"),
    (lambda s: s.add_object("box"), "a scene holds Object3D objects and Light3D lights"),
])
def test_bad_edits_raise_and_change_nothing(edit, needle):
    scene = default_scene()
    with pytest.raises(Lights3DError, match=needle):
        edit(scene)
    assert scene == default_scene()


def test_scene_bounds():
    with pytest.raises(Lights3DError, match="at most 64 objects, got 65"):
        Scene3D(objects=(Object3D(),) * 65)
    with pytest.raises(Lights3DError, match="at most 8 lights, got 9"):
        Scene3D(lights=(Light3D(),) * 9)
    big = Object3D("sphere", (10, 400))  # 159,200 triangles
    scene = Scene3D(objects=(big,))
    with pytest.raises(Lights3DError, match="the scene's objects have 318400 triangles, more than 200000"):
        scene.add_object(big)
    assert Scene3D(objects=(Object3D(),) * 64).triangles == 64 * 12


def test_default_scene_holds_the_seeds_lights_and_grounded_objects():
    scene = default_scene()
    point, spot = scene.lights
    assert (point.kind, point.position, point.colour, point.range, point.falloff) == \
        ("point", (50.0, 40.0, 0.0), (1.0, 1.0, 1.0), 100.0, 2.0)
    assert (spot.kind, spot.position, spot.colour, spot.angle, spot.falloff) == \
        ("spot", (200.0, 150.0, 0.0), (1.0, 1.0, 1.0), 15.0, 20.0)
    np.testing.assert_allclose(spot.direction, np.array([-200.0, -150.0, 0.0]) / 250.0)
    kinds = [o.kind for o in scene.objects]
    assert kinds == ["plane", "box", "sphere", "torus", "lprism"]
    assert scene.objects[0].size == (400.0,) and scene.objects[0].position == (0.0, 0.0, 0.0)
    for obj in scene.objects[1:]:
        lo, hi = obj.mesh().positions.min(0), obj.mesh().positions.max(0)
        assert lo[1] == pytest.approx(0.0, abs=1e-9)  # standing on the ground
        assert 15 <= (hi - lo).max() <= 60 and obj.mesh().closed


# ---- the light formulas ---------------------------------------------------------------------------------


def test_point_attenuation_by_hand():
    # katt = 1 - saturate(d / r)^f
    np.testing.assert_allclose(lm.point_attenuation([0, 50, 100, 150], 100.0, 2.0), [1.0, 0.75, 0.0, 0.0])
    assert lm.point_attenuation(25.0, 100.0, 1.0) == pytest.approx(0.75)
    assert lm.point_attenuation(50.0, 100.0, 3.0) == pytest.approx(0.875)


def test_spot_attenuation_by_hand():
    # the seed's fixed formula: (1 - saturate(cos(angle) / c)^f), c the cosine off the axis; 0 outside the cone
    cos15 = math.cos(math.radians(15))
    on_axis = 1 - cos15 ** 20
    assert on_axis == pytest.approx(0.5001087, abs=1e-6)
    c10 = math.cos(math.radians(10))
    values = lm.spot_attenuation([1.0, c10, cos15, 0.5, -1.0], 15.0, 20.0)
    np.testing.assert_allclose(values, [on_axis, 1 - (cos15 / c10) ** 20, 0.0, 0.0, 0.0])
    spot = Light3D("spot", (0, 100, 0), (0, -1, 0), angle=15, falloff=20)
    # a point 10 degrees off the axis, 100 below the light
    p = np.array([[100 * math.tan(math.radians(10)), 0.0, 0.0]])
    assert lm.attenuation(spot, p)[0] == pytest.approx(1 - (cos15 / c10) ** 20)
    assert lm.in_reach(spot, p)[0] and not lm.in_reach(spot, np.array([[50.0, 0.0, 0.0]]))[0]


def test_shading_by_hand():
    """A point light 50 above a floor point seen from the light's place: L = V = N, so H = N."""
    scene = Scene3D(lights=(Light3D("point", (0, 50, 0), range=100, falloff=2),), ambient=(0.1, 0.1, 0.1),
                    shininess=32, specular=0.5)
    albedo, p, n = np.array([[0.5, 0.4, 0.2]]), np.zeros((1, 3)), np.array([[0.0, 1.0, 0.0]])
    lit = np.ones((1, 1), bool)
    # ambient * albedo + katt (0.75) * (albedo * diffuse (1) + specular (0.5 * 1^32))
    expected = 0.1 * albedo + 0.75 * (albedo + 0.5)
    np.testing.assert_allclose(lm.shade(scene, albedo, p, n, (0, 50, 0), lit), expected)
    np.testing.assert_allclose(lm.shade(scene, albedo, p, n, (0, 50, 0), ~lit), 0.1 * albedo)  # in shadow
    # a normal tilted 60 degrees: diffuse = N . L = cos 60 = 0.5, and with H = L also N . H = 0.5
    tilted = np.array([[math.sin(math.radians(60)), math.cos(math.radians(60)), 0.0]])
    expected = 0.1 * albedo + 0.75 * (albedo * 0.5 + 0.5 * 0.5 ** 32)
    np.testing.assert_allclose(lm.shade(scene, albedo, p, tilted, (0, 50, 0), lit), expected)


def test_specular_only_where_the_light_is_in_front():
    n = np.array([[0.0, 1.0, 0.0]])
    below = np.array([[0.0, -1.0, 0.0]])
    assert lm.specular(n, below, n, 8.0, 1.0)[0] == 0.0
    assert lm.specular(n, n, n, 8.0, 1.0)[0] == 1.0
    grazing = np.array([[1.0, 0.0, 0.0]])
    assert lm.specular(n, grazing, n, 8.0, 1.0)[0] == 0.0  # N . L = 0: not in front


def test_directional_light_has_no_attenuation_and_the_colour_clamps():
    sun = Light3D("directional", direction=(0, -1, 0), colour=(4, 4, 4))
    points = np.array([[0.0, 0.0, 0.0], [1e4, 0.0, -1e4]])
    np.testing.assert_allclose(lm.attenuation(sun, points), [1.0, 1.0])
    direction, distance = lm.to_light(sun, points)
    np.testing.assert_allclose(direction, [[0, 1, 0], [0, 1, 0]])
    np.testing.assert_equal(distance, np.inf)
    scene = Scene3D(lights=(sun,))
    rgb = lm.shade(scene, np.full((2, 3), 0.5), points, np.tile([0.0, 1.0, 0.0], (2, 1)), (0, 10, 0),
                   np.ones((1, 2), bool))
    np.testing.assert_allclose(rgb, 1.0)  # 4 x 0.5 saturates


# ---- the camera -----------------------------------------------------------------------------------------


def test_orbit_camera_defaults_are_unchanged():
    cam = OrbitCamera()
    assert (cam.MIN_DISTANCE, cam.MAX_DISTANCE, cam.NEAR, cam.FAR) == (0.5, 100.0, 0.05, 200.0)
    np.testing.assert_array_equal(cam.projection(1.5), cam.projection(1.5, 0.05, 200.0))
    np.testing.assert_array_equal(cam.centre(), 0.0)
    with pytest.raises(ValueError, match="distance must be within 0.5..100, got 200"):
        OrbitCamera(distance=200)


def test_lights3d_camera_scale_and_target():
    cam = Lights3DCamera()
    assert (cam.NEAR, cam.FAR) == (1.0, 5000.0)
    with pytest.raises(ValueError, match="distance must be within 20..2000, got 10"):
        Lights3DCamera(distance=10)
    with pytest.raises(Lights3DError, match="camera target must be finite"):
        Lights3DCamera(target=(0, math.nan, 0))
    assert Lights3DCamera(distance=2000).distance == 2000
    assert np.linalg.norm(cam.position() - cam.centre()) == pytest.approx(cam.distance)
    # the target is at the middle of the picture, and the projection's planes are the class's
    clip = cam.projection(16 / 9) @ cam.view() @ np.r_[cam.target, 1.0]
    np.testing.assert_allclose(clip[:2] / clip[3], 0.0, atol=1e-12)
    near = cam.projection(1.0) @ np.array([0.0, 0.0, -1.0, 1.0])
    assert near[2] / near[3] == pytest.approx(-1.0)


def test_default_camera_shows_every_default_object():
    cam = Lights3DCamera()
    clip_from_world = cam.projection(16 / 9) @ cam.view()
    for obj in default_scene().objects[1:]:
        p = obj.mesh().positions
        clip = np.c_[p, np.ones(len(p))] @ clip_from_world.T
        ndc = clip[:, :3] / clip[:, 3:]
        assert (np.abs(ndc[:, :2]) < 0.9).all() and (np.abs(ndc[:, 2]) < 1).all(), obj.kind
