"""The 3D lights' meshes: every closed generator is a 2-manifold wound outward (its signed volume is the
analytic volume, within the tessellation's error), normals are unit and outward, segment counts set the
triangle counts, and the adjacency pairs each edge's two triangles."""
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from app.model.lights3d import mesh as mesh3d
from app.model.lights3d.mesh import Mesh, MeshError

LENGTH = st.floats(0.5, 400.0)
SEGMENTS = st.integers(mesh3d.MIN_SEGMENTS, 48)
FAST = settings(max_examples=25, deadline=None)


def assert_closed_outward(mesh: Mesh) -> None:
    """Every directed edge once, its reverse once (so each edge joins exactly two triangles, wound
    consistently), and the shading normals on the outer side of their triangles."""
    directed = mesh.triangles[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2)
    as_set = {tuple(e) for e in directed.tolist()}
    assert len(as_set) == len(directed), "a directed edge appears twice"
    assert all((b, a) in as_set for a, b in as_set), "an edge with one triangle"
    assert mesh.closed
    adjacency = mesh.adjacency()
    assert len(adjacency.edges) * 2 == len(directed) and (adjacency.faces >= 0).all()
    np.testing.assert_allclose(np.linalg.norm(mesh.normals, axis=2), 1.0, atol=1e-12)
    # each corner's shading normal leans the way the winding says is out
    assert (np.einsum("tkd,td->tk", mesh.normals, mesh.face_normals()) > 0).all()


def relative_deficit(mesh: Mesh, exact: float) -> float:
    return (exact - mesh.signed_volume()) / exact


@FAST
@given(LENGTH, LENGTH, LENGTH)
def test_box_is_closed_with_its_exact_volume(sx, sy, sz):
    mesh = mesh3d.box(sx, sy, sz)
    assert_closed_outward(mesh)
    assert len(mesh.triangles) == mesh3d.BOX_TRIANGLES and len(mesh.positions) == 8
    assert mesh.signed_volume() == pytest.approx(sx * sy * sz, rel=1e-12)
    np.testing.assert_allclose(mesh.positions.max(0), [sx / 2, sy / 2, sz / 2])  # centred on the origin
    np.testing.assert_allclose(mesh.positions.min(0), [-sx / 2, -sy / 2, -sz / 2])


@FAST
@given(st.floats(0.5, 200.0), SEGMENTS)
def test_sphere_is_closed_and_its_volume_converges(radius, segments):
    mesh = mesh3d.sphere(radius, segments)
    assert_closed_outward(mesh)
    assert len(mesh.triangles) == mesh3d.sphere_triangles(segments)
    np.testing.assert_allclose(np.linalg.norm(mesh.positions, axis=1), radius, rtol=1e-12)
    # the smooth normals point straight out: the corner's position over the radius
    np.testing.assert_allclose(mesh.normals * radius, mesh.corners(), atol=1e-9 * radius)
    # inscribed, so never more than the ball; the deficit shrinks as 1 / segments^2
    rings = mesh3d.sphere_rings(segments)
    deficit = relative_deficit(mesh, 4 / 3 * math.pi * radius ** 3)
    assert 0 < deficit <= math.pi ** 2 * (1 / segments ** 2 + 1 / (2 * rings) ** 2)


def test_sphere_poles_are_single_shared_vertices():
    mesh = mesh3d.sphere(1.0, 12)
    assert np.count_nonzero(np.isclose(np.abs(mesh.positions[:, 1]), 1.0)) == 2
    top = np.count_nonzero((mesh.triangles == 0).any(1))
    assert top == 12  # the whole top cap fans around vertex 0


@FAST
@given(st.floats(2.0, 100.0), st.floats(0.05, 0.95), SEGMENTS, SEGMENTS)
def test_torus_is_closed_and_its_volume_converges(major, ratio, segments, sides):
    minor = major * ratio
    mesh = mesh3d.torus(major, minor, segments, sides)
    assert_closed_outward(mesh)
    assert len(mesh.triangles) == mesh3d.torus_triangles(segments, sides) == 2 * segments * sides
    ring = np.hypot(mesh.positions[:, 0], mesh.positions[:, 2])
    np.testing.assert_allclose(np.hypot(ring - major, mesh.positions[:, 1]), minor, rtol=1e-9)
    deficit = relative_deficit(mesh, 2 * math.pi ** 2 * major * minor ** 2)
    assert 0 < deficit <= math.pi ** 2 * (1 / segments ** 2 + 1 / sides ** 2)


