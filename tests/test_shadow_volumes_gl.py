"""Shadow volumes in the stencil (EGL, llvmpipe, 64 x 64) against the CPU's answer per pixel: the seed's order
claim, the camera outside (looking along a point light's rays too), inside and cut by the near plane, a light
inside the caster, a caster on the receiver and grazing light. The numbers measured are printed (pytest -s);
docs quote them from here."""
import numpy as np
import pytest

from app.gl.lights3d.shadow_methods import SHADOW_VALUE
from app.gl.lights3d.shadow_volume_pass import METHODS, shadowed, volume
from app.gl.lights3d.shadow_volumes import VolumeGeometry, facing_light, onepass_volume
from app.gl.core.stencil import GL, clear_stencil
from tests.gl_state import differences, snapshot
from tests.shadow_cases import stencil_host
from tests.shadow_scenes import box, cpu_shadow, ground, in_shadow, soup, view_proj

SIZE = (64, 64)
EDGE = 0.002  # 8 of 4096 pixels: where a volume's edge passes a pixel centre, float32 and float64 may part
GROUND = ground()
BOX = box((-0.5, 0.8, -0.5), (0.5, 1.8, 0.5))  # floating over the ground
LAMP = (1.2, 4.0, 0.8, 1.0)
SIDE_VIEW = ((-4.0, 2.0, 1.5), (0.0, 0.7, 0.0))


@pytest.fixture(scope="module")
def host(gl):
    yield from stencil_host(gl, SIZE)


def draw_scene(host, view, near=0.1, casters=(BOX,), receivers=(GROUND,)):
    """The scene's depth in the target; returns its view-projection matrix."""
    shadow_pass, target = host
    vp = view_proj(*view, SIZE, near=near)
    target.clear()
    shadow_pass.draw_depth(target.fbo, soup([*receivers, *casters]), vp)
    return vp


def compare(host, view, light, near=0.1, casters=(BOX,), receivers=(GROUND,)):
    """Each method's mask against the CPU's: (the CPU's shadow mask, {method: ShadowMask}, {method: mismatch}),
    the mismatch as a fraction of all pixels."""
    vp = draw_scene(host, view, near, casters, receivers)
    cpu = cpu_shadow(SIZE, vp, list(receivers), list(casters), light)
    masks = {m: host[0].shadow_mask(host[1], m, list(casters), light, vp) for m in METHODS}
    assert GL.glGetError() == GL.GL_NO_ERROR
    # a face edge-on to the light gets none of it, shadowed or not: which one is no error
    return cpu.shadow, masks, {m: float(((r.mask != cpu.shadow) & ~cpu.edge_on).mean()) for m, r in masks.items()}


def report(case, reference, errors):
    print(f"\n{case}: {reference.mean():.1%} of pixels in shadow; mismatch "
          + ", ".join(f"{m} {e:.2%}" for m, e in errors.items()))


def screen_front_facing(vertices: np.ndarray, vp: np.ndarray) -> np.ndarray:
    """Per triangle, whether GL calls it front-facing: the sign of its clip-space (x, y, w) determinant, which
    holds for w = 0 and w < 0 vertices too."""
    clip = vertices.astype(np.float64).reshape(-1, 3, 4) @ vp.T
    return np.linalg.det(clip[:, :, [0, 1, 3]]) > 0


def onepass_stencils(host, geometry: VolumeGeometry, vp, orders: dict) -> dict:
    """The onepass stencil of the volume's triangles drawn in each order."""
    shadow_pass, target = host
    triangles = geometry.vertices.reshape(-1, 3, 4)
    out = {}
    for name, order in orders.items():
        clear_stencil(target.fbo)
        shadow_pass.mark(target.fbo, "onepass", [VolumeGeometry(triangles[order].reshape(-1, 4), 0)], vp)
        out[name] = target.read_stencil()
    return out


def orders_of(geometry: VolumeGeometry, vp, rng, per_caster: int) -> dict:
    front = screen_front_facing(geometry.vertices, vp)
    casters = geometry.triangles // per_caster
    # each caster's triangles kept together, the casters and the triangles within each shuffled
    grouped = (rng.permutation(casters)[:, None] * per_caster
               + rng.permuted(np.tile(np.arange(per_caster), (casters, 1)), axis=1))
    return {"as built": np.arange(geometry.triangles), "front faces first": np.r_[np.flatnonzero(front),
            np.flatnonzero(~front)], "back faces first": np.r_[np.flatnonzero(~front), np.flatnonzero(front)],
            "shuffled": rng.permutation(geometry.triangles), "casters shuffled": grouped.ravel()}


