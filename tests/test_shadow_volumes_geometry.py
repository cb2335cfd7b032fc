"""Shadow volume geometry (numpy only): the seed's 7 triangles per caster triangle and the closed one-pass
prism's 8 (of the triangles turned from the light), the silhouette of a box, and z-fail volumes closed and
facing out, counting the vertices at infinity, also where a point light lies on the mesh (a corner, an edge, a
face) or in a face's plane."""
from collections import Counter

import numpy as np
import pytest

from app.gl.lights3d.shadow_volumes import facing_light, onepass_volume, silhouette_volume
from app.model.lights3d import mesh as mesh3d
from tests.shadow_scenes import box, ground

UNIT_BOX = box((-1, -1, -1), (1, 1, 1))
POINT_OFF_CORNER = np.array([3.0, 4.0, 5.0, 1.0])


def sphere(rings: int, segments: int):
    """A closed UV sphere: two poles and rings x segments shared vertices, counter-clockwise from outside."""
    theta = np.linspace(0, np.pi, rings + 2)[1:-1]
    phi = np.linspace(0, 2 * np.pi, segments, endpoint=False)
    t, p = np.meshgrid(theta, phi, indexing="ij")
    ring = np.stack([np.sin(t) * np.cos(p), np.cos(t), -np.sin(t) * np.sin(p)], -1).reshape(-1, 3)
    positions = np.vstack([[0, 1, 0], ring, [0, -1, 0]])
    r, s = np.meshgrid(np.arange(rings - 1), np.arange(segments), indexing="ij")
    a, b = 1 + r * segments + s, 1 + r * segments + (s + 1) % segments
    c, d = a + segments, b + segments
    quads = np.concatenate([np.stack([a, c, d], -1).reshape(-1, 3), np.stack([a, d, b], -1).reshape(-1, 3)])
    s = np.arange(segments)
    top = np.stack([np.zeros(segments, int), 1 + s, 1 + (s + 1) % segments], -1)
    last = len(positions) - 1
    base = 1 + (rings - 1) * segments
    bottom = np.stack([np.full(segments, last), base + (s + 1) % segments, base + s], -1)
    return positions, np.concatenate([top, quads, bottom]).astype(np.int32)


def signed_volume(corners: np.ndarray) -> float:
    return float(np.einsum("ij,ij->i", corners[:, 0], np.cross(corners[:, 1], corners[:, 2])).sum() / 6)


def finite(vertices: np.ndarray, light: np.ndarray, reach: float = 1e3) -> np.ndarray:
    """A point light's volume with each w = 0 vertex (a direction from the light) put at `reach` along it."""
    v = vertices.astype(np.float64)
    return np.where(v[:, 3:] == 0, light[:3] + reach * v[:, :3], v[:, :3]).reshape(-1, 3, 3)


def directed_edges(vertices: np.ndarray) -> Counter:
    """Directed edges of the triangles, vertices told apart by all four coordinates (w = 0 ones included)."""
    keys = [v.tobytes() for v in vertices]
    tris = [keys[i:i + 3] for i in range(0, len(keys), 3)]
    return Counter((t[k], t[(k + 1) % 3]) for t in tris for k in range(3))


def test_test_meshes_are_closed_and_face_out():
    for positions, triangles in (UNIT_BOX, sphere(6, 9)):
        assert signed_volume(positions[triangles]) > 0
        silhouette_volume(positions, triangles, POINT_OFF_CORNER, caps=True)  # no ValueError: closed


