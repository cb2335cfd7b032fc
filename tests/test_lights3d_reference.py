"""The 3D lights' CPU reference: its binning gives exactly what testing every ray against every triangle
gives, shadows match analytic ray-sphere and ray-box tests away from the tessellation, the light formulas give
hand-computed colours, back faces shadow themselves, a caster standing on the receiver and a light inside an
object behave, and a 100k-triangle scene is traced with a small fraction of all ray-triangle pairs."""
import math

import numpy as np
import pytest

from app.model.lights3d import scene as lm
from app.model.lights3d import mesh as mesh3d
from app.model.lights3d.scene import Light3D, Lights3DCamera, Object3D, Scene3D, default_scene
from app.reference import lights3d as ref

GROUND = Object3D("plane", (400.0,), (0.0, 0.0, 0.0), (0.8, 0.8, 0.8))
TOP = Lights3DCamera(yaw=0.0, pitch=89.0, distance=300.0, target=(0.0, 0.0, 0.0))  # looking down


def small_scene() -> Scene3D:
    """The default scene, coarser, with a directional light besides the seed's two."""
    scene = default_scene().with_object(2, size=(18.0, 12)).with_object(3, size=(20.0, 6.0, 16, 6))
    return scene.add_light(Light3D("directional", (0, 0, 0), (-0.3, -1.0, 0.5), (0.4, 0.4, 0.4)))


# ---- brute force: every ray against every triangle --------------------------------------------------------


def nearest_hits(tris, origin, dirs, near, far, forward):
    """(triangle, u, v) of each ray's nearest hit within the clip planes' depths, -1 for none."""
    count, n = len(dirs), len(tris.v0)
    ray, tri = np.repeat(np.arange(count), n), np.tile(np.arange(n), count)
    hit, t, u, v = ref.intersect(tris, tri, np.broadcast_to(origin, (len(ray), 3)), dirs[ray])
    depth = t * (dirs[ray] @ forward)
    hit &= (depth >= near) & (depth <= far)
    best = np.full(count, -1)
    order = np.lexsort((tri[hit], t[hit], ray[hit]))
    _, first = np.unique(ray[hit][order], return_index=True)
    pick = np.flatnonzero(hit)[order[first]]
    best[ray[pick]] = tri[pick]
    return best, u, v, pick


def blocked_brute(tris, light, points, own, scale):
    casters = np.flatnonzero(tris.casts)
    ray, tri = np.repeat(np.arange(len(points)), len(casters)), np.tile(casters, len(points))
    if light.kind == "directional":
        directions = np.broadcast_to(-np.asarray(light.direction), (len(ray), 3))
        t_lo, t_hi = np.full(len(ray), ref.SELF_EPS * scale), np.full(len(ray), np.inf)
    else:
        directions = np.asarray(light.position) - points[ray]
        length = np.linalg.norm(directions, axis=1)
        t_lo = ref.SELF_EPS * scale / length
        t_hi = 1 - t_lo
    hit, t, _, _ = ref.intersect(tris, tri, points[ray], directions)
    hit &= (t > t_lo) & (t < t_hi) & (tri != own[ray])
    return np.bincount(ray[hit], minlength=len(points)) > 0


AWKWARD_LIGHTS = (  # on the corners, faces and planes where the cube map's depths are 0
    Light3D("point", (10.0, 36.0, 0.0), range=300.0),            # on the sphere's top pole
    Light3D("point", (-10.0, 15.0, 0.0), range=300.0),           # on the box's face, level with its middle
    Light3D("spot", (-25.0, 30.0, 15.0), (1.0, -1.0, 0.0), angle=60.0),  # on the box's top edge
    Light3D("point", (-25.0, 15.0, 0.0), range=300.0),           # inside the box
)


