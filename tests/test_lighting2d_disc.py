"""Hulls that enter the light's disc (issue 13): the reference's closed form (the disc clipped by the
union of the pieces' shadows) against sampling the disc, and the default GPU method (nearest piece
first where the hulls lie apart, the shadows' union where two overlap) against the reference on seeded
random scenes, the sample scenes k, l and m, and the degenerate cases of the closed form (a vertex on
the circle, an edge touching it, pieces of one hull meeting at a vertex)."""
import math
from dataclasses import replace

import numpy as np
import pytest

from app.gl.lighting2d.renderer import Lighting2DRenderer, Shading2D
from app.gl.core.shaders import ShaderLibrary
from app.io import lighting2d_scene as scene2d
from app.model.camera2d import Camera2D
from app.model.lighting2d.scene import Hull, Light, Scene2D, inside_convex, outlines_overlap
from app.model.lighting2d.index import SceneIndex
from app.reference import lighting2d as reference
from app.reference.lighting2d_disc import hidden_share
from app.resources import SCENES, SHADERS

TWO = 2 / 255 + 1e-6
SIZE = (96, 60)


def box(x0, y0, x1, y1):
    return np.array([(x0, y0), (x1, y0), (x1, y1), (x0, y1)], float)


def random_scene(seed: int) -> Scene2D:
    """1..4 hulls (convex, star-shaped, slivers; a third of the time clustered) and one white point
    light of radius 2..140 whose disc one of them enters."""
    rng = np.random.default_rng(seed)
    radius = float(rng.uniform(2, 140))
    centre = rng.uniform(-100, 100, 2)
    clustered = rng.random() < 0.3
    hulls = []
    for _ in range(int(rng.integers(1, 5))):
        size = float(rng.uniform(10, 70))
        kind = int(rng.integers(3))
        if kind == 0:  # convex
            a = np.sort(rng.uniform(0, 2 * math.pi, int(rng.integers(3, 8))))
            points = size * rng.uniform(0.6, 1.0, len(a))[:, None] * np.stack([np.cos(a), np.sin(a)], axis=1)
        elif kind == 1:  # a star
            a = np.linspace(0, 2 * math.pi, 10, endpoint=False)
            points = np.where(np.arange(10) % 2 == 0, size, 0.4 * size)[:, None] * np.stack([np.cos(a), np.sin(a)], 1)
        else:  # a sliver
            points = box(-size, -0.05 * size, size, 0.05 * size)
        at = centre + rng.normal(0, 30, 2) if clustered else rng.uniform(-180, 180, 2)
        hulls.append(Hull(points, position=tuple(at), rotation=float(rng.uniform(0, 2 * math.pi))))
    scene = Scene2D(ambient=(0, 0, 0), hulls=hulls, background="builtin:white")
    while True:
        near = hulls[int(rng.integers(len(hulls)))].world().mean(axis=0)
        light = Light(position=tuple(near + rng.normal(0, radius + 30, 2)), scale=(500, 500), radius=radius)
        lit = replace(scene, lights=(light,))
        index = SceneIndex(lit)
        if index.disc_touched(light) and not index.centre_blocked(light):
            return replace(lit, view=(*light.position, 400.0))


@pytest.fixture(scope="module")
def renderer(gl):
    return Lighting2DRenderer(gl, ShaderLibrary(gl, [SHADERS]))


def exact_error(renderer, scene, size=SIZE) -> float:
    image = renderer.read_lightmap(scene, Camera2D(*scene.view), size, Shading2D(method="exact"))
    return float(np.abs(image - reference.render(scene, *size)).max())


# ---- the reference's closed form ------------------------------------------------------------------

DEGENERATE = {
    "a corner on the circle": [box(20, 0, 40, 20)],
    "an edge touching the circle": [box(20, -50, 30, 50)],
    "a gap as wide as the disc": [box(20, -50, 30, 50), box(-30, -50, -20, 50)],
    "boxes meeting at a corner": [box(10, 10, 30, 30), box(30, 30, 50, 50)],
    "a square cut along its diagonal": [np.array([(10, -10), (30, -10), (30, 10)], float),
                                        np.array([(10, -10), (30, 10), (10, 10)], float)],
    "a wall through the disc": [box(-60, 5, 60, 12)],
}


@pytest.mark.parametrize("name", sorted(DEGENERATE))
def test_the_closed_form_agrees_with_sampling_the_disc(name):
    """Radius 20 at the origin; sampling's own error at 96 x 96 strata is about 1e-3."""
    pieces = DEGENERATE[name]
    points = np.random.default_rng(1).uniform(-100, 100, (150, 2))
    outside = ~np.any([inside_convex(points, p) for p in pieces], axis=0)
    exact = 1.0 - hidden_share(points, pieces, 20.0)
    sampled = reference.sampled(points, pieces, 20.0, 96)
    assert np.abs(exact - sampled)[outside].max() < 3e-3
    assert exact[~outside].max(initial=0.0) == 0.0  # inside a piece every segment starts in it


@pytest.mark.parametrize("seed", range(4))
def test_the_closed_form_agrees_with_sampling_on_random_scenes(seed):
    scene = random_scene(seed)
    light = scene.lights[0]
    pieces = [p - np.asarray(light.position) for _, p in reference.blockers(scene, light)]
    rng = np.random.default_rng(seed)
    points = np.concatenate([rng.uniform(-200, 200, (60, 2)), rng.normal(0, light.radius, (40, 2))])
    outside = ~np.any([inside_convex(points, p) for p in pieces], axis=0)
    exact = 1.0 - hidden_share(points, pieces, light.radius)
    sampled = reference.sampled(points, pieces, light.radius, 96)
    assert np.abs(exact - sampled)[outside].max() < 3e-3


