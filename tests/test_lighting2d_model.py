"""The 2D lighting model: constraints, hull validity and winding, transforms, and the scene file."""
import json
import math
from dataclasses import FrozenInstanceError, replace

import numpy as np
import pytest

from app.io import lighting2d_scene as scene2d
from app.model.lighting2d.scene import Hull, Light, Lighting2DError, Scene2D, outlines_overlap, signed_area, validity

SQUARE = [(0, 0), (1, 0), (1, 1), (0, 1)]


def star(n: int, r1: float = 1.0, r2: float = 0.4) -> np.ndarray:
    a = np.arange(2 * n) * math.pi / n
    r = np.where(np.arange(2 * n) % 2 == 0, r1, r2)
    return np.stack([r * np.cos(a), r * np.sin(a)], axis=1)


@pytest.mark.parametrize("points, needle", [
    ([(0, 0), (1, 1)], "at least 3 points"),
    ([(0, 0), (1, 1), (2, 2)], "collinear"),
    ([(0, 0), (1, 1), (1, 0), (0, 1)], "cross"),             # a bow tie
    ([(0, 0), (2, 0), (2, 2), (1, -1), (0, 2)], "cross"),
])
def test_invalid_hulls_are_marked_with_the_reason(points, needle):
    hull = Hull(points)
    assert not hull.valid and needle in hull.invalid_reason


def test_valid_hulls_and_winding_normalised():
    cw = Hull(SQUARE[::-1])
    assert cw.valid and signed_area(cw.points) > 0
    assert Hull(star(500)).valid  # 1,000 vertices, concave
    big = Hull(np.array(SQUARE) * 10 + 1e6)
    assert big.valid and validity(big.points) is None  # coordinates near 1e6


def test_editing_points_moves_a_hull_between_valid_and_invalid():
    hull = Hull(SQUARE)
    tangled = replace(hull, points=[(0, 0), (1, 1), (1, 0), (0, 1)])
    assert not tangled.valid and hull.valid
    assert replace(tangled, points=SQUARE).valid and not tangled.valid


def test_world_transform_worked_out_once_per_hull():
    hull = Hull(SQUARE, position=(10, 5), origin=(0.5, 0.5), rotation=math.pi / 2, scale=(2, 2))
    world = hull.world()
    assert world is hull.world()  # worked out once
    np.testing.assert_allclose(world.mean(axis=0), (10, 5), atol=1e-12)
    np.testing.assert_allclose(world[0], (11, 4), atol=1e-12)  # (-1, -1) turned a quarter: (1, -1)
    placed = replace(hull, position=(0, 0), origin=(0, 0), rotation=0.0, scale=(1, 1))
    np.testing.assert_allclose(placed.world(), placed.points)
    assert placed.contains(0.5, 0.5) and not placed.contains(1.5, 0.5)
    np.testing.assert_allclose(hull.world(), world)  # the hull it came from is unchanged


@pytest.mark.parametrize("kwargs, needle", [
    (dict(radius=-1), "radius must be >= 0"),
    (dict(intensity=-0.5), "intensity must be >= 0"),
    (dict(scale=(-1, 2)), "scale must be >= 0"),
    (dict(cone_decay=-1), "cone decay must be >= 0"),
    (dict(color=(1, 2, 0)), "within 0..1"),
    (dict(kind="laser"), "light kind"),
    (dict(shadow_type="dark"), "shadow type"),
    (dict(kind="textured"), "needs a texture"),
    (dict(position=(math.nan, 0)), "must be finite"),
])
def test_light_constraints_refused_with_a_message(kwargs, needle):
    with pytest.raises(Lighting2DError, match=needle):
        Light(**kwargs)


def test_hull_scale_refused():
    with pytest.raises(Lighting2DError, match="hull scale must be >= 0"):
        Hull(SQUARE, scale=(1, -1))


def test_spot_cone_angle_from_the_quad():
    spot = Light(kind="spot", scale=(100, 200))
    assert spot.cone_half_angle() == pytest.approx(0.5 * (math.pi - 2 * math.atan(1.0)))