@pytest.mark.parametrize("camera, lights", [
    (Lights3DCamera(), ()),
    (Lights3DCamera(yaw=-60.0, pitch=8.0, distance=40.0, target=(0.0, 5.0, 0.0)), ()),  # the ground behind the eye
    (Lights3DCamera(yaw=10.0, pitch=20.0, distance=20.0, target=(-25.0, 15.0, 0.0)), ()),  # inside the box
    (Lights3DCamera(yaw=-20.0, pitch=25.0, distance=150.0), AWKWARD_LIGHTS),
])
def test_binning_is_exact(camera, lights):
    scene = small_scene()
    if lights:
        scene = Scene3D(scene.objects, lights)
    w, h = 48, 27
    result = ref.render(scene, camera, (w, h))
    tris = ref.Triangles.of(scene)
    origin, dirs = ref.primary_rays(camera, w, h)
    best, u, v, pick = nearest_hits(tris, origin, dirs, camera.NEAR, camera.FAR, -camera.view()[2, :3])
    expected_id = np.where(best >= 0, tris.owner[np.maximum(best, 0)], -1)
    np.testing.assert_array_equal(result.object_id.ravel(), expected_id)
    assert (best >= 0).sum() > 100
    hit = best >= 0
    k = best[hit]
    points = tris.v0[k] + u[pick, None] * tris.e1[k] + v[pick, None] * tris.e2[k]
    np.testing.assert_array_equal(result.position.reshape(-1, 3)[hit], points)
    scale = ref.world_scale(tris, origin, scene.lights)
    shadowed = 0
    for i, light in enumerate(scene.lights):
        blocked = blocked_brute(tris, light, points, k, scale)
        np.testing.assert_array_equal(result.visible[i].ravel()[hit], ~blocked)
        shadowed += blocked.sum()
    assert shadowed > 0
    assert result.pairs < 0.2 * result.rays * len(tris.v0)


def test_primary_rays_are_the_cameras():
    camera = Lights3DCamera(yaw=-30.0, pitch=40.0, distance=250.0)
    origin, dirs = ref.primary_rays(camera, 40, 30)
    for px, py in ((0, 0), (39, 0), (17, 11), (39, 29)):
        o, d = camera.ray(px + 0.5, py + 0.5, 40, 30)
        np.testing.assert_allclose(origin, o)
        np.testing.assert_allclose(dirs[py * 40 + px], d, atol=1e-12)


# ---- analytic shadows ---------------------------------------------------------------------------------------


def inradius(mesh, centre) -> float:
    """The largest ball about `centre` inside a convex mesh: its nearest face plane."""
    return float(np.einsum("td,td->t", mesh.face_normals(), mesh.corners()[:, 0] - centre).min())


def segment_distance(points, ends, centre):
    """Distance from `centre` to each segment points[i] -> ends[i]."""
    d = ends - points
    s = np.clip(np.einsum("id,id->i", centre - points, d) / np.einsum("id,id->i", d, d), 0, 1)
    return np.linalg.norm(points + s[:, None] * d - centre, axis=1)


@pytest.mark.parametrize("light", [
    Light3D("point", (60.0, 110.0, 25.0), range=1000.0),
    Light3D("spot", (-80.0, 140.0, -30.0), (80.0, -120.0, 30.0), angle=40.0),
    Light3D("directional", (0, 0, 0), (-0.5, -1.0, 0.3)),
])
def test_a_spheres_shadow_on_the_ground_matches_the_analytic_sphere(light):
    centre, radius = np.array([0.0, 30.0, 0.0]), 20.0
    ball = Object3D("sphere", (radius, 48), tuple(centre))
    scene = Scene3D((GROUND, ball), (light,))
    result = ref.render(scene, TOP, (96, 96))
    ground = result.object_id == 0
    points = result.position[ground]
    ends = np.asarray(light.position) + 0 * points if light.kind != "directional" else \
        points - 1e4 * np.asarray(light.direction)
    gap = segment_distance(points, ends, centre)
    inner = inradius(ball.mesh(), centre)
    assert radius - inner < 0.1
    visible = result.visible[0][ground]
    sure_shadow, sure_light = gap < inner - 0.01, gap > radius + 0.01  # away from the tessellation
    assert sure_shadow.sum() > 100 and sure_light.sum() > 1000
    assert not visible[sure_shadow].any() and visible[sure_light].all()
    assert (sure_shadow | sure_light).mean() > 0.97