def test_onepass_gives_seven_triangles_per_caster_triangle_the_seventh_the_caster():
    positions, triangles = UNIT_BOX
    volume = onepass_volume(positions, triangles, POINT_OFF_CORNER, closed=False)
    assert volume.vertices.dtype == np.float32 and volume.vertices.shape == (7 * 12 * 3, 4)
    assert volume.triangles == 7 * len(triangles) and volume.extruded_edges == 3 * len(triangles)
    groups = volume.vertices.reshape(len(triangles), 7, 3, 4)
    np.testing.assert_array_equal(groups[:, 0, :, :3], positions[triangles])  # the caster itself, w = 1
    assert (groups[:, 0, :, 3] == 1).all()
    at_infinity = groups[:, 1:][groups[:, 1:, :, 3] == 0]
    assert len(at_infinity) == 12 * 3 * 3  # 3 quads, each with 3 of its 6 vertices at infinity
    # every w = 0 vertex is a caster corner minus the light: the seed's extrusion away from a point light
    corners = {tuple(np.float32(p - POINT_OFF_CORNER[:3])) for p in positions}
    assert {tuple(v[:3]) for v in at_infinity} == corners


def closed_surfaces(vertices: np.ndarray) -> bool:
    """Every directed edge once and its reverse once: each edge shared by two triangles, opposite ways."""
    edges = directed_edges(vertices)
    return set(edges.values()) == {1} and all(edges[(b, a)] == 1 for a, b in edges)


@pytest.mark.parametrize("light", [POINT_OFF_CORNER, (0.3, 1.0, 0.2, 0.0)], ids=["point", "directional"])
def test_closed_onepass_caps_the_prisms_of_the_triangles_turned_from_the_light(light):
    """The seed's 7 and the far cap: the caster's corners at infinity, wound against the caster, so each caster
    triangle's 8 close around its prism; of the triangles turned from the light alone."""
    positions, triangles = sphere(4, 6)
    behind = ~facing_light(positions, triangles, light)
    assert 0 < behind.sum() < len(triangles)
    seed = onepass_volume(positions, triangles, light, closed=False)
    closed = onepass_volume(positions, triangles, light)
    assert closed.triangles == 8 * behind.sum() and closed.extruded_edges == 3 * behind.sum()
    groups = closed.vertices.reshape(-1, 8, 3, 4)
    np.testing.assert_array_equal(groups[:, :7], seed.vertices.reshape(-1, 7, 3, 4)[behind])
    light = np.asarray(light, float)
    far = light[3] * positions[triangles[behind]] - light[:3]  # the corners at infinity, away from the light
    np.testing.assert_array_equal(groups[:, 7, :, :3], np.float32(far[:, ::-1]))
    assert (groups[:, 7, :, 3] == 0).all()
    if light[3]:  # a directional light's corners all go to one point at infinity: its far caps have no area
        for prism in groups:
            assert closed_surfaces(prism.reshape(-1, 4))


def test_closed_onepass_leaves_out_the_flat_prisms_of_faces_in_the_lights_plane():
    positions, triangles = UNIT_BOX
    level = np.array([3.0, 1.0, 0.5, 1.0])  # level with the top face: its 2 triangles' prisms hold nothing
    # turned from it: the bottom, the far side and both ends (the near side faces it, the top is flat)
    assert onepass_volume(positions, triangles, level).triangles == 8 * 8
    assert onepass_volume(positions, triangles, level, closed=False).triangles == 7 * 12  # the seed draws all


def test_a_directional_light_sends_every_vertex_to_the_one_point_it_shines_towards():
    light = np.array([0.3, 1.0, 0.2, 0.0])
    volume = onepass_volume(*UNIT_BOX, light)
    far = volume.vertices[volume.vertices[:, 3] == 0]
    assert np.allclose(far[:, :3], -light[:3])


@pytest.mark.parametrize("light, faces, edges", [
    ((3.0, 4.0, 5.0, 1.0), 3, 6),    # off a corner: three faces lit, a hexagon of silhouette edges
    ((0.2, 5.0, -0.1, 1.0), 1, 4),   # above the top face: its square
    ((4.0, 4.0, 0.0, 1.0), 2, 6),    # off an edge: two faces
    ((0.3, 1.0, 0.2, 0.0), 3, 6),    # a directional light from a corner's side
])
def test_box_silhouette_edges(light, faces, edges):
    positions, triangles = UNIT_BOX
    assert facing_light(positions, triangles, light).sum() == 2 * faces
    volume = silhouette_volume(positions, triangles, light, caps=False)
    assert volume.extruded_edges == edges
    assert volume.triangles == 2 * edges  # z-pass: the side quads only
    capped = silhouette_volume(positions, triangles, light, caps=True)
    assert capped.triangles == 2 * edges + len(triangles)  # every mesh triangle is in one cap or the other