def test_scene_round_trip(tmp_path):
    scene = Scene2D(lights=[Light(position=(3, 4), radius=12, shadow_type="illuminated", ignored_hulls=(1,)),
                            Light(kind="spot", color=(1, 0.5, 0.25), cone_decay=2)],
                    hulls=[Hull(SQUARE, position=(5, 5)), Hull(star(5), rotation=0.3)])
    path = tmp_path / "s.json"
    scene2d.save(path, scene)
    back = scene2d.load(path)
    assert back.digest() == scene.digest()


@pytest.mark.parametrize("data, needle", [
    ({"format": "other", "version": 1}, "not a shadelab.lighting2d file"),
    ({"format": "shadelab.lighting2d", "version": 2}, "unsupported version 2"),
    ({"format": "shadelab.lighting2d", "version": 1, "lights": [{"radius": -3}]}, r"lights\[0\]: light radius"),
    ({"format": "shadelab.lighting2d", "version": 1, "lights": [{"brightness": 3}]}, "unknown keys: brightness"),
    ({"format": "shadelab.lighting2d", "version": 1, "hulls": [{"points": [[0, 0], ["a", 1], [1, 1]]}]},
     r"hulls\[0\]\.points\[1\]\[0\]: expected a number, got a string"),
    ({"format": "shadelab.lighting2d", "version": 1, "ambient": [2, 0, 0]}, "within 0..1"),
])
def test_malformed_scene_files_are_refused(tmp_path, data, needle):
    path = tmp_path / "bad.json"
    path.write_text(json.dumps(data))
    with pytest.raises(Lighting2DError, match=needle):
        scene2d.load(path)


def test_outlines_overlap_only_where_they_share_interior():
    square = np.array([(0, 0), (1, 0), (1, 1), (0, 1)], float)
    assert not outlines_overlap([square, square + (1, 0)])       # an edge in common
    assert not outlines_overlap([square, square + (1, 1)])       # a corner
    assert not outlines_overlap([square, square + (3, 0), square + (0, 5)])
    assert outlines_overlap([square, square + (0.5, 0.5)])
    assert outlines_overlap([square, 0.5 * square + (0.25, 0.25)])  # one inside the other
    assert not outlines_overlap([square]) and not outlines_overlap([])


def test_scene_values_are_immutable_and_an_edit_leaves_the_scene_before_untouched():
    light, hull = Light(position=(3, 4), ignored_hulls=(0, 1)), Hull(SQUARE, position=(5, 5))
    scene = Scene2D(lights=[light], hulls=[hull, Hull(star(5))])
    for thing, name, value in ((scene, "ambient", (0, 0, 0)), (scene, "lights", ()), (light, "radius", 3.0),
                               (hull, "position", (0, 0)), (hull, "points", np.zeros((3, 2)))):
        with pytest.raises(FrozenInstanceError):
            setattr(thing, name, value)
    for array in (hull.points, hull.world(), hull.world_pieces()[0]):
        with pytest.raises(ValueError, match="read-only"):
            array[0] = (9, 9)
    assert isinstance(scene.lights, tuple) and isinstance(scene.hulls, tuple)
    digest, world = scene.digest(), hull.world().copy()
    moved = scene.with_hull(0, replace(hull, position=(50, 50))).with_light(0, replace(light, radius=3.0))
    removed = moved.remove_hull(0)
    assert removed.lights[0].ignored_hulls == (0,) and moved.lights[0].ignored_hulls == (0, 1)  # renumbered
    assert scene.digest() == digest and scene.lights == (light,) and scene.hulls[0] is hull
    np.testing.assert_array_equal(hull.world(), world)
    assert light.radius == 20.0 and hull.position == (5.0, 5.0)


def test_a_moved_hull_shares_its_outline_with_the_hull_before():
    """Its points' validity and convex pieces are worked out once, however often a drag moves it; a clockwise
    hull's too (stored counter-clockwise, which its moved copies are made from)."""
    for points in (star(50), star(50)[::-1]):
        hull = Hull(points)
        pieces = hull.outline.pieces
        assert len(pieces) > 1
        moved = replace(replace(hull, position=(10, 0)), rotation=1.0, enabled=False)
        assert moved.outline is hull.outline and moved.outline.pieces is pieces
        assert replace(hull, points=hull.points[:-1]).outline is not hull.outline