def test_the_closed_form_is_the_interval_method_where_no_piece_enters_the_disc():
    pieces = [box(40, -10, 60, 30), box(70, -40, 90, 0), box(-80, 20, -50, 40)]
    points = np.random.default_rng(2).uniform(-150, 150, (400, 2))
    points = points[~np.any([inside_convex(points, p) for p in pieces], axis=0)]
    assert np.abs((1.0 - hidden_share(points, pieces, 25.0)) - reference._exact(points, pieces, 25.0)).max() < 1e-9


# ---- the default method against the reference ------------------------------------------------------

@pytest.mark.parametrize("seed", range(12))
def test_default_method_is_exact_on_random_scenes_with_a_hull_in_the_disc(renderer, seed):
    scene = random_scene(seed)
    assert exact_error(renderer, scene) <= TWO
    casters = [scene.hulls[i] for i in SceneIndex(scene).casters(scene.lights[0])]
    ordered = not outlines_overlap([h.world() for h in casters]) and sum(len(h.world_pieces()) for h in casters) <= 16
    assert (renderer.stats.disc_ordered, renderer.stats.disc_fused) == (int(ordered), int(not ordered))


def ring(count: int, at: float = 26.0) -> Scene2D:
    """`count` 8-unit boxes `at` from a light whose disc enters every one (a light among pillars), apart."""
    angles = np.linspace(0.0, 2.0 * math.pi, count, endpoint=False) + 0.3
    hulls = [Hull(box(-4, -4, 4, 4) + at * np.array([math.cos(a), math.sin(a)])) for a in angles]
    assert not outlines_overlap([h.world() for h in hulls])
    return Scene2D(ambient=(0, 0, 0), view=(0.3, 0.7, 240), background="builtin:white",
                   lights=[Light(position=(0, 0), scale=(300, 300), radius=at + 4.0)], hulls=hulls)


@pytest.mark.parametrize("count", [9, 12])
def test_a_light_among_many_pillars_is_exact(renderer, count):
    """Every pillar in the disc: the circle is crossed 2 * count times, more than the fused program's 12."""
    assert exact_error(renderer, ring(count)) <= TWO
    assert renderer.stats.disc_ordered == 1


def test_a_light_of_more_pieces_than_the_ordered_program_holds_takes_the_fused_one(renderer):
    """Two intervals a piece at most (one across the cut behind a pixel in the disc): 32 slots hold 16 pieces."""
    renderer.read_lightmap(ring(17, at=40.0), Camera2D(0, 0, 240), (64, 40), Shading2D(method="exact"))
    assert (renderer.stats.disc_ordered, renderer.stats.disc_fused) == (0, 1)


@pytest.mark.parametrize("shift", [0.0, 15.0, 30.0, 45.0])
def test_both_disc_programs_are_exact_as_a_hull_slides_into_another(renderer, shift):
    """Apart or touching along an edge (shift 30), the pieces are taken nearest first; overlapping, the
    shadows' union is fused: the same answer either way."""
    scene = Scene2D(ambient=(0, 0, 0), view=(0.3, 0.7, 240), background="builtin:white",
                    lights=[Light(position=(0, 0), scale=(300, 300), radius=35.0)],
                    hulls=[Hull(box(10, -30, 40, 0)), Hull(box(70 - shift, -12, 100 - shift, 25))])
    assert exact_error(renderer, scene) <= TWO
    overlapping = shift > 30.0
    assert (renderer.stats.disc_ordered, renderer.stats.disc_fused) == (int(not overlapping), int(overlapping))


@pytest.mark.parametrize("name", ["k_light_wider_than_a_gap", "l_hull_through_the_disc", "m_disc_touching_two_hulls"])
def test_default_method_is_exact_on_the_samples_where_hulls_enter_the_disc(renderer, name):
    scene = scene2d.load(SCENES / f"{name}.json")
    assert all(SceneIndex(scene).disc_touched(light) for light in scene.lights)
    assert exact_error(renderer, scene, (128, 80)) <= TWO


@pytest.mark.parametrize("name", sorted(DEGENERATE))
def test_default_method_is_exact_in_the_degenerate_cases(renderer, name):
    # the view off the integers: a pixel centre right on an edge is inside for the float64 reference and
    # a hair outside for the GPU, where a hull's edge hides what lies beyond its line
    scene = Scene2D(ambient=(0, 0, 0), view=(0.3, 0.7, 240), background="builtin:white",
                    lights=[Light(position=(0, 0), scale=(300, 300), radius=20.0)],
                    hulls=[Hull(p) for p in DEGENERATE[name]])
    assert SceneIndex(scene).disc_touched(scene.lights[0])
    assert exact_error(renderer, scene) <= TWO


@pytest.mark.parametrize("kind", ["illuminated", "occluded"])
def test_hull_semantics_hold_where_hulls_enter_the_disc(renderer, kind):
    """The disc program finds the pixel's own hull as the interval one does: lit inside (illuminated), or
    lit by what the other hull lets through (occluded)."""
    scene = scene2d.load(SCENES / "m_disc_touching_two_hulls.json")
    scene = scene.with_light(0, replace(scene.lights[0], shadow_type=kind))
    image = renderer.read_lightmap(scene, Camera2D(*scene.view), (128, 80), Shading2D(method="exact"))
    exact = reference.render(scene, 128, 80)
    assert float(np.abs(image - exact).max()) <= TWO
    box_pixel = (33, 70)  # inside the square, which the light reaches past the disc's edge
    assert exact[box_pixel][0] > 0.2 and image[box_pixel][0] > 0.2