def test_a_box_standing_on_the_ground_shadows_it_exactly():
    """The caster touches the receiver: the box's bottom face lies in the ground's plane. A box's mesh is the
    box, so the ground's shadow is the analytic segment-box test wherever a segment does not graze an edge;
    the ground right at the box's foot on the light's side stays lit."""
    lo, hi = np.array([-20.0, 0.0, -15.0]), np.array([20.0, 30.0, 15.0])
    box = Object3D("box", tuple(hi - lo), tuple((lo + hi) / 2))
    light = Light3D("point", (90.0, 60.0, 40.0), range=1000.0)
    scene = Scene3D((GROUND, box), (light,))
    from_the_light = Lights3DCamera(yaw=70.0, pitch=35.0, distance=220.0, target=(0.0, 0.0, 0.0))
    result = ref.render(scene, from_the_light, (96, 96))
    ground = result.object_id == 0
    points = result.position[ground]
    d = np.asarray(light.position) - points

    def crosses(grow):
        with np.errstate(divide="ignore", invalid="ignore"):
            t0, t1 = (lo - grow - points) / d, (hi + grow - points) / d
        near = np.nanmax(np.minimum(t0, t1), axis=1)
        far = np.nanmin(np.maximum(t0, t1), axis=1)
        return (near <= far) & (far > 0) & (near < 1)

    sure_shadow, sure_light = crosses(-0.05), ~crosses(0.05)
    visible = result.visible[0][ground]
    assert sure_shadow.sum() > 300
    assert not visible[sure_shadow].any() and visible[sure_light].all()
    at_the_foot = (points[:, 0] > hi[0]) & (points[:, 0] < hi[0] + 3) & (np.abs(points[:, 2]) < 10)
    assert at_the_foot.sum() > 3 and visible[at_the_foot].all()
    faces = result.object_id == 1
    lit_faces = result.facing[0][faces]
    assert lit_faces.sum() > 100 and result.visible[0][faces][lit_faces].all()  # no self-shadowing acne


def test_back_faces_shadow_themselves():
    sun = Light3D("directional", (0, 0, 0), (-1.0, -0.2, 0.0))  # from +x, nearly level
    ball = Object3D("sphere", (40.0, 40), (0.0, 50.0, 0.0), (0.2, 0.6, 0.9))
    scene = Scene3D((ball,), (sun,), ambient=(0.1, 0.2, 0.3))
    camera = Lights3DCamera(yaw=0.0, pitch=0.0, distance=200.0, target=(0.0, 50.0, 0.0))  # the terminator in view
    result = ref.render(scene, camera, (64, 64))
    on = result.object_id == 0
    geometric = result.facing[0] & on
    away = on & ~result.facing[0]
    assert geometric.sum() > 300 and away.sum() > 300
    # where the triangle turns away but its smooth normal still catches light, only the ambient remains
    rgb = result.rgb[away]
    np.testing.assert_allclose(rgb, np.tile(np.multiply(scene.ambient, ball.colour), (len(rgb), 1)))
    normals = result.normal[away]
    assert (normals @ -np.asarray(sun.direction) > 0).any()
    # and the segment towards the light runs through the ball (away from the terminator)
    deep = away & (result.normal @ -np.asarray(sun.direction) < -0.2)
    assert deep.sum() > 100 and not result.visible[0][deep].any()
    assert result.visible[0][geometric].all()


@pytest.mark.parametrize("inside", [
    Object3D("box", (30.0, 30.0, 30.0), (0.0, 15.0, 0.0)),
    Object3D("sphere", (20.0, 24), (0.0, 20.0, 0.0)),
])
def test_a_light_inside_a_closed_object_lights_nothing(inside):
    light = Light3D("point", (0.0, 15.0, 0.0), range=500.0)
    scene = Scene3D((GROUND, inside), (light,), ambient=(0.2, 0.2, 0.2))
    result = ref.render(scene, Lights3DCamera(distance=200.0), (64, 36))
    on = result.object_id >= 0
    assert (result.object_id == 1).sum() > 20 and (result.object_id == 0).sum() > 500
    assert not result.visible[0][result.object_id == 0].any()
    assert not result.facing[0][result.object_id == 1].any()  # every face turns its back on the light
    albedo = np.array([o.colour for o in scene.objects])[result.object_id[on]]
    np.testing.assert_allclose(result.rgb[on], 0.2 * albedo)


# ---- the formulas in the picture ----------------------------------------------------------------------------