ON_THE_MESH = {  # point lights on the unit box or the sphere(6, 9) of radius 1, or in a face's plane
    "box corner": ("box", (1.0, 1.0, 1.0)), "box edge": ("box", (1.0, 1.0, 0.3)),
    "box face": ("box", (1.0, 0.2, -0.4)), "box face diagonal": ("box", (1.0, 0.3, 0.3)),
    "level with the top": ("box", (3.0, 1.0, 0.5)), "in two faces' planes": ("box", (3.0, 1.0, 1.0)),
    "sphere pole": ("sphere", (0.0, 1.0, 0.0)), "sphere vertex": ("sphere", None),
}


def mesh_and_light(case: str):
    mesh, light = ON_THE_MESH[case]
    positions, triangles = UNIT_BOX if mesh == "box" else sphere(6, 9)
    return positions, triangles, np.array([*(positions[20] if light is None else light), 1.0])


@pytest.mark.parametrize("mesh", ["box", "sphere"])
@pytest.mark.parametrize("light", [(3.0, 4.0, 5.0, 1.0), (0.0, 0.1, 0.0, 1.0)], ids=["outside", "inside"])
def test_zfail_volumes_are_closed_and_face_out(mesh, light):
    positions, triangles = UNIT_BOX if mesh == "box" else sphere(6, 9)
    light = np.array(light)
    volume = silhouette_volume(positions, triangles, light, caps=True)
    assert closed_surfaces(volume.vertices)
    assert signed_volume(finite(volume.vertices, light)) > 0  # faces point out of the volume


@pytest.mark.parametrize("case", list(ON_THE_MESH))
def test_a_light_on_the_mesh_or_in_a_faces_plane_keeps_the_volumes_closed_and_placeable(case):
    """No vertex at (0, 0, 0, 0) (GL cannot place it: the frame went dark), the z-fail volume closed and facing
    out, each closed one-pass prism closed, and a face with the light in its plane lit by neither side."""
    positions, triangles, light = mesh_and_light(case)
    in_plane = np.abs(np.einsum("ij,ij->i", np.cross(positions[triangles[:, 1]] - positions[triangles[:, 0]],
                                                     positions[triangles[:, 2]] - positions[triangles[:, 0]]),
                                light[:3] - positions[triangles[:, 0]])) < 1e-9
    assert in_plane.any()
    assert not (facing_light(positions, triangles, light) & in_plane).any()
    capped = silhouette_volume(positions, triangles, light, caps=True)
    for v in (capped, silhouette_volume(positions, triangles, light, caps=False),
              onepass_volume(positions, triangles, light), onepass_volume(positions, triangles, light, False)):
        assert np.isfinite(v.vertices).all() and np.abs(v.vertices).max(axis=1).min() > 0
    assert closed_surfaces(capped.vertices)
    assert signed_volume(finite(capped.vertices, light)) > 0
    for prism in onepass_volume(positions, triangles, light).vertices.reshape(-1, 24, 4):
        assert closed_surfaces(prism)


@pytest.mark.parametrize("height, faces", [(0.0, False), (2e-6, False), (-2e-6, False), (1e-3, True), (-1e-3, False)])
def test_a_light_within_the_in_plane_margin_of_a_face_is_behind_it(height, faces):
    """app/model/lights3d/facing.py: lit only above the plane by more than IN_PLANE of the way to the light (the
    sine of its elevation; 2e-6 of 10 units is 2e-7 of it)."""
    positions, triangles = UNIT_BOX
    light = np.array([10.0, 1.0 + height, 0.3, 1.0])  # level with the top face (y = 1), far off its side
    top = np.flatnonzero(positions[triangles][:, :, 1].min(axis=1) == 1.0)
    assert (facing_light(positions, triangles, light)[top] == faces).all()