@pytest.mark.parametrize("closed", [False, True], ids=["seed", "closed"])
def test_onepass_one_caster_triangle_gives_the_same_stencil_in_any_order(host, closed):
    """The seed's figures 4.4 and 4.5: one triangle's volume, front faces or back faces first, or any order; the
    prism closed at infinity too (its far cap adds a depth fail where a view ray ends inside it)."""
    triangle = (np.array([[-0.6, 1.2, -0.4], [0.6, 1.0, -0.3], [0.0, 1.4, 0.6]]), np.array([[0, 1, 2]], np.int32))
    vp = draw_scene(host, SIDE_VIEW, casters=(triangle,))
    geometry = onepass_volume(*triangle, LAMP, closed)
    stencils = onepass_stencils(host, geometry, vp, orders_of(geometry, vp, np.random.default_rng(2), 7 + closed))
    reference = cpu_shadow(SIZE, vp, [GROUND], [triangle], LAMP).shadow
    assert reference.mean() > 0.02
    for name, stencil in stencils.items():
        np.testing.assert_array_equal(stencil, stencils["as built"], err_msg=name)
        assert set(np.unique(stencil)) <= {0, 1, 0xFD, SHADOW_VALUE}
    shadow = (stencils["as built"] == SHADOW_VALUE) & (host[1].read_depth() < 1)
    assert (shadow != reference).mean() <= EDGE


TWO_BOXES = (BOX, box((-1.6, 0.0, -1.0), (-0.9, 0.9, -0.2)))  # the second in the first's shadow


@pytest.mark.parametrize("closed, casters", [(False, (BOX,)), (True, (BOX,)), (True, TWO_BOXES)],
                         ids=["seed, a box", "closed, a box", "closed, two boxes"])
def test_onepass_order_freedom_within_and_across_casters_volumes(host, closed, casters):
    """A box's 12 volumes overlap: their triangles interleaved (front faces of all first, or shuffled) can meet
    a depth pass and a depth fail of different volumes first and lock a pixel in or out of shadow. Drawn a
    caster triangle at a time, in any order of them, the stencil is the same and right. Closed, of the box's
    triangles turned from the light alone, the prisms do not overlap and their union is convex: any order of
    all their triangles gives the same stencil. Across two casters it does not: a ray can pass one's shadow,
    then a lit point, then the other's, and an interleaved pass and fail lock the lit point."""
    vp = draw_scene(host, SIDE_VIEW, casters=casters)
    geometry = VolumeGeometry(np.concatenate([onepass_volume(*c, LAMP, closed).vertices for c in casters]), 0)
    stencils = onepass_stencils(host, geometry, vp, orders_of(geometry, vp, np.random.default_rng(2), 7 + closed))
    reference = cpu_shadow(SIZE, vp, [GROUND], list(casters), LAMP).shadow
    covered = host[1].read_depth() < 1
    errors = {name: float((((s == SHADOW_VALUE) & covered) != reference).mean()) for name, s in stencils.items()}
    report(f"onepass{'' if closed else '-seed'}, {len(casters)} box(es), by draw order", reference, errors)
    np.testing.assert_array_equal(stencils["casters shuffled"], stencils["as built"])
    assert errors["as built"] <= EDGE
    if closed and len(casters) == 1:
        for name, stencil in stencils.items():
            np.testing.assert_array_equal(stencil, stencils["as built"], err_msg=name)
    else:
        assert errors["shuffled"] > EDGE  # the seed's order freedom does not reach across volumes that overlap


@pytest.mark.parametrize("light", [LAMP, (0.3, 1.0, 0.2, 0.0)], ids=["point", "directional"])
@pytest.mark.parametrize("view", [SIDE_VIEW, ((3.5, 5.0, -3.0), (-0.5, 0.3, 0.0))], ids=["side", "above"])
def test_camera_outside_every_method_matches_the_cpu(host, view, light):
    assert not in_shadow(np.array([view[0]], float), [BOX], light)[0]
    reference, masks, errors = compare(host, view, light)
    report(f"outside, {light}", reference, errors)
    assert reference.mean() > 0.02
    assert max(errors.values()) <= EDGE
    assert masks["onepass-seed"].triangles == 7 * 12
    assert masks["onepass"].triangles == 8 * (~facing_light(*BOX, light)).sum()  # the triangles turned from it
    edges = masks["zfail"].extruded_edges
    assert masks["zpass"].triangles == 2 * edges and masks["zfail"].triangles == 2 * edges + 12


def test_camera_looking_along_a_point_lights_rays_breaks_only_the_seeds_open_volumes(host):
    """The eye beyond the lamp, looking past the box onto its shadow: the view rays through the shadow run on to
    infinity inside the prisms of the box's triangles. The seed's prisms, open there, count the entry alone;
    closed, every prism a ray enters it also leaves."""
    view = ((2.0, 5.4, 1.0), (-0.6, 0.0, -0.4))
    assert not in_shadow(np.array([view[0]], float), [BOX], LAMP)[0]
    reference, _, errors = compare(host, view, LAMP)
    report("looking along the light's rays", reference, errors)
    assert reference.mean() > 0.02
    assert errors["onepass-seed"] > 0.01  # over half of the shadow shows lit
    assert max(errors[m] for m in ("onepass", "zpass", "zfail")) <= EDGE