def test_ground_colour_by_hand():
    """One unshadowed point light over the ground: each pixel's colour from the seed's formulas, written out."""
    light = Light3D("point", (10.0, 60.0, -20.0), colour=(1.0, 0.8, 0.6), range=150.0, falloff=2.0)
    scene = Scene3D((GROUND,), (light,), ambient=(0.05, 0.05, 0.05), shininess=16.0, specular=0.4)
    result = ref.render(scene, TOP, (32, 32))
    eye = TOP.position()
    albedo = np.array(GROUND.colour)
    checked = 0
    for y, x in ((3, 4), (16, 16), (20, 9), (30, 28)):
        p = result.position[y, x]
        to_light = np.array(light.position) - p
        d = math.sqrt(to_light @ to_light)
        katt = 1 - min(d / 150.0, 1.0) ** 2
        l_dir, v_dir = to_light / d, (eye - p) / np.linalg.norm(eye - p)
        diffuse = max(l_dir[1], 0.0)
        h = (l_dir + v_dir) / np.linalg.norm(l_dir + v_dir)
        spec = 0.4 * max(h[1], 0.0) ** 16
        expected = np.clip(0.05 * albedo + katt * (albedo * diffuse + spec) * np.array(light.colour), 0, 1)
        np.testing.assert_allclose(result.rgb[y, x], expected, rtol=1e-12)
        checked += katt > 0
    assert checked >= 2
    assert (result.facing[0] == (np.linalg.norm(result.position - light.position, axis=2) < 150)).all()


def test_the_default_scene_casts_shadows_on_the_ground_and_on_objects():
    scene = default_scene()
    result = ref.render(scene, Lights3DCamera(), (160, 90))
    # the sphere (object 2) shades the box (object 1): without it, those box pixels see the light
    no_sphere = ref.render(scene.remove_object(2), Lights3DCamera(), (160, 90))
    ground, box = result.object_id == 0, (result.object_id == 1) & (no_sphere.object_id == 1)
    for i in range(len(scene.lights)):
        shadow = result.facing[i] & ~result.visible[i]
        assert (shadow & ground).sum() > 50, f"light {i} shadows the ground"
        assert (shadow & box & no_sphere.visible[i]).sum() > 5, f"light {i} shadows the box by the sphere"
        assert (result.facing[i] & result.visible[i] & ground).sum() > 200
    background = result.object_id < 0
    np.testing.assert_array_equal(result.rgb[background], np.tile(lm.BACKGROUND, (background.sum(), 1)))
    assert np.isnan(result.position[background]).all() and np.isfinite(result.rgb).all()
    # a light without shadows lights through: the picture changes only where that light was shadowed
    unshadowed = ref.render(scene.with_light(0, shadow="none"), Lights3DCamera(), (160, 90))
    changed = (np.abs(unshadowed.rgb - result.rgb) > 1e-12).any(2)
    assert changed.any() and not (changed & result.facing[0] & result.visible[0]).any()


def test_a_100k_triangle_scene_is_traced_with_few_pairs():
    scene = default_scene()
    segments = mesh3d.sphere_segments(100_000)
    scene = scene.with_object(2, size=(18.0, segments))
    assert scene.triangles > 100_000
    result = ref.render(scene, Lights3DCamera(), (64, 36))
    assert result.rays == 64 * 36 + len(scene.lights) * (result.object_id >= 0).sum()  # primary, then shadow
    assert result.pairs < 1e-3 * result.rays * scene.triangles  # binned: nowhere near every pair
    assert (result.object_id == 2).sum() > 4 and (~result.visible[0] & (result.object_id == 0)).any()


def test_empty_scenes():
    nothing = ref.render(Scene3D(), Lights3DCamera(), (8, 6))
    assert (nothing.object_id == -1).all() and nothing.facing.shape == (0, 6, 8)
    np.testing.assert_array_equal(nothing.rgb, np.tile(lm.BACKGROUND, (6, 8, 1)))
    dark = ref.render(Scene3D((GROUND,), ambient=(0.5, 0.5, 0.5)), Lights3DCamera(), (8, 6))
    np.testing.assert_allclose(dark.rgb[dark.object_id == 0], 0.4)  # ambient x albedo, nothing casts