@pytest.mark.parametrize("case", ["box corner", "box edge", "box face", "sphere pole"])
def test_a_light_on_the_mesh_still_gives_z_pass_a_volume(case):
    """Every face is behind such a light (none faces it: no silhouette), yet the volume has finite faces: the
    fans from the light over the faces that hold it, which z-pass counts."""
    positions, triangles, light = mesh_and_light(case)
    assert not facing_light(positions, triangles, light).any()
    volume = silhouette_volume(positions, triangles, light, caps=False)
    assert volume.extruded_edges == 0 and volume.triangles > 0
    assert (volume.vertices[:, 3] == 1).any()  # the light itself, the fans' apex
    np.testing.assert_array_equal(volume.vertices[volume.vertices[:, 3] == 1, :3], np.float32(light[:3])[None]
                                  .repeat((volume.vertices[:, 3] == 1).sum(), 0))


def test_light_inside_a_closed_mesh_leaves_only_the_dark_cap():
    positions, triangles = UNIT_BOX
    volume = silhouette_volume(positions, triangles, (0.0, 0.2, 0.1, 1.0), caps=True)
    assert volume.extruded_edges == 0 and volume.triangles == len(triangles)
    assert (volume.vertices[:, 3] == 0).all()


def test_silhouette_volumes_refuse_open_and_badly_wound_meshes():
    with pytest.raises(ValueError, match="not closed"):
        silhouette_volume(*ground(), POINT_OFF_CORNER, caps=True)
    positions, triangles = UNIT_BOX
    flipped = triangles.copy()
    flipped[0] = flipped[0, ::-1]
    with pytest.raises(ValueError, match="inconsistent"):
        silhouette_volume(positions, flipped, POINT_OFF_CORNER, caps=True)
    onepass_volume(*ground(), POINT_OFF_CORNER, closed=False)  # the seed's, a triangle at a time: open meshes are fine


@pytest.mark.parametrize("light", [(1, 2, 3, 0.5), (0, 0, 0, 0), (np.nan, 1, 1, 1), (1, 2, 3)])
def test_bad_lights_are_refused(light):
    with pytest.raises(ValueError):
        onepass_volume(*UNIT_BOX, light)


def test_bad_meshes_are_refused():
    positions, triangles = UNIT_BOX
    with pytest.raises(ValueError, match="index"):
        onepass_volume(positions, triangles + 8, POINT_OFF_CORNER)
    with pytest.raises(ValueError, match="finite"):
        onepass_volume(np.full((8, 3), np.inf), triangles, POINT_OFF_CORNER)


def test_a_big_mesh_builds_whole():
    """40 000 triangles (vectorised numpy, no per-triangle loop): 8 of every triangle turned from the light, and
    the capped silhouette volume's two triangles per silhouette edge plus every triangle once as a light or dark
    cap."""
    positions, triangles = sphere(100, 200)
    capped = silhouette_volume(positions, triangles, POINT_OFF_CORNER, caps=True)
    onepass = onepass_volume(positions, triangles, POINT_OFF_CORNER)
    assert onepass.triangles == 8 * (~facing_light(positions, triangles, POINT_OFF_CORNER)).sum()
    assert capped.extruded_edges > 0 and capped.triangles == 2 * capped.extruded_edges + len(triangles)


@pytest.mark.parametrize("caps", [False, True])
def test_a_mesh_kept_adjacency_gives_the_volume_paired_here(caps):
    mesh = mesh3d.torus(5.0, 1.5, 16, 8).moved((2.0, 1.0, -1.0))
    for light in (POINT_OFF_CORNER, np.array([0.0, 0.5, 0.0, 1.0]), np.array([0.3, 1.0, -0.2, 0.0])):
        kept = silhouette_volume(mesh.positions, mesh.triangles, light, caps, adjacency=mesh.adjacency())
        paired = silhouette_volume(mesh.positions, mesh.triangles, light, caps)
        assert kept.extruded_edges == paired.extruded_edges > 0
        np.testing.assert_array_equal(kept.vertices, paired.vertices)