def test_camera_inside_a_volume_breaks_zpass_and_onepass_not_zfail(host):
    view = ((-0.3, 0.3, -0.2), (-2.5, 0.0, -1.5))  # under the box, looking out across its shadow
    assert in_shadow(np.array([view[0]], float), [BOX], LAMP)[0]
    reference, _, errors = compare(host, view, LAMP, near=0.05)
    report("camera inside a volume", reference, errors)
    assert reference.mean() > 0.2
    assert errors["zfail"] <= EDGE
    assert errors["zpass"] > 0.3  # the count starts one short: lit and shadowed swap
    assert errors["onepass"] > 0.05  # the volumes around the eye have no face in front of it either


def near_plane_corners(vp: np.ndarray) -> np.ndarray:
    g = np.linspace(-1, 1, 9)
    x, y = np.meshgrid(g, g)
    clip = np.stack([x.ravel(), y.ravel(), -np.ones(x.size), np.ones(x.size)], 1) @ np.linalg.inv(vp).T
    return clip[:, :3] / clip[:, 3:]


def test_near_plane_cutting_a_volume_breaks_zpass_only(host):
    view, near = ((-1.8, 0.5, -0.4), (-1.5, 0.2, -3.0)), 0.6
    assert not in_shadow(np.array([view[0]], float), [BOX], LAMP)[0]
    on_near_plane = in_shadow(near_plane_corners(view_proj(*view, SIZE, near=near)), [BOX], LAMP)
    assert 0 < on_near_plane.mean() < 1  # the near plane cuts the volume
    reference, _, errors = compare(host, view, LAMP, near=near)
    report("near plane cutting a volume", reference, errors)
    assert errors["zpass"] > 0.1
    assert errors["zfail"] <= EDGE and errors["onepass"] <= EDGE  # depth clamping: nothing clipped at the near plane


def test_light_inside_the_caster(host):
    light = (0.0, 1.3, 0.0, 1.0)
    reference, masks, errors = compare(host, SIDE_VIEW, light)
    report("light inside the caster", reference, errors)
    assert reference.mean() > 0.5  # all it lights is the box's inside
    assert errors["zfail"] <= EDGE and masks["zfail"].triangles == 12  # the dark cap alone
    assert masks["zpass"].triangles == 0 and not masks["zpass"].mask.any()  # no silhouette: no shadow at all
    assert errors["onepass"] > 0.05


def test_caster_touching_the_receiver(host):
    resting = box((-0.5, 0.0, -0.5), (0.5, 1.0, 0.5))
    reference, _, errors = compare(host, SIDE_VIEW, LAMP, casters=(resting,))
    report("caster on the receiver", reference, errors)
    assert reference.mean() > 0.05
    assert max(errors.values()) <= EDGE


@pytest.mark.parametrize("light", [(1.0, 0.03, 0.3, 0.0), (1.0, 0.0, 0.3, 0.0), (3.9, 0.05, 1.0, 1.0),
                                   (2.0, 1.81, 0.3, 1.0), (2.0, 1.8, 0.3, 1.0)],
                         ids=["directional-1.7deg", "directional-in-ground-plane", "point-near-ground",
                              "top-face-grazed", "top-face-edge-on"])
def test_grazing_light(host, light):
    reference, masks, errors = compare(host, SIDE_VIEW, light)
    report(f"grazing {light}", reference, errors)
    for method in METHODS:
        assert np.isfinite(volume(method, *BOX, light).vertices).all()
    assert reference.mean() > 0.02
    assert max(errors.values()) <= EDGE


def test_a_pass_leaves_no_state_behind_and_draws_no_colour(host):
    shadow_pass, target = host
    vp = view_proj(*SIDE_VIEW, SIZE)
    target.clear(colour=(0.25, 0.5, 0.75, 1.0))
    colour = target.fbo.read(components=4)
    target.fbo.use()  # the passes bind it: a test run before this one may have left another bound
    before = snapshot()
    shadow_pass.draw_depth(target.fbo, soup([GROUND, BOX]), vp)
    for method in METHODS:
        shadow_pass.shadow_mask(target, method, [BOX], LAMP, vp)
        after = snapshot()
        assert differences(before, after) == {}, method
        assert not after["GL_STENCIL_TEST"] and not after["GL_DEPTH_CLAMP"]
    assert target.fbo.read(components=4) == colour
    assert GL.glGetError() == GL.GL_NO_ERROR


def test_unknown_methods_are_refused(host):
    with pytest.raises(ValueError, match="onepass, onepass-seed, zpass, zfail"):
        volume("zmiddle", *BOX, LAMP)
    with pytest.raises(ValueError, match="unknown"):
        shadowed("zmiddle", np.zeros((2, 2), np.uint8))