@FAST
@given(LENGTH, LENGTH, LENGTH, st.floats(0.05, 0.95))
def test_l_prism_is_closed_not_convex_with_its_exact_volume(sx, sy, sz, ratio):
    t = ratio * min(sx, sy)
    mesh = mesh3d.l_prism(sx, sy, sz, t)
    assert_closed_outward(mesh)
    assert len(mesh.triangles) == mesh3d.LPRISM_TRIANGLES
    assert mesh.signed_volume() == pytest.approx(sz * t * (sx + sy - t), rel=1e-9)
    np.testing.assert_allclose(mesh.positions.max(0), [sx / 2, sy / 2, sz / 2])
    # not convex: some vertex lies in front of some face's plane (the column's, over the foot's top)
    ahead = np.einsum("td,vtd->vt", mesh.face_normals(), mesh.positions[:, None] - mesh.corners()[None, :, 0])
    assert ahead.max() > 1e-6 * max(sx, sy, sz)


def test_plane_is_open_and_faces_up():
    mesh = mesh3d.plane(400.0)
    assert not mesh.closed and len(mesh.triangles) == 2
    np.testing.assert_allclose(mesh.face_normals(), [[0, 1, 0], [0, 1, 0]])
    np.testing.assert_allclose(mesh.positions[:, 1], 0.0)
    assert np.abs(mesh.positions).max() == 200.0
    borders = mesh.adjacency().faces[:, 1] == -1
    assert borders.sum() == 4 and (~borders).sum() == 1  # the diagonal joins the two triangles


def test_adjacency_pairs_opposite_directed_edges():
    mesh = mesh3d.l_prism(4.0, 5.0, 2.0, 1.0)
    adjacency = mesh.adjacency()
    for (a, b), (f, g) in zip(adjacency.edges.tolist(), adjacency.faces.tolist()):
        first, second = mesh.triangles[f].tolist(), mesh.triangles[g].tolist()
        assert (a, b) in zip(first, first[1:] + first[:1])
        assert (b, a) in zip(second, second[1:] + second[:1])


def test_moved_translates_and_shares_the_topology():
    mesh = mesh3d.sphere(2.0, 8)
    adjacency = mesh.adjacency()
    moved = mesh.moved((10.0, -2.0, 3.0))
    np.testing.assert_allclose(moved.positions - mesh.positions, np.tile([10.0, -2.0, 3.0], (len(mesh.positions), 1)))
    assert moved.triangles is mesh.triangles and moved.normals is mesh.normals
    assert moved.adjacency() is adjacency
    assert moved.signed_volume() == pytest.approx(mesh.signed_volume(), rel=1e-9)
    with pytest.raises(ValueError):
        moved.positions[0, 0] = 5.0  # shared arrays are read-only


def test_moves_share_one_adjacency_whichever_asks_first():
    mesh = mesh3d.torus(5.0, 1.0, 12, 6)
    first, second = mesh.moved((1.0, 0.0, 0.0)), mesh.moved((0.0, 2.0, 0.0)).moved((0.0, 0.0, 3.0))
    adjacency = first.adjacency()  # asked of a moved copy before the mesh itself was asked
    assert second.adjacency() is adjacency and mesh.adjacency() is adjacency


@pytest.mark.parametrize("triangles", [100, 5_000, 100_000])
def test_sphere_segments_reach_a_triangle_count(triangles):
    n = mesh3d.sphere_segments(triangles)
    assert mesh3d.sphere_triangles(n) >= triangles > mesh3d.sphere_triangles(n - 1)
    if triangles == 100_000:
        mesh = mesh3d.sphere(30.0, n)
        assert len(mesh.triangles) == mesh3d.sphere_triangles(n) < 102_000
        assert mesh.adjacency().faces.min() >= 0  # still closed at bench size


@pytest.mark.parametrize("triangles, needle", [
    ([[0, 1, 2], [0, 1, 2]], "same way"),                         # a duplicated triangle
    ([[0, 1, 2], [0, 2, 3], [0, 1, 3]], "inconsistent|same way"),  # one wound the wrong way
    ([[0, 1, 2], [1, 0, 3], [0, 1, 4]], "more than two"),
    ([[0, 1, 2], [0, 2, 3]], "not closed"),
])
def test_a_mesh_that_is_not_what_it_claims_is_refused(triangles, needle):
    positions = np.random.default_rng(1).normal(size=(5, 3))
    tri = np.array(triangles)
    mesh = Mesh(positions, tri, np.tile([0.0, 0.0, 1.0], (len(tri), 3, 1)), closed=True)
    with pytest.raises(MeshError, match=needle):
        mesh.adjacency()


@pytest.mark.parametrize("kwargs, needle", [
    (dict(positions=np.zeros((4, 2))), "positions must have shape"),
    (dict(triangles=[[0, 1, 7]]), "must index the 4 positions"),
    (dict(positions=np.full((4, 3), np.nan)), "finite"),
    (dict(normals=np.zeros((2, 3, 3))), "normals must have shape"),
    (dict(triangles=np.zeros((0, 3)), normals=np.zeros((0, 3, 3))), "at least one triangle"),
])
def test_bad_arrays_are_refused(kwargs, needle):
    args = dict(positions=np.zeros((4, 3)), triangles=[[0, 1, 2]], normals=np.zeros((1, 3, 3)), closed=False)
    with pytest.raises(MeshError, match=needle):
        Mesh(**{**args, **kwargs})
